//! The direction the engraving's lines run in ([`super::streamlines`]): along the metric's long
//! axes (paper section 3: along the photo's edges, the minor direction of its structure
//! tensor).
//!
//! Where the metric is round it says no direction; there a constant direction takes over
//! smoothly (`flat_angle`, as an engraver shades a flat area with one set of parallel lines), so
//! the lines never wander. The direction field is a tensor field (`anisotropy · e₁e₁ᵀ + ε ·
//! d₀d₀ᵀ`) blurred over a line spacing, plus the same blurred over six spacings (and, for a
//! photo, over twenty-four): tensors average without the sign ambiguity of vectors, and where
//! the fine direction is weak (grain, noise, a sky's faint gradients) the wider ones lead, so
//! the lines run calm there instead of swirling. For a photo's structure tensor, which spreads
//! the directions of its edges into the areas round them, the two finer directions count only
//! as far as they hold over a wider reach: where structures cross (a lattice, a net) lines that
//! followed them looped. A tensor field given as it is keeps its own directions.
//! Tensors are `f32` (the blur's), positions `f64` in domain units.

use crate::field::{Tensor, TensorField};
use glam::DVec2;

/// Weight of the flat direction against a fully anisotropic metric (`anisotropy = 1`).
const FLAT_WEIGHT: f64 = 0.04;
/// Where the field's direction is weak (noise in a dark sky, a textured wall), the lines
/// follow the direction of a wider neighbourhood: the direction tensors blurred over this many
/// times the line spacing, added with [`COARSE_WEIGHT`]. Where the field is strongly
/// anisotropic the fine tensors outweigh it and the lines keep to the form.
const COARSE_SIGMA: f32 = 6.0;
/// Weight of the coarse neighbourhood's direction tensors against the fine ones: the lines in
/// flat and dark areas run long and calm instead of swirling with the grain, at the cost of a
/// little of a textured wall's edges.
const COARSE_WEIGHT: f32 = 2.0;
/// The run of the lines over a whole region (a sky, a wall, a field of grass): the direction
/// tensors blurred over this many line spacings, added with [`WIDE_WEIGHT`]. It leads only
/// where the two finer fields are weak or do not hold (see [`FINE_HOLDS_OVER`]), so the lines
/// cross a sky in long, calm arcs instead of swirling round every faint gradient of it.
const WIDE_SIGMA: f32 = 24.0;
/// Weight of the region's direction tensors (see [`WIDE_SIGMA`]). At 4 it also overrode the
/// forms of strong, textured objects (a tyre's rings turned to diagonals across its tread).
const WIDE_WEIGHT: f32 = 2.0;
/// The fine direction counts as far as it holds over this many line spacings: its tensors
/// are weighted by the square of the coherence of the tensors blurred over that reach.
/// Where structures cross within it (a lattice's braces and rungs, a net), lines that followed
/// each one in turn went round in ovals between them (the rocket's launch towers were stacks
/// of ovals); there the wider fields lead, and the outlines draw the crossing structures over
/// calm lines. Smooth forms hold over it and keep their lines. The reach is a compromise
/// between the smallest round forms and the lattices: the isophotes of a dome 3.3 spacings
/// in radius are followed within 7.6° over 2 spacings, 12.4° over 3, up to 90° over 4
/// (`tests/engraving.rs`); over 2 the towers kept half their ovals, over 6 a face's cheeks
/// were crossed by straight lines.
const FINE_HOLDS_OVER: f32 = 3.0;
/// [`FINE_HOLDS_OVER`] for the coarse direction's tensors (twice their own reach).
const COARSE_HOLDS_OVER: f32 = 2.0 * COARSE_SIGMA;

/// A smooth line field: at every point the direction the lines run in.
pub struct Directions {
    nodes: TensorField,
}

impl Directions {
    /// The line field of `metric` (its long axes) as it is, blurred over `sigma` domain units
    /// and, where that is weak, over six times it, with `flat_angle` (radians) where the
    /// metric is round: the field a tensor field's own lines show.
    #[must_use]
    pub fn new(metric: &TensorField, flat_angle: f64, sigma: f64) -> Self {
        let scales = Scales::new(metric, flat_angle, sigma);
        let (mut data, coarse) = (scales.blurred(1.0), scales.blurred(COARSE_SIGMA));
        for (d, c) in data.iter_mut().zip(&coarse) {
            *d += COARSE_WEIGHT * c;
        }
        Self::of(metric, &data)
    }

