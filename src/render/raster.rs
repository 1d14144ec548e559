//! Rasterising the generalized Voronoi cells (paper section 6) onto an output image: a
//! [`Raster`] says where pixels lie in the field's domain; the anisotropic Delaunay triangles
//! are scan-converted in parallel bands of rows, so every pixel centre gets its containing
//! triangle without a search, and [`VoronoiCells::shade_rows`] hands each output row its
//! pixels' [`Owner`]s, band by band, so memory stays a few rows deep whatever the image size.
//! [`owner_map`] and [`label_map`] keep the owners themselves; [`pixel_sums`] and
//! [`BlockSums`] sum a photo's pixels per cell (from the cell map when there is one).
//! Positions are `f64`.

use super::cellmap::CellMap;
use super::rounding::{ceil, floor};
use super::voronoi::{Owner, VoronoiCells, NONE};
use glam::DVec2;
use rayon::prelude::*;

/// Where the raster points of an output image lie in the field's domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Raster {
    /// Output width in pixels.
    pub width: usize,
    /// Output height in pixels.
    pub height: usize,
    /// Raster points per pixel along each axis (1 = pixel centres only).
    pub supersample: usize,
    /// Size of the domain the sites live in (pixels of the input).
    pub domain: DVec2,
}

impl Raster {
    /// Raster points per row.
    #[must_use]
    pub fn points_per_row(&self) -> usize {
        self.width * self.supersample
    }

    /// Raster point rows.
    #[must_use]
    pub fn point_rows(&self) -> usize {
        self.height * self.supersample
    }

    /// Domain units per raster point along x and y.
    #[must_use]
    pub fn step(&self) -> DVec2 {
        DVec2::new(
            self.domain.x / self.points_per_row() as f64,
            self.domain.y / self.point_rows() as f64,
        )
    }

    /// The domain position of raster point (`gx`, `gy`).
    #[must_use]
    pub fn point(&self, gx: usize, gy: usize) -> DVec2 {
        let s = self.step();
        DVec2::new((gx as f64 + 0.5) * s.x, (gy as f64 + 0.5) * s.y)
    }

    /// Output pixels per domain unit (the geometric mean of x and y).
    #[must_use]
    pub fn pixels_per_unit(&self) -> f64 {
        ((self.width as f64 / self.domain.x) * (self.height as f64 / self.domain.y)).sqrt()
    }
}

