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
//! Pieces are 4-connected; the map is the photo's pixel grid. Everything runs in one thread
//! in a fixed order, so the result does not depend on the thread count.

use super::voronoi::{CellMap, NONE};

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
    owners: &[u32],
    width: usize,
    height: usize,
    means: &[[f32; 3]],
    colour: impl Fn(usize, usize) -> [f32; 3],
) -> CellMap {
    let (piece, pieces) = label_pieces(owners, width, height);
    // Size, owner and colour sum of every piece; the main piece of every cell.
    let mut size = vec![0usize; pieces.len()];
    let mut sum = vec![[0.0f64; 3]; pieces.len()];
    for (k, &id) in piece.iter().enumerate() {
        if id == NONE {
            continue;
        }
        size[id as usize] += 1;
        let c = colour(k % width, k / width);
        for (s, v) in sum[id as usize].iter_mut().zip(c) {
            *s += f64::from(v);
        }
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
    let target = targets(&piece, width, height, &pieces, &small, &size, &sum, means);
    let mut out = owners.to_vec();
    for (o, &id) in out.iter_mut().zip(&piece) {
        if id != NONE && small[id as usize] {
            let to = target[id as usize];
            if to != *o {
                *o = to | CellMap::ABSORBED;
            }
        }
    }
    CellMap::new(width, height, out)
}

/// 4-connected pieces of equal owner: the piece of every pixel ([`NONE`] where no site owns
/// it) and the owner of every piece, numbered in scan order.
fn label_pieces(owners: &[u32], width: usize, height: usize) -> (Vec<u32>, Vec<u32>) {
    let mut piece = vec![NONE; owners.len()];
    let mut cells = Vec::new();
    let mut stack = Vec::new();
    for start in 0..owners.len() {
        if piece[start] != NONE || owners[start] == NONE {
            continue;
        }
        let id = cells.len() as u32;
        let cell = owners[start];
        cells.push(cell);
        piece[start] = id;
        stack.push(start);
        while let Some(k) = stack.pop() {
            let (x, y) = (k % width, k / width);
            let mut visit = |n: usize| {
                if piece[n] == NONE && owners[n] == cell {
                    piece[n] = id;
                    stack.push(n);
                }
            };
            if x > 0 {
                visit(k - 1);
            }
            if x + 1 < width {
                visit(k + 1);
            }
            if y > 0 {
                visit(k - width);
            }
            if y + 1 < height {
                visit(k + width);
            }
        }
    }
    (piece, cells)
}

/// For every piece, the cell it belongs to at the end: a small piece goes to the cell of the
/// piece it touches whose colour is nearest its mean colour (preferring pieces that are not
/// small), if that colour is near enough; a small piece that touches only other small pieces
/// goes where they go.
#[allow(clippy::too_many_arguments)]
fn targets(
    piece: &[u32],
    width: usize,
    height: usize,
    pieces: &[u32],
    small: &[bool],
    size: &[usize],
    sum: &[[f64; 3]],
    means: &[[f32; 3]],
) -> Vec<u32> {
    // Every (small piece, piece it touches) pair, once per shared pixel edge.
    let mut touching: Vec<(u32, u32)> = Vec::new();
    let mut pair = |a: u32, b: u32| {
        if a != b && a != NONE && b != NONE {
            if small[a as usize] {
                touching.push((a, b));
            }
            if small[b as usize] {
                touching.push((b, a));
            }
        }
    };
    for y in 0..height {
        for x in 0..width {
            let k = y * width + x;
            if x + 1 < width {
                pair(piece[k], piece[k + 1]);
            }
            if y + 1 < height {
                pair(piece[k], piece[k + width]);
            }
        }
    }
    touching.sort_unstable();
    touching.dedup();
    let mut target: Vec<u32> = pieces.to_vec();
    let mut via: Vec<u32> = vec![NONE; pieces.len()];
    let mut k = 0;
    while k < touching.len() {
        let a = touching[k].0 as usize;
        let mean = sum[a].map(|v| (v / size[a].max(1) as f64) as f32);
        let distance = |b: u32| {
            let m = means[pieces[b as usize] as usize];
            (0..3).map(|i| (mean[i] - m[i]).powi(2)).sum::<f32>()
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
        let map = one_piece(&owners, w, h, means, |x, y| {
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

    #[test]
    fn a_small_piece_goes_to_the_neighbour_nearest_in_colour() {
        // A piece of c between a (dark) and b (light); c's pixels are dark.
        let means = [[0.1; 3], [0.9; 3], [0.15; 3]];
        let (owners, w, h) = map_of(&[
            "ccccccccc",
            "ccccccccc",
            "ccccccccc",
            "aaaacbbbb",
            "aaaacbbbb",
        ]);
        let map = one_piece(&owners, w, h, &means, |x, y| {
            means[owners[y * w + x] as usize]
        });
        // Joined to the rest of c: one piece, kept.
        assert_eq!(map.absorbed_into(glam::DVec2::new(4.5, 3.5)), None);
        let (owners, w, h) = map_of(&[
            "ccccccccc",
            "ccccccccc",
            "aaaaaaaaa",
            "aaaacbbbb",
            "aaaacbbbb",
        ]);
        let map = one_piece(&owners, w, h, &means, |x, y| {
            means[owners[y * w + x] as usize]
        });
        assert_eq!(
            map.absorbed_into(glam::DVec2::new(4.5, 4.5)),
            Some(0),
            "dark c → dark a"
        );
    }
}
