//! Distances from the cell map's pixel centres to the borders between its cells, for borders
//! drawn wider than the pixels next to a border: the mosaic's leading and a texture's cell
//! borders in pictures larger than a one-megapixel photo. The border is taken through the
//! midpoints of the pixel edges where the cell changes (generalized Voronoi cells of paper
//! section 6, as the cell map holds them), so the distance is exact to that point set and
//! smooth: a band of ink within half a width of it has clean edges, where the first-order
//! distance the owner search measures (`f / |∇f|`, with the photo's colour in `f`) is accurate
//! only within a pixel or so of the border. Distances are `f32` pixels.

use super::cellmap::CellMap;
use rayon::prelude::*;

/// Per pixel of a cell map, how far its centre lies from the nearest pixel edge where the cell
/// changes, found from two tables of one byte per pixel.
pub struct BorderDistances {
    width: usize,
    height: usize,
    /// Per pixel: `n` where the nearest change inside its row (between columns `k` and
    /// `k + 1`, at `x = k + 1`) lies `n + 0.5` from its centre; [`FAR`] when none is nearer.
    along_row: Vec<u8>,
    /// Per pixel (`x`, `y`), `y` under the last row: `|k − x|` for the nearest column `k`
    /// where rows `y` and `y + 1` hold different cells; [`FAR`] when none is nearer.
    to_next_row: Vec<u8>,
    /// Per pixel: the least horizontal offset of any change in the rows [`Self::within`]
    /// reads for distances under `limit`, a lower bound of the distance that settles most
    /// pixels, far from any border, with one read.
    lower: Vec<u8>,
    /// The `limit` the tables were made for.
    limit: f32,
}

/// No change within this many pixels.
const FAR: u8 = u8::MAX;

impl BorderDistances {
    /// The tables of `map` (rows in parallel), for distances under `limit` pixels (at most
    /// 250).
    #[must_use]
    pub fn new(map: &CellMap, limit: f32) -> Self {
        let (width, height) = map.size();
        let mut along_row = vec![FAR; width * height];
        let mut to_next_row = vec![FAR; width * height];
        along_row
            .par_chunks_mut(width.max(1))
            .zip(to_next_row.par_chunks_mut(width.max(1)))
            .enumerate()
            .for_each(|(y, (along, next))| {
                let row = |r: usize, x: usize| map.cell(r * width + x);
                // A change between columns k and k + 1 is nearest `x` at `k − x` (k ≥ x) or
                // `x − k − 1` (k < x) in the table's units.
                nearest_marks(along, |x| x + 1 < width && row(y, x) != row(y, x + 1), 1);
                if y + 1 < height {
                    nearest_marks(next, |x| row(y, x) != row(y + 1, x), 0);
                }
            });
        let reach = reach_of(limit);
        let mut lower = vec![FAR; width * height];
        lower
            .par_chunks_mut(width.max(1))
            .enumerate()
            .for_each(|(y, low)| {
                for ny in y.saturating_sub(reach)..(y + reach + 1).min(height) {
                    let rows = [&along_row, &to_next_row].map(|t| &t[ny * width..][..width]);
                    for ((l, &a), &n) in low.iter_mut().zip(rows[0]).zip(rows[1]) {
                        *l = (*l).min(a).min(n);
                    }
                }
            });
        BorderDistances {
            width,
            height,
            along_row,
            to_next_row,
            lower,
            limit,
        }
    }

    /// The distance from the centre of pixel (`x`, `y`) to the nearest border, if it is under
    /// the `limit` the tables were made for.
    #[must_use]
    pub fn within(&self, x: usize, y: usize) -> Option<f32> {
        let limit = self.limit;
        if f32::from(self.lower[y * self.width + x]) >= limit {
            return None;
        }
        let reach = reach_of(limit);
        let mut best = limit * limit;
        let w = self.width;
        // Changes inside rows: `dy` whole rows away.
        for ny in y.saturating_sub(reach)..(y + reach + 1).min(self.height) {
            let n = self.along_row[ny * w + x];
            if n != FAR {
                let (dx, dy) = (f32::from(n) + 0.5, ny.abs_diff(y) as f32);
                best = best.min(dx * dx + dy * dy);
            }
        }
        // Changes between row `ny` and the next: half a row past `ny`.
        for ny in y.saturating_sub(reach)..(y + reach).min(self.height) {
            let n = self.to_next_row[ny * w + x];
            if n != FAR {
                let (dx, dy) = (f32::from(n), ny as f32 + 0.5 - y as f32);
                best = best.min(dx * dx + dy * dy);
            }
        }
        (best < limit * limit).then(|| best.sqrt())
    }
}

