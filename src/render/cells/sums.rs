//! Per-cell sums of a photo's pixels over the generalized Voronoi cells (paper section 6):
//! the cells' mean colours, centroids and shapes. Pixels are summed block by block, each block
//! to the owner of its centre ([`VoronoiCells::site_rows`] through
//! [`owner_map`]), or pixel by pixel from the cell map when the
//! cells have one. Sums run in fixed row blocks added in order, so they do not depend on the
//! thread count. Sums are `f64`.

use super::cellmap::CellMap;
use super::raster::{owner_map, Raster};
use super::voronoi::{VoronoiCells, NONE};
use glam::DVec2;
use rayon::prelude::*;

/// Per-cell sums of `value(x, y)` over the pixels of a `width × height` image whose pixels
/// are domain units (a photo under its own field). When cells average 64 pixels or more,
/// owners are searched at the centres of `s × s` pixel blocks and the block's pixels go to
/// that owner, `s` the largest of 2 to `max_stride` that still leaves 64 blocks per cell on
/// average ([`block_stride`]): every pixel counts, far fewer owner searches, and only pixels
/// next to a border can land in the neighbouring cell. Cells whose colour term holds a
/// [`CellMap`] of these pixels are summed from it, exactly and without a search. Sums run in
/// fixed row blocks added in order, so the result does not depend on the thread count.
pub fn pixel_sums<const N: usize, F>(
    cells: &VoronoiCells,
    width: usize,
    height: usize,
    max_stride: usize,
    value: F,
) -> Vec<[f64; N]>
where
    F: Fn(usize, usize) -> [f64; N] + Sync,
{
    let n = cells.positions().len();
    if let Some(map) = cells.colour().and_then(|term| term.map.as_ref()) {
        if map.size() == (width, height) {
            return mapped_sums(map, n, value);
        }
    }
    let stride = block_stride(width, height, n, BLOCKS_PER_CELL, max_stride);
    let blocks = BlockGrid::new(width, height, stride);
    // Each block's pixels straight into its owner's sums: no buffer of block sums, which at
    // stride 1 (small cells) would hold N values per pixel.
    per_block_owner(cells, &blocks, n, |gx, gy, s: &mut [f64; N]| {
        blocks.add_block(gx, gy, &value, s);
    })
}

/// The block side for `n` cells on a `width × height` image: 1 when cells average under 64
/// pixels, else the largest of 2 to `max_stride` that leaves at least `blocks_per_cell` blocks
/// per cell on average ([`pixel_sums`] leaves [`BLOCKS_PER_CELL`]).
#[must_use]
pub fn block_stride(
    width: usize,
    height: usize,
    n: usize,
    blocks_per_cell: f64,
    max_stride: usize,
) -> usize {
    let per_cell = (width * height) as f64 / n.max(1) as f64;
    if per_cell >= 64.0 {
        ((per_cell / blocks_per_cell.max(1.0)).sqrt() as usize).clamp(2, max_stride.max(2))
    } else {
        1
    }
}

/// Blocks per cell of [`pixel_sums`]: enough that centroids and mean colours are those of the
/// pixels (the assign-and-move rounds' last sums use as many).
pub const BLOCKS_PER_CELL: f64 = 64.0;

/// Blocks of `stride × stride` pixels over a `width × height` image (a last partial block
/// included).
#[derive(Clone, Copy, Debug)]
struct BlockGrid {
    width: usize,
    height: usize,
    stride: usize,
}

impl BlockGrid {
    fn new(width: usize, height: usize, stride: usize) -> Self {
        BlockGrid {
            width,
            height,
            stride: stride.max(1),
        }
    }

    /// Blocks across and down.
    fn size(&self) -> (usize, usize) {
        (
            self.width.div_ceil(self.stride),
            self.height.div_ceil(self.stride),
        )
    }

    /// Adds `value` over the pixels of block (gx, gy) into `acc`, row by row.
    #[inline]
    fn add_block<const N: usize>(
        &self,
        gx: usize,
        gy: usize,
        value: &impl Fn(usize, usize) -> [f64; N],
        acc: &mut [f64; N],
    ) {
        let s = self.stride;
        for y in gy * s..((gy + 1) * s).min(self.height) {
            for x in gx * s..((gx + 1) * s).min(self.width) {
                for (a, v) in acc.iter_mut().zip(value(x, y)) {
                    *a += v;
                }
            }
        }
    }

