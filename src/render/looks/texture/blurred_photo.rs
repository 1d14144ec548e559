//! The photo as the textured looks read it under their ink (paper section 6's cells over a
//! photo): in linear light, box-reduced to a diagonal of at most [`INK_DIAGONAL`] and blurred
//! by [`INK_BLUR`] of that diagonal, read bilinearly at any point of the picture
//! ([`BlurredPhoto`]); and the ink coverage its colours ask for, one value per reduced pixel,
//! blurred as ink (as coverage) and read the same way ([`ToneGrid`], the hatching's tone point
//! by point from `local_tone.rs`).
//! `f32` colours and tones, `f64` positions (photo pixels).

use super::local_tone::LocalTone;
use crate::render::lines::outline_share::OutlineShare;
use crate::render::support::bilinear::bilinear_nonnegative;
use crate::render::support::colour::Linear;
use glam::DVec2;
use rayon::prelude::*;

/// Blur of the photo under the ink, as a fraction of the photo's diagonal: about half a pixel
/// of a 512² photo, at most 1.4 px of the reduced image (diagonal ≤ `INK_DIAGONAL`) a
/// larger photo is read from (at 0.002 the pointillist's faces go soft); the per-dot colour
/// shift hides the photo's grain.
pub const INK_BLUR: f32 = 0.0007;

/// The largest diagonal (px) of the photo the pixel ink reads its colours from and the
/// hatchings their tone; a larger photo is box-reduced by whole factors to fit. Large enough
/// that a photo of ordinary size is read at its own resolution (read at half its size, fine
/// detail fades: a pier's planks, moss, a facade's slats), small enough that a 12 MP photo is
/// read at a third of its size.
pub const INK_DIAGONAL: usize = 2048;

/// The photo in linear light at a reduced resolution, blurred.
pub(crate) struct BlurredPhoto {
    image: crate::field::structure::LinearImage,
    factor: f64,
}

impl BlurredPhoto {
    pub(crate) fn new(photo: &image::DynamicImage) -> Self {
        use crate::field::structure::{analysis_factor, linear_analysis_image};
        let (w, h) = (photo.width() as usize, photo.height() as usize);
        let factor = analysis_factor(w, h, INK_DIAGONAL);
        let mut image = linear_analysis_image(photo, factor);
        let diagonal = ((image.width * image.width + image.height * image.height) as f32).sqrt();
        crate::field::blur::gaussian_blur_parallel_mut(
            &mut image.data,
            image.width,
            image.height,
            3,
            INK_BLUR * diagonal,
        );
        BlurredPhoto {
            image,
            factor: factor as f64,
        }
    }

    /// The colour at domain point `p` (photo pixels), bilinear in the reduced image, clamped
    /// at its edges.
    pub(crate) fn at(&self, p: DVec2) -> Linear {
        let (w, h) = (self.image.width, self.image.height);
        let (x, y) = texel_point(p, self.factor, w, h);
        let data = &self.image.data;
        bilinear_nonnegative(x, y, |xi, yi| {
            let i = 3 * texel_index(xi, yi, w, h);
            let [r, g, b] = data[i..i + 3] else {
                unreachable!("three channels")
            };
            [r, g, b]
        })
    }
}

/// The ink coverage of every pixel of the reduced photo, read bilinearly (reading the colour
/// and the table at every point of a 12 MP cross-hatching instead cost 0.17 s).
pub(crate) struct ToneGrid {
    coverage: Vec<f32>,
    width: usize,
    height: usize,
    /// Photo pixels per grid pixel.
    factor: f64,
}

impl ToneGrid {
    /// The coverage `tone` gives each pixel of `photo`, box-reduced as [`BlurredPhoto`] is,
    /// then blurred by [`INK_BLUR`] as coverage, and less what `outlines` laid over the look
    /// will ink there ([`OutlineShare::leave_out`]). Blurred as ink, not as light: the colours
    /// blurred in linear light and then read as ink came out lighter wherever the photo's
    /// texture is fine (grass hatched 1.8 levels of luma light, 0.15 without the blur).
    pub(crate) fn new(
        photo: &image::DynamicImage,
        tone: &LocalTone,
        outlines: Option<&OutlineShare>,
    ) -> Self {
        use crate::field::structure::{analysis_factor, linear_analysis_image};
        let (w, h) = (photo.width() as usize, photo.height() as usize);
        let factor = analysis_factor(w, h, INK_DIAGONAL);
        let image = linear_analysis_image(photo, factor);
        let (width, height) = (image.width, image.height);
        let mut coverage = tone.coverages(&image.data);
        drop(image);
        let diagonal = ((width * width + height * height) as f32).sqrt();
        crate::field::blur::gaussian_blur_parallel_mut(
            &mut coverage,
            width,
            height,
            1,
            INK_BLUR * diagonal,
        );
        let factor = factor as f64;
        if let Some(share) = outlines {
            coverage
                .par_chunks_mut(width)
                .enumerate()
                .for_each(|(y, row)| {
                    for (x, c) in row.iter_mut().enumerate() {
                        let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5) * factor;
                        *c = share.leave_out(*c, p);
                    }
                });
        }
        ToneGrid {
            coverage,
            width,
            height,
            factor,
        }
    }

    /// The coverage at domain point `p` (photo pixels), bilinear, clamped at the edges.
    #[inline]
    #[must_use]
    pub(crate) fn at(&self, p: DVec2) -> f32 {
        let (w, h) = (self.width, self.height);
        let (x, y) = texel_point(p, self.factor, w, h);
        bilinear_nonnegative(x, y, |xi, yi| [self.coverage[texel_index(xi, yi, w, h)]])[0]
    }
}

/// Domain point `p` in texel units of a `w` × `h` image whose texels are `factor` photo
/// pixels wide, clamped to the texel centres.
#[inline]
fn texel_point(p: DVec2, factor: f64, w: usize, h: usize) -> (f64, f64) {
    (
        (p.x / factor - 0.5).clamp(0.0, (w - 1) as f64),
        (p.y / factor - 0.5).clamp(0.0, (h - 1) as f64),
    )
}

/// Index of texel `(xi, yi)` (at most one past the last, from a clamped point's right or lower
/// neighbour) in a `w` × `h` image.
#[inline]
fn texel_index(xi: i64, yi: i64, w: usize, h: usize) -> usize {
    yi.min(h as i64 - 1) as usize * w + xi.min(w as i64 - 1) as usize
}
