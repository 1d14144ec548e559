//! Cells in one piece. With a colour term in the owner ([`ColourTerm`](super::voronoi)), a
//! pixel of fur or grass whose colour happens to be nearer a neighbour's mean goes to that
//! neighbour, and cells leave specks and spurs inside each other: ragged borders, a ring of
//! leading round every speck. As SLIC does after its iterations (Achanta et al., *SLIC
//! Superpixels*, 2012, section 3.2, "enforce connectivity"), every piece of a cell that is
//! not its largest and holds under [`MAX_SHARE`] of that largest piece's pixels is given to
//! the neighbouring cell nearest it in colour, when that colour is within
//! [`MAX_COLOUR_STEP`] of the piece's. Larger pieces stay (a cell cut in two by a thin line
//! keeps both halves), and so do pieces unlike all their neighbours: a stretch of a thin line
//! or a highlight is never handed to the ground.
//!
//! Pieces are 4-connected, found on runs of equal owner along rows with a union-find; the map
//! is the photo's pixel grid. Everything runs in one thread in a fixed order, so the result
//! does not depend on the thread count.

use super::cellmap::{CellMap, NONE};
use crate::render::support::disjoint::DisjointSets;

/// Largest share of its cell's main piece a detached piece may hold and still be absorbed.
pub const MAX_SHARE: f64 = 0.25;

/// Largest colour difference (sRGB, root mean square over the channels) between a detached
/// piece and the neighbour it goes to: the grain of fur or grass is under it, a highlight or a
/// stretch of a dark line is over it and stays.
pub const MAX_COLOUR_STEP: f32 = 0.1;

/// The owners `owners` (row-major `width × height`, [`NONE`] for none) with every small
/// detached piece absorbed; `means` are the cells' colours and `colour(x, y)` a pixel's, both
/// sRGB in [0, 1].
#[must_use]
pub fn one_piece(
    mut owners: Vec<u32>,
    width: usize,
    height: usize,
    means: &[[f32; 3]],
    colour: impl Fn(usize, usize) -> [f32; 3],
) -> CellMap {
    let runs = Runs::of(&owners, width, height);
    let (piece_of_run, pieces) = runs.pieces();
    // Size of every piece; the main piece of every cell; which pieces are small.
    let mut size = vec![0usize; pieces.len()];
    for (run, &id) in runs.runs.iter().zip(&piece_of_run) {
        size[id as usize] += run.len as usize;
    }
    let mut main = vec![NONE; means.len()];
    for (id, &cell) in pieces.iter().enumerate() {
        let m = &mut main[cell as usize];
        if *m == NONE || size[id] > size[*m as usize] {
            *m = id as u32;
        }
    }
    let small: Vec<bool> = (0..pieces.len())
        .map(|id| {
            let m = main[pieces[id] as usize] as usize;
            m != id && (size[id] as f64) < MAX_SHARE * size[m] as f64
        })
        .collect();
    // Mean colours of the small pieces only.
    let mut mean = vec![[0.0f32; 3]; pieces.len()];
    for (k, y, run) in runs.with_rows() {
        let id = piece_of_run[k] as usize;
        if !small[id] {
            continue;
        }
        for x in run.x as usize..(run.x + run.len) as usize {
            let c = colour(x, y);
            for (m, v) in mean[id].iter_mut().zip(c) {
                *m += v / size[id] as f32;
            }
        }
    }
    let target = targets(&runs, &piece_of_run, &pieces, &small, &mean, means);
    for (k, y, run) in runs.with_rows() {
        let id = piece_of_run[k] as usize;
        if small[id] && target[id] != run.owner {
            let row = y * width;
            let span = row + run.x as usize..row + (run.x + run.len) as usize;
            owners[span].fill(target[id] | CellMap::ABSORBED);
        }
    }
    CellMap::new(width, height, owners)
}

/// Appends the runs of one row of owners to `runs`.
fn row_runs(row: &[u32], runs: &mut Vec<Run>) {
    let mut x = 0;
    while x < row.len() {
        let owner = row[x];
        let end = row[x..]
            .iter()
            .position(|&o| o != owner)
            .map_or(row.len(), |n| x + n);
        if owner != NONE {
            runs.push(Run {
                x: x as u32,
                len: (end - x) as u32,
                owner,
            });
        }
        x = end;
    }
}

/// One row's stretch of pixels of one owner.
#[derive(Clone, Copy, Debug)]
struct Run {
    x: u32,
    len: u32,
    owner: u32,
}

