//! From tensors to a metric (paper sections 3 and 4): the field of ellipses the sampler packs.
//!
//! A metric `m = R diag(a, b) Rᵀ` is positive definite; its eigenvalues are the ellipse's
//! semi-axes in pixels. From a photo's structure tensor `J` (eigenvalues `λ1 ≥ λ2`):
//! - the long axis `a` lies along the edge, orthogonal to the gradient (the "orthogonal vector
//!   field");
//! - the short axis `b` (the *size*) follows detail `√(λ1 + λ2)`, the local RMS gradient, read
//!   above the photo's grain ([`GRAIN_MARGIN`]): it goes geometrically from `max_size` in flat
//!   areas to `min_size` where the detail reaches its `detail_quantile` over the photo, both
//!   sizes fractions of the image diagonal;
//! - the anisotropy `a/b` grows with coherence `(λ1 − λ2)/(λ1 + λ2)` up to `max_anisotropy`;
//! - section 3 asks that neighbouring samples differ little: the size map is limited to grow at
//!   most `gradation` pixels per pixel (so two touching ellipses differ by at most a factor of
//!   about `1 + 2·gradation`), both maps are smoothed, and finally the metric itself is smoothed
//!   with a σ proportional to each ellipse's own radius, so its orientation does not turn within
//!   one ellipse (without this last step photos' packings overlap several times more).
//!
//! General symmetric tensors (stress, with negative eigenvalues) become a metric by the
//! anti-symmetric mapping of \[HFH*04\]: eigenvectors kept, each eigenvalue λ mapped to the
//! semi-axis `s·exp(κ·tanh(λ/q))`, `q` the field's median eigenvalue magnitude (see
//! [`metric_from_general`]).

use super::blur::{gaussian_blur_parallel, gaussian_blur_parallel_mut};
use super::grid::TensorField;
use super::tensor::Tensor;
use crate::error::{Error, Result};
use rayon::prelude::*;
use std::borrow::Cow;

/// Every parameter of the photo → metric stage. Lengths are fractions of the image diagonal so
/// that the same settings give the same look at any resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct MetricParams {
    /// Short semi-axis where the photo has the most detail (fraction of the diagonal).
    pub min_size: f64,
    /// Radius of the (isotropic) ellipses in flat areas (fraction of the diagonal).
    pub max_size: f64,
    /// Largest ratio of long to short semi-axis, reached on perfectly coherent edges.
    pub max_anisotropy: f64,
    /// Pre-smoothing σ before the gradient, the noise scale (fraction of the diagonal).
    pub noise_sigma: f64,
    /// Integration σ of the structure tensor (fraction of the diagonal).
    pub integration_sigma: f64,
    /// Quantile of the detail over the photo that maps to `min_size` (0 < q ≤ 1).
    pub detail_quantile: f64,
    /// Exponent shaping detail → size: below 1 favours small cells, above 1 large ones.
    pub detail_gamma: f64,
    /// Largest growth of the size map in pixels per pixel (mesh gradation).
    pub gradation: f64,
    /// σ of the final smoothing of the size and anisotropy maps (fraction of the diagonal).
    pub smoothing: f64,
    /// σ of the final smoothing of the metric as a multiple of each ellipse's mean radius
    /// `√(ab)`, so neighbouring samples see nearly the same ellipse (0 disables it).
    pub ellipse_smoothing: f64,
    /// Longest diagonal, in pixels, of the analysis image (0: always full resolution).
    pub analysis_diagonal: usize,
}

impl Default for MetricParams {
    fn default() -> Self {
        MetricParams {
            min_size: 0.003,
            max_size: 0.02,
            max_anisotropy: 4.0,
            noise_sigma: 0.0012,
            integration_sigma: 0.004,
            detail_quantile: 0.9,
            detail_gamma: 0.7,
            gradation: 0.25,
            smoothing: 0.003,
            ellipse_smoothing: 1.25,
            analysis_diagonal: 1536,
        }
    }
}