    /// Raster point (gx, gy) at the centre of the block of pixels from (stride·gx, stride·gy).
    fn raster(&self) -> Raster {
        let (w, h) = self.size();
        Raster {
            width: w,
            height: h,
            supersample: 1,
            domain: DVec2::new((w * self.stride) as f64, (h * self.stride) as f64),
        }
    }
}

/// Per-cell sums over the blocks of `blocks`, each block going whole to the owner of its
/// centre: `add(gx, gy, sums)` adds block (gx, gy) into its owner's sums. Fixed row blocks,
/// added in order.
fn per_block_owner<const N: usize>(
    cells: &VoronoiCells,
    blocks: &BlockGrid,
    n: usize,
    add: impl Fn(usize, usize, &mut [f64; N]) + Sync,
) -> Vec<[f64; N]> {
    let raster = blocks.raster();
    let w = raster.width;
    let owners = owner_map(cells, &raster);
    let block_rows = raster.height.div_ceil(SUM_BLOCKS).max(1);
    let partial: Vec<Vec<[f64; N]>> = owners
        .par_chunks(w * block_rows)
        .enumerate()
        .map(|(block, owners)| {
            let mut sums = vec![[0.0f64; N]; n];
            for (k, &o) in owners.iter().enumerate() {
                if o != NONE {
                    add(k % w, block * block_rows + k / w, &mut sums[o as usize]);
                }
            }
            sums
        })
        .collect();
    add_in_order(partial, n)
}

/// Sums of `value(x, y)` over every `stride × stride` block of a `width × height` image,
/// computed once for cells that are summed again and again over the same pixels (the
/// assign-and-move rounds of edge-following cells): each round then costs its owner search
/// at the blocks' centres and one addition per block, not a `value` per pixel.
pub struct BlockSums<const N: usize> {
    blocks: BlockGrid,
    sums: Vec<[f64; N]>,
}

impl<const N: usize> BlockSums<N> {
    /// The block sums of `value` (blocks of side `stride`, see [`block_stride`]).
    #[must_use]
    pub fn new<F>(width: usize, height: usize, stride: usize, value: F) -> Self
    where
        F: Fn(usize, usize) -> [f64; N] + Sync,
    {
        let blocks = BlockGrid::new(width, height, stride);
        Self::from_blocks(width, height, stride, |gx, gy| {
            let mut s = [0.0; N];
            blocks.add_block(gx, gy, &value, &mut s);
            s
        })
    }

    /// Block sums given block by block: `block(gx, gy)` is the sum over the pixels of block
    /// (gx, gy), those from (`stride`·gx, `stride`·gy) up to `stride` further in each direction
    /// (fewer at the image's right and bottom edges), for callers that sum a block faster than
    /// pixel by pixel.
    #[must_use]
    pub fn from_blocks<F>(width: usize, height: usize, stride: usize, block: F) -> Self
    where
        F: Fn(usize, usize) -> [f64; N] + Sync,
    {
        let blocks = BlockGrid::new(width, height, stride);
        let (w, h) = blocks.size();
        let mut sums = vec![[0.0f64; N]; w * h];
        sums.par_chunks_mut(w.max(1))
            .enumerate()
            .for_each(|(gy, row)| {
                for (gx, s) in row.iter_mut().enumerate() {
                    *s = block(gx, gy);
                }
            });
        BlockSums { blocks, sums }
    }

    /// Per-cell sums: every block to the owner of its centre, as [`pixel_sums`] gives them.
    #[must_use]
    pub fn per_cell(&self, cells: &VoronoiCells) -> Vec<[f64; N]> {
        let (w, _) = self.blocks.size();
        per_block_owner(cells, &self.blocks, cells.positions().len(), |gx, gy, s| {
            for (acc, v) in s.iter_mut().zip(self.sums[gy * w + gx]) {
                *acc += v;
            }
        })
    }
}

