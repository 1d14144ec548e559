//! Which cells the looks paint: the paper's generalized Voronoi cells (section 6, owner by
//! metric distance alone), or cells that stop at the photo's edges.
//!
//! The paper's cell of a site straddles any edge its ellipse crosses, so a cell covering both
//! sides of a silhouette gets the mean of both colours and every outline becomes a grey band.
//! Edge-following cells add a colour term to the owner ([`ColourTerm`]):
//! `D_i(p)² = δ_i(p)² + w·|c(p) − c_i|²`, an anisotropic SLIC step seeded from the samples
//! (Achanta et al., *SLIC Superpixels*, 2012, with the metric's `δ` as the spatial term). A few
//! iterations alternate assigning pixels by `D` with moving every free site to its cell's
//! centroid and `c_i` to its cell's mean colour, so a site that sat on an edge settles on one
//! side and takes that side's colour; the triangulation is rebuilt after every move, so the
//! candidates of the owner search stay the anisotropic Delaunay neighbours. Sites on the
//! domain's boundary stay where they are. Last, small detached pieces of the final cells are
//! given to their neighbours ([`pieces`]), so every cell is one piece.
//! Positions are `f64`, colours `f32` sRGB in [0, 1].

pub mod border_distance;
pub mod cellmap;
pub mod colour_term;
pub mod means;
pub(crate) mod photo_stats;
pub mod pieces;
pub(crate) mod quiet_cells;
pub mod raster;
pub mod sums;
pub mod voronoi;

use crate::field::blur::gaussian_blur_u8_parallel;
use crate::field::{Tensor, TensorField};
use crate::sampling::AnisotropicDelaunay;
use cellmap::CellMap;
use glam::DVec2;
use image::{DynamicImage, RgbImage};
use photo_stats::{colour_spread, grain_sigma};
use pieces::one_piece;
use raster::{owner_map, Raster};
use rayon::prelude::*;
use sums::{block_stride, BlockSums, BLOCKS_PER_CELL};
use voronoi::{ColourTerm, VoronoiCells};

/// Which cells the looks paint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellKind {
    /// The paper's generalized Voronoi cells: the owner by metric distance alone.
    Voronoi,
    /// Cells that stop at the photo's edges (the paper's cells without a photo).
    Edges,
}

/// How the cells are made.
#[derive(Clone, Debug, PartialEq)]
pub struct CellParams {
    /// Which cells.
    pub kind: CellKind,
    /// `w` of the colour term: a colour difference of `1/√w` (sRGB, summed over channels)
    /// weighs as much as the ellipse's radius; in a dim or flat photo, whose colours span
    /// less than 0.3 of the range, differences weigh as in one spanning 0.3.
    pub colour_weight: f64,
    /// Assign-and-move rounds.
    pub iterations: usize,
    /// How far past the paper's border a cell may reach, in units of `δ` (see
    /// [`ColourTerm::reach`]).
    pub reach: f64,
    /// σ in photo pixels of the blur the colour term sees, so that cells follow edges but
    /// not the grain of fur or foliage (none for a picture without grain, a drawing or a
    /// render, whose hard edges it would only spread).
    pub blur_px: f32,
}

impl Default for CellParams {
    fn default() -> Self {
        CellParams {
            kind: CellKind::Edges,
            // Chosen with benches/fidelity.sh: at w = 300 and a reach of one ellipse radius the
            // cells beat SLIC superpixels at equal count in PSNR and SSIM, with few pixels in
            // detached pieces (a reach of 0.5 trails SLIC on fur; a larger w adds nothing).
            colour_weight: 300.0,
            iterations: 5,
            reach: 1.0,
            blur_px: 1.0,
        }
    }
}

