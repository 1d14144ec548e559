//! Previews for people. Of a metric field: `Ellipses` draws the metric's ellipses at their true
//! size on a regular grid over the faded photo (paper Figure 5b's "samples at grid positions");
//! `Orientation` colours every pixel by the direction of the long axis (hue, axial so θ and
//! θ + 180° agree) and its anisotropy `1 − b/a` (saturation), over the photo's luminance.
//! Of a sampling: [`ellipses_preview`] draws each sample's ellipse over the faded photo.

use super::support::colour::{ramp, to_srgb};
use crate::field::{Tensor, TensorField};
use glam::DVec2;
use image::{DynamicImage, RgbaImage};
use rayon::prelude::*;
use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};

/// Which picture [`field_preview`] draws.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PreviewMode {
    /// A grid of the metric's ellipses over the faded photo.
    #[default]
    Ellipses,
    /// Long-axis direction as hue, anisotropy as saturation.
    Orientation,
}

/// A `width × height` preview of `metric` (domain scaled to the picture) over `photo`.
#[must_use]
pub fn field_preview(
    metric: &TensorField,
    photo: Option<&DynamicImage>,
    mode: PreviewMode,
) -> RgbaImage {
    let domain = metric.domain();
    let (w, h) = (
        domain.x.round().max(1.0) as u32,
        domain.y.round().max(1.0) as u32,
    );
    let backdrop = luminance_backdrop(photo, w, h);
    match mode {
        PreviewMode::Ellipses => ellipse_grid(metric, &backdrop, w, h),
        PreviewMode::Orientation => orientation_map(metric, &backdrop, w, h),
    }
}

/// The photo's luminance in `[0, 1]` per output pixel (white without a photo).
fn luminance_backdrop(photo: Option<&DynamicImage>, w: u32, h: u32) -> Vec<f32> {
    match photo {
        Some(p) if p.width() == w && p.height() == h => p
            .to_luma8()
            .into_raw()
            .into_iter()
            .map(|v| f32::from(v) / 255.0)
            .collect(),
        _ => vec![1.0; (w * h) as usize],
    }
}

fn ellipse_grid(metric: &TensorField, backdrop: &[f32], w: u32, h: u32) -> RgbaImage {
    let spacing = grid_spacing(metric);
    let (cols, rows) = (
        (f64::from(w) / spacing).floor().max(1.0) as usize,
        (f64::from(h) / spacing).floor().max(1.0) as usize,
    );
    let offset = DVec2::new(
        (f64::from(w) - (cols - 1) as f64 * spacing) / 2.0,
        (f64::from(h) - (rows - 1) as f64 * spacing) / 2.0,
    );
    let centres: Vec<DVec2> = (0..rows)
        .flat_map(|r| (0..cols).map(move |c| offset + DVec2::new(c as f64, r as f64) * spacing))
        .collect();
    let metrics: Vec<Tensor> = centres.iter().map(|&p| metric.sample(p)).collect();
    draw_ellipses(backdrop, w, h, &centres, &metrics)
}

/// Each sample's ellipse `{p + m·u : |u| = 1}` over the faded photo, `width × height` pixels.
#[must_use]
pub fn ellipses_preview(
    positions: &[DVec2],
    metrics: &[Tensor],
    photo: Option<&DynamicImage>,
    width: u32,
    height: u32,
) -> RgbaImage {
    let backdrop = luminance_backdrop(photo, width.max(1), height.max(1));
    draw_ellipses(&backdrop, width.max(1), height.max(1), positions, metrics)
}