/// [`pixel_sums`] over cells whose owners `map` already holds pixel by pixel (edge-following
/// cells once their pieces are joined): every pixel to its exact cell, no owner search.
fn mapped_sums<const N: usize, F>(map: &CellMap, n: usize, value: F) -> Vec<[f64; N]>
where
    F: Fn(usize, usize) -> [f64; N] + Sync,
{
    let (width, height) = map.size();
    let block_rows = height.div_ceil(SUM_BLOCKS).max(1);
    let partial: Vec<Vec<[f64; N]>> = (0..height.div_ceil(block_rows))
        .into_par_iter()
        .map(|block| {
            let mut sums = vec![[0.0f64; N]; n];
            for y in block * block_rows..((block + 1) * block_rows).min(height) {
                for x in 0..width {
                    let o = map.cell(y * width + x);
                    if o == NONE {
                        continue;
                    }
                    for (acc, v) in sums[o as usize].iter_mut().zip(value(x, y)) {
                        *acc += v;
                    }
                }
            }
            sums
        })
        .collect();
    add_in_order(partial, n)
}

/// The sum of per-block sums, added block by block in order (the same at any thread count).
fn add_in_order<const N: usize>(partial: Vec<Vec<[f64; N]>>, n: usize) -> Vec<[f64; N]> {
    let mut total = vec![[0.0f64; N]; n];
    for block in partial {
        for (t, s) in total.iter_mut().zip(block) {
            for (acc, v) in t.iter_mut().zip(s) {
                *acc += v;
            }
        }
    }
    total
}

/// Fixed number of row blocks for [`pixel_sums`] (not the thread count: determinism).
const SUM_BLOCKS: usize = 16;

#[cfg(test)]
mod tests {
    use super::super::raster::tests::constant_samples;
    use super::*;
    use crate::render::VoronoiCells;

    #[test]
    fn sums_over_a_cell_map_count_every_pixel_for_its_cell() {
        let (field, s) = constant_samples(60, 40, 0.05);
        let raster = Raster {
            width: 60,
            height: 40,
            supersample: 1,
            domain: field.domain(),
        };
        let mut owners = owner_map(
            &VoronoiCells::new(&s.positions, &s.metrics, &s.mesh),
            &raster,
        );
        // Pixel 0 changes cell, as an absorbed piece does.
        let new_owner = owners[59];
        owners[0] = new_owner | CellMap::ABSORBED;
        let mut expected = vec![0.0; s.positions.len()];
        for &o in &owners {
            expected[(o & !CellMap::ABSORBED) as usize] += 1.0;
        }
        let mut term =
            super::super::colour_term::ColourTerm::new(image::RgbImage::new(60, 40), 1.0);
        term.means = vec![[0.0; 3]; s.positions.len()];
        term.map = Some(CellMap::new(60, 40, owners));
        let cells = VoronoiCells::new(&s.positions, &s.metrics, &s.mesh).with_colour(&term);
        let sums = pixel_sums(&cells, 60, 40, 8, |_, _| [1.0]);
        let counts: Vec<f64> = sums.iter().map(|s| s[0]).collect();
        assert_eq!(counts, expected);
    }

    #[test]
    fn block_sums_per_cell_are_the_pixel_sums() {
        let (_, s) = constant_samples(90, 70, 0.05);
        let cells = VoronoiCells::new(&s.positions, &s.metrics, &s.mesh);
        let value = |x: usize, y: usize| [1.0, x as f64, ((x * 31 + y * 17) % 13) as f64];
        let stride = block_stride(90, 70, s.positions.len(), BLOCKS_PER_CELL, 8);
        assert!(
            stride >= 2,
            "cells of {} pixels",
            90 * 70 / s.positions.len()
        );
        let want = pixel_sums(&cells, 90, 70, 8, value);
        let got = BlockSums::new(90, 70, stride, value).per_cell(&cells);
        for (g, w) in got.iter().zip(&want) {
            for (a, b) in g.iter().zip(w) {
                assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "{g:?} vs {w:?}");
            }
        }
        // Every pixel counted once.
        assert_eq!(got.iter().map(|s| s[0]).sum::<f64>(), 90.0 * 70.0);
    }
}
