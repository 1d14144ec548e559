//! How strongly the outlines in the photo's own colour
//! ([`OutlineInk::Pixel`](super::outline_ink::OutlineInk::Pixel), a painter's rigger brush)
//! are laid. A pen's line is as dark as its edge: the soft threshold of
//! [`super::outline`] turns the flow-averaged response into ink, so a faint edge gets a faint
//! line. A rigger lays the photo's own colour, which carries the edge's contrast itself: a line
//! laid whole brings back only the contrast the photo has there. So where lines are sparse (a
//! mast or a lattice against the sky, a whisker, a wire) the rigger lays them at up to
//! [`SPARSE_GAIN`] times the threshold's argument, `ink' = tanh(g·atanh(ink))`: brown steel on a
//! dark blue sky, which the broad strokes paint over and the pen's threshold inks at about 0.4
//! (a launch tower's lattice: the strongest ink of its rows 0.38 at the median), comes back
//! whole. Where nearly every node carries some line, the lines are a texture (grass, gravel)
//! or the photo's grain, the strokes are the texture, and the rigger keeps the pen's strength
//! (`g = 1`): laid whole there, it would lay the photo, or its noise, back over the painting.
//!
//! Sparseness is the share of inked nodes (any ink at all, however faint) within a Gaussian of
//! [`DENSITY_SIGMA`]·σ_c: at and under [`SPARSE`] the gain is whole, at and over [`DENSE`] it
//! is 1, linear between. Measured on the line maps of photos, medians at their lines (ink over
//! 0.15): lattice towers against the sky 0.61–0.77, a cat 0.75, grass 0.97, gravel 0.90, and
//! flat colour under Gaussian noise of 16 levels 0.93. (The mean ink instead, which is small
//! on faint lines however many, raised that noise into a speckle over half the picture.)
//! `f32`, on the structure tensor's grid.

use crate::field::blur::gaussian_blur_parallel_mut;

/// The gain on the threshold's argument where the lines are sparse (a gain everywhere would
/// make grass photographic).
pub const SPARSE_GAIN: f32 = 6.0;

/// Share of inked nodes at and under which the gain is whole.
pub const SPARSE: f32 = 0.7;

/// Share of inked nodes at and over which the rigger lays lines as the pen would.
pub const DENSE: f32 = 0.9;

/// σ of the share's Gaussian, in σ_c (the lines' width): about a stroke's half width.
pub const DENSITY_SIGMA: f32 = 6.0;

/// Raises the ink of `lines` (a line map on a `cols × rows` grid, σ_c = `sigma_c` nodes) where
/// its lines are sparse, as a rigger lays them.
pub(crate) fn sparse_lines_whole_mut(
    lines: &mut [f32],
    (cols, rows): (usize, usize),
    sigma_c: f32,
) {
    let mut inked: Vec<f32> = lines
        .iter()
        .map(|&v| f32::from(u8::from(v > 0.0)))
        .collect();
    gaussian_blur_parallel_mut(&mut inked, cols, rows, 1, DENSITY_SIGMA * sigma_c);
    for (ink, &d) in lines.iter_mut().zip(&inked) {
        if *ink > 0.0 {
            *ink = (gain(d) * ink.min(MOST_INK).atanh()).tanh();
        }
    }
}

/// The largest ink whose `atanh` is taken: `tanh` rounds to 1 in `f32` from about 9, and a
/// node inked that fully stays so.
const MOST_INK: f32 = 0.999_999;

/// The gain where a share `d` of the nodes around is inked.
fn gain(d: f32) -> f32 {
    let sparse = ((DENSE - d) / (DENSE - SPARSE)).clamp(0.0, 1.0);
    1.0 + (SPARSE_GAIN - 1.0) * sparse
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gain_is_whole_where_sparse_and_one_where_dense() {
        assert_eq!(gain(0.0), SPARSE_GAIN);
        assert_eq!(gain(SPARSE), SPARSE_GAIN);
        assert_eq!(gain(DENSE), 1.0);
        assert_eq!(gain(0.9), 1.0);
        let mid = gain(0.5 * (SPARSE + DENSE));
        assert!((mid - 0.5 * (1.0 + SPARSE_GAIN)).abs() < 1e-5, "{mid}");
    }

    #[test]
    fn lines_among_lines_keep_their_ink_and_lone_ones_are_raised() {
        // A grid where every node is inked 0.4, and one with a single column inked 0.4.
        let (cols, rows) = (60usize, 40usize);
        let mut dense = vec![0.4f32; cols * rows];
        sparse_lines_whole_mut(&mut dense, (cols, rows), 1.0);
        assert!(dense.iter().all(|&v| (v - 0.4).abs() < 1e-6));
        // Faint ink on every node (a grain) is as dense as strong ink.
        let mut grain = vec![0.05f32; cols * rows];
        sparse_lines_whole_mut(&mut grain, (cols, rows), 1.0);
        assert!(grain.iter().all(|&v| (v - 0.05).abs() < 1e-6));
        let mut sparse = vec![0.0f32; cols * rows];
        for r in 0..rows {
            sparse[r * cols + 30] = 0.4;
        }
        sparse_lines_whole_mut(&mut sparse, (cols, rows), 1.0);
        let want = (SPARSE_GAIN * 0.4f32.atanh()).tanh();
        for r in 0..rows {
            assert!((sparse[r * cols + 30] - want).abs() < 1e-5);
            assert_eq!(sparse[r * cols + 29], 0.0, "no ink is added beside a line");
        }
    }
}
