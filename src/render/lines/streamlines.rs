//! Evenly spaced streamlines of the field's long axes (Jobard and Lefer, *Creating Evenly-Spaced
//! Streamlines of Arbitrary Density*, 1997), the lines of the engraving look
//! ([`crate::render::looks::engraving`]). A line runs along the major eigenvector of the metric
//! (paper section 3: along the photo's edges, the minor direction of its structure tensor) and is
//! traced both ways from a seed with midpoint (RK2) steps until it is two spacings past the
//! domain's border (so the lines beside it find a neighbour right up to the border), comes closer
//! than `d_test` to a line already laid (or to itself), turns too sharply (a singularity of the
//! field), or crosses a strong edge of the tone. New seeds go at `d_sep` on either side of every
//! line laid, line after line, so the lines fill the picture as neighbours of each other; what that
//! leaves (areas cut off by edges) is seeded from the samples' positions (the paper's particles),
//! then from a grid, and last one seed clearance from every line, which fills the gaps too narrow
//! for a seed at `d_sep` from either side yet too wide to be the two lines' paper.
//!
//! The lines run along [`Directions`] ([`super::line_field`]): the metric's long axes, calm
//! where the photo gives no direction.
//!
//! Every line point also gets its share of the paper on either side (half the gap to its
//! neighbour there), from which the engraving sets how far the line's ink reaches on that side
//! for the tone there.
//! Everything is `f64` in domain units (photo pixels); the occupancy grid has cells of `d_sep`,
//! so a distance query reads at most nine cells. Tracing is sequential and deterministic (tens
//! of thousands of points at any output size, as the spacing is a share of the diagonal); the
//! shares are measured in parallel.

use super::line_field::Directions;
use glam::DVec2;
use rayon::prelude::*;
use std::collections::VecDeque;

/// One streamline: its points in domain units, in order, and at each point the width across
/// the lines that belongs to it (domain units; `d_sep` where the lines are evenly spaced).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Streamline {
    /// The points, [`STEP_RATIO`]` · d_sep` apart.
    pub points: Vec<DVec2>,
    /// At every point, half the gap to the neighbouring line on its left (along
    /// [`normal_at`]) and on its right: the paper this line answers for on either side.
    pub halves: Vec<[f64; 2]>,
}

/// How the lines are laid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineLayout {
    /// Separation of neighbouring lines, domain units.
    pub d_sep: f64,
    /// Direction (radians from +x) where the field has none.
    pub flat_angle: f64,
    /// A line stops where the tone changes by more than this (lightness, 0 to 1) over one line
    /// spacing along it: a strong edge across its path. 1 or more: never.
    pub edge_break: f32,
}

/// Closest approach of two lines as a share of `d_sep` (Jobard and Lefer's `d_test`).
pub const TEST_RATIO: f64 = 0.5;
/// Integration step as a share of `d_sep`.
pub const STEP_RATIO: f64 = 0.25;
/// A seed needs this share of `d_sep` free around it.
const SEED_RATIO: f64 = 0.9;
/// A step may turn the line by at most 40° (its cosine): beyond, the field has a singularity
/// there and the line stops.
const MAX_TURN_COS: f64 = 0.766;
/// A line runs on this many steps (two spacings) past the picture's border, where the lines
/// beside it find it as their neighbour. Lines that ended at the border would leave, where
/// they meet it at a slant, the corner between one line's end and the next line as paper on no
/// line's normal: dots of paper along the border of dark areas. Two spacings, as a slanted
/// line goes only `sin θ` as deep.
const OUTSIDE_STEPS: usize = 8;
/// The gaps to the neighbouring lines are looked for up to this share of `d_sep` away; no line
/// there counts as a gap of `d_sep` (a border, a break). A gap narrower than twice a seed's
/// clearance can take no new line, so it is the paper of the two lines beside it, however
/// wide: where lines part (round a form, or fanning out), their shares, and so their widths,
/// grow with it until a new line fits. (At 1.5 spacings, gaps of 1.5 to 1.8 would count as
/// one spacing, and dark areas where lines part keep hairlines of paper.)
const GAP_REACH: f64 = 2.0 * SEED_RATIO;
/// A line's own points this share of `d_sep` or more across it are the line come round again
/// (see [`PackedGrid::halves`]): the inside of a loop or of a spiral's next turn is the paper
/// of the line's two sides there. Counted as no line, it was a gap of one spacing on the inner
/// side whatever its width: the middle of a small loop was left as paper (white eyes in dark
/// swirls), and the wider turns of a spiral (the coins' faces) were inked too thin.
const OWN_RETURN: f64 = 0.5 * TEST_RATIO;

