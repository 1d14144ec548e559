//! The first stage: any input becomes a metric, the field of ellipses the sampler packs
//! (paper sections 3 and 4).
//!
//! - [`tensor`]: the symmetric 2x2 tensor and its eigen-decomposition;
//! - [`grid`]: a tensor field on a regular grid with bilinear interpolation;
//! - [`blur`]: the parallel Gaussian blur behind the structure tensor;
//! - [`structure`]: the colour structure tensor of a photo at analysis resolution;
//! - [`noise`]: the photo's grain and the trace it adds to that tensor;
//! - [`metric`]: structure tensor → metric, and the anti-symmetric mapping of general tensors;
//! - [`analytic`]: named analytic fields.
//!
//! [`photo_metric`] ties them together for a photo; [`crate::input`] reads files and names
//! into fields.

pub mod analytic;
pub mod blur;
pub mod grid;
pub mod metric;
pub mod noise;
pub mod structure;
pub mod tensor;

pub use analytic::AnalyticField;
pub use grid::TensorField;
pub use metric::{MappingParams, MetricParams};
pub use tensor::{Eigen, Tensor};

use image::DynamicImage;
use structure::{linear_to_srgb, srgb_to_linear};

/// The photo as the renderers read it: 8-bit RGB or grey. Transparency is composited over
/// white paper (as the structure tensor sees it, see [`structure::linear_analysis_image`]),
/// so a transparent background paints as paper, not as whatever colour hides under alpha 0;
/// 16-bit and float photos are rounded to 8 bits (the metric was already computed from the
/// full-depth photo).
#[must_use]
pub fn flatten_on_paper(photo: DynamicImage) -> DynamicImage {
    match photo {
        DynamicImage::ImageRgb8(_) | DynamicImage::ImageLuma8(_) => photo,
        DynamicImage::ImageLuma16(_) => DynamicImage::ImageLuma8(photo.to_luma8()),
        other if !other.color().has_alpha() => DynamicImage::ImageRgb8(other.to_rgb8()),
        other => {
            let rgba = other.to_rgba32f();
            let over_white = |v: f32, a: f32| {
                // Composited in linear light, like the analysis image.
                let lin = srgb_to_linear(v.clamp(0.0, 1.0)) * a + (1.0 - a);
                (linear_to_srgb(lin) * 255.0).round() as u8
            };
            let rgb = image::RgbImage::from_fn(rgba.width(), rgba.height(), |x, y| {
                let [r, g, b, a] = rgba.get_pixel(x, y).0;
                let a = a.clamp(0.0, 1.0);
                image::Rgb([over_white(r, a), over_white(g, a), over_white(b, a)])
            });
            DynamicImage::ImageRgb8(rgb)
        }
    }
}

/// The structure tensor of `photo` and the metric derived from it (`params` must be valid).
///
/// The metric is made on a grid [`metric_step`] times coarser than the analysis resolution,
/// and so is the tensor's integration: the gradient products (pre-smoothed, at analysis
/// resolution) are box-averaged over blocks of that many nodes and integrated there, with
/// the Gaussian's σ less the blocks' own spread. The integrating Gaussian's σ is at least
/// twice the block, so the integrated tensor is band-limited at the coarse grid (its spectrum
/// at the coarse Nyquist frequency is below 1e-8): integrating the block means instead of
/// every node moves it by about 1 % of the largest trace at most (more in the last rows, where
/// each grid extends its own edge nodes) and the ellipses by about as much (tested against the
/// integration at analysis resolution), for a quarter of the nodes or fewer and a kernel half
/// as long; every step of the metric (eigen-decomposition, sizes, gradation, smoothing) works
/// on that grid too. The tensor returned is at analysis resolution (the outlines draw on its grid),
/// read bilinearly from the coarse one. The metric reads only the detail above the photo's
/// grain ([`noise`]).
#[must_use]
pub fn photo_metric(photo: &DynamicImage, params: &MetricParams) -> (TensorField, TensorField) {
    let (raw, coarse, noise) = structure_and_noise(photo, params);
    let metric =
        metric::metric_from_structure_over_noise(coarse.as_ref().unwrap_or(&raw), noise, params);
    (raw, metric)
}

