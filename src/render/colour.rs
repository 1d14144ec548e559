//! Colour for the looks: sRGB ↔ linear light (averages and blends happen in linear light, as
//! light adds), the cells' mean photo colours (paper section 6: a cell filled with the colour
//! of the photo under it), and a colour map for fields without a photo. Linear values are
//! `f32` in [0, 1]; encoded values are `u8`.

use super::rounding::floor;
use super::sums::pixel_sums;
use super::voronoi::VoronoiCells;
use crate::field::Tensor;
use image::DynamicImage;
use std::sync::OnceLock;

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

/// Mean colour of the photo over every cell, in linear light. The photo is read at its own
/// resolution (the domain of the sites is the photo's pixel grid), summed by
/// [`pixel_sums`]. A cell that receives no pixel takes the photo's colour at its site.
#[must_use]
pub fn cell_means(cells: &VoronoiCells, photo: &DynamicImage) -> Vec<Linear> {
    let rgb = rgb8(photo);
    let sums = pixel_sums(
        cells,
        rgb.width() as usize,
        rgb.height() as usize,
        2,
        |x, y| {
            let [r, g, b] = rgb.get_pixel(x as u32, y as u32).0.map(to_linear);
            [f64::from(r), f64::from(g), f64::from(b), 1.0]
        },
    );
    means_of(&sums, cells, &rgb)
}

/// Mean colours from per-cell sums whose first four entries are the linear colour sums and
/// the pixel count; a cell without pixels takes the photo's colour at its site.
fn means_of<const N: usize>(
    sums: &[[f64; N]],
    cells: &VoronoiCells,
    rgb: &image::RgbImage,
) -> Vec<Linear> {
    let (pw, ph) = (rgb.width() as usize, rgb.height() as usize);
    sums.iter()
        .zip(cells.positions())
        .map(|(s, p)| {
            if s[3] > 0.0 {
                [s[0] / s[3], s[1] / s[3], s[2] / s[3]].map(|v| v as f32)
            } else {
                let x = (p.x as usize).min(pw - 1) as u32;
                let y = (p.y as usize).min(ph - 1) as u32;
                linear_of(rgb.get_pixel(x, y).0)
            }
        })
        .collect()
}