/// The owner map as runs, row by row: far fewer items than pixels, and two runs in
/// neighbouring rows touch (4-connected) when their x ranges overlap.
struct Runs {
    runs: Vec<Run>,
    /// Index of every row's first run; one more at the end.
    row_start: Vec<usize>,
}

impl Runs {
    fn of(owners: &[u32], width: usize, height: usize) -> Runs {
        let mut runs = Vec::new();
        let mut row_start = Vec::with_capacity(height + 1);
        for row in owners.chunks_exact(width.max(1)).take(height) {
            row_start.push(runs.len());
            row_runs(row, &mut runs);
        }
        row_start.push(runs.len());
        Runs { runs, row_start }
    }

    /// Every run with its index and row, in scan order.
    fn with_rows(&self) -> impl Iterator<Item = (usize, usize, Run)> + '_ {
        self.row_start
            .windows(2)
            .enumerate()
            .flat_map(move |(y, w)| (w[0]..w[1]).map(move |k| (k, y, self.runs[k])))
    }

    /// Calls `touch(a, b)` for every pair of runs that share a pixel edge: neighbours in a row
    /// and overlapping runs of neighbouring rows.
    fn each_touching(&self, mut touch: impl FnMut(usize, usize)) {
        for y in 0..self.row_start.len() - 1 {
            let (row, next) = (self.row_start[y], self.row_start[y + 1]);
            for k in row..next.saturating_sub(1) {
                if self.runs[k].x + self.runs[k].len == self.runs[k + 1].x {
                    touch(k, k + 1);
                }
            }
            if y + 2 >= self.row_start.len() {
                continue;
            }
            let (mut a, mut b, below_end) = (row, next, self.row_start[y + 2]);
            while a < next && b < below_end {
                let (ra, rb) = (self.runs[a], self.runs[b]);
                if ra.x < rb.x + rb.len && rb.x < ra.x + ra.len {
                    touch(a, b);
                }
                if ra.x + ra.len <= rb.x + rb.len {
                    a += 1;
                } else {
                    b += 1;
                }
            }
        }
    }

    /// 4-connected pieces of equal owner: the piece of every run and the owner of every
    /// piece, numbered in scan order.
    fn pieces(&self) -> (Vec<u32>, Vec<u32>) {
        // The lower index is the root, so numbering follows scan order.
        let mut sets = DisjointSets::new(self.runs.len());
        self.each_touching(|a, b| {
            if self.runs[a].owner == self.runs[b].owner {
                sets.join(a as u32, b as u32);
            }
        });
        let mut piece_of_run = vec![NONE; self.runs.len()];
        let mut owners = Vec::new();
        for k in 0..self.runs.len() {
            let r = sets.root(k as u32) as usize;
            if piece_of_run[r] == NONE {
                piece_of_run[r] = owners.len() as u32;
                owners.push(self.runs[r].owner);
            }
            piece_of_run[k] = piece_of_run[r];
        }
        (piece_of_run, owners)
    }
}