/// Ellipses filled by anisotropy colour and outlined, anti-aliased, over a faded backdrop.
fn draw_ellipses(
    backdrop: &[f32],
    w: u32,
    h: u32,
    centres: &[DVec2],
    metrics: &[Tensor],
) -> RgbaImage {
    let mut pixmap = Pixmap::new(w, h).expect("preview size is non-zero");
    for (px, &l) in pixmap.data_mut().chunks_exact_mut(4).zip(backdrop) {
        // Fade towards white so the ellipses read clearly.
        let v = (255.0 * (0.55 + 0.45 * l)) as u8;
        px.copy_from_slice(&[v, v, v, 255]);
    }
    // tiny-skia paints anti-aliased by default.
    let mut fill = Paint::default();
    let mut line = Paint::default();
    line.set_color(Color::from_rgba8(20, 30, 60, 230));
    let stroke = Stroke {
        width: 1.0,
        ..Stroke::default()
    };
    for (p, m) in centres.iter().zip(metrics) {
        let e = m.eigen();
        if !(e.l2 > 0.0 && e.l1.is_finite()) {
            continue;
        }
        let Some(rect) = Rect::from_xywh(
            -e.l1 as f32,
            -e.l2 as f32,
            2.0 * e.l1 as f32,
            2.0 * e.l2 as f32,
        ) else {
            continue;
        };
        let Some(path) = PathBuilder::from_oval(rect) else {
            continue;
        };
        let t = Transform::from_rotate(e.angle.to_degrees() as f32)
            .post_translate(p.x as f32, p.y as f32);
        let [cr, cg, cb] = ramp(e.anisotropy() as f32).map(to_srgb);
        fill.set_color(Color::from_rgba8(cr, cg, cb, 140));
        pixmap.fill_path(&path, &fill, FillRule::Winding, t, None);
        pixmap.stroke_path(&path, &line, &stroke, t, None);
    }
    RgbaImage::from_raw(w, h, pixmap.take()).expect("pixmap holds w·h RGBA pixels")
}

/// Grid spacing: twice the median long semi-axis, at least 6 px.
fn grid_spacing(metric: &TensorField) -> f64 {
    let mut axes: Vec<f64> = metric
        .data()
        .iter()
        .step_by((metric.data().len() / 4096).max(1))
        .map(|&c| Tensor::from_f32(c).eigen().l1.abs())
        .filter(|v| v.is_finite())
        .collect();
    if axes.is_empty() {
        return 6.0;
    }
    let mid = axes.len() / 2;
    let (_, median, _) = axes.select_nth_unstable_by(mid, f64::total_cmp);
    (2.0 * *median).max(6.0)
}

fn orientation_map(metric: &TensorField, backdrop: &[f32], w: u32, h: u32) -> RgbaImage {
    let mut out = vec![0u8; (w * h * 4) as usize];
    let scale = metric.domain() / DVec2::new(f64::from(w), f64::from(h));
    out.par_chunks_mut(w as usize * 4)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, px) in row.chunks_exact_mut(4).enumerate() {
                let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5) * scale;
                let e = metric.sample(p).eigen();
                let anisotropy = e.anisotropy();
                // Axial hue: 2θ covers the colour wheel once per half turn.
                let hue = (2.0 * e.angle).rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU;
                let value = 0.45 + 0.55 * f64::from(backdrop[y * w as usize + x]);
                let [r, g, b] = hsv_to_rgb(hue, anisotropy, value);
                px.copy_from_slice(&[r, g, b, 255]);
            }
        });
    RgbaImage::from_raw(w, h, out).expect("buffer holds w·h RGBA pixels")
}

/// HSV (all in `[0, 1]`) to 8-bit RGB.
fn hsv_to_rgb(h: f64, s: f64, v: f64) -> [u8; 3] {
    let h6 = (h.fract() * 6.0).clamp(0.0, 6.0);
    let i = h6.floor();
    let f = h6 - i;
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f)));
    let (r, g, b) = match i as u32 % 6 {
        0 => (v, t, p),
        1 => (q, v, p),
        2 => (p, v, t),
        3 => (p, q, v),
        4 => (t, p, v),
        _ => (v, p, q),
    };
    let to8 = |c: f64| (c * 255.0).round().clamp(0.0, 255.0) as u8;
    [to8(r), to8(g), to8(b)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hsv_primaries() {
        assert_eq!(hsv_to_rgb(0.0, 1.0, 1.0), [255, 0, 0]);
        assert_eq!(hsv_to_rgb(1.0 / 3.0, 1.0, 1.0), [0, 255, 0]);
        assert_eq!(hsv_to_rgb(0.5, 0.0, 0.5), [128, 128, 128]);
    }

    #[test]
    fn orientation_map_is_grey_where_isotropic() {
        let m = TensorField::constant(5, 4, Tensor::isotropic(3.0));
        let img = field_preview(&m, None, PreviewMode::Orientation);
        assert_eq!(img.dimensions(), (5, 4));
        let p = img.get_pixel(2, 2).0;
        assert!(p[0] == p[1] && p[1] == p[2]);
    }
}