/// How many structure-tensor nodes per side a node of the metric's grid spans: the largest
/// block no wider than half the integration σ (at least 1).
#[must_use]
pub fn metric_step(tensor: &TensorField, params: &MetricParams) -> usize {
    let sigma_nodes = params.integration_sigma * tensor.diagonal() / tensor.spacing();
    ((sigma_nodes / 2.0).floor() as usize).max(1)
}

/// The structure tensor of `photo` at analysis resolution, as a field over the photo's pixels.
#[must_use]
pub fn photo_structure_tensor(photo: &DynamicImage, params: &MetricParams) -> TensorField {
    structure_and_noise(photo, params).0
}

/// [`photo_structure_tensor`], the same tensor on the metric's grid when that is coarser
/// ([`photo_metric`]), and the trace the photo's noise adds ([`noise::noise_energy`]).
fn structure_and_noise(
    photo: &DynamicImage,
    params: &MetricParams,
) -> (TensorField, Option<TensorField>, f64) {
    let (w, h) = (photo.width() as usize, photo.height() as usize);
    let factor = structure::analysis_factor(w, h, params.analysis_diagonal);
    let lin = structure::linear_analysis_image(photo, factor);
    let diag = ((lin.width * lin.width + lin.height * lin.height) as f64).sqrt();
    let (cols, rows) = (lin.width, lin.height);
    let pre_smoothing = (params.noise_sigma * diag) as f32;
    let noise = noise::noise_energy(&lin, pre_smoothing);
    let sigma = (params.integration_sigma * diag) as f32;
    let products = structure::structure_tensor(lin, pre_smoothing, 0.0);
    let mut field =
        TensorField::with_spacing(cols, rows, factor as f64, (w as f64, h as f64), products);
    let step = metric_step(&field, params);
    if step == 1 {
        blur::gaussian_blur_parallel_mut(field.data_mut().as_flattened_mut(), cols, rows, 3, sigma);
        return (field, None, noise);
    }
    let mut coarse = field.coarsened(step);
    drop(field);
    // A block of `step` nodes spreads them by a variance of (step² − 1)/12 nodes²; the
    // Gaussian adds the rest of σ², in coarse nodes.
    let spread = (step * step - 1) as f32 / 12.0;
    let coarse_sigma = (sigma * sigma - spread).max(0.0).sqrt() / step as f32;
    let (cc, cr) = (coarse.cols(), coarse.rows());
    blur::gaussian_blur_parallel_mut(
        coarse.data_mut().as_flattened_mut(),
        cc,
        cr,
        3,
        coarse_sigma,
    );
    let raw = coarse.sampled_on(cols, rows, factor as f64);
    (raw, Some(coarse), noise)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// A 1200 × 800 synthetic photo (diagonal under the analysis limit, so the tensor is at full
    /// resolution and its integration σ spans about 5.8 pixels): a disc, a band of stripes
    /// turning with x, and a soft vertical ramp.
    fn synthetic_photo() -> DynamicImage {
        let img = image::RgbImage::from_fn(1200, 800, |x, y| {
            let (fx, fy) = (f64::from(x), f64::from(y));
            let disc = (fx - 350.0).hypot(fy - 400.0) < 180.0;
            let angle = fx / 1200.0 * 1.5;
            let stripes = fx > 650.0 && ((fx * angle.cos() + fy * angle.sin()) / 9.0).sin() > 0.0;
            let ramp = (fy / 800.0 * 120.0) as u8;
            let v = if disc {
                230
            } else if stripes {
                40
            } else {
                60 + ramp
            };
            image::Rgb([v, v.saturating_sub(20), v / 2])
        });
        DynamicImage::ImageRgb8(img)
    }

    /// How far ellipse `a` is from the truth `b`: the relative difference of their mean
    /// radii, and the angle between their long axes in degrees where `b` is clearly elongated
    /// (elsewhere the angle means nothing).
    fn ellipse_difference(a: Tensor, b: Tensor) -> (f64, Option<f64>) {
        let size = (a.det().sqrt() / b.det().sqrt() - 1.0).abs();
        let (ea, eb) = (a.eigen(), b.eigen());
        let angle = (eb.l2 < 0.6 * eb.l1).then(|| {
            let d = (ea.angle - eb.angle).abs() % std::f64::consts::PI;
            d.min(std::f64::consts::PI - d).to_degrees()
        });
        (size, angle)
    }

    #[test]
    fn integrating_on_the_coarse_grid_gives_the_metric_of_the_full_resolution_integration() {
        let photo = synthetic_photo();
        let params = MetricParams::default();
        let (raw, metric) = photo_metric(&photo, &params);
        assert_eq!(metric_step(&raw, &params), 2);
        // The truth: the products integrated at every node of the analysis grid, and the
        // metric made from them box-averaged onto the metric's grid.
        let lin = structure::linear_analysis_image(&photo, 1);
        let diag = ((lin.width * lin.width + lin.height * lin.height) as f64).sqrt();
        let pre = (params.noise_sigma * diag) as f32;
        let noise = noise::noise_energy(&lin, pre);
        let sigma = (params.integration_sigma * diag) as f32;
        let truth = structure::structure_tensor(lin, pre, sigma);
        let truth = TensorField::with_spacing(1200, 800, 1.0, (1200.0, 800.0), truth);
        let truth_metric =
            metric::metric_from_structure_over_noise(&truth.coarsened(2), noise, &params);

        // The tensor, away from the borders (where each grid extends its own edge nodes),
        // within 2 % of the largest trace.
        let largest = truth.data().iter().map(|t| t[0] + t[2]).fold(0.0, f32::max);
        let margin = (3.0 * sigma).ceil() as usize;
        let mut worst = 0.0f32;
        for y in margin..800 - margin {
            for x in margin..1200 - margin {
                let (a, b) = (raw.node(x, y), truth.node(x, y));
                let d = [a.xx - b.xx, a.xy - b.xy, a.yy - b.yy].map(f64::abs);
                worst = worst.max((d[0].max(d[1]).max(d[2]) / f64::from(largest)) as f32);
            }
        }
        assert!(
            worst < 0.02,
            "tensor differs by {worst} of the largest trace"
        );

        // The metric everywhere: ellipse sizes and long axes.
        let (mut worst_size, mut mean_size, mut worst_angle) = (0.0f64, 0.0f64, 0.0f64);
        for (a, b) in metric.data().iter().zip(truth_metric.data()) {
            let (size, angle) = ellipse_difference(Tensor::from_f32(*a), Tensor::from_f32(*b));
            worst_size = worst_size.max(size);
            mean_size += size / metric.data().len() as f64;
            worst_angle = worst_angle.max(angle.unwrap_or(0.0));
        }
        // Measured: 1.1 % (tensor), 1.3 % worst and 0.06 % mean (sizes), 2.5° (axes).
        assert!(worst_size < 0.03, "mean radius differs by {worst_size}");
        assert!(
            mean_size < 0.003,
            "mean radius differs by {mean_size} on average"
        );
        assert!(worst_angle < 5.0, "long axis turns by {worst_angle}°");
    }

    #[test]
    fn the_metric_on_the_coarse_grid_is_the_full_resolution_metric() {
        let photo = synthetic_photo();
        let params = MetricParams::default();
        let (raw, coarse) = photo_metric(&photo, &params);
        assert_eq!(metric_step(&raw, &params), 2);
        assert_eq!(coarse.spacing(), 2.0 * raw.spacing());

        // The truth: every step of the metric on the tensor's own grid.
        let full = metric::metric_from_structure(&raw, &params);
        let (mut worst_size, mut worst_angle) = (0.0f64, 0.0f64);
        for y in (20..780).step_by(7) {
            for x in (20..1180).step_by(7) {
                let p = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
                let (size, angle) = ellipse_difference(coarse.sample(p), full.sample(p));
                worst_size = worst_size.max(size);
                worst_angle = worst_angle.max(angle.unwrap_or(0.0));
            }
        }
        assert!(worst_size < 0.05, "mean radius differs by {worst_size}");
        // Measured: 3.5 % and 0.5°; a grid of five tensor nodes per metric node (σ of 1.2 of
        // its nodes) gives 12 % and 5.9°.
        assert!(worst_angle < 2.0, "long axis turns by {worst_angle}°");
    }
}
