//! Cell outlines traced from a label map, for vector output. The borders between pixels of
//! different labels are followed as polylines between junctions (corners where three or more
//! cells, or the image edge, meet) and each polyline is simplified once by Douglas–Peucker, so
//! two neighbouring cells share exactly the same simplified border: no gaps, no overlaps.
//! The polylines are then linked into closed rings per cell, every ring with its cell on the
//! left, so holes wind the other way and fill correctly under the non-zero rule.
//!
//! Coordinates are pixel corners of the label map (`i32`); simplified rings are `f32`.

/// A label outside the map: the image edge is a border like any other.
const OUTSIDE: i32 = i32::MIN;

/// A border polyline between two junctions (or a closed loop), with the labels on its left
/// and right when walked from its first point to its last.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// Corners along the border, first and last included (equal for a closed loop).
    pub points: Vec<[i32; 2]>,
    /// Label on the left (image coordinates, y down).
    pub left: i32,
    /// Label on the right.
    pub right: i32,
}

/// The borders of a `width × height` label map (row-major) as chains.
#[derive(Clone, Debug)]
pub struct Borders {
    /// Every border once.
    pub chains: Vec<Chain>,
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Dir {
    East,
    West,
    South,
    North,
}

struct Map<'a> {
    labels: &'a [i32],
    w: i32,
    h: i32,
}

impl Map<'_> {
    fn label(&self, x: i32, y: i32) -> i32 {
        if x < 0 || y < 0 || x >= self.w || y >= self.h {
            OUTSIDE
        } else {
            self.labels[(y * self.w + x) as usize]
        }
    }

    /// Index of the edge leaving corner `(x, y)` in `dir` among all edges (horizontal ones
    /// first), or `None` off the map.
    fn edge(&self, x: i32, y: i32, dir: Dir) -> Option<usize> {
        let (w, h) = (self.w, self.h);
        let horizontal = |ex: i32, ey: i32| (ey * w + ex) as usize;
        let vertical = |ex: i32, ey: i32| ((h + 1) * w + ey * (w + 1) + ex) as usize;
        match dir {
            Dir::East if x < w => Some(horizontal(x, y)),
            Dir::West if x > 0 => Some(horizontal(x - 1, y)),
            Dir::South if y < h => Some(vertical(x, y)),
            Dir::North if y > 0 => Some(vertical(x, y - 1)),
            _ => None,
        }
    }

    /// (left, right) labels of the step from `(x, y)` in `dir`.
    fn sides(&self, x: i32, y: i32, dir: Dir) -> (i32, i32) {
        match dir {
            Dir::East => (self.label(x, y - 1), self.label(x, y)),
            Dir::West => (self.label(x - 1, y), self.label(x - 1, y - 1)),
            Dir::South => (self.label(x, y), self.label(x - 1, y)),
            Dir::North => (self.label(x - 1, y - 1), self.label(x, y - 1)),
        }
    }

    fn is_border(&self, x: i32, y: i32, dir: Dir) -> bool {
        if self.edge(x, y, dir).is_none() {
            return false;
        }
        let (l, r) = self.sides(x, y, dir);
        l != r
    }

    fn degree(&self, x: i32, y: i32) -> usize {
        [Dir::East, Dir::West, Dir::South, Dir::North]
            .into_iter()
            .filter(|&d| self.is_border(x, y, d))
            .count()
    }
}

fn step(x: i32, y: i32, dir: Dir) -> (i32, i32) {
    match dir {
        Dir::East => (x + 1, y),
        Dir::West => (x - 1, y),
        Dir::South => (x, y + 1),
        Dir::North => (x, y - 1),
    }
}

fn reverse(dir: Dir) -> Dir {
    match dir {
        Dir::East => Dir::West,
        Dir::West => Dir::East,
        Dir::South => Dir::North,
        Dir::North => Dir::South,
    }
}

const DIRS: [Dir; 4] = [Dir::East, Dir::South, Dir::West, Dir::North];

impl Borders {
    /// Traces every border of `labels` (`width × height`, row-major).
    #[must_use]
    pub fn trace(labels: &[i32], width: usize, height: usize) -> Self {
        assert_eq!(labels.len(), width * height, "label map size");
        let map = Map {
            labels,
            w: width as i32,
            h: height as i32,
        };
        let edges = (height + 1) * width + height * (width + 1);
        let mut visited = vec![false; edges];
        let mut chains = Vec::new();
        let junction = |x: i32, y: i32| map.degree(x, y) != 2;
        // Chains between junctions first, then closed loops that meet no junction.
        for pass in 0..2 {
            for y in 0..=map.h {
                for x in 0..=map.w {
                    if pass == 0 && !junction(x, y) {
                        continue;
                    }
                    for dir in DIRS {
                        if !map.is_border(x, y, dir) {
                            continue;
                        }
                        let e = map.edge(x, y, dir).expect("a border is on the map");
                        if !visited[e] {
                            chains.push(walk(&map, &mut visited, x, y, dir, &junction));
                        }
                    }
                }
            }
        }
        Borders { chains }
    }
}