impl VoronoiCells<'_> {
    /// Calls `shade(y, owners, row)` for every output row `y` of `out` (rows of `row_len`
    /// values, `raster.height` of them), in parallel bands, with `owners` the owners of the
    /// row's pixel centres (`raster.supersample` is not read: looks that supersample do it
    /// themselves, on the border the centres' owners give).
    pub fn shade_rows<P, F>(&self, raster: &Raster, out: &mut [P], row_len: usize, shade: F)
    where
        P: Send,
        F: Fn(usize, &[Owner], &mut [P]) + Sync,
    {
        self.rows_of(
            raster,
            out,
            row_len,
            Owner::NOBODY,
            |t, p| match t {
                Some(t) => self.owner_in_triangle(t, p),
                None => self.owner_brute_force(p),
            },
            shade,
        );
    }

    /// [`Self::shade_rows`] with only the owning sites ([`VoronoiCells::site_in_triangle`]),
    /// for callers that need no runner-up or distance.
    pub fn site_rows<P, F>(&self, raster: &Raster, out: &mut [P], row_len: usize, shade: F)
    where
        P: Send,
        F: Fn(usize, &[u32], &mut [P]) + Sync,
    {
        self.rows_of(
            raster,
            out,
            row_len,
            NONE,
            |t, p| match t {
                Some(t) => self.site_in_triangle(t, p),
                None => self.owner_brute_force(p).site,
            },
            shade,
        );
    }

    /// The driver of [`Self::shade_rows`] and [`Self::site_rows`]: `at(triangle, p)` is what
    /// a pixel centre `p` gets, its triangle `None` where no triangle covers its row.
    fn rows_of<T, P, A, F>(
        &self,
        raster: &Raster,
        out: &mut [P],
        row_len: usize,
        none: T,
        at: A,
        shade: F,
    ) where
        T: Copy + Send + Sync,
        P: Send,
        A: Fn(Option<usize>, DVec2) -> T + Sync,
        F: Fn(usize, &[T], &mut [P]) + Sync,
    {
        let raster = Raster {
            supersample: 1,
            ..*raster
        };
        let width = raster.width;
        let bands = raster.height.div_ceil(BAND_ROWS).max(1);
        let lists = self.band_lists(&raster, BAND_ROWS, bands);
        out.par_chunks_mut(row_len * BAND_ROWS)
            .zip(lists.par_iter())
            .enumerate()
            .for_each(|(band, (chunk, list))| {
                let first_row = band * BAND_ROWS;
                let rows_here = chunk.len() / row_len.max(1);
                let mut tri = vec![NONE; rows_here * width];
                self.rasterise(&raster, list, first_row, &mut tri);
                let mut values = vec![none; width];
                let step = raster.step();
                for (k, row) in chunk.chunks_mut(row_len).enumerate() {
                    let tris = &tri[k * width..(k + 1) * width];
                    let y = (((first_row + k) as f64) + 0.5) * step.y;
                    for (x, v) in values.iter_mut().enumerate() {
                        // `raster.point(x, first_row + k)`, with the step divided out once.
                        let p = DVec2::new((x as f64 + 0.5) * step.x, y);
                        *v = at(triangle_near(tris, x), p);
                    }
                    shade(first_row + k, &values, row);
                }
            });
    }

    /// For every band of `rows_per_band` raster point rows, the triangles that reach it.
    fn band_lists(&self, raster: &Raster, rows_per_band: usize, bands: usize) -> Vec<Vec<u32>> {
        let step = raster.step();
        let mut lists = vec![Vec::new(); bands];
        for (t, [a, b, c]) in self.mesh().triangles().enumerate() {
            let ys = [a, b, c].map(|v| self.positions()[v as usize].y / step.y - 0.5);
            let lo = ys
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min)
                .floor()
                .max(0.0);
            let hi = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max).ceil();
            if hi < 0.0 {
                continue;
            }
            let first = (lo as usize) / rows_per_band;
            let last = ((hi as usize) / rows_per_band).min(bands - 1);
            for list in &mut lists[first.min(bands - 1)..=last] {
                list.push(t as u32);
            }
        }
        lists
    }

    /// Writes each triangle of `list` into the raster points it covers, for the point rows
    /// `first_row..` that `tri` (whole rows of points) holds.
    fn rasterise(&self, raster: &Raster, list: &[u32], first_row: usize, tri: &mut [u32]) {
        let per_row = raster.points_per_row();
        let rows = tri.len() / per_row.max(1);
        let step = raster.step();
        for &t in list {
            let [a, b, c] = self.mesh().triangle(t as usize);
            // In raster point units, where point (gx, gy) sits at (gx + ½, gy + ½).
            let v = [a, b, c].map(|i| self.positions()[i as usize] / step - DVec2::splat(0.5));
            let y_lo = v.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            let y_hi = v.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
            // floor and ceil without libm calls (baseline x86-64 has no rounding instruction).
            let r0 = (ceil(y_lo).max(first_row as f64)) as usize;
            let r1 = (floor(y_hi) as i64).min((first_row + rows) as i64 - 1);
            for gy in r0 as i64..=r1 {
                let y = gy as f64;
                let Some((x0, x1)) = span(&v, y) else {
                    continue;
                };
                // A hair wider than the exact span, so shared edges leave no gaps.
                let lo = ceil(x0 - 1e-9).max(0.0) as usize;
                let hi = floor(x1 + 1e-9).min(per_row as f64 - 1.0);
                if hi < 0.0 || (lo as f64) > hi {
                    continue;
                }
                let row = (gy as usize - first_row) * per_row;
                tri[row + lo..=row + hi as usize].fill(t);
            }
        }
    }
}

/// Rows of output pixels per parallel band.
const BAND_ROWS: usize = 16;