impl MetricParams {
    /// Checks every parameter's range; the error names the parameter.
    pub fn validate(&self) -> Result<()> {
        let positive = |key: &str, v: f64| {
            if v > 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(Error::param(
                    format!("metric.{key}"),
                    format!("{v} must be positive"),
                ))
            }
        };
        for (key, v) in [("min_size", self.min_size), ("max_size", self.max_size)] {
            if !(v > 0.0 && v <= 1.0) {
                return Err(Error::param(
                    format!("metric.{key}"),
                    format!("{v} must be in (0, 1] (a fraction of the image diagonal)"),
                ));
            }
        }
        positive("detail_gamma", self.detail_gamma)?;
        positive("gradation", self.gradation)?;
        if self.min_size > self.max_size {
            return Err(Error::param(
                "metric.min_size",
                format!("{} exceeds max_size {}", self.min_size, self.max_size),
            ));
        }
        if !(self.max_anisotropy >= 1.0 && self.max_anisotropy <= 100.0) {
            return Err(Error::param(
                "metric.max_anisotropy",
                format!("{} must be in [1, 100]", self.max_anisotropy),
            ));
        }
        if !(self.detail_quantile > 0.0 && self.detail_quantile <= 1.0) {
            return Err(Error::param(
                "metric.detail_quantile",
                format!("{} must be in (0, 1]", self.detail_quantile),
            ));
        }
        for (key, v) in [
            ("noise_sigma", self.noise_sigma),
            ("integration_sigma", self.integration_sigma),
            ("smoothing", self.smoothing),
        ] {
            if !(0.0..1.0).contains(&v) {
                return Err(Error::param(
                    format!("metric.{key}"),
                    format!("{v} must be in [0, 1)"),
                ));
            }
        }
        Ok(())
    }
}

/// Grain's share of the structure tensor's trace varies from place to place about its
/// expectation ([`super::noise::noise_energy`]); at this many times the expectation it is left
/// behind everywhere but in rare specks, so detail is read above it.
pub const GRAIN_MARGIN: f64 = 3.0;

/// Detail below this RMS gradient (linear light per analysis pixel) counts as flat even in a
/// photo with no structure at all, so a flat photo gets `max_size` everywhere.
const DETAIL_FLOOR: f64 = 2e-3;

/// The metric of a photo from its structure tensor `j` (an analysis-resolution field whose
/// node spacing and domain are those of the photo). Semi-axes are in photo pixels.
#[must_use]
pub fn metric_from_structure(j: &TensorField, params: &MetricParams) -> TensorField {
    metric_from_structure_over_noise(j, 0.0, params)
}

