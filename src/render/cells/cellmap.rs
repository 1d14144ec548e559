//! The cell map: the owner of every photo pixel once edge-following cells are in one piece
//! ([`pieces`](super::pieces)), with the pixels that changed cell flagged. The owner search
//! of the generalized Voronoi cells ([`voronoi`](super::voronoi), paper section 6) reads it:
//! an absorbed pixel keeps its new cell, a border is drawn only where a neighbouring pixel
//! really belongs to the other cell, and inside a cell the owner needs no search. Positions
//! are `f64` domain units, one per photo pixel.

use glam::DVec2;

/// No site / no triangle.
pub const NONE: u32 = u32::MAX;

/// The owner of every photo pixel after small detached pieces of cells were absorbed by their
/// neighbours: an absorbed pixel belongs to its new cell whatever `D` says, and a border is
/// drawn only where a neighbouring pixel really belongs to the other cell.
#[derive(Clone, Debug)]
pub struct CellMap {
    width: usize,
    height: usize,
    /// Owner per pixel, row-major; [`CellMap::ABSORBED`] marks a pixel that changed cell.
    owners: Vec<u32>,
}

impl CellMap {
    /// The flag of an absorbed pixel, above every site index.
    pub const ABSORBED: u32 = 1 << 31;

    /// A map of `width × height` owners (row-major, flagged with [`CellMap::ABSORBED`]).
    #[must_use]
    pub fn new(width: usize, height: usize, owners: Vec<u32>) -> Self {
        debug_assert_eq!(owners.len(), width * height);
        CellMap {
            width,
            height,
            owners,
        }
    }

    /// Width and height in pixels.
    #[must_use]
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The cell of pixel `k` (row-major), absorbed or not; [`NONE`] where no site owns it.
    #[inline]
    #[must_use]
    pub fn cell(&self, k: usize) -> u32 {
        match self.owners[k] {
            NONE => NONE,
            o => o & !Self::ABSORBED,
        }
    }

    /// The cell of the pixel whose centre is `p` when a pixel beside it (left, right, above or
    /// below) belongs to another cell: where the shading takes its border from the map's
    /// crossings ([`VoronoiCells::map_crossings`](super::voronoi::VoronoiCells::map_crossings)).
    #[must_use]
    pub fn beside_another(&self, p: DVec2) -> Option<u32> {
        let (x, y) = self.pixel_xy(p)?;
        let (w, k) = (self.width, y * self.width + x);
        let own = self.cell(k);
        if own == NONE {
            return None;
        }
        let neighbours = [
            (x > 0).then(|| k - 1),
            (x + 1 < w).then(|| k + 1),
            (y > 0).then(|| k - w),
            (y + 1 < self.height).then(|| k + w),
        ];
        neighbours
            .into_iter()
            .flatten()
            .any(|n| {
                let c = self.cell(n);
                c != own && c != NONE
            })
            .then_some(own)
    }

    /// The pixel holding `p`, if inside.
    #[inline]
    fn pixel(&self, p: DVec2) -> Option<usize> {
        self.pixel_xy(p).map(|(x, y)| y * self.width + x)
    }

    /// Column and row of the pixel holding `p`, if inside.
    #[inline]
    fn pixel_xy(&self, p: DVec2) -> Option<(usize, usize)> {
        if !(p.x >= 0.0 && p.y >= 0.0) {
            return None;
        }
        // Truncation is the floor of a non-negative coordinate.
        let (x, y) = (p.x as usize, p.y as usize);
        (x < self.width && y < self.height).then_some((x, y))
    }

    /// The cell an absorbed pixel went to (`None` for a pixel that kept its owner).
    #[inline]
    #[must_use]
    pub fn absorbed_into(&self, p: DVec2) -> Option<u32> {
        let o = self.owners[self.pixel(p)?];
        (o != NONE && o & Self::ABSORBED != 0).then_some(o & !Self::ABSORBED)
    }

    /// The owner the map settles at `p` without a search, when `p` is a pixel's centre whose
    /// eight neighbours (those inside the map) all belong to its own cell: there the owner
    /// search's runner-up owns no pixel around it and is dropped (as the owner search reads the
    /// map), so the owner is the map's and there is no border. An absorbed pixel next to
    /// another cell is not settled: a border passes by it, which the search's shading
    /// measures ([`Self::border_distance_at`]).
    #[inline]
    #[must_use]
    pub fn settled_owner(&self, p: DVec2) -> Option<u32> {
        let (x, y) = self.pixel_xy(p)?;
        if p.x != x as f64 + 0.5 || p.y != y as f64 + 0.5 {
            return None;
        }
        self.settled_at(x, y)
    }

