//! How strongly the outlines in the photo's own colour
//! ([`OutlineInk::Pixel`](super::outline_ink::OutlineInk::Pixel), a painter's rigger brush)
//! are laid. A pen's line is as dark as its edge: the soft threshold of
//! [`super::outline`] turns the flow-averaged response into ink, so a faint edge gets a faint
//! line. A rigger lays the photo's own colour, which carries the edge's contrast itself: a line
//! laid whole brings back only the contrast the photo has there. So where lines are sparse (a
//! mast or a lattice against the sky, a whisker, a wire) the rigger lays them at up to
//! [`SPARSE_GAIN`] times the threshold's argument, `ink' = tanh(g·atanh(ink))`: brown steel on a
//! dark blue sky, which the broad strokes paint over and the pen's threshold inks at about 0.4
//! (a launch tower's lattice: the strongest ink of its rows 0.38 at the median, now 0.98),
//! comes back whole. Where lines are dense and strong (grass, gravel) the strokes are the texture and
//! the rigger keeps the pen's strength (`g = 1`); laid whole there, it would lay the photo
//! back over the painting.
//!
//! The density is the line map's ink averaged over a Gaussian of [`DENSITY_SIGMA`]·σ_c: under
//! [`SPARSE`] the gain is whole, over [`DENSE`] it is 1, linear between (measured on the line
//! maps of photos at σ = 6 nodes, medians at their lines: a lattice tower against the sky
//! 0.11–0.19, grass 0.37, gravel 0.32). Being ink, it counts lines that are both dense and
//! strong: faint lines are raised however dense, which brings back no more than their faint
//! contrast. `f32`, on the structure tensor's grid.

use crate::field::blur::gaussian_blur_parallel_mut;

/// The gain on the threshold's argument where the lines are sparse. Measured on 22 photos in
/// `strokes` (`tone.py`): 3, 4 and 6 give 39.06, 39.19 and 39.37 dB against 38.63 without,
/// while grass (dense) moves 0.4–0.7 dB only, against 3 dB for a gain of 2 everywhere.
pub const SPARSE_GAIN: f32 = 6.0;

/// Line density (mean ink around a node) at and under which the gain is whole.
pub const SPARSE: f32 = 0.15;

/// Line density at and over which the rigger lays lines as the pen would.
pub const DENSE: f32 = 0.3;

/// σ of the density's Gaussian, in σ_c (the lines' width): about a stroke's half width.
pub const DENSITY_SIGMA: f32 = 6.0;

/// Raises the ink of `lines` (a line map on a `cols × rows` grid, σ_c = `sigma_c` nodes) where
/// its lines are sparse, as a rigger lays them.
pub(super) fn sparse_lines_whole_mut(
    lines: &mut [f32],
    (cols, rows): (usize, usize),
    sigma_c: f32,
) {
    let mut density = lines.to_vec();
    gaussian_blur_parallel_mut(&mut density, cols, rows, 1, DENSITY_SIGMA * sigma_c);
    for (ink, &d) in lines.iter_mut().zip(&density) {
        if *ink > 0.0 {
            *ink = (gain(d) * ink.min(MOST_INK).atanh()).tanh();
        }
    }
}

/// The largest ink whose `atanh` is taken: `tanh` rounds to 1 in `f32` from about 9, and a
/// node inked that fully stays so.
const MOST_INK: f32 = 0.999_999;

/// The gain at line density `d`.
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
    fn dense_lines_keep_their_ink_and_sparse_ones_are_raised() {
        // A grid where every node is inked 0.4 (dense), and one with a single column inked
        // 0.4 (sparse).
        let (cols, rows) = (60usize, 40usize);
        let mut dense = vec![0.4f32; cols * rows];
        sparse_lines_whole_mut(&mut dense, (cols, rows), 1.0);
        assert!(dense.iter().all(|&v| (v - 0.4).abs() < 1e-6));
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
