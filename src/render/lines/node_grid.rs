//! The structure tensor's grid as the line drawings read it (outlines, highlights): a value
//! per node computed row by row in parallel, the photo's lightness and chroma per node, the
//! tensor's major axis (the edge's normal) per node, and the bilinear reads of such a grid at
//! any point. `f32`.

use crate::field::TensorField;
use image::DynamicImage;
use rayon::prelude::*;

/// The unit major eigenvector of `t` with a non-negative x (the `cos`, `sin` of
/// [`crate::field::Tensor::eigen`]'s angle in (−π/2, π/2]), from half-angle formulas instead
/// of `atan2`, `cos` and `sin`: the cosine and sine of twice the angle are `h/r` and `b/r`
/// (`h` the half-difference of the diagonal, `b` the off-diagonal, `r = √(h² + b²)`), and each
/// half is taken on the side where it does not cancel. `(1, 0)` for an isotropic tensor, as
/// `eigen`.
pub(crate) fn major_axis(t: &crate::field::Tensor) -> [f32; 2] {
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

/// The photo's lightness (sRGB luma in [0, 1]) and its two opponent chroma channels,
/// yellow–blue `P = (R + G)/2 − B` and red–green `Q = R − G` (in [−1, 1]; Grundland and
/// Dodgson's YPQ, *Decolorize*, 2007), each averaged over every node's block of pixels.
pub(crate) fn colour_grid(photo: &DynamicImage, tensor: &TensorField) -> (Vec<f32>, [Vec<f32>; 2]) {
    let rgb = crate::render::support::colour::rgb8(photo);
    let (cols, rows) = (tensor.cols(), tensor.rows());
    let s = tensor.spacing();
    let (w, h) = (rgb.width() as usize, rgb.height() as usize);
    let nodes = per_node(cols, rows, |c, r| {
        let (x0, y0) = ((c as f64 * s) as usize, (r as f64 * s) as usize);
        let (x1, y1) = (
            (((c + 1) as f64 * s) as usize).clamp(x0 + 1, w.max(x0 + 1)),
            (((r + 1) as f64 * s) as usize).clamp(y0 + 1, h.max(y0 + 1)),
        );
        let (mut sum, mut p, mut q, mut n) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
        for y in y0..y1.min(h) {
            for x in x0..x1.min(w) {
                let i = 3 * (y * w + x);
                let [red, green, blue] = [0, 1, 2].map(|k| f32::from(rgb.as_raw()[i + k]));
                sum += 0.299 * red + 0.587 * green + 0.114 * blue;
                p += 0.5 * (red + green) - blue;
                q += red - green;
                n += 1.0;
            }
        }
        if n > 0.0 {
            [sum / n / 255.0, p / n / 255.0, q / n / 255.0]
        } else {
            [1.0, 0.0, 0.0]
        }
    });
    let channel = |k: usize| nodes.iter().map(|v| v[k]).collect::<Vec<f32>>();
    (channel(0), [channel(1), channel(2)])
}

/// `value(c, r)` at every node of a `cols × rows` grid, row-major, rows in parallel: a loop over
/// flat indices would divide twice per node to find its column and row, which cost as much as
/// the work of a light loop (the normals: 14 ms of 1 M nodes on two threads).
pub(crate) fn per_node<T: Copy + Default + Send>(
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

/// `values` (row-major `cols × rows`) at grid position `(x, y)`, bilinear, clamped at the grid's
/// edges: the same values as [`crate::render::support::bilinear::bilinear`] with clamped texel
/// indices, all in `f32`. Clamping the position instead of the four indices gives the same blend (a
/// texel blended with its clamped copy is itself), with two conversions instead of eight: the line
/// map reads tens of these per node, and they were a third of a pen-hatch paint.
#[inline]
pub(crate) fn bilinear(values: &[f32], cols: usize, rows: usize, x: f32, y: f32) -> f32 {
    blend(values, cols, clamped_axis(x, cols), clamped_axis(y, rows))
}

/// [`bilinear`] at a position already on the grid (`0 ≤ x ≤ cols − 1`, `0 ≤ y ≤ rows − 1`),
/// where its clamps change nothing: the same value without them. The across-edge taps and the
/// flow walk, which stops at the grid's edge, read the grid this way.
#[inline(always)]
pub(crate) fn bilinear_inside(values: &[f32], cols: usize, rows: usize, x: f32, y: f32) -> f32 {
    blend(values, cols, axis(x, cols), axis(y, rows))
}

/// Along one axis: a node, the next one (clamped to the grid) and the weight of the next.
pub(crate) type AxisWeights = (usize, usize, f32);

/// [`AxisWeights`] at `g`, `0 ≤ g ≤ n − 1` (or NaN, which gives node 0 and a NaN weight):
/// truncation is the floor. Through `u32` (grids are far smaller): on x86-64 an `f32` becomes
/// a `u32` in one conversion with its clamps, and back likewise, where `usize` (a `u64`) takes
/// a branchy sequence each way; the line map's 24 M reads of a 1 MP pen-hatch paint were
/// 20 ms faster.
#[inline(always)]
pub(crate) fn axis(g: f32, n: usize) -> AxisWeights {
    let i = g as u32;
    let t = g - i as f32;
    let i = i as usize;
    (i, (i + 1).min(n - 1), t)
}

/// [`axis`] at `g` clamped to the grid, as [`bilinear`] reads it.
pub(crate) fn clamped_axis(g: f32, n: usize) -> AxisWeights {
    axis(g.clamp(0.0, (n - 1) as f32), n)
}

/// `values` (row-major, `cols` wide) blended between the columns and rows of `x` and `y`.
#[inline(always)]
pub(crate) fn blend(
    values: &[f32],
    cols: usize,
    (i, i1, tx): AxisWeights,
    (j, j1, ty): AxisWeights,
) -> f32 {
    let (r0, r1) = (j * cols, j1 * cols);
    let top = values[r0 + i] + (values[r0 + i1] - values[r0 + i]) * tx;
    let bottom = values[r1 + i] + (values[r1 + i1] - values[r1 + i]) * tx;
    top + (bottom - top) * ty
}