impl CellKind {
    /// The names presets use.
    pub const NAMES: [&'static str; 2] = ["edges", "voronoi"];

    /// The kind a preset name means.
    #[must_use]
    pub fn named(name: &str) -> Option<CellKind> {
        match name {
            "edges" => Some(CellKind::Edges),
            "voronoi" => Some(CellKind::Voronoi),
            _ => None,
        }
    }
}

/// The sites the cells are made from, moved when they follow edges, with their triangulation
/// and colour term.
#[derive(Clone, Debug)]
pub struct CellSites {
    /// Site positions (domain units).
    pub positions: Vec<DVec2>,
    /// The metric at each site.
    pub metrics: Vec<Tensor>,
    /// Their anisotropic Delaunay triangulation.
    pub mesh: AnisotropicDelaunay,
    /// The colour term of edge-following cells.
    pub colour: Option<ColourTerm>,
}

impl CellSites {
    /// The paper's cells of samples, as they are.
    #[must_use]
    pub fn voronoi(
        positions: Vec<DVec2>,
        metrics: Vec<Tensor>,
        mesh: AnisotropicDelaunay,
    ) -> CellSites {
        CellSites {
            positions,
            metrics,
            mesh,
            colour: None,
        }
    }

    /// The cells `params` asks for from samples of `field`: edge-following ones need a photo
    /// (without one, or with `w = 0`, the paper's cells are kept).
    #[must_use]
    pub fn new(
        positions: Vec<DVec2>,
        metrics: Vec<Tensor>,
        mesh: AnisotropicDelaunay,
        field: &TensorField,
        photo: Option<&DynamicImage>,
        params: &CellParams,
    ) -> CellSites {
        let blurred = Self::photo_read(photo, params);
        Self::with_photo_read(positions, metrics, mesh, field, blurred, params)
    }

    /// What the cells `params` asks for read of `photo`: for edge-following cells the photo
    /// blurred by [`CellParams::blur_px`], `None` for the paper's cells. It does not depend on
    /// the samples, so a pipeline can make it while the sampler runs.
    #[must_use]
    pub fn photo_read(photo: Option<&DynamicImage>, params: &CellParams) -> Option<RgbImage> {
        match photo {
            Some(photo) if params.kind == CellKind::Edges && params.colour_weight > 0.0 => {
                let rgb = crate::render::support::colour::rgb8(photo);
                Some(blurred(
                    &rgb,
                    params.blur_px * grain_share(grain_sigma(&rgb)),
                ))
            }
            _ => None,
        }
    }

    /// [`Self::new`] with what the cells read of the photo already made
    /// ([`Self::photo_read`] of the same `params`).
    #[must_use]
    pub fn with_photo_read(
        positions: Vec<DVec2>,
        metrics: Vec<Tensor>,
        mesh: AnisotropicDelaunay,
        field: &TensorField,
        blurred: Option<RgbImage>,
        params: &CellParams,
    ) -> CellSites {
        let mut sites = CellSites::voronoi(positions, metrics, mesh);
        if let Some(blurred) = blurred {
            sites.follow_edges(field, blurred, params);
        }
        sites
    }

    /// The cells.
    #[must_use]
    pub fn cells(&self) -> VoronoiCells<'_> {
        let cells = VoronoiCells::new(&self.positions, &self.metrics, &self.mesh);
        match &self.colour {
            Some(term) => cells.with_colour(term),
            None => cells,
        }
    }