/// Follows the border from `(x, y)` in `dir` to the next junction (or back to the start).
fn walk(
    map: &Map,
    visited: &mut [bool],
    x0: i32,
    y0: i32,
    dir0: Dir,
    junction: &impl Fn(i32, i32) -> bool,
) -> Chain {
    let (left, right) = map.sides(x0, y0, dir0);
    let mut points = vec![[x0, y0]];
    let (mut x, mut y, mut dir) = (x0, y0, dir0);
    loop {
        visited[map.edge(x, y, dir).expect("on the map")] = true;
        (x, y) = step(x, y, dir);
        points.push([x, y]);
        if (x, y) == (x0, y0) || junction(x, y) {
            break;
        }
        // A corner of degree 2: the one other border edge, which separates the same labels.
        let back = reverse(dir);
        dir = DIRS
            .into_iter()
            .find(|&d| d != back && map.is_border(x, y, d))
            .expect("degree-2 corner has a second border edge");
    }
    Chain {
        points,
        left,
        right,
    }
}

/// `points` simplified by Douglas–Peucker: every dropped point lies within `tolerance` of the
/// kept polyline; the first and last points are kept. A closed polyline (first = last) is
/// split at its point farthest from the start first.
#[must_use]
pub fn simplify(points: &[[i32; 2]], tolerance: f32) -> Vec<[f32; 2]> {
    let p: Vec<[f32; 2]> = points.iter().map(|&[x, y]| [x as f32, y as f32]).collect();
    if p.len() <= 2 {
        return p;
    }
    let mut keep = vec![false; p.len()];
    keep[0] = true;
    keep[p.len() - 1] = true;
    let mut stack = Vec::new();
    if p[0] == p[p.len() - 1] {
        let far = (1..p.len() - 1)
            .max_by(|&a, &b| dist2(p[a], p[0]).total_cmp(&dist2(p[b], p[0])))
            .unwrap_or(1);
        keep[far] = true;
        stack.push((0, far));
        stack.push((far, p.len() - 1));
    } else {
        stack.push((0, p.len() - 1));
    }
    let t2 = tolerance * tolerance;
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (mut worst, mut at) = (0.0f32, a);
        for k in a + 1..b {
            let d = segment_dist2(p[k], p[a], p[b]);
            if d > worst {
                (worst, at) = (d, k);
            }
        }
        if worst > t2 {
            keep[at] = true;
            stack.push((a, at));
            stack.push((at, b));
        }
    }
    p.into_iter()
        .zip(keep)
        .filter_map(|(q, k)| k.then_some(q))
        .collect()
}

fn dist2(a: [f32; 2], b: [f32; 2]) -> f32 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

fn segment_dist2(p: [f32; 2], a: [f32; 2], b: [f32; 2]) -> f32 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    if len2 == 0.0 {
        return dist2(p, a);
    }
    let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0);
    dist2(p, [a[0] + t * dx, a[1] + t * dy])
}