/// The x-interval where the horizontal line at `y` crosses the triangle `v`.
fn span(v: &[DVec2; 3], y: f64) -> Option<(f64, f64)> {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for i in 0..3 {
        let (p, q) = (v[i], v[(i + 1) % 3]);
        if !((p.y <= y && y <= q.y) || (q.y <= y && y <= p.y)) {
            continue;
        }
        let (a, b) = if p.y == q.y {
            (p.x, q.x)
        } else {
            let x = p.x + (q.x - p.x) * (y - p.y) / (q.y - p.y);
            (x, x)
        };
        lo = lo.min(a.min(b));
        hi = hi.max(a.max(b));
    }
    (lo <= hi).then_some((lo, hi))
}

/// The triangle at pixel `x` of a row, or the nearest one found on the row (a point can fall
/// between two triangles by rounding); `None` if the row has none.
fn triangle_near(row: &[u32], x: usize) -> Option<usize> {
    if row[x] != NONE {
        return Some(row[x] as usize);
    }
    (1..row.len())
        .flat_map(|d| [x.checked_sub(d), Some(x + d)])
        .flatten()
        .filter(|&i| i < row.len())
        .map(|i| row[i])
        .find(|&t| t != NONE)
        .map(|t| t as usize)
}

/// The owning site of every pixel centre of `raster` (`raster.supersample` is not read),
/// row-major, [`NONE`] where no site owns it.
#[must_use]
pub fn owner_map(cells: &VoronoiCells, raster: &Raster) -> Vec<u32> {
    let mut owners = vec![NONE; raster.width * raster.height];
    cells.site_rows(raster, &mut owners, raster.width, |_, sites, row| {
        row.copy_from_slice(sites);
    });
    owners
}

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

/// The label map: [`owner_map`] as `i32` for export (`.npy`), -1 where no site owns a pixel.
#[must_use]
pub fn label_map(cells: &VoronoiCells, raster: &Raster) -> Vec<i32> {
    owner_map(cells, raster)
        .into_iter()
        .map(|site| if site == NONE { -1 } else { site as i32 })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::{AnalyticField, TensorField};
    use crate::render::VoronoiCells;
    use crate::sampling::{self, SamplerParams};

    #[test]
    fn spans_of_a_triangle() {
        let v = [
            DVec2::new(0.0, 0.0),
            DVec2::new(4.0, 0.0),
            DVec2::new(0.0, 4.0),
        ];
        assert_eq!(span(&v, 2.0), Some((0.0, 2.0)));
        assert_eq!(span(&v, 5.0), None);
        assert_eq!(span(&v, 0.0), Some((0.0, 4.0)));
    }

    /// Samples of a constant 3:1 field at 30° on a `w × h` domain, ellipses of `size`
    /// diagonals.
    fn constant_samples(w: usize, h: usize, size: f64) -> (TensorField, sampling::Sampling) {
        let field = AnalyticField::parse(&format!("constant:angle=30,anisotropy=3,size={size}"))
            .unwrap()
            .field(w, h);
        let s = sampling::sample(&field, &SamplerParams::default()).unwrap();
        (field, s)
    }

    #[test]
    fn label_map_matches_brute_force_on_a_constant_field() {
        let (field, s) = constant_samples(120, 90, 0.02);
        let cells = VoronoiCells::new(&s.positions, &s.metrics, &s.mesh);
        for (w, h) in [(120, 90), (61, 47), (1, 9), (9, 1)] {
            let raster = Raster {
                width: w,
                height: h,
                supersample: 1,
                domain: field.domain(),
            };
            let labels = label_map(&cells, &raster);
            let mut agree = 0;
            for y in 0..h {
                for x in 0..w {
                    let o = cells.owner_brute_force(raster.point(x, y));
                    agree += usize::from(labels[y * w + x] == o.site as i32);
                }
            }
            let rate = agree as f64 / (w * h) as f64;
            assert!(rate >= 0.995, "{w}x{h}: {rate}");
        }
    }

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
        let mut term = super::super::voronoi::ColourTerm::new(image::RgbImage::new(60, 40), 1.0);
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