    /// The anisotropic SLIC rounds: assign, then move sites and colours to their cells'
    /// centroids and means; a last assignment sets the colours the final cells use.
    fn follow_edges(&mut self, field: &TensorField, blurred: RgbImage, params: &CellParams) {
        let mut term = ColourTerm::new(blurred, 0.0);
        term.reach = params.reach;
        let domain = field.domain();
        // The rounds move sites, not pixels: the pixels' sums per block are made once, in
        // coarse blocks for the first rounds, where sites still travel far, and in fine ones
        // for the last.
        let n = self.positions.len();
        // Colour differences weigh by the photo's own range: a dim photo's edges are as
        // much edges as a bright one's.
        let weight = params.colour_weight * low_contrast_boost(colour_spread(term.photo()));
        let sums = photo_block_sums(term.photo(), n, BLOCKS_PER_CELL);
        let coarse = photo_block_sums(term.photo(), n, COARSE_BLOCKS_PER_CELL);
        for round in 0..=params.iterations {
            let sums = if round + FINE_ROUNDS > params.iterations {
                &sums
            } else {
                &coarse
            };
            let stats = {
                let cells = VoronoiCells::new(&self.positions, &self.metrics, &self.mesh);
                let cells = if round == 0 {
                    cells
                } else {
                    cells.with_colour(&term)
                };
                cell_stats(&cells, sums)
            };
            term.means = stats
                .iter()
                .zip(&self.positions)
                .map(|(s, &p)| s.mean_colour().unwrap_or_else(|| term.colour_at(p)[0]))
                .collect();
            term.weight = weight;
            if round == params.iterations {
                break;
            }
            let previous = self.positions.clone();
            for (p, s) in self.positions.iter_mut().zip(&stats) {
                if let Some(c) = s.centroid() {
                    if !on_boundary(*p, domain) {
                        *p = c;
                    }
                }
            }
            self.metrics = self
                .positions
                .par_iter()
                .map(|&p| field.sample(p))
                .collect();
            self.mesh = self.triangulate(field, &previous);
        }
        term.map = Some(self.pieces_absorbed(&term, domain));
        self.colour = Some(term);
    }

    /// The final cells' owners on the photo's pixels with every small detached piece given
    /// to a neighbour ([`one_piece`]).
    fn pieces_absorbed(&self, term: &ColourTerm, domain: DVec2) -> CellMap {
        let photo = term.photo();
        let (w, h) = (photo.width() as usize, photo.height() as usize);
        let cells = VoronoiCells::new(&self.positions, &self.metrics, &self.mesh).with_colour(term);
        let pixels = Raster {
            width: w,
            height: h,
            supersample: 1,
            domain,
        };
        let owners = owner_map(&cells, &pixels);
        let raw = photo.as_raw();
        one_piece(owners, w, h, &term.means, |x, y| {
            let i = 3 * (y * w + x);
            [raw[i], raw[i + 1], raw[i + 2]].map(|v| f32::from(v) / 255.0)
        })
    }

    /// The triangulation of the moved sites. Every site keeps its index (the label map
    /// indexes the samples), so a site that landed on another goes back to `previous`, and if
    /// that still collides, every site does.
    fn triangulate(&mut self, field: &TensorField, previous: &[DVec2]) -> AnisotropicDelaunay {
        let (mesh, missing) = AnisotropicDelaunay::build(&self.positions, field);
        if missing.is_empty() {
            return mesh;
        }
        for &k in &missing {
            self.positions[k as usize] = previous[k as usize];
            self.metrics[k as usize] = field.sample(previous[k as usize]);
        }
        let (mesh, missing) = AnisotropicDelaunay::build(&self.positions, field);
        if missing.is_empty() {
            return mesh;
        }
        self.positions = previous.to_vec();
        self.metrics = self
            .positions
            .par_iter()
            .map(|&p| field.sample(p))
            .collect();
        AnisotropicDelaunay::build(&self.positions, field).0
    }
}

/// The share of [`CellParams::blur_px`] a photo whose grain is `sigma` levels
/// ([`grain_sigma`]) is blurred by: all of it from [`GRAIN_FOR_FULL_BLUR`] up, none for a
/// picture without grain.
#[must_use]
fn grain_share(sigma: f64) -> f32 {
    (sigma / GRAIN_FOR_FULL_BLUR).min(1.0) as f32
}