/// Lays evenly spaced streamlines of `directions` over `domain`. `lightness` is the tone the
/// edge breaks read; `seeds` are tried, in order, where the lines' own seeding leaves room.
#[must_use]
pub fn streamlines(
    directions: &Directions,
    lightness: &(dyn Fn(DVec2) -> f32 + Sync),
    domain: DVec2,
    layout: &LineLayout,
    seeds: &[DVec2],
) -> Vec<Streamline> {
    let d_sep = layout.d_sep.max(1e-3);
    let mut tracer = Tracer {
        directions,
        lightness,
        domain,
        layout: LineLayout { d_sep, ..*layout },
        grid: Occupancy::new(domain, d_sep),
        lines: Vec::new(),
        queue: VecDeque::new(),
    };
    let centre = domain * 0.5;
    tracer.try_seed(centre);
    tracer.drain();
    for &s in seeds {
        tracer.try_seed(s);
        tracer.drain();
    }
    let (nx, ny) = (
        (domain.x / d_sep).ceil() as usize,
        (domain.y / d_sep).ceil() as usize,
    );
    for j in 0..ny {
        for i in 0..nx {
            tracer.try_seed(DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * d_sep);
            tracer.drain();
        }
    }
    tracer.fill_wide_gaps();
    let Tracer { grid, lines, .. } = tracer;
    let grid = grid.packed();
    lines
        .into_par_iter()
        .enumerate()
        .map(|(id, points)| {
            let halves = (0..points.len())
                .map(|i| grid.halves(&points, i, id as u32, d_sep))
                .collect();
            Streamline { points, halves }
        })
        .collect()
}

struct Tracer<'a> {
    directions: &'a Directions,
    lightness: &'a (dyn Fn(DVec2) -> f32 + Sync),
    domain: DVec2,
    layout: LineLayout,
    grid: Occupancy,
    lines: Vec<Vec<DVec2>>,
    queue: VecDeque<DVec2>,
}

impl Tracer<'_> {
    fn inside(&self, p: DVec2) -> bool {
        p.x >= 0.0 && p.y >= 0.0 && p.x <= self.domain.x && p.y <= self.domain.y
    }

    /// Traces a line from `seed` if there is room for it, and queues seeds beside it.
    fn try_seed(&mut self, seed: DVec2) {
        let d_sep = self.layout.d_sep;
        if !self.inside(seed) || !self.grid.clear(seed, SEED_RATIO * d_sep, u32::MAX, 0, 0) {
            return;
        }
        let id = self.lines.len() as u32;
        let d0 = self.directions.at(seed);
        self.grid.insert(seed, id, 0);
        let forward = self.walk(seed, d0, id, 1);
        let backward = self.walk(seed, -d0, id, -1);
        if forward.is_empty() && backward.is_empty() {
            self.grid.remove_last();
            return;
        }
        let mut points: Vec<DVec2> = backward.into_iter().rev().collect();
        points.push(seed);
        points.extend(forward);
        for i in (0..points.len()).step_by(2) {
            let t = (points[(i + 1).min(points.len() - 1)] - points[i.saturating_sub(1)])
                .normalize_or_zero();
            let n = t.perp();
            self.queue.push_back(points[i] + n * d_sep);
            self.queue.push_back(points[i] - n * d_sep);
        }
        self.lines.push(points);
    }

    fn drain(&mut self) {
        while let Some(s) = self.queue.pop_front() {
            self.try_seed(s);
        }
    }

    /// Seeds the gaps that the seeds one spacing from a line miss. A gap wider than
    /// [`GAP_REACH`] (two seed clearances) no longer counts as the paper of the two lines
    /// beside it, but one under 1.9 spacings (one spacing and one clearance) has no room one
    /// spacing from either side, so it would take no line, and its two lines would ink a
    /// spacing of it between them: a strip of paper down the middle (white scratches on a night
    /// sky or a dark coat). Seeds one clearance from every line (lines laid by this pass
    /// included) fit in the gaps wider than two clearances.
    fn fill_wide_gaps(&mut self) {
        let off = (SEED_RATIO + 1e-6) * self.layout.d_sep;
        let mut id = 0;
        while id < self.lines.len() {
            for i in (0..self.lines[id].len()).step_by(2) {
                let (p, n) = (self.lines[id][i], normal_at(&self.lines[id], i));
                for side in [1.0, -1.0] {
                    self.try_seed(p + n * (side * off));
                    self.drain();
                }
            }
            id += 1;
        }
    }

    /// Steps from `start` along `dir` (sign `sign` of the sequence numbers), inserting every
    /// point into the grid, until a stopping rule holds.
    fn walk(&mut self, start: DVec2, dir: DVec2, id: u32, sign: i32) -> Vec<DVec2> {
        let d_sep = self.layout.d_sep;
        let h = STEP_RATIO * d_sep;
        let d_test = TEST_RATIO * d_sep;
        // Nearby points of the line itself are not "another line" (its own last few steps).
        let skip = (2.0 * TEST_RATIO / STEP_RATIO).ceil() as i32 + 1;
        let max_steps = (4.0 * (self.domain.x + self.domain.y) / h) as i32 + 8;
        let (mut p, mut dir) = (start, dir);
        let mut out = Vec::new();
        let mut outside = 0;
        for k in 1..max_steps {
            let a = aligned(self.directions.at(p), dir);
            let b = aligned(self.directions.at(p + a * (0.5 * h)), a);
            if b.dot(dir) < MAX_TURN_COS {
                break;
            }
            let q = p + b * h;
            if !self.inside(q) {
                outside += 1;
                if outside > OUTSIDE_STEPS {
                    break;
                }
            }
            let step = ((self.lightness)(q) - (self.lightness)(p)).abs() / STEP_RATIO as f32;
            if step > self.layout.edge_break {
                break;
            }
            let seq = sign * k;
            if !self.grid.clear(q, d_test, id, seq, skip) {
                break;
            }
            self.grid.insert(q, id, seq);
            out.push(q);
            (p, dir) = (q, b);
        }
        out
    }
}