    /// [`Self::new`] for the metric of a photo's structure tensor, whose directions near an
    /// edge are spread by the tensor's integration into the areas round it: the fine and the
    /// coarse directions count only as far as they hold (over three and twelve line
    /// spacings), and the region's (24 spacings) leads where they do not.
    #[must_use]
    pub fn of_photo(metric: &TensorField, flat_angle: f64, sigma: f64) -> Self {
        let scales = Scales::new(metric, flat_angle, sigma);
        // Each of the two finer fields with the reach over which it must hold.
        let (fine, fine_reach) = (scales.blurred(1.0), scales.blurred(FINE_HOLDS_OVER));
        let coarse = scales.blurred(COARSE_SIGMA);
        let coarse_reach = scales.blurred(COARSE_HOLDS_OVER);
        let mut data = scales.blurred(WIDE_SIGMA);
        for (i, d) in data.chunks_exact_mut(3).enumerate() {
            let k = 3 * i..3 * i + 3;
            let fine_holds = coherence(&fine_reach[k.clone()]).powi(2);
            let coarse_holds = COARSE_WEIGHT * coherence(&coarse_reach[k.clone()]).powi(2);
            for (j, v) in d.iter_mut().enumerate() {
                let at = k.start + j;
                *v = fine_holds * fine[at] + coarse_holds * coarse[at] + WIDE_WEIGHT * *v;
            }
        }
        Self::of(metric, &data)
    }

    /// The line field of a photo's `metric` ([`Self::of_photo`]) at the scale of the mean
    /// radius of `count` cells over its domain, on the metric's grid coarsened to about half
    /// that radius between nodes (the blurs, up to 24 radii, cost the cube of the grid's
    /// fineness: at 12 MP, 525 × 350 nodes 8 px apart took 73 ms against 8 ms at 16 px). What
    /// the brush strokes of flat areas and the fabric's and LIC's streamlines follow.
    #[must_use]
    pub fn at_cell_scale(metric: &TensorField, flat_angle: f64, count: usize) -> Self {
        let d = metric.domain();
        let radius = (d.x * d.y / count.max(1) as f64 / std::f64::consts::PI).sqrt();
        let factor = (0.5 * radius / metric.spacing()).floor();
        if factor >= 2.0 {
            Self::of_photo(&metric.coarsened(factor as usize), flat_angle, radius)
        } else {
            Self::of_photo(metric, flat_angle, radius)
        }
    }

    /// The direction tensors: at every node, the lines' direction is the long axis.
    #[must_use]
    pub fn tensors(&self) -> &TensorField {
        &self.nodes
    }

    /// The field of direction tensors `data` (three per node of `metric`'s grid).
    fn of(metric: &TensorField, data: &[f32]) -> Self {
        let mut nodes = metric.clone();
        for (v, c) in nodes.data_mut().iter_mut().zip(data.chunks_exact(3)) {
            *v = [c[0], c[1], c[2]];
        }
        Directions { nodes }
    }

    /// The unit direction of the lines at `p` (its sign is arbitrary).
    #[must_use]
    pub fn at(&self, p: DVec2) -> DVec2 {
        let t = self.nodes.sample(p);
        let angle = 0.5 * (2.0 * t.xy).atan2(t.xx - t.yy);
        DVec2::new(angle.cos(), angle.sin())
    }
}

/// A metric's direction tensors (`anisotropy · e₁e₁ᵀ + ε · d₀d₀ᵀ`, `xx`, `xy`, `yy` per node)
/// and the blur that reads them at a multiple of the line spacing.
struct Scales {
    tensors: Vec<f32>,
    cols: usize,
    rows: usize,
    /// The line spacing in grid nodes.
    grid_sigma: f32,
}

impl Scales {
    fn new(metric: &TensorField, flat_angle: f64, sigma: f64) -> Self {
        let flat = Tensor::outer(DVec2::new(flat_angle.cos(), flat_angle.sin()));
        let (cols, rows) = (metric.cols(), metric.rows());
        let mut tensors: Vec<f32> = Vec::with_capacity(3 * cols * rows);
        for v in metric.data() {
            let e = Tensor::from_f32(*v).eigen();
            let t = Tensor::outer(e.e1());
            let a = e.anisotropy();
            tensors.extend_from_slice(&[
                (a * t.xx + FLAT_WEIGHT * flat.xx) as f32,
                (a * t.xy + FLAT_WEIGHT * flat.xy) as f32,
                (a * t.yy + FLAT_WEIGHT * flat.yy) as f32,
            ]);
        }
        Scales {
            tensors,
            cols,
            rows,
            grid_sigma: (sigma / metric.spacing()) as f32,
        }
    }

    /// The tensors blurred over `times` line spacings.
    fn blurred(&self, times: f32) -> Vec<f32> {
        let mut out = self.tensors.clone();
        crate::field::blur::gaussian_blur_parallel_mut(
            &mut out,
            self.cols,
            self.rows,
            3,
            self.grid_sigma * times,
        );
        out
    }
}

/// How strongly the direction tensor `t` (`xx`, `xy`, `yy`) holds one direction: the
/// difference of its eigenvalues over their sum, 1 for one direction, 0 where directions
/// cancel out (or there are none).
fn coherence(t: &[f32]) -> f32 {
    let (xx, xy, yy) = (t[0], t[1], t[2]);
    let trace = xx + yy;
    if trace > 0.0 {
        (((xx - yy) * (xx - yy) + 4.0 * xy * xy).sqrt() / trace).min(1.0)
    } else {
        0.0
    }
}