    /// [`Self::settled_owner`] at the centre of pixel (`x`, `y`), which must be inside the map.
    #[inline]
    #[must_use]
    pub fn settled_at(&self, x: usize, y: usize) -> Option<u32> {
        let own = self.owners[y * self.width + x];
        if own == NONE {
            return None;
        }
        let own = own & !Self::ABSORBED;
        self.around(x, y)
            .iter()
            .all(|row| row.iter().all(|&o| o & !Self::ABSORBED == own))
            .then_some(own)
    }

    /// [`Self::settled_at`] for every pixel of row `y`, into `out` (one per column; [`NONE`]
    /// where a pixel is not settled): the same answers from one pass over the three rows,
    /// each column's sameness found once for the three pixels that read it.
    pub fn settled_row(&self, y: usize, out: &mut [u32]) {
        let w = self.width;
        let row = |r: usize| &self.owners[r * w..(r + 1) * w];
        let (above, here, below) = (
            row(y.saturating_sub(1)),
            row(y),
            row((y + 1).min(self.height - 1)),
        );
        let cell = |o: u32| o & !Self::ABSORBED;
        // Whether column x of the three rows is one cell.
        let column = |x: usize| {
            let c = cell(here[x]);
            cell(above[x]) == c && cell(below[x]) == c
        };
        let mut left = column(0);
        let mut centre = left;
        for x in 0..w {
            let right = if x + 1 < w { column(x + 1) } else { centre };
            let own = here[x];
            let c = cell(own);
            let beside = |nx: usize| cell(here[nx]) == c;
            let settled = own != NONE
                && left
                && centre
                && right
                && beside(x.saturating_sub(1))
                && beside((x + 1).min(w - 1));
            out[x] = if settled { c } else { NONE };
            (left, centre) = (centre, right);
        }
    }

    /// How far the centre of pixel (`x`, `y`) lies from the map's nearest border, as far as
    /// its eight neighbours tell: 0.5 when a pixel beside it (left, right, above, below)
    /// belongs to another cell (the midpoint of the edge between them), `√1.25` when only a
    /// diagonal one does (the midpoints of the edges beside that pixel), infinite when none
    /// does. Within 1.5 pixels this is the distance to the nearest midpoint of an edge where
    /// the cell changes ([`BorderDistances`](super::border_distance::BorderDistances)).
    #[must_use]
    pub fn border_distance_at(&self, x: usize, y: usize) -> f32 {
        let w = self.width;
        let cell = |nx: usize, ny: usize| self.owners[ny * w + nx] & !Self::ABSORBED;
        let own = cell(x, y);
        let (left, right) = (x.saturating_sub(1), (x + 1).min(w - 1));
        let (up, down) = (y.saturating_sub(1), (y + 1).min(self.height - 1));
        if [(left, y), (right, y), (x, up), (x, down)]
            .iter()
            .any(|&(nx, ny)| cell(nx, ny) != own)
        {
            return 0.5;
        }
        if [(left, up), (right, up), (left, down), (right, down)]
            .iter()
            .any(|&(nx, ny)| cell(nx, ny) != own)
        {
            return 1.25f32.sqrt();
        }
        f32::INFINITY
    }

    /// Whether `site` owns the pixel of `p` or one of its eight neighbours.
    #[must_use]
    pub fn near(&self, p: DVec2, site: u32) -> bool {
        let Some((x, y)) = self.pixel_xy(p) else {
            return true;
        };
        self.around(x, y)
            .iter()
            .any(|row| row.iter().any(|&o| o & !Self::ABSORBED == site))
    }