/// [`metric_from_structure`] for a tensor whose trace holds `noise`, the photo's grain
/// ([`super::noise::noise_energy`]): the detail that sets the sizes and lets the anisotropy in
/// is the trace above what grain reaches, `√max(λ1 + λ2 − GRAIN_MARGIN·noise, 0)`, so grain
/// alone neither shrinks the ellipses nor turns them every way; the detail reference is at
/// least that of the margin, so a photo of grain alone keeps large ones.
#[must_use]
pub fn metric_from_structure_over_noise(
    j: &TensorField,
    noise: f64,
    params: &MetricParams,
) -> TensorField {
    let (cols, rows) = (j.cols(), j.rows());
    let diag = j.diagonal();
    let spacing = j.spacing();
    let eigen: Vec<_> = j
        .data()
        .par_iter()
        .map(|&c| Tensor::from_f32(c).eigen())
        .collect();
    let detail: Vec<f64> = eigen
        .par_iter()
        .map(|e| (e.l1 + e.l2 - GRAIN_MARGIN * noise).max(0.0).sqrt())
        .collect();
    // Detail within the grain's own level never reaches `min_size`: a photo of grain alone
    // (a fogged sky, a blank wall) is painted with large cells.
    let reference = quantile(&detail, params.detail_quantile)
        .max(DETAIL_FLOOR)
        .max((GRAIN_MARGIN * noise).sqrt());

    // Size (short semi-axis) in analysis pixels, geometric between max and min.
    let (max_px, min_px) = (
        params.max_size * diag / spacing,
        params.min_size * diag / spacing,
    );
    let ratio = min_px / max_px;
    let mut size: Vec<f32> = detail
        .par_iter()
        .map(|&d| {
            let t = (d / reference).clamp(0.0, 1.0).powf(params.detail_gamma);
            (max_px * ratio.powf(t)) as f32
        })
        .collect();
    limit_gradation(&mut size, cols, rows, params.gradation as f32);

    // Anisotropy: coherence, faded out where the detail (above the grain) is near the floor.
    let mut anisotropy: Vec<f32> = eigen
        .par_iter()
        .zip(&detail)
        .map(|(e, &d)| {
            let sum = e.l1 + e.l2;
            let coherence = if sum > 0.0 { (e.l1 - e.l2) / sum } else { 0.0 };
            let confidence = (d / (0.25 * reference)).clamp(0.0, 1.0);
            (1.0 + (params.max_anisotropy - 1.0) * coherence * coherence * confidence) as f32
        })
        .collect();

    let sigma = (params.smoothing * diag / spacing) as f32;
    gaussian_blur_parallel_mut(&mut size, cols, rows, 1, sigma);
    gaussian_blur_parallel_mut(&mut anisotropy, cols, rows, 1, sigma);

    let max_axis = max_px.max(min_px) * spacing;
    let data: Vec<[f32; 3]> = eigen
        .par_iter()
        .zip(size.par_iter().zip(&anisotropy))
        .map(|(e, (&b, &a_ratio))| {
            let b = f64::from(b) * spacing;
            let a = (b * f64::from(a_ratio)).min(max_axis.max(b));
            // e.angle is the gradient direction; the long axis is orthogonal to it.
            Tensor::from_eigen(e.angle + std::f64::consts::FRAC_PI_2, a, b).to_f32()
        })
        .collect();
    let data = smooth_by_size(&data, cols, rows, params.ellipse_smoothing / spacing);
    let d = j.domain();
    TensorField::with_spacing(cols, rows, spacing, (d.x, d.y), data)
}

