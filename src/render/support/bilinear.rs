//! Bilinear reads of texel grids (photos, tone grids, node grids): the four texels round a
//! point blended across, then down.

use super::rounding::floor;

/// Bilinear interpolation at `(x, y)` in texel units (texel `(i, j)` at `(i, j)`) of the
/// texels `texel(i, j)` gives; the caller clamps or wraps indices outside the image.
#[inline]
pub(crate) fn bilinear<const N: usize>(
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
pub(crate) fn bilinear_nonnegative<const N: usize>(
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
