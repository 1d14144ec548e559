//! Tone point by point for the hatched looks (paper section 6's textured cells, with lines
//! that follow the photo inside a cell): the coverage `texture::cell_tones` gives a cell of
//! the photo's colour at each point, read from the photo blurred as the pixel ink is
//! (`blurred_photo::INK_BLUR`). Lines keep their cell's direction and spacing and swell and thin
//! with the tone under them, as an engraver's do, so an eye or a nostril inside a cell of skin
//! is drawn in darker lines, not in the cell's one width. The coverage depends only on the
//! colour's luminance `Y` (the ink is fixed): a table over `√Y` (denser in the dark tones,
//! where the eye tells tones apart) is built once per picture and read once per pixel of the
//! reduced photo (`blurred_photo::ToneGrid`, bilinear at the picture's points). `f32`.

use crate::render::support::colour::{luminance, Linear};
use rayon::prelude::*;

/// Entries of the table over `√Y`.
const STEPS: usize = 1024;

/// Ink coverage by the luminance of the photo's colour.
pub(crate) struct LocalTone {
    coverage: Vec<f32>,
}

impl LocalTone {
    /// The grey ramp the table is made of: [`STEPS`] greys, evenly spaced in `√Y`.
    #[must_use]
    pub(crate) fn greys() -> Vec<Linear> {
        (0..STEPS)
            .map(|i| {
                let s = i as f32 / (STEPS - 1) as f32;
                [s * s; 3]
            })
            .collect()
    }

    /// The table from the tones `(coverage, ink)` of [`Self::greys`], as `cell_tones` gives
    /// them.
    #[must_use]
    pub(crate) fn new(tones: &[(f32, Linear)]) -> Self {
        debug_assert_eq!(tones.len(), STEPS);
        LocalTone {
            coverage: tones.iter().map(|&(cover, _)| cover).collect(),
        }
    }

    /// The coverage for the photo's colour `c` at a point (the nearest entry: neighbouring
    /// entries are less than 0.4 of an sRGB level apart).
    #[inline]
    #[must_use]
    pub(crate) fn at(&self, c: Linear) -> f32 {
        let s = luminance(c).clamp(0.0, 1.0).sqrt();
        self.coverage[(s * (STEPS - 1) as f32 + 0.5) as usize]
    }
}

impl LocalTone {
    /// The coverage of every pixel of `rgb` (linear, three `f32` per pixel).
    #[must_use]
    pub(crate) fn coverages(&self, rgb: &[f32]) -> Vec<f32> {
        rgb.par_chunks_exact(3)
            .map(|c| self.at([c[0], c[1], c[2]]))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_reads_back_the_tone_of_every_grey() {
        // Coverage falling with lightness, as a cell's tone would: a stand-in for cell_tones.
        let tones: Vec<(f32, Linear)> = LocalTone::greys()
            .iter()
            .map(|g| {
                (
                    1.0 - crate::render::support::colour::lightness(*g),
                    [0.0; 3],
                )
            })
            .collect();
        let table = LocalTone::new(&tones);
        for v in [0u8, 1, 7, 30, 64, 128, 200, 254, 255] {
            let c = [crate::render::support::colour::to_linear(v); 3];
            let want = 1.0 - f32::from(v) / 255.0;
            let got = table.at(c);
            assert!((got - want).abs() < 0.02, "sRGB {v}: {got} against {want}");
        }
    }
}