/// [`cell_means`], and every cell's width across its narrowest direction in domain units,
/// `√(12 λ_min)` of its pixels' position covariance (exact for a strip; a cell without pixels
/// gets 0).
#[must_use]
pub fn cell_means_and_widths(
    cells: &VoronoiCells,
    photo: &DynamicImage,
) -> (Vec<Linear>, Vec<f64>) {
    let rgb = rgb8(photo);
    let (pw, ph) = (rgb.width() as usize, rgb.height() as usize);
    let sums = pixel_sums(cells, pw, ph, 2, |x, y| {
        let [r, g, b] = rgb.get_pixel(x as u32, y as u32).0.map(to_linear);
        let (u, v) = (x as f64 + 0.5, y as f64 + 0.5);
        [
            f64::from(r),
            f64::from(g),
            f64::from(b),
            1.0,
            u,
            v,
            u * u,
            u * v,
            v * v,
        ]
    });
    let widths = sums
        .iter()
        .map(|s| {
            if s[3] <= 0.0 {
                return 0.0;
            }
            let n = s[3];
            let (mu, mv) = (s[4] / n, s[5] / n);
            let (cuu, cuv, cvv) = (s[6] / n - mu * mu, s[7] / n - mu * mv, s[8] / n - mv * mv);
            let half_trace = 0.5 * (cuu + cvv);
            let least = half_trace - (0.25 * (cuu - cvv).powi(2) + cuv * cuv).sqrt();
            (12.0 * least.max(0.0)).sqrt()
        })
        .collect();
    (means_of(&sums, cells, &rgb), widths)
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

/// Salts of [`site_hash`]: every per-cell (or per-pixel) random choice of the looks has its
/// own, so that two choices about one cell are independent and no look's pattern repeats
/// another's. The values are arbitrary but fixed: changing one changes the pictures.
pub mod salt {
    /// Stipple dot position inside its grid cell (x and y) and its order among its
    /// neighbours (which lies above), cut from one word.
    pub const STIPPLE: u64 = 2;
    /// Phase of a stroke texture's bristle streaks along the cell.
    pub const STROKE_PHASE: u64 = 4;
    /// Brightness of one bristle streak of a stroke texture.
    pub const STROKE_BRISTLE: u64 = 5;
    /// Brightness of one bristle of a brush glyph.
    pub const GLYPH_BRISTLE: u64 = 6;
    /// Brightness change of a mosaic cell (`look.jitter`).
    pub const MOSAIC_JITTER: u64 = 7;
    /// The white noise of the LIC look, per pixel.
    pub const LIC_NOISE: u64 = 11;
    /// Brightness of a fabric thread dot; the axis (0 or 1) is added.
    pub const FABRIC_THREAD: u64 = 12;
    /// Lightness, red, green and blue of a pointillist dot (16 bits each of one word).
    pub const DOT_COLOUR: u64 = 16;
    /// The turn of a brush stroke in a flat area from the flat angle.
    pub const FLAT_STROKE: u64 = 17;
}

/// Knuth's multiplicative hash constant (2³² / φ): spreads consecutive integers over `u32`
/// before they are combined with a site index.
pub const GOLDEN_U32: u32 = 2_654_435_761;

/// A small deterministic hash of a site index to [0, 1) (SplitMix64 finaliser).
#[inline]
#[must_use]
pub fn site_hash(site: u32, salt: u64) -> f32 {
    // The top 24 bits, exact in an f32. Through `u32`: on x86-64 a `u64` becomes a float in a
    // branchy sequence, a `u32` in one instruction (dot centres hash twice per lattice cell
    // at every stippled pixel).
    (site_bits(site, salt) >> 40) as u32 as f32 / (1u32 << 24) as f32
}

/// The 64 bits [`site_hash`] takes its top 24 from: per-pixel code that needs several
/// independent values (a pointillist dab's four) cuts them from one word.
#[inline]
#[must_use]
pub fn site_bits(site: u32, salt: u64) -> u64 {
    let mut z = u64::from(site)
        .wrapping_add(salt.wrapping_mul(0x9E37_79B9_7F4A_7C15))
        .wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// `photo` as 8-bit sRGB: borrowed when it already is, converted once otherwise.
#[must_use]
pub fn rgb8(photo: &DynamicImage) -> std::borrow::Cow<'_, image::RgbImage> {
    match photo.as_rgb8() {
        Some(rgb) => std::borrow::Cow::Borrowed(rgb),
        None => std::borrow::Cow::Owned(photo.to_rgb8()),
    }
}

/// Bilinear interpolation at `(x, y)` in texel units (texel `(i, j)` at `(i, j)`) of the
/// texels `texel(i, j)` gives; the caller clamps or wraps indices outside the image.
#[inline]
pub(super) fn bilinear<const N: usize>(
    x: f64,
    y: f64,
    texel: impl Fn(i64, i64) -> [f32; N],
) -> [f32; N] {
    let (x0, y0) = (floor(x), floor(y));
    let (tx, ty) = ((x - x0) as f32, (y - y0) as f32);
    blend_texels((x0 as i64, y0 as i64), (tx, ty), texel)
}

/// [`bilinear`] at a point with `x`, `y` ≥ 0 (one clamped to the texel centres): the floor is
/// the integer part, found without [`floor`]'s compare (the same values; the 12 MP
/// pointillist reads the photo under its dabs so at every point, 4 % faster).
#[inline]
pub(super) fn bilinear_nonnegative<const N: usize>(
    x: f64,
    y: f64,
    texel: impl Fn(i64, i64) -> [f32; N],
) -> [f32; N] {
    let (i, j) = (x as i64, y as i64);
    let (tx, ty) = ((x - i as f64) as f32, (y - j as f64) as f32);
    blend_texels((i, j), (tx, ty), texel)
}

/// The texels round `(i, j)` blended across by `tx`, then down by `ty`.
#[inline]
fn blend_texels<const N: usize>(
    (i, j): (i64, i64),
    (tx, ty): (f32, f32),
    texel: impl Fn(i64, i64) -> [f32; N],
) -> [f32; N] {
    let lerp = |a: [f32; N], b: [f32; N], t: f32| std::array::from_fn(|k| a[k] + (b[k] - a[k]) * t);
    let top = lerp(texel(i, j), texel(i + 1, j), tx);
    let bottom = lerp(texel(i, j + 1), texel(i + 1, j + 1), tx);
    lerp(top, bottom, ty)
}

/// `a + (b − a)·t` in the sRGB encoding, `a` given [`encoded`]: ink covering a share `t` of a
/// pixel reads as that share of the way from paper to ink in lightness, as ink on paper
/// averages at a distance and as SVG viewers blend (in linear light every partly inked pixel of
/// a fine hatch comes out far lighter than its share of ink, and dark tones never get dark).
pub(super) fn mix_encoded(a: [f32; 3], b: Linear, t: f32) -> Linear {
    let b = encoded(b);
    std::array::from_fn(|k| {
        let e = a[k] + (b[k] - a[k]) * t;
        // Round half up of a value in [0, 255] (no libm call; the same as `round` there).
        to_linear((e.clamp(0.0, 255.0) + 0.5) as u8)
    })
}

/// A linear colour's sRGB codes, as `f32`.
pub(super) fn encoded(c: Linear) -> [f32; 3] {
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
    fn hash_is_spread() {
        let mean: f32 = (0..10_000).map(|i| site_hash(i, 3)).sum::<f32>() / 10_000.0;
        assert!((mean - 0.5).abs() < 0.02);
        assert_ne!(site_hash(1, 0), site_hash(1, 1));
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
