//! What the outlines of [`super::outline`] are drawn in: one ink, as a pen draws them, or the
//! photo's own colour under every line, as a painter's rigger brush draws the thin lines and
//! crisp edges that broad strokes paint over (a mast, a lattice, an eyelid, a lamp post keep
//! their colour and their place; the strokes' Hertzmann refinement cannot, its finest brush
//! is a quarter of a stroke). The line map says where; this file says in what colour.
//!
//! The photo is read bilinearly in 8-bit sRGB at every picture pixel's centre (clamped at the
//! photo's edges), `f32`; at the photo's own size that is the pixel itself. The SVG shows that
//! photo inside the outlines' traced shapes ([`crate::render::vector::outlines`]). One ink is no
//! lighter than the photo under it ([`DarkerInk`]; in the SVG, per connected piece of line, over
//! its mean photo colour).

use crate::render::support::bilinear::bilinear;
use crate::render::support::colour::{linear_of, rgb8, to_srgb, Linear};
use glam::DVec2;
use image::{DynamicImage, RgbImage};
use std::borrow::Cow;

/// The ink of the outlines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OutlineInk {
    /// One ink colour, sRGB.
    Colour([u8; 3]),
    /// The photo's colour under every pixel of the lines (as `look.ink = "pixel"` is for the
    /// hatching, but neither blurred nor darkened: a line is as dark as the photo there).
    Pixel,
}

impl OutlineInk {
    /// The preset's name of [`OutlineInk::Pixel`] (`outlines.ink = "pixel"`).
    pub const PIXEL: &'static str = "pixel";
}

/// The photo read at the pixel centres of a `width × height` picture of `domain` (the photo's
/// size in domain units): the ink of [`OutlineInk::Pixel`].
pub struct PhotoInk<'a> {
    photo: Cow<'a, RgbImage>,
    /// Photo texels per picture pixel, across and down.
    scale: DVec2,
}

impl<'a> PhotoInk<'a> {
    /// The photo's ink for a `width × height` picture.
    #[must_use]
    pub fn new(photo: &'a DynamicImage, (width, height): (usize, usize)) -> Self {
        let photo = rgb8(photo);
        let scale = DVec2::new(
            f64::from(photo.width()) / width.max(1) as f64,
            f64::from(photo.height()) / height.max(1) as f64,
        );
        PhotoInk { photo, scale }
    }

    /// The photo's colour (sRGB, 0 to 255) at the centre of picture pixel (`x`, `y`).
    #[inline]
    #[must_use]
    pub fn at(&self, x: usize, y: usize) -> [f32; 3] {
        // At the photo's own size a pixel's centre is a texel's: the texel itself, as the blend
        // gives it (its weights are 0), without the blend.
        if self.scale == DVec2::ONE {
            let (cx, cy) = (
                x.min(self.photo.width() as usize - 1),
                y.min(self.photo.height() as usize - 1),
            );
            return self.photo.get_pixel(cx as u32, cy as u32).0.map(f32::from);
        }
        let (w, h) = (
            i64::from(self.photo.width()),
            i64::from(self.photo.height()),
        );
        let tx = (x as f64 + 0.5) * self.scale.x - 0.5;
        let ty = (y as f64 + 0.5) * self.scale.y - 0.5;
        bilinear(tx, ty, |i, j| {
            let p = self
                .photo
                .get_pixel(i.clamp(0, w - 1) as u32, j.clamp(0, h - 1) as u32);
            p.0.map(f32::from)
        })
    }
}

/// The connected pieces (4-neighbours) of `mask` (`width × height`, non-zero = inked):
/// every inked pixel's piece, numbered from 0 in the order of their first pixel row by row,
/// −1 elsewhere; and the number of pieces.
#[must_use]
pub fn pieces(mask: &[i32], width: usize, height: usize) -> (Vec<i32>, usize) {
    let mut labels = vec![-1i32; width * height];
    let mut count = 0usize;
    let mut stack = Vec::new();
    for start in 0..labels.len() {
        if mask[start] == 0 || labels[start] >= 0 {
            continue;
        }
        let label = count as i32;
        count += 1;
        labels[start] = label;
        stack.push(start);
        while let Some(i) = stack.pop() {
            let (x, y) = (i % width, i / width);
            let neighbours = [
                (x > 0).then(|| i - 1),
                (x + 1 < width).then(|| i + 1),
                (y > 0).then(|| i - width),
                (y + 1 < height).then(|| i + width),
            ];
            for j in neighbours.into_iter().flatten() {
                if mask[j] != 0 && labels[j] < 0 {
                    labels[j] = label;
                    stack.push(j);
                }
            }
        }
    }
    (labels, count)
}