/// Smooths a metric component-wise with a Gaussian whose σ at each node is `factor·√det m`
/// (the ellipse's mean radius, in nodes when `factor` includes 1/spacing), so that a sample's
/// neighbours see nearly the same ellipse (paper section 3). Uses a Gaussian pyramid (blur
/// σ = 1, then halve) and blends the two levels whose σ bracket the wanted one.
fn smooth_by_size(data: &[[f32; 3]], cols: usize, rows: usize, factor: f64) -> Vec<[f32; 3]> {
    if factor <= 0.0 {
        return data.to_vec();
    }
    // levels[k] = (values, width, height, σ in level-0 nodes); level 0 is `data` itself.
    let mut levels: Vec<(Cow<[f32]>, usize, usize, f64)> =
        vec![(Cow::Borrowed(data.as_flattened()), cols, rows, 0.0f64)];
    let wanted_max = data
        .par_iter()
        .map(|&c| factor * Tensor::from_f32(c).det().max(0.0).sqrt())
        .reduce(|| 0.0f64, f64::max);
    while levels
        .last()
        .is_some_and(|l| l.3 < wanted_max && l.1 > 2 && l.2 > 2)
    {
        let (prev, w, h, _) = levels.last().expect("non-empty");
        let k = levels.len() as i32 - 1;
        let blurred = gaussian_blur_parallel(prev, *w, *h, 3, 1.0);
        let (hw, hh) = (w.div_ceil(2), h.div_ceil(2));
        let mut half = vec![0.0f32; hw * hh * 3];
        half.par_chunks_mut(hw * 3)
            .enumerate()
            .for_each(|(y, row)| {
                for x in 0..hw {
                    for ch in 0..3 {
                        let mut acc = 0.0;
                        for (dy, dx) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                            let (sx, sy) = ((2 * x + dx).min(w - 1), (2 * y + dy).min(h - 1));
                            acc += blurred[(sy * w + sx) * 3 + ch];
                        }
                        row[x * 3 + ch] = 0.25 * acc;
                    }
                }
            });
        // Variance added at this level: blur σ = 1 and a 2-wide box, at scale 2^k.
        let sigma2 = 1.25 * (4f64.powi(k + 1) - 1.0) / 3.0;
        levels.push((Cow::Owned(half), hw, hh, sigma2.sqrt()));
    }
    // Where every column and row of the grid reads each level (bilinear between that level's
    // node centres, clamped): the same positions and weights for every node of a column or a
    // row, so they are found once, not at every node.
    let axis = |n: usize, level: usize, len: usize| -> Vec<Lerp> {
        // 2^−level: multiplying by it divides exactly.
        let shrink = 1.0 / f64::from(1u32 << level);
        (0..n)
            .map(|i| {
                let u = ((i as f64 + 0.5) * shrink - 0.5).clamp(0.0, (len - 1) as f64);
                let i0 = u as usize;
                (i0, (i0 + 1).min(len - 1), u - i0 as f64)
            })
            .collect()
    };
    let columns: Vec<Vec<Lerp>> = (0..levels.len())
        .map(|k| axis(cols, k, levels[k].1))
        .collect();
    let rows_at: Vec<Vec<Lerp>> = (0..levels.len())
        .map(|k| axis(rows, k, levels[k].2))
        .collect();
    let sample = |level: usize, c: usize, r: usize| -> [f64; 3] {
        let (values, w, _, _) = &levels[level];
        let (x0, x1, tx) = columns[level][c];
        let (y0, y1, ty) = rows_at[level][r];
        let at = |x: usize, y: usize, ch: usize| f64::from(values[(y * w + x) * 3 + ch]);
        [0, 1, 2].map(|ch| {
            let top = at(x0, y0, ch) + (at(x1, y0, ch) - at(x0, y0, ch)) * tx;
            let bottom = at(x0, y1, ch) + (at(x1, y1, ch) - at(x0, y1, ch)) * tx;
            top + (bottom - top) * ty
        })
    };
    let mut out = vec![[0.0f32; 3]; data.len()];
    out.par_chunks_mut(cols).enumerate().for_each(|(r, row)| {
        for (c, o) in row.iter_mut().enumerate() {
            let wanted = factor * Tensor::from_f32(data[r * cols + c]).det().max(0.0).sqrt();
            let k = levels.iter().rposition(|l| l.3 <= wanted).unwrap_or(0);
            let value = if k + 1 < levels.len() {
                let (s0, s1) = (levels[k].3, levels[k + 1].3);
                let t = ((wanted - s0) / (s1 - s0)).clamp(0.0, 1.0);
                let (a, b) = (sample(k, c, r), sample(k + 1, c, r));
                [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * t)
            } else {
                sample(k, c, r)
            };
            *o = value.map(|v| v as f32);
        }
    });
    out
}

/// Along one axis of a pyramid level: the node before a position, the node after (clamped to
/// the level) and the weight of the second.
type Lerp = (usize, usize, f64);

/// Limits the growth of `size` to `gradation` per pixel (8-neighbour chamfer distance, two
/// sweeps): afterwards `size(p) ≤ size(q) + gradation·|p − q|` for all pixels.
fn limit_gradation(size: &mut [f32], cols: usize, rows: usize, gradation: f32) {
    // Each sweep is serial (a node reads the one just relaxed before it), so its interior
    // nodes, whose four neighbours all exist, are relaxed without a bounds check per
    // neighbour; the border nodes take `relax`'s checks. The same minima either way.
    let (forward, backward) = gradation_neighbours(gradation);
    for y in 0..rows {
        sweep_row(size, cols, rows, y, false, &forward);
    }
    for y in (0..rows).rev() {
        sweep_row(size, cols, rows, y, true, &backward);
    }
}

/// The neighbours (dx, dy) a node of [`limit_gradation`]'s forward and backward sweeps reads,
/// with the growth allowed over the step to each.
type Neighbours = [(isize, isize, f32); 4];