/// How many rows either side hold every change nearer than `limit`.
fn reach_of(limit: f32) -> usize {
    limit.clamp(0.0, 250.0).ceil() as usize
}

/// Fills `table[x]` with the distance, in the table's units, from `x` to the nearest `k` where
/// `marked(k)`: `k − x` for `k ≥ x`, `x − k − behind` for `k < x` (`behind` 0 or 1), capped at
/// [`FAR`].
fn nearest_marks(table: &mut [u8], marked: impl Fn(usize) -> bool, behind: usize) {
    let cap = usize::from(FAR);
    let mut last: Option<usize> = None;
    for (x, t) in table.iter_mut().enumerate() {
        if marked(x) {
            last = Some(x);
        }
        // A mark at x itself counts as ahead (distance 0).
        *t = match last {
            Some(k) if k == x => 0,
            Some(k) => (x - k - behind).min(cap) as u8,
            None => FAR,
        };
    }
    let mut next: Option<usize> = None;
    for x in (0..table.len()).rev() {
        if marked(x) {
            next = Some(x);
        }
        if let Some(k) = next {
            table[x] = table[x].min((k - x).min(cap) as u8);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The distance from pixel (x, y)'s centre to the nearest midpoint of a pixel edge between
    /// two cells, by brute force over the whole map.
    fn brute(cells: &[u32], w: usize, h: usize, x: usize, y: usize) -> f32 {
        let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
        let mut best = f32::INFINITY;
        for j in 0..h {
            for i in 0..w {
                let c = cells[j * w + i];
                let mut consider = |mx: f32, my: f32| {
                    best = best.min(((mx - px).powi(2) + (my - py).powi(2)).sqrt());
                };
                if i + 1 < w && cells[j * w + i + 1] != c {
                    consider(i as f32 + 1.0, j as f32 + 0.5);
                }
                if j + 1 < h && cells[(j + 1) * w + i] != c {
                    consider(i as f32 + 0.5, j as f32 + 1.0);
                }
            }
        }
        best
    }

    #[test]
    fn distances_match_brute_force() {
        for (w, h, seed) in [(23, 17, 1u32), (1, 9, 2), (9, 1, 3), (31, 29, 4)] {
            // Blobby cells, some pixels absorbed (flagged): the flag is not a cell of its own.
            let cells: Vec<u32> = (0..w * h)
                .map(|k| {
                    let (x, y) = ((k % w) as u32, (k / w) as u32);
                    (x / 5 + (y / 4) * 3 + (x * y * seed) % 3) % 5
                })
                .collect();
            let flagged = cells
                .iter()
                .enumerate()
                .map(|(k, &c)| {
                    if k % 11 == 0 {
                        c | CellMap::ABSORBED
                    } else {
                        c
                    }
                })
                .collect();
            let map = CellMap::new(w, h, flagged);
            for limit in [1.25f32, 2.05, 3.3] {
                let d = BorderDistances::new(&map, limit);
                for y in 0..h {
                    for x in 0..w {
                        let want = brute(&cells, w, h, x, y);
                        let got = d.within(x, y);
                        if want < limit - 1e-4 {
                            let got = got.unwrap_or(f32::NAN);
                            assert!(
                                (got - want).abs() < 1e-5,
                                "{w}x{h} ({x}, {y}): {got} vs {want}"
                            );
                        } else if want > limit + 1e-4 {
                            assert!(got.is_none(), "{w}x{h} ({x}, {y}): {got:?} past {limit}");
                        }
                    }
                }
            }
        }
    }
}