/// The mean photo colour (averaged in linear light, returned as sRGB bytes) over every piece
/// of `labels` (as [`pieces`] gives them), read as [`PhotoInk`] reads it.
#[must_use]
pub fn piece_colours(labels: &[i32], count: usize, ink: &PhotoInk, width: usize) -> Vec<[u8; 3]> {
    let mut sums = vec![([0.0f64; 3], 0u32); count];
    for (i, &l) in labels.iter().enumerate() {
        let Ok(l) = usize::try_from(l) else { continue };
        let c = ink
            .at(i % width, i / width)
            .map(|v| v.round().clamp(0.0, 255.0) as u8);
        let lin: Linear = linear_of(c);
        let (sum, n) = &mut sums[l];
        for k in 0..3 {
            sum[k] += f64::from(lin[k]);
        }
        *n += 1;
    }
    sums.iter()
        .map(|(sum, n)| sum.map(|s| to_srgb((s / f64::from((*n).max(1))) as f32)))
        .collect()
}

/// One ink no lighter than the photo under it ([`super::outline::draw_outlines`]): where the
/// photo is darker, the ink's colour scaled in linear light to the photo's luminance.
pub struct DarkerInk {
    ink: Linear,
    luminance: f32,
    /// The ink's sRGB luma (0 to 255) and a margin: a photo colour whose luma is above this is
    /// not darker than the ink (the luma of the encoding and the encoded luminance differ by
    /// a few levels at most for dark colours), so no power is taken there.
    luma_above: f32,
}

impl DarkerInk {
    /// The darkening of `ink` (sRGB).
    #[must_use]
    pub fn new(ink: [u8; 3]) -> Self {
        let linear = linear_of(ink);
        DarkerInk {
            ink: linear,
            luminance: crate::render::support::colour::luminance(linear),
            luma_above: luma(ink.map(f32::from)) + DARKER_MARGIN,
        }
    }

    /// The ink over a photo of colour `photo` (sRGB, 0 to 255): `None` where the photo is not
    /// darker than the ink.
    #[inline]
    #[must_use]
    pub fn under(&self, photo: [f32; 3]) -> Option<[f32; 3]> {
        use crate::field::structure::{linear_to_srgb, srgb_to_linear};
        if luma(photo) > self.luma_above || self.luminance <= 0.0 {
            return None;
        }
        let below =
            crate::render::support::colour::luminance(photo.map(|v| srgb_to_linear(v / 255.0)));
        (below < self.luminance).then(|| {
            crate::render::support::colour::darkened_to(self.ink, below)
                .map(|v| 255.0 * linear_to_srgb(v))
        })
    }
}

/// Levels of sRGB luma above the ink's within which [`DarkerInk`] compares luminances.
const DARKER_MARGIN: f32 = 24.0;

/// The sRGB luma of `c` (0 to 255).
fn luma(c: [f32; 3]) -> f32 {
    0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_photo_is_read_at_pixel_centres() {
        let photo = DynamicImage::ImageRgb8(RgbImage::from_fn(4, 2, |x, y| {
            image::Rgb([(x * 60) as u8, (y * 100) as u8, 7])
        }));
        let same = PhotoInk::new(&photo, (4, 2));
        assert_eq!(same.at(2, 1), [120.0, 100.0, 7.0]);
        // Twice the size: pixel 1's centre lies a quarter of the way from texel 0 to 1.
        let double = PhotoInk::new(&photo, (8, 4));
        assert_eq!(double.at(1, 0), [15.0, 0.0, 7.0]);
        // Clamped past the edges.
        assert_eq!(double.at(0, 0), [0.0, 0.0, 7.0]);
        assert_eq!(double.at(7, 3), [180.0, 100.0, 7.0]);
    }

    #[test]
    fn pieces_are_four_connected() {
        #[rustfmt::skip]
        let mask = [
            1, 1, 0, 1,
            0, 1, 0, 1,
            1, 0, 0, 0,
        ];
        let (labels, count) = pieces(&mask, 4, 3);
        assert_eq!(count, 3, "a diagonal touch does not join");
        #[rustfmt::skip]
        assert_eq!(labels, [
            0, 0, -1, 1,
            -1, 0, -1, 1,
            2, -1, -1, -1,
        ]);
    }

    #[test]
    fn a_piece_takes_the_mean_colour_under_it() {
        let photo = DynamicImage::ImageRgb8(RgbImage::from_fn(2, 1, |x, _| {
            if x == 0 {
                image::Rgb([200, 0, 0])
            } else {
                image::Rgb([0, 0, 200])
            }
        }));
        let ink = PhotoInk::new(&photo, (2, 1));
        let (labels, count) = pieces(&[1, 1], 2, 1);
        let [c] = piece_colours(&labels, count, &ink, 2)[..] else {
            panic!("one piece")
        };
        // The mean in linear light: brighter than the mean of the bytes.
        assert_eq!(c[1], 0);
        assert!(c[0] == c[2] && c[0] > 140 && c[0] < 160, "{c:?}");
    }
}