/// `v` or `−v`, whichever points along `reference`.
fn aligned(v: DVec2, reference: DVec2) -> DVec2 {
    if v.dot(reference) < 0.0 {
        -v
    } else {
        v
    }
}

/// Line points bucketed in square cells of `d_sep`.
struct Occupancy {
    domain: DVec2,
    cell: f64,
    cols: usize,
    rows: usize,
    cells: Vec<Vec<u32>>,
    points: Vec<DVec2>,
    /// Line and sequence number (signed: negative behind the seed) of every point.
    tags: Vec<(u32, i32)>,
}

impl Occupancy {
    fn new(domain: DVec2, cell: f64) -> Self {
        let cols = (domain.x / cell).ceil().max(1.0) as usize;
        let rows = (domain.y / cell).ceil().max(1.0) as usize;
        Occupancy {
            domain,
            cell,
            cols,
            rows,
            cells: vec![Vec::new(); cols * rows],
            points: Vec::new(),
            tags: Vec::new(),
        }
    }

    fn cell_of(&self, p: DVec2) -> (usize, usize) {
        cell_of(p, self.cell, self.cols, self.rows)
    }

    /// The points packed cell by cell, row-major, for the queries that follow the tracing.
    fn packed(self) -> PackedGrid {
        let mut offsets = Vec::with_capacity(self.cells.len() + 1);
        let mut points = Vec::with_capacity(self.points.len());
        offsets.push(0u32);
        for cell in &self.cells {
            points.extend(
                cell.iter()
                    .map(|&i| (self.points[i as usize], self.tags[i as usize].0)),
            );
            offsets.push(points.len() as u32);
        }
        PackedGrid {
            domain: self.domain,
            cell: self.cell,
            cols: self.cols,
            rows: self.rows,
            offsets,
            points,
        }
    }

    fn insert(&mut self, p: DVec2, line: u32, seq: i32) {
        let (c, r) = self.cell_of(p);
        self.cells[r * self.cols + c].push(self.points.len() as u32);
        self.points.push(p);
        self.tags.push((line, seq));
    }

    fn remove_last(&mut self) {
        if let Some(p) = self.points.pop() {
            let (c, r) = self.cell_of(p);
            self.cells[r * self.cols + c].pop();
            self.tags.pop();
        }
    }