/// The grain (levels, [`grain_sigma`]) from which the colour term's photo is blurred by the
/// whole [`CellParams::blur_px`]: the least above none the estimate gives (a median response
/// of one level is 0.247), so every camera photo measured takes it (0.25–10 levels: noise,
/// fur, grass; a logo's anti-aliased ground 0.25). A drawing or a render whose pixels are
/// mostly flat or ramps has none (a black horse on white, a colour wheel), and the blur would
/// only spread its hard edges into bands of grey, which thin cells along the edge would take
/// for their colour. A photo enlarged several times has none at the pixel either, its grain
/// spread over pixels a 1 px blur does not reach.
const GRAIN_FOR_FULL_BLUR: f64 = 0.2;

/// How much more the colour term weighs in a photo whose colours span `spread`
/// ([`colour_spread`]) than in one spanning at least [`LOW_CONTRAST_SPREAD`]: the square of
/// their ratio, so that the photo's colour differences weigh as in that one (at most
/// `(LOW_CONTRAST_SPREAD / 0.05)²`).
#[must_use]
fn low_contrast_boost(spread: f64) -> f64 {
    (LOW_CONTRAST_SPREAD / spread.max(0.05)).powi(2).max(1.0)
}

/// The range of colours ([`colour_spread`]) under which a photo is dim or flat (underexposed,
/// foggy) and its colour differences weigh more ([`low_contrast_boost`]). The weight `w` suits
/// photos spanning 0.42–0.99; in an underexposed one the same weight would leave the cells as
/// round as the paper's (a face's smile and eyes gone), weighed as at 0.3 they follow its
/// features. Weighed as at 0.6, a brick wall (0.42) or a page of handwriting (0.45) would come
/// out ragged, their mortar and strokes in many small pieces.
const LOW_CONTRAST_SPREAD: f64 = 0.3;

/// `rgb` blurred with a Gaussian of `sigma` pixels (none for σ ≤ 0), all channels at once in
/// bands of rows ([`gaussian_blur_u8_parallel`]).
fn blurred(rgb: &RgbImage, sigma: f32) -> RgbImage {
    let (w, h) = (rgb.width(), rgb.height());
    let data = gaussian_blur_u8_parallel(rgb.as_raw(), w as usize, h as usize, 3, sigma);
    image::RgbImage::from_raw(w, h, data).expect("w·h RGB pixels")
}

/// Whether `p` lies on the domain's boundary (the sampler's fixed samples).
fn on_boundary(p: DVec2, domain: DVec2) -> bool {
    p.x <= 0.0 || p.y <= 0.0 || p.x >= domain.x || p.y >= domain.y
}

/// Pixel count, position sum and sRGB colour sum of one cell.
#[derive(Clone, Copy, Debug, Default)]
struct CellStats {
    count: f64,
    position: [f64; 2],
    colour: [f64; 3],
}

impl CellStats {
    fn mean_colour(&self) -> Option<[f32; 3]> {
        (self.count > 0.0).then(|| self.colour.map(|c| (c / self.count) as f32))
    }

    fn centroid(&self) -> Option<DVec2> {
        (self.count > 0.0).then(|| DVec2::new(self.position[0], self.position[1]) / self.count)
    }
}

/// Largest block side of the owner searches of the assign-and-move rounds: centroids and mean
/// colours need no pixel-exact borders, and a 12 MP photo's few thousand cells keep hundreds
/// of blocks each.
const STATS_STRIDE: usize = 8;

/// The last this many sums of the assign-and-move rounds (the final colours among them) use
/// [`BLOCKS_PER_CELL`]; the earlier ones [`COARSE_BLOCKS_PER_CELL`]: the early rounds only
/// move the sites, so coarse sums serve them as well as fine ones (the cells as good, in less
/// time), while the final colours need the fine ones.
const FINE_ROUNDS: usize = 3;

/// Blocks per cell of the first rounds' sums.
const COARSE_BLOCKS_PER_CELL: f64 = 16.0;

