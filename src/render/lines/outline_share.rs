//! The share of the picture the outlines ink around every point, for the ink looks to leave
//! out of their own tone. Outlines are laid over a look that already gives the photo's tone,
//! so along every edge they would add their ink to the look's and darken it. A hatching
//! or an engraving that knows how much the outlines will ink nearby draws that much less
//! itself: with outlines inking a share `e` of an area over the look's `d'`, the area reads
//! `e + (1 − e)·d'`, which is the photo's darkness `d` at `d' = (d − e) / (1 − e)`.
//!
//! Paper laid along the photo's light lines (highlights) takes a share `w` of the area the other
//! way: the look draws `d' = (d − e) / (1 − e − w)` there.
//!
//! The share is the outlines' line map (ink 0 to 1 per node of the structure tensor's grid,
//! times their strength) blurred over [`SHARE_BLUR`] nodes: the neighbourhood over which the
//! eye, or an evaluator's blur, averages the lines with the hatching beside them. `f32`.

use crate::field::TensorField;
use glam::DVec2;

/// The outlines' ink averaged around every node of the structure tensor's grid.
#[derive(Clone, Debug)]
pub struct OutlineShare {
    /// The outlines' ink around every node (empty: no outlines).
    values: Vec<f32>,
    cols: usize,
    rows: usize,
    /// Domain units per node.
    spacing: f64,
    /// The paper the highlights leave bare around every node, blurred likewise (empty: none).
    paper: Vec<f32>,
}

/// σ of the blur of the line map, in nodes of the structure tensor's grid (analysis pixels),
/// about a line spacing of the hatching there (narrower, the looks keep the edges a little
/// worse; wider, the tone beside the lines drifts).
pub const SHARE_BLUR: f32 = 1.5;

/// The outlines never take more than this share of an area's tone: the look keeps some ink
/// of its own wherever the photo has any.
const MOST: f32 = 0.9;

impl OutlineShare {
    /// The share of `lines` (a line map on `tensor`'s grid, see
    /// [`line_map`](super::outline::line_map), or empty: no outlines) drawn at `strength`.
    #[must_use]
    pub fn new(lines: &[f32], tensor: &TensorField, strength: f32) -> Self {
        let (cols, rows) = (tensor.cols(), tensor.rows());
        OutlineShare {
            values: blurred(lines, (cols, rows), strength),
            cols,
            rows,
            spacing: tensor.spacing(),
            paper: Vec::new(),
        }
    }

    /// The same share with the highlights' paper: `highlights`, their
    /// [`highlight_map`](super::highlights::highlight_map) on the same grid, laid at `strength`.
    #[must_use]
    pub fn with_highlights(mut self, highlights: &[f32], strength: f32) -> Self {
        self.paper = blurred(highlights, (self.cols, self.rows), strength);
        self
    }

    /// The share at domain point `p` (bilinear between node centres, clamped at the borders,
    /// as the outlines read their line map).
    #[must_use]
    pub fn at(&self, p: DVec2) -> f32 {
        self.read(&self.values, p)
    }

    /// `values` (the ink or the paper share) at `p`; 0 where there are none.
    fn read(&self, values: &[f32], p: DVec2) -> f32 {
        if values.is_empty() {
            return 0.0;
        }
        let node = |u: f64| (u / self.spacing - 0.5) as f32;
        super::node_grid::bilinear(values, self.cols, self.rows, node(p.x), node(p.y))
    }

    /// The darkness (ink coverage, 0 to 1) a look draws at `p` for the photo's `darkness`
    /// there, so that with the outlines over it (and the highlights' paper beside them) the
    /// area reads `darkness`.
    #[must_use]
    pub fn leave_out(&self, darkness: f32, p: DVec2) -> f32 {
        let e = self.at(p).clamp(0.0, MOST);
        let w = self.read(&self.paper, p).clamp(0.0, MOST - e);
        if e <= 0.0 && w <= 0.0 {
            return darkness;
        }
        ((darkness - e) / (1.0 - e - w)).clamp(0.0, 1.0)
    }
}

/// `map` (per node of a `cols × rows` grid, or empty) at `strength`, blurred over
/// [`SHARE_BLUR`] nodes; empty stays empty.
fn blurred(map: &[f32], (cols, rows): (usize, usize), strength: f32) -> Vec<f32> {
    let mut values: Vec<f32> = map.iter().map(|&v| v * strength.clamp(0.0, 1.0)).collect();
    if !values.is_empty() {
        crate::field::blur::gaussian_blur_parallel_mut(&mut values, cols, rows, 1, SHARE_BLUR);
    }
    values
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_look_and_the_outlines_together_give_the_photos_darkness() {
        // Uniform lines (no blur can change them) inking half of every node.
        let tensor = TensorField::from_fn(8, 6, |_| crate::field::Tensor::new(1.0, 0.0, 1.0));
        let share = OutlineShare::new(&[0.5; 48], &tensor, 1.0);
        let p = DVec2::new(3.3, 2.7);
        assert!((share.at(p) - 0.5).abs() < 1e-6);
        for d in [0.0f32, 0.3, 0.5, 0.8, 1.0] {
            let left = share.leave_out(d, p);
            if d >= 0.5 {
                // e + (1 − e)·d' = d.
                assert!((0.5 + 0.5 * left - d).abs() < 1e-6, "{d}: {left}");
            } else {
                // Lighter than the outlines alone: the look draws no ink.
                assert_eq!(left, 0.0);
            }
        }
        // At half strength the lines ink a quarter.
        let half = OutlineShare::new(&[0.5; 48], &tensor, 0.5);
        assert!((half.at(p) - 0.25).abs() < 1e-6);
        // No lines, no change.
        let none = OutlineShare::new(&[0.0; 48], &tensor, 1.0);
        assert_eq!(none.leave_out(0.37, p), 0.37);
        // Highlights leaving a fifth bare: e + (1 − e − w)·d' = d.
        let both = OutlineShare::new(&[0.5; 48], &tensor, 1.0).with_highlights(&[0.2; 48], 1.0);
        let left = both.leave_out(0.8, p);
        assert!((0.5 + 0.3 * left - 0.8).abs() < 1e-6, "{left}");
    }
}