    /// Whether `found` holds for a point within `reach` cell rings of `p`, stopping at the
    /// first.
    fn any_near(
        &self,
        p: DVec2,
        reach: usize,
        mut found: impl FnMut(DVec2, (u32, i32)) -> bool,
    ) -> bool {
        let (c, r) = self.cell_of(p);
        for row in r.saturating_sub(reach)..=(r + reach).min(self.rows - 1) {
            for col in c.saturating_sub(reach)..=(c + reach).min(self.cols - 1) {
                for &i in &self.cells[row * self.cols + col] {
                    if found(self.points[i as usize], self.tags[i as usize]) {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// No point within `radius` of `p`, other than points of line `line` at most `skip`
    /// steps from sequence number `seq` (the line's own last steps). Stops at the first such
    /// point: most seeds are refused, by a point of the first cells read.
    fn clear(&self, p: DVec2, radius: f64, line: u32, seq: i32, skip: i32) -> bool {
        let r2 = radius * radius;
        !self.any_near(p, 1, |q, (l, s)| {
            let own_recent = l == line && (s - seq).abs() <= skip;
            !own_recent && q.distance_squared(p) < r2
        })
    }
}

/// Column and row of the cell (side `cell`) holding `p` in a `cols × rows` grid, clamped.
fn cell_of(p: DVec2, cell: f64, cols: usize, rows: usize) -> (usize, usize) {
    (
        ((p.x / cell).max(0.0) as usize).min(cols - 1),
        ((p.y / cell).max(0.0) as usize).min(rows - 1),
    )
}

/// The occupancy grid once the lines are laid: every cell's points (with their line) in one
/// array, cell after cell, row-major, so the five cells of a row that a share reads are one
/// contiguous run instead of five separate vectors (the shares were an eighth of an
/// engraving).
struct PackedGrid {
    /// The picture's domain: beyond its border no line shares the paper.
    domain: DVec2,
    cell: f64,
    cols: usize,
    rows: usize,
    /// Where each cell's points start in `points`, one per cell plus one.
    offsets: Vec<u32>,
    /// Position and line of every point.
    points: Vec<(DVec2, u32)>,
}

impl PackedGrid {
    /// The points within two cell rings of `p` (rows of five cells, each row one run).
    fn near(&self, p: DVec2) -> impl Iterator<Item = (DVec2, u32)> + '_ {
        let (c, r) = cell_of(p, self.cell, self.cols, self.rows);
        let (c0, c1) = (c.saturating_sub(2), (c + 2).min(self.cols - 1));
        (r.saturating_sub(2)..=(r + 2).min(self.rows - 1)).flat_map(move |row| {
            let start = self.offsets[row * self.cols + c0] as usize;
            let end = self.offsets[row * self.cols + c1 + 1] as usize;
            self.points[start..end].iter().copied()
        })
    }

    /// Point `i` of line `line`'s shares across the lines: half the gap to the nearest other
    /// line on its left (along [`normal_at`]) and half that on its right; with no line on a
    /// side but the picture's border within [`GAP_REACH`], the whole strip up to the border.
    /// (As half a spacing, that strip would be paper along a border the lines run beside: a
    /// dotted edge on a dark lake.)
    fn halves(&self, points: &[DVec2], i: usize, line: u32, d_sep: f64) -> [f64; 2] {
        let p = points[i];
        let n = normal_at(points, i);
        let t = -n.perp();
        let reach = GAP_REACH * d_sep;
        let (mut left, mut right) = (d_sep, d_sep);
        let (mut found_left, mut found_right) = (false, false);
        let band = STEP_RATIO * d_sep;
        for (q, l) in self.near(p) {
            let v = q - p;
            if v.dot(t).abs() > band {
                continue;
            }
            let across = v.dot(n);
            // The line's own points count where it comes round again (the inside of a loop is
            // the paper of the loop's two sides), not its own stretch beside `p`: within the
            // band that lies under a tenth of a spacing across (a step turns by at most 40°),
            // and a line never comes back within `d_test` of itself.
            if l == line && across.abs() < OWN_RETURN * d_sep {
                continue;
            }
            if across > 0.0 && across < reach && (!found_left || across < left) {
                left = across;
                found_left = true;
            } else if across <= 0.0 && -across < reach && (!found_right || -across < right) {
                right = -across;
                found_right = true;
            }
        }
        // No line beyond, but the picture's border within reach: the strip up to it can take
        // no line of its own, and is this line's paper.
        let share = |found: bool, gap: f64, dir: DVec2| {
            let border = (!found)
                .then(|| border_along(p, dir, self.domain))
                .flatten();
            border.filter(|&b| b < reach).unwrap_or(0.5 * gap)
        };
        [share(found_left, left, n), share(found_right, right, -n)]
    }
}

/// How far from `p`, inside `domain`, the border lies along the unit direction `dir`; `None`
/// for a point outside (the lines run on past the border) or a direction that meets none.
fn border_along(p: DVec2, dir: DVec2, domain: DVec2) -> Option<f64> {
    if !(p.x >= 0.0 && p.y >= 0.0 && p.x <= domain.x && p.y <= domain.y) {
        return None;
    }
    let along = |at: f64, d: f64, end: f64| {
        if d > 0.0 {
            (end - at) / d
        } else if d < 0.0 {
            -at / d
        } else {
            f64::INFINITY
        }
    };
    let t = along(p.x, dir.x, domain.x).min(along(p.y, dir.y, domain.y));
    t.is_finite().then_some(t)
}

/// The unit normal of a polyline at point `i` (its left, the tangent turned a quarter), from
/// the chord between the points either side.
#[must_use]
pub fn normal_at(points: &[DVec2], i: usize) -> DVec2 {
    (points[(i + 1).min(points.len() - 1)] - points[i.saturating_sub(1)])
        .normalize_or_zero()
        .perp()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn border_along_is_the_distance_to_the_first_border_met() {
        let domain = DVec2::new(100.0, 50.0);
        let p = DVec2::new(10.0, 5.0);
        assert_eq!(border_along(p, DVec2::NEG_Y, domain), Some(5.0));
        assert_eq!(border_along(p, DVec2::X, domain), Some(90.0));
        assert_eq!(border_along(p, DVec2::NEG_X, domain), Some(10.0));
        // Diagonally down and right the bottom (45 below) comes before the right (90 across).
        let t = border_along(p, DVec2::ONE.normalize(), domain).unwrap();
        assert!((t - 45.0 * 2f64.sqrt()).abs() < 1e-9, "{t}");
        assert_eq!(border_along(DVec2::new(-1.0, 5.0), DVec2::X, domain), None);
        assert_eq!(border_along(p, DVec2::ZERO, domain), None);
    }

    /// The grid holding one line, `points` (line 0), packed.
    fn grid_of(points: &[DVec2], d_sep: f64) -> PackedGrid {
        let mut grid = Occupancy::new(DVec2::splat(20.0 * d_sep), d_sep);
        for (seq, &p) in points.iter().enumerate() {
            grid.insert(p, 0, seq as i32);
        }
        grid.packed()
    }

    #[test]
    fn a_loop_is_the_paper_of_its_own_two_sides() {
        // A closed loop of radius r (too small for a seed inside): across its inside the
        // nearest line is the loop itself, 2r away, so each point answers for r of it; outside
        // there is no line (a gap of one spacing). A straight line has no such neighbour on
        // either side. The points of the band nearest across are at most a quarter spacing
        // along, which puts the loop's other side up to `r − √(r² − b²)` nearer.
        let d_sep = 2.0;
        let centre = DVec2::splat(10.0 * d_sep);
        for r in [0.4, 0.7, 0.85].map(|k| k * d_sep) {
            let steps = (std::f64::consts::TAU * r / (STEP_RATIO * d_sep)).ceil() as usize;
            let points: Vec<DVec2> = (0..=steps)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / steps as f64;
                    centre + r * DVec2::new(a.cos(), a.sin())
                })
                .collect();
            let grid = grid_of(&points, d_sep);
            let b = STEP_RATIO * d_sep;
            for i in 1..steps {
                let [left, right] = grid.halves(&points, i, 0, d_sep);
                // The inside is on whichever side the normal points towards the centre.
                let inward = normal_at(&points, i).dot(centre - points[i]) > 0.0;
                let (inner, outer) = if inward { (left, right) } else { (right, left) };
                assert!(
                    inner <= r + 1e-9 && inner >= 0.5 * (r + (r * r - b * b).sqrt()) - 1e-9,
                    "r {r}: inner half {inner} at point {i}"
                );
                assert_eq!(outer, 0.5 * d_sep, "r {r}: outer half at point {i}");
            }
        }
        let line: Vec<DVec2> = (0..40)
            .map(|i| DVec2::new(2.0 + 0.5 * f64::from(i), 7.0 + 0.01 * f64::from(i * i)))
            .collect();
        let grid = grid_of(&line, d_sep);
        for i in 1..39 {
            assert_eq!(
                grid.halves(&line, i, 0, d_sep),
                [0.5 * d_sep; 2],
                "point {i}"
            );
        }
    }
}
