//! Colour for the looks: sRGB ↔ linear light (averages and blends happen in linear light, as
//! light adds), blends in the sRGB encoding where ink on paper is seen from afar, and a colour
//! map for fields without a photo. Linear values are `f32` in [0, 1]; encoded values are `u8`.

use crate::field::Tensor;
use image::DynamicImage;
use std::sync::OnceLock;

/// Black ink as printed: a warm near-black rather than `#000`, which reads harsh on cream
/// paper and looks like a screen, not a pen.
pub const BLACK_INK: [u8; 3] = [20, 18, 16];

/// A linear-light RGB colour.
pub type Linear = [f32; 3];

/// sRGB-encoded byte → linear light.
#[inline]
#[must_use]
pub fn to_linear(v: u8) -> f32 {
    static LUT: OnceLock<[f32; 256]> = OnceLock::new();
    LUT.get_or_init(|| {
        let mut t = [0.0; 256];
        for (i, x) in t.iter_mut().enumerate() {
            let c = i as f32 / 255.0;
            *x = if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            };
        }
        t
    })[v as usize]
}

/// Linear light → sRGB-encoded byte (rounded, clamped).
#[inline]
#[must_use]
pub fn to_srgb(v: f32) -> u8 {
    encode_table()[encode_index(v)]
}

/// The table of [`to_srgb`]: 4096 steps of linear light, finer than one code in the darks,
/// where sRGB is steepest, only for the first few codes (measured error ≤ 1 code above
/// code 5). An array in a static, so a look-up is one load after the first.
fn encode_table() -> &'static [u8; ENCODE_STEPS + 1] {
    static LUT: OnceLock<[u8; ENCODE_STEPS + 1]> = OnceLock::new();
    LUT.get_or_init(|| {
        std::array::from_fn(|i| {
            let c = i as f32 / ENCODE_STEPS as f32;
            let e = if c <= 0.003_130_8 {
                12.92 * c
            } else {
                1.055 * c.powf(1.0 / 2.4) - 0.055
            };
            (e * 255.0 + 0.5).clamp(0.0, 255.0) as u8
        })
    })
}

/// The table index of `v` (NaN and below 0 give 0, above 1 the last).
#[inline]
fn encode_index(v: f32) -> usize {
    // Scaled first, then clamped as an integer (`as i32` saturates, NaN gives 0): the same
    // index as clamping `v` to [0, 1] first.
    ((v * ENCODE_STEPS as f32 + 0.5) as i32).clamp(0, ENCODE_STEPS as i32) as usize
}

const ENCODE_STEPS: usize = 4096;

/// Relative luminance of a linear colour (Rec. 709 weights).
#[inline]
#[must_use]
pub fn luminance(c: Linear) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// `c` scaled in linear light to the luminance `y`, never above its own (black stays black):
/// how the ink looks lay their ink again over a tone darker than it (the hatchings' cells, the
/// engraving's dark tones, one-ink outlines over a darker photo).
#[inline]
#[must_use]
pub fn darkened_to(c: Linear, y: f32) -> Linear {
    let own = luminance(c);
    if own <= 0.0 {
        return c;
    }
    let k = (y / own).clamp(0.0, 1.0);
    c.map(|v| v * k)
}

/// Perceived lightness in [0, 1] (the sRGB encoding of the luminance, close to CIE L*/100):
/// what tone mapping of ink density follows.
#[inline]
#[must_use]
pub fn lightness(c: Linear) -> f32 {
    f32::from(to_srgb(luminance(c))) / 255.0
}

/// `a + (b − a)·t`, per channel.
#[inline]
#[must_use]
pub fn mix(a: Linear, b: Linear, t: f32) -> Linear {
    [
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
    ]
}

/// An sRGB byte triple as linear light.
#[must_use]
pub fn linear_of(rgb: [u8; 3]) -> Linear {
    rgb.map(to_linear)
}

/// Colours for sites without a photo: a perceptually ordered ramp (deep blue → teal → sand →
/// brick) over the anisotropy `1 − b/a` of each site's ellipse, in linear light.
#[must_use]
pub fn anisotropy_colours(metrics: &[Tensor]) -> Vec<Linear> {
    metrics.iter().map(anisotropy_colour).collect()
}

/// The ramp's colour for one ellipse: its anisotropy `1 − b/a` (0 for a degenerate tensor).
#[must_use]
pub fn anisotropy_colour(m: &Tensor) -> Linear {
    ramp(m.eigen().anisotropy() as f32)
}

/// The ramp of [`anisotropy_colours`] at `t ∈ [0, 1]`.
#[must_use]
pub fn ramp(t: f32) -> Linear {
    const STOPS: [[u8; 3]; 4] = [
        [38, 70, 133],
        [42, 157, 143],
        [233, 196, 106],
        [190, 75, 52],
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
    let i = (x as usize).min(STOPS.len() - 2);
    mix(linear_of(STOPS[i]), linear_of(STOPS[i + 1]), x - i as f32)
}

/// `photo` as 8-bit sRGB: borrowed when it already is, converted once otherwise.
#[must_use]
pub fn rgb8(photo: &DynamicImage) -> std::borrow::Cow<'_, image::RgbImage> {
    match photo.as_rgb8() {
        Some(rgb) => std::borrow::Cow::Borrowed(rgb),
        None => std::borrow::Cow::Owned(photo.to_rgb8()),
    }
}

/// `a + (b − a)·t` in the sRGB encoding, `a` given [`encoded`]: ink covering a share `t` of a
/// pixel reads as that share of the way from paper to ink in lightness, as ink on paper
/// averages at a distance and as SVG viewers blend (in linear light every partly inked pixel of
/// a fine hatch comes out far lighter than its share of ink, and dark tones never get dark).
pub(crate) fn mix_encoded(a: [f32; 3], b: Linear, t: f32) -> Linear {
    let b = encoded(b);
    std::array::from_fn(|k| {
        let e = a[k] + (b[k] - a[k]) * t;
        // Round half up of a value in [0, 255] (no libm call; the same as `round` there).
        to_linear((e.clamp(0.0, 255.0) + 0.5) as u8)
    })
}

/// A linear colour's sRGB codes, as `f32`.
pub(crate) fn encoded(c: Linear) -> [f32; 3] {
    c.map(|v| f32::from(to_srgb(v)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trip() {
        for v in 0..=255u8 {
            let back = to_srgb(to_linear(v));
            assert!(
                (i32::from(back) - i32::from(v)).abs() <= i32::from(v < 6),
                "{v} -> {back}"
            );
        }
        assert_eq!(to_srgb(-1.0), 0);
        assert_eq!(to_srgb(2.0), 255);
        assert_eq!(to_srgb(f32::NAN), 0);
    }

    #[test]
    fn encode_index_is_the_clamped_scaled_value() {
        let reference = |v: f32| (v.clamp(0.0, 1.0) * ENCODE_STEPS as f32 + 0.5) as usize;
        let mut values: Vec<f32> = (-5000..=1_100_000).map(|i| i as f32 / 1e6).collect();
        values.extend([
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e30,
            -1e30,
            -0.0,
        ]);
        for v in values {
            assert_eq!(encode_index(v), reference(v), "{v}");
        }
    }
}