/// [`Neighbours`] of the forward sweep (left, and the row above) and of the backward one
/// (right, and the row below), for `gradation` per pixel (8-neighbour chamfer).
fn gradation_neighbours(gradation: f32) -> (Neighbours, Neighbours) {
    let diag = gradation * std::f32::consts::SQRT_2;
    let forward = [
        (-1isize, 0isize, gradation),
        (-1, -1, diag),
        (0, -1, gradation),
        (1, -1, diag),
    ];
    (forward, forward.map(|(dx, dy, w)| (-dx, -dy, w)))
}

/// One row `y` of a [`limit_gradation`] sweep, left to right or (`reverse`) right to left.
fn sweep_row(
    size: &mut [f32],
    cols: usize,
    rows: usize,
    y: usize,
    reverse: bool,
    neighbours: &Neighbours,
) {
    // The row the sweep came from: above going forward, below going back.
    let inner_row = if reverse { y + 1 < rows } else { y > 0 };
    if !inner_row || cols < 3 {
        for k in 0..cols {
            let x = if reverse { cols - 1 - k } else { k };
            relax(size, cols, rows, x, y, neighbours);
        }
        return;
    }
    let (first, last) = if reverse {
        (cols - 1, 0)
    } else {
        (0, cols - 1)
    };
    relax(size, cols, rows, first, y, neighbours);
    let offsets = neighbours.map(|(dx, dy, w)| (dy * cols as isize + dx, w));
    let mut relax_inner = |x: usize| {
        let i = y * cols + x;
        let mut s = size[i];
        for &(off, w) in &offsets {
            let limit = size[i.wrapping_add_signed(off)] + w;
            if limit < s {
                s = limit;
            }
        }
        size[i] = s;
    };
    if reverse {
        (1..cols - 1).rev().for_each(&mut relax_inner);
    } else {
        (1..cols - 1).for_each(&mut relax_inner);
    }
    relax(size, cols, rows, last, y, neighbours);
}

fn relax(size: &mut [f32], cols: usize, rows: usize, x: usize, y: usize, neighbours: &Neighbours) {
    let i = y * cols + x;
    for &(dx, dy, w) in neighbours {
        let (nx, ny) = (x as isize + dx, y as isize + dy);
        if nx >= 0 && ny >= 0 && (nx as usize) < cols && (ny as usize) < rows {
            let limit = size[ny as usize * cols + nx as usize] + w;
            if limit < size[i] {
                size[i] = limit;
            }
        }
    }
}