    /// The flagged owners of pixel (`x`, `y`) and of its neighbours inside the map: a run of up
    /// to three in each of the rows above, at and below (at the map's top or bottom edge its
    /// own row stands in for the missing one, which changes no "all" or "any" over them).
    /// Three slices, not a flattened iterator: the owner search reads them at most pixels of
    /// a picture.
    #[inline]
    fn around(&self, x: usize, y: usize) -> [&[u32]; 3] {
        let w = self.width;
        if x > 0 && y > 0 && x + 1 < w && y + 1 < self.height {
            // Away from the map's edges, without the clamps.
            let k = y * w + x;
            return [k - w - 1, k - 1, k + w - 1].map(|r| &self.owners[r..r + 3]);
        }
        let columns = x.saturating_sub(1)..=(x + 1).min(self.width - 1);
        let row = |ny: usize| &self.owners[ny * self.width..(ny + 1) * self.width][columns.clone()];
        [
            row(y.saturating_sub(1)),
            row(y),
            row((y + 1).min(self.height - 1)),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small map of a few cells in irregular patches, some pixels absorbed, some owned by
    /// nobody.
    fn patchy_map(width: usize, height: usize) -> CellMap {
        let owners = (0..width * height)
            .map(|k| {
                let (x, y) = (k % width, k / width);
                let hash = (x * 7 + y * 13 + (x * y) % 5) % 23;
                match hash {
                    0 => NONE,
                    1 | 2 => ((x / 3 + y / 4) % 4) as u32 | CellMap::ABSORBED,
                    _ => ((x / 3 + y / 4) % 4) as u32,
                }
            })
            .collect();
        CellMap::new(width, height, owners)
    }

    /// The cells of pixel (x, y) and of its neighbours inside the map, by definition.
    fn neighbourhood(map: &CellMap, x: usize, y: usize) -> Vec<u32> {
        let (w, h) = map.size();
        let mut cells = Vec::new();
        for ny in y.saturating_sub(1)..=(y + 1).min(h - 1) {
            for nx in x.saturating_sub(1)..=(x + 1).min(w - 1) {
                cells.push(map.owners[ny * w + nx] & !CellMap::ABSORBED);
            }
        }
        cells
    }

    #[test]
    fn settled_owners_and_neighbours_match_their_definition() {
        for (w, h) in [(17, 11), (1, 6), (5, 1), (2, 2)] {
            let map = patchy_map(w, h);
            for y in 0..h {
                for x in 0..w {
                    let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                    let own = map.owners[y * w + x];
                    let around = neighbourhood(&map, x, y);
                    let cell = own & !CellMap::ABSORBED;
                    let want = if own == NONE {
                        None
                    } else {
                        around.iter().all(|&c| c == cell).then_some(cell)
                    };
                    assert_eq!(map.settled_owner(p), want, "{w}x{h} at ({x}, {y})");
                    let mut row = vec![0; w];
                    map.settled_row(y, &mut row);
                    assert_eq!(Some(row[x]).filter(|&s| s != NONE), want, "row {y}, {x}");
                    // Off the pixel's centre nothing is settled.
                    assert_eq!(map.settled_owner(p + DVec2::new(0.25, 0.0)), None);
                    for site in 0..5 {
                        assert_eq!(map.near(p, site), around.contains(&site), "({x}, {y})");
                    }
                }
            }
        }
    }

    #[test]
    fn border_distances_near_a_pixel_match_brute_force() {
        // Against the nearest midpoint of every pixel edge where the cell changes: exact
        // below 1.5 px, infinite beyond.
        for (w, h) in [(17, 11), (1, 6), (5, 1), (2, 2)] {
            let map = patchy_map(w, h);
            let cell = |x: usize, y: usize| map.owners[y * w + x] & !CellMap::ABSORBED;
            let mut midpoints = Vec::new();
            for y in 0..h {
                for x in 0..w {
                    if x + 1 < w && cell(x, y) != cell(x + 1, y) {
                        midpoints.push(DVec2::new(x as f64 + 1.0, y as f64 + 0.5));
                    }
                    if y + 1 < h && cell(x, y) != cell(x, y + 1) {
                        midpoints.push(DVec2::new(x as f64 + 0.5, y as f64 + 1.0));
                    }
                }
            }
            for y in 0..h {
                for x in 0..w {
                    let centre = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                    let nearest = midpoints
                        .iter()
                        .map(|m| m.distance(centre))
                        .fold(f64::INFINITY, f64::min);
                    let got = f64::from(map.border_distance_at(x, y));
                    if nearest < 1.5 {
                        assert!(
                            (got - nearest).abs() < 1e-6,
                            "({x}, {y}): {got} against {nearest}"
                        );
                    } else {
                        assert_eq!(got, f64::INFINITY, "({x}, {y}): nearest {nearest}");
                    }
                }
            }
        }
    }
}
