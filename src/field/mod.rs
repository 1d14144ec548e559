//! The first stage: any input becomes a metric, the field of ellipses the sampler packs
//! (paper sections 3 and 4).
//!
//! - [`tensor`]: the symmetric 2x2 tensor and its eigen-decomposition;
//! - [`grid`]: a tensor field on a regular grid with bilinear interpolation;
//! - [`blur`]: the parallel Gaussian blur behind the structure tensor;
//! - [`structure`]: the colour structure tensor of a photo at analysis resolution;
//! - [`metric`]: structure tensor → metric, and the anti-symmetric mapping of general tensors;
//! - [`analytic`]: named analytic fields.
//!
//! [`photo_metric`] ties them together for a photo; [`crate::input`] reads files and names
//! into fields.

pub mod analytic;
pub mod blur;
pub mod grid;
pub mod metric;
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
#[must_use]
pub fn photo_metric(photo: &DynamicImage, params: &MetricParams) -> (TensorField, TensorField) {
    let raw = photo_structure_tensor(photo, params);
    let metric = metric::metric_from_structure(&raw, params);
    (raw, metric)
}

/// The structure tensor of `photo` at analysis resolution, as a field over the photo's pixels.
#[must_use]
pub fn photo_structure_tensor(photo: &DynamicImage, params: &MetricParams) -> TensorField {
    let (w, h) = (photo.width() as usize, photo.height() as usize);
    let factor = structure::analysis_factor(w, h, params.analysis_diagonal);
    let lin = structure::linear_analysis_image(photo, factor);
    let diag = ((lin.width * lin.width + lin.height * lin.height) as f64).sqrt();
    let (cols, rows) = (lin.width, lin.height);
    let j = structure::structure_tensor(
        lin,
        (params.noise_sigma * diag) as f32,
        (params.integration_sigma * diag) as f32,
    );
    TensorField::with_spacing(cols, rows, factor as f64, (w as f64, h as f64), j)
}