/// The `q`-quantile of `values` (0 < q ≤ 1) without sorting the whole slice.
fn quantile(values: &[f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v = values.to_vec();
    let k = ((v.len() - 1) as f64 * q).round() as usize;
    let (_, kth, _) = v.select_nth_unstable_by(k, f64::total_cmp);
    *kth
}

/// Parameters of the anti-symmetric mapping of a general symmetric tensor to a metric.
#[derive(Clone, Debug, PartialEq)]
pub struct MappingParams {
    /// Base semi-axis `s` for a zero eigenvalue (fraction of the diagonal).
    pub base_size: f64,
    /// Strength `κ`: the largest eigenvalue magnitude maps to `s·e^{±κ}`.
    pub kappa: f64,
}

impl Default for MappingParams {
    fn default() -> Self {
        MappingParams {
            base_size: 0.02,
            kappa: 0.7,
        }
    }
}

/// The anti-symmetric mapping: eigenvectors kept, each eigenvalue λ mapped to the semi-axis
/// `s·exp(κ·tanh(λ/q))`, so compression (λ < 0) shrinks and tension stretches, symmetrically
/// about the base size. A zero field maps to circles of radius `s`.
///
/// `q` is the median over the field of the larger eigenvalue magnitude, not its maximum:
/// fields with point loads or singularities (stress near a load grows as 1/r) have a maximum
/// far above most of the field, and dividing by it left every ellipse but those at the loads
/// round (the eigenvalue ratio lost to normalisation). With the median, half the field maps
/// to its full anisotropy and the `tanh` keeps the peaks bounded (semi-axes within `s·e^{±κ}`).
#[must_use]
pub fn metric_from_general(field: &TensorField, params: &MappingParams) -> TensorField {
    let magnitudes: Vec<f64> = field
        .data()
        .par_iter()
        .map(|&c| {
            let e = Tensor::from_f32(c).eigen();
            e.l1.abs().max(e.l2.abs())
        })
        .filter(|m| m.is_finite())
        .collect();
    let q = if magnitudes.is_empty() {
        0.0
    } else {
        quantile(&magnitudes, 0.5)
    };
    let s = params.base_size * field.diagonal();
    let mut out = field.clone();
    out.data_mut().par_iter_mut().for_each(|c| {
        *c = Tensor::from_f32(*c)
            .map_eigenvalues(|l| {
                let t = if q > 0.0 { (l / q).tanh() } else { 0.0 };
                s * (params.kappa * t).exp()
            })
            .to_f32();
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradation_bounds_growth() {
        let (cols, rows) = (40, 30);
        let mut size = vec![100.0f32; cols * rows];
        size[15 * cols + 20] = 1.0;
        limit_gradation(&mut size, cols, rows, 0.5);
        for y in 0..rows {
            for x in 0..cols {
                let d = ((x as f32 - 20.0).powi(2) + (y as f32 - 15.0).powi(2)).sqrt();
                let s = size[y * cols + x];
                // Chamfer distance is within 8 % of the Euclidean one.
                assert!(s <= 1.0 + 0.5 * d * 1.09 + 1e-4, "{x},{y}: {s}");
                assert!(s >= 1.0 + 0.5 * d * 0.99 - 1e-4, "{x},{y}: {s}");
            }
        }
    }

    /// The unhurried sweeps: every node through `relax`'s bounds checks.
    fn checked_gradation(size: &mut [f32], cols: usize, rows: usize, gradation: f32) {
        let (forward, backward) = gradation_neighbours(gradation);
        for y in 0..rows {
            for x in 0..cols {
                relax(size, cols, rows, x, y, &forward);
            }
        }
        for y in (0..rows).rev() {
            for x in (0..cols).rev() {
                relax(size, cols, rows, x, y, &backward);
            }
        }
    }

    #[test]
    fn gradation_sweeps_match_the_checked_ones_bit_for_bit() {
        // Random sizes over grids down to one node wide or tall.
        let mut state = 0x9e37_79b9_u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32
        };
        for (cols, rows) in [(37, 23), (1, 9), (9, 1), (2, 5), (3, 3), (64, 2)] {
            let size: Vec<f32> = (0..cols * rows).map(|_| 1.0 + 40.0 * next()).collect();
            let (mut fast, mut checked) = (size.clone(), size);
            limit_gradation(&mut fast, cols, rows, 0.3);
            checked_gradation(&mut checked, cols, rows, 0.3);
            let bits = |v: &[f32]| v.iter().map(|s| s.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&fast), bits(&checked), "{cols}x{rows}");
        }
    }

    #[test]
    fn quantile_picks_the_right_element() {
        let v: Vec<f64> = (0..101).rev().map(f64::from).collect();
        assert_eq!(quantile(&v, 0.9), 90.0);
        assert_eq!(quantile(&v, 1.0), 100.0);
    }

    #[test]
    fn anti_symmetric_mapping() {
        let field = TensorField::constant(3, 4, Tensor::new(-2.0, 0.0, 1.0));
        let p = MappingParams {
            base_size: 0.1,
            kappa: 1.0,
        };
        let m = metric_from_general(&field, &p);
        let e = m.node(1, 1).eigen();
        // Every node's larger magnitude is 2: q = 2.
        let s = 0.1 * 5.0;
        assert!((e.l1 - s * (0.5f64).tanh().exp()).abs() < 1e-5);
        assert!((e.l2 - s * (-1.0f64).tanh().exp()).abs() < 1e-5);
        // The long axis is y, the direction of the larger (tensile) eigenvalue.
        assert!(e.e1().y.abs() > 0.999);
    }

    #[test]
    fn defaults_are_valid_and_bad_values_are_named() {
        MetricParams::default().validate().unwrap();
        let bad = MetricParams {
            max_anisotropy: 0.5,
            ..MetricParams::default()
        };
        let err = bad.validate().unwrap_err().to_string();
        assert!(err.contains("metric.max_anisotropy"), "{err}");
    }
}