/// Closed rings of every label `0..labels` from simplified chains (`simplified[k]` belongs to
/// `borders.chains[k]`): `rings[label]` lists its rings, each with the cell on its left and
/// its first point not repeated at the end. Negative labels (no cell) get no rings.
#[must_use]
pub fn rings(
    borders: &Borders,
    simplified: &[Vec<[f32; 2]>],
    labels: usize,
) -> Vec<Vec<Vec<[f32; 2]>>> {
    // Per label: (chain, reversed), so that the label is on the chain's left.
    let mut sides: Vec<Vec<(u32, bool)>> = vec![Vec::new(); labels];
    for (k, c) in borders.chains.iter().enumerate() {
        if let Ok(l) = usize::try_from(c.left) {
            sides[l].push((k as u32, false));
        }
        if let Ok(r) = usize::try_from(c.right) {
            sides[r].push((k as u32, true));
        }
    }
    let ends = |k: u32, reversed: bool| {
        let p = &borders.chains[k as usize].points;
        let (first, last) = (p[0], p[p.len() - 1]);
        if reversed {
            (last, first)
        } else {
            (first, last)
        }
    };
    sides
        .iter()
        .map(|parts| {
            let mut used = vec![false; parts.len()];
            let mut out = Vec::new();
            for start in 0..parts.len() {
                if used[start] {
                    continue;
                }
                let mut ring: Vec<[f32; 2]> = Vec::new();
                let ring_start = ends(parts[start].0, parts[start].1).0;
                let mut at = start;
                loop {
                    used[at] = true;
                    let (k, reversed) = parts[at];
                    let s = &simplified[k as usize];
                    // Each piece's last point is the next piece's first: skip it.
                    if reversed {
                        ring.extend(s.iter().rev().take(s.len() - 1));
                    } else {
                        ring.extend(s.iter().take(s.len() - 1));
                    }
                    let end = ends(k, reversed).1;
                    if end == ring_start {
                        break;
                    }
                    match (0..parts.len())
                        .find(|&j| !used[j] && ends(parts[j].0, parts[j].1).0 == end)
                    {
                        Some(next) => at = next,
                        None => break,
                    }
                }
                if ring.len() >= 3 {
                    out.push(ring);
                }
            }
            out
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the signed area of a ring (shoelace); positive is clockwise on screen (y down).
    fn area2(ring: &[[f32; 2]]) -> f64 {
        let n = ring.len();
        (0..n)
            .map(|i| {
                let (a, b) = (ring[i], ring[(i + 1) % n]);
                f64::from(a[0]) * f64::from(b[1]) - f64::from(b[0]) * f64::from(a[1])
            })
            .sum()
    }

    #[test]
    fn unsimplified_rings_enclose_exactly_each_cells_pixels() {
        // Three cells, one of them an island with a hole, on a 9×7 map.
        let (w, h) = (9usize, 7usize);
        let mut labels = vec![0i32; w * h];
        for y in 0..h {
            for x in 0..w {
                let i = y * w + x;
                if x >= 5 {
                    labels[i] = 1;
                }
                if (1..4).contains(&x) && (1..6).contains(&y) {
                    labels[i] = 2;
                }
                if x == 2 && y == 3 {
                    labels[i] = 0; // a hole in cell 2, belonging to cell 0
                }
            }
        }
        let borders = Borders::trace(&labels, w, h);
        let exact: Vec<Vec<[f32; 2]>> = borders
            .chains
            .iter()
            .map(|c| {
                c.points
                    .iter()
                    .map(|&[x, y]| [x as f32, y as f32])
                    .collect()
            })
            .collect();
        let rings = rings(&borders, &exact, 3);
        for (label, cell_rings) in rings.iter().enumerate() {
            let pixels = labels.iter().filter(|&&l| l == label as i32).count() as f64;
            // Cell on the left with y down: outer rings run anticlockwise on screen, which is
            // a negative shoelace sum; holes the other way.
            let area: f64 = cell_rings.iter().map(|r| -area2(r) / 2.0).sum();
            assert_eq!(area, pixels, "label {label}");
        }
        assert_eq!(rings[2].len(), 2, "cell 2 has an outline and a hole");
    }

    #[test]
    fn neighbours_share_their_simplified_border() {
        // A diagonal staircase between two cells.
        let (w, h) = (40usize, 40usize);
        let labels: Vec<i32> = (0..w * h).map(|i| i32::from(i % w > i / w)).collect();
        let borders = Borders::trace(&labels, w, h);
        let simplified: Vec<_> = borders
            .chains
            .iter()
            .map(|c| simplify(&c.points, 0.75))
            .collect();
        let shared = borders
            .chains
            .iter()
            .position(|c| (c.left.min(c.right), c.left.max(c.right)) == (0, 1))
            .expect("a border between 0 and 1");
        // The staircase simplifies to its diagonal.
        assert_eq!(simplified[shared].len(), 2);
        let rings = rings(&borders, &simplified, 2);
        assert_eq!(rings[0].len(), 1);
        assert_eq!(rings[1].len(), 1);
        // The two triangles together cover the square exactly.
        let total: f64 = rings.iter().flatten().map(|r| -area2(r) / 2.0).sum();
        assert_eq!(total, (w * h) as f64);
    }

    #[test]
    fn simplification_keeps_points_within_tolerance() {
        let wave: Vec<[i32; 2]> = (0..200)
            .map(|i| {
                [
                    i,
                    (f64::from(i) * 0.2).sin().mul_add(6.0, 0.0).round() as i32,
                ]
            })
            .collect();
        let s = simplify(&wave, 1.0);
        assert!(s.len() < wave.len() / 3, "{} points kept", s.len());
        for p in &wave {
            let q = [p[0] as f32, p[1] as f32];
            let d = s
                .windows(2)
                .map(|ab| segment_dist2(q, ab[0], ab[1]))
                .fold(f32::INFINITY, f32::min);
            assert!(d.sqrt() <= 1.0 + 1e-4);
        }
    }
}