/// Every pixel's count, position and sRGB colour, summed over the blocks of the assign-and-move
/// rounds' owner searches (`photo` has one pixel per domain unit; `n` cells, about
/// `blocks_per_cell` blocks each). A block's colour bytes are summed as integers and divided
/// by 255 once; its count and position sums are whole and half-whole numbers, exact in `f64`.
fn photo_block_sums(photo: &image::RgbImage, n: usize, blocks_per_cell: f64) -> BlockSums<6> {
    let (w, h) = (photo.width() as usize, photo.height() as usize);
    let raw = photo.as_raw();
    let stride = block_stride(w, h, n, blocks_per_cell, STATS_STRIDE);
    BlockSums::from_blocks(w, h, stride, |gx, gy| {
        let (x0, x1) = (gx * stride, ((gx + 1) * stride).min(w));
        let (y0, y1) = (gy * stride, ((gy + 1) * stride).min(h));
        let mut colour = [0u32; 3];
        for y in y0..y1 {
            for px in raw[3 * (y * w + x0)..3 * (y * w + x1)].chunks_exact(3) {
                for (c, &v) in colour.iter_mut().zip(px) {
                    *c += u32::from(v);
                }
            }
        }
        let count = ((x1 - x0) * (y1 - y0)) as f64;
        // Σ (x + ½) over the block is count·(x0 + x1)/2, and likewise for y.
        let (mid_x, mid_y) = ((x0 + x1) as f64 / 2.0, (y0 + y1) as f64 / 2.0);
        let [r, g, b] = colour.map(|c| f64::from(c) / 255.0);
        [count, count * mid_x, count * mid_y, r, g, b]
    })
}

/// Every cell's pixels: count, position and sRGB colour sums ([`BlockSums::per_cell`]).
fn cell_stats(cells: &VoronoiCells, sums: &BlockSums<6>) -> Vec<CellStats> {
    sums.per_cell(cells)
        .into_iter()
        .map(|s| CellStats {
            count: s[0],
            position: [s[1], s[2]],
            colour: [s[3], s[4], s[5]],
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::AnalyticField;
    use crate::sampling::{self, SamplerParams};

    #[test]
    fn photo_block_sums_are_the_pixel_sums() {
        // Partial blocks at the right and bottom edges, and colours that vary pixel by pixel.
        let (w, h) = (97usize, 71usize);
        let photo = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            image::Rgb([
                ((x * 7 + y * 3) % 256) as u8,
                ((x * y) % 251) as u8,
                ((x + 5 * y) % 256) as u8,
            ])
        });
        let field = AnalyticField::parse("constant:angle=30,anisotropy=3,size=0.05")
            .unwrap()
            .field(w, h);
        let s = sampling::sample(&field, &SamplerParams::default()).unwrap();
        let cells = VoronoiCells::new(&s.positions, &s.metrics, &s.mesh);
        let n = s.positions.len();
        for blocks_per_cell in [BLOCKS_PER_CELL, COARSE_BLOCKS_PER_CELL] {
            let stride = block_stride(w, h, n, blocks_per_cell, STATS_STRIDE);
            assert!(
                stride >= 2 && w % stride != 0 && h % stride != 0,
                "stride {stride}"
            );
            let got = photo_block_sums(&photo, n, blocks_per_cell).per_cell(&cells);
            // The truth: every pixel's values added one by one.
            let raw = photo.as_raw();
            let want = BlockSums::new(w, h, stride, |x, y| {
                let i = 3 * (y * w + x);
                let [r, g, b] = [raw[i], raw[i + 1], raw[i + 2]].map(|v| f64::from(v) / 255.0);
                [1.0, x as f64 + 0.5, y as f64 + 0.5, r, g, b]
            })
            .per_cell(&cells);
            for (g, t) in got.iter().zip(&want) {
                for (a, b) in g.iter().zip(t) {
                    assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{g:?} vs {t:?}");
                }
                // Counts and positions are exact.
                assert_eq!(g[..3], t[..3]);
            }
            assert_eq!(got.iter().map(|s| s[0]).sum::<f64>(), (w * h) as f64);
        }
    }
}
