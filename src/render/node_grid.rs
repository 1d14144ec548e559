//! The structure tensor's grid as the line drawings read it (outlines, highlights): a value
//! per node computed row by row in parallel, the photo's lightness per node and the tensor's
//! major axis (the edge's normal) per node. `f32`.

use crate::field::TensorField;
use image::DynamicImage;
use rayon::prelude::*;

/// The unit major eigenvector of `t` with a non-negative x (the `cos`, `sin` of
/// [`crate::field::Tensor::eigen`]'s angle in (−π/2, π/2]), from half-angle formulas instead
/// of `atan2`, `cos` and `sin`: the cosine and sine of twice the angle are `h/r` and `b/r`
/// (`h` the half-difference of the diagonal, `b` the off-diagonal, `r = √(h² + b²)`), and each
/// half is taken on the side where it does not cancel. `(1, 0)` for an isotropic tensor, as
/// `eigen`.
pub(super) fn major_axis(t: &crate::field::Tensor) -> [f32; 2] {
    let (h, b) = (0.5 * (t.xx - t.yy), t.xy);
    // Scaled by the larger of the two, so that no square underflows (the angle only depends
    // on their ratio).
    let scale = h.abs().max(b.abs());
    if !(scale > 0.0 && scale.is_finite()) {
        return [1.0, 0.0];
    }
    let (h, b) = (h / scale, b / scale);
    let r = (h * h + b * b).sqrt();
    let (cos, sin) = if h >= 0.0 {
        let cos = ((r + h) / (2.0 * r)).sqrt();
        (cos, b / (2.0 * r * cos))
    } else {
        let sin = ((r - h) / (2.0 * r)).sqrt();
        // The sign of b, as atan2's ±π for b = ±0 (the angle ±π/2).
        (b.abs() / (2.0 * r * sin), sin.copysign(b))
    };
    [cos as f32, sin as f32]
}

/// The photo's lightness (sRGB luma in [0, 1]) averaged over every node's block of pixels.
pub(super) fn lightness_grid(photo: &DynamicImage, tensor: &TensorField) -> Vec<f32> {
    let rgb = super::colour::rgb8(photo);
    let (cols, rows) = (tensor.cols(), tensor.rows());
    let s = tensor.spacing();
    let (w, h) = (rgb.width() as usize, rgb.height() as usize);
    per_node(cols, rows, |c, r| {
        let (x0, y0) = ((c as f64 * s) as usize, (r as f64 * s) as usize);
        let (x1, y1) = (
            (((c + 1) as f64 * s) as usize).clamp(x0 + 1, w.max(x0 + 1)),
            (((r + 1) as f64 * s) as usize).clamp(y0 + 1, h.max(y0 + 1)),
        );
        let (mut sum, mut n) = (0.0f32, 0.0f32);
        for y in y0..y1.min(h) {
            for x in x0..x1.min(w) {
                let i = 3 * (y * w + x);
                let p = &rgb.as_raw()[i..i + 3];
                sum += 0.299 * f32::from(p[0]) + 0.587 * f32::from(p[1]) + 0.114 * f32::from(p[2]);
                n += 1.0;
            }
        }
        if n > 0.0 {
            sum / n / 255.0
        } else {
            1.0
        }
    })
}

/// `value(c, r)` at every node of a `cols × rows` grid, row-major, rows in parallel: a loop over
/// flat indices would divide twice per node to find its column and row, which cost as much as
/// the work of a light loop (the normals: 14 ms of 1 M nodes on two threads).
pub(super) fn per_node<T: Copy + Default + Send>(
    cols: usize,
    rows: usize,
    value: impl Fn(usize, usize) -> T + Sync,
) -> Vec<T> {
    let mut out = vec![T::default(); cols * rows];
    out.par_chunks_mut(cols.max(1))
        .enumerate()
        .for_each(|(r, row)| {
            for (c, v) in row.iter_mut().enumerate() {
                *v = value(c, r);
            }
        });
    out
}