/// For every piece, the cell it belongs to at the end: a small piece goes to the cell of the
/// piece it touches whose colour is nearest its mean colour (preferring pieces that are not
/// small), if that colour is near enough; a small piece that touches only other small pieces
/// goes where they go.
fn targets(
    runs: &Runs,
    piece_of_run: &[u32],
    pieces: &[u32],
    small: &[bool],
    mean: &[[f32; 3]],
    means: &[[f32; 3]],
) -> Vec<u32> {
    // Every (small piece, piece it touches) pair.
    let mut touching: Vec<(u32, u32)> = Vec::new();
    runs.each_touching(|a, b| {
        let (a, b) = (piece_of_run[a], piece_of_run[b]);
        if a != b {
            if small[a as usize] {
                touching.push((a, b));
            }
            if small[b as usize] {
                touching.push((b, a));
            }
        }
    });
    touching.sort_unstable();
    touching.dedup();
    let mut target: Vec<u32> = pieces.to_vec();
    let mut via: Vec<u32> = vec![NONE; pieces.len()];
    let mut k = 0;
    while k < touching.len() {
        let a = touching[k].0 as usize;
        let distance = |b: u32| {
            let m = means[pieces[b as usize] as usize];
            (0..3).map(|i| (mean[a][i] - m[i]).powi(2)).sum::<f32>()
        };
        let mut best: Option<(bool, f32, u32)> = None;
        while k < touching.len() && touching[k].0 as usize == a {
            let b = touching[k].1;
            // Staying pieces first, then the nearest colour, then the lowest piece number.
            let key = (small[b as usize], distance(b), b);
            if best.is_none_or(|cur| (key.0, key.1) < (cur.0, cur.1)) {
                best = Some(key);
            }
            k += 1;
        }
        // A piece unlike every neighbour is detail (a highlight, a stretch of a thin line):
        // it stays in its cell.
        if let Some((_, d, b)) = best {
            if d <= 3.0 * MAX_COLOUR_STEP * MAX_COLOUR_STEP {
                via[a] = b;
            }
        }
    }
    // Follow chains of absorbed pieces to one that stays (a bounded walk: chains are short,
    // and a ring of small pieces that only touch each other keeps its owners).
    for a in 0..pieces.len() {
        if via[a] == NONE {
            continue;
        }
        let mut b = via[a];
        for _ in 0..16 {
            if via[b as usize] == NONE {
                break;
            }
            b = via[b as usize];
        }
        if via[b as usize] == NONE {
            target[a] = pieces[b as usize];
        }
    }
    target
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map_of(rows: &[&str]) -> (Vec<u32>, usize, usize) {
        let w = rows[0].len();
        let owners = rows
            .iter()
            .flat_map(|r| r.bytes().map(|b| u32::from(b - b'a')))
            .collect();
        (owners, w, rows.len())
    }

    fn owners_after(rows: &[&str], means: &[[f32; 3]]) -> Vec<String> {
        let (owners, w, h) = map_of(rows);
        // Every pixel has its cell's colour, so colour decides nothing but ties.
        let map = one_piece(owners.clone(), w, h, means, |x, y| {
            means[owners[y * w + x] as usize]
        });
        (0..h)
            .map(|y| {
                (0..w)
                    .map(|x| {
                        let p = glam::DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                        let o = map.absorbed_into(p).unwrap_or(owners[y * w + x]);
                        char::from(b'a' + o as u8)
                    })
                    .collect()
            })
            .collect()
    }

    #[test]
    fn a_speck_goes_to_the_cell_round_it_and_large_pieces_stay() {
        let grey = [[0.5; 3], [0.5; 3], [0.5; 3]];
        let out = owners_after(
            &[
                "aaaaaabbbbbb",
                "aabaaabbbbbb",
                "aaaaaabbbbbb",
                "aaaaaabbbbbb",
                "cccccccccccc",
                "cccccccccccc",
                "aaaaaaaaaacc",
                "aaaaaaaaaacc",
            ],
            &grey,
        );
        assert_eq!(out[1], "aaaaaabbbbbb", "the speck of b inside a");
        // The lower piece of a (20 pixels) is 87 % of its main piece (23): both stay.
        assert_eq!(out[6], "aaaaaaaaaacc");
    }

    #[test]
    fn a_piece_unlike_its_neighbours_stays() {
        // A bright stretch of b (a highlight) inside dark a: detail, not grain.
        let means = [[0.1; 3], [0.9; 3]];
        let rows = ["aaaaaabbbbbb", "aabaaabbbbbb", "aaaaaabbbbbb"];
        assert_eq!(owners_after(&rows, &means)[1], "aabaaabbbbbb");
    }

    /// Where the pixel `(x, y)` of `rows` went, if it was absorbed.
    fn absorbed_at(rows: &[&str], means: &[[f32; 3]], x: f64, y: f64) -> Option<u32> {
        let (owners, w, h) = map_of(rows);
        let map = one_piece(owners.clone(), w, h, means, |x, y| {
            means[owners[y * w + x] as usize]
        });
        map.absorbed_into(glam::DVec2::new(x, y))
    }

    #[test]
    fn a_small_piece_goes_to_the_neighbour_nearest_in_colour() {
        // A piece of c between a (dark) and b (light); c's pixels are dark.
        let means = [[0.1; 3], [0.9; 3], [0.15; 3]];
        // Joined to the rest of c: one piece, kept.
        let joined = [
            "ccccccccc",
            "ccccccccc",
            "ccccccccc",
            "aaaacbbbb",
            "aaaacbbbb",
        ];
        assert_eq!(absorbed_at(&joined, &means, 4.5, 3.5), None);
        let detached = [
            "ccccccccc",
            "ccccccccc",
            "aaaaaaaaa",
            "aaaacbbbb",
            "aaaacbbbb",
        ];
        assert_eq!(
            absorbed_at(&detached, &means, 4.5, 4.5),
            Some(0),
            "dark c → dark a"
        );
    }
}
