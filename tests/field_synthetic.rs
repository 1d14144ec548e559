//! The photo → metric stage on synthetic images whose answer is known: stripes give long axes
//! along the stripes, a flat image gives isotropic ellipses of the largest size, a disc gives
//! long axes tangent to its circle.

use anisopaint::field::{photo_metric, MetricParams, TensorField};
use glam::DVec2;
use image::{DynamicImage, Rgb, RgbImage};
use std::f64::consts::PI;

fn grey_image(w: u32, h: u32, f: impl Fn(f64, f64) -> f64) -> DynamicImage {
    let img = RgbImage::from_fn(w, h, |x, y| {
        let v = (f(f64::from(x) + 0.5, f64::from(y) + 0.5).clamp(0.0, 1.0) * 255.0).round() as u8;
        Rgb([v, v, v])
    });
    DynamicImage::ImageRgb8(img)
}

/// Angle between two axes (undirected), degrees in [0, 90].
fn axis_difference_deg(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(PI);
    d.min(PI - d).to_degrees()
}

fn interior_nodes(m: &TensorField, margin: f64) -> Vec<DVec2> {
    let d = m.domain();
    let mut out = Vec::new();
    for r in 0..m.rows() {
        for c in 0..m.cols() {
            let p = m.node_position(c, r);
            if p.x > margin && p.y > margin && p.x < d.x - margin && p.y < d.y - margin {
                out.push(p);
            }
        }
    }
    out
}

#[test]
fn stripes_give_long_axes_along_the_stripes() {
    let params = MetricParams::default();
    for angle_deg in [0.0f64, 30.0, 75.0] {
        let theta = angle_deg.to_radians();
        let normal = DVec2::new(-theta.sin(), theta.cos());
        let period = 14.0;
        let img = grey_image(240, 200, |x, y| {
            0.5 + 0.4 * (2.0 * PI * normal.dot(DVec2::new(x, y)) / period).sin()
        });
        let (_, metric) = photo_metric(&img, &params);
        let mut worst = 0.0f64;
        for p in interior_nodes(&metric, 20.0) {
            let e = metric.sample(p).eigen();
            assert!(
                e.l1 > 1.5 * e.l2,
                "stripes at {angle_deg}° should be anisotropic: {e:?}"
            );
            worst = worst.max(axis_difference_deg(e.angle, theta));
        }
        assert!(
            worst <= 1.0,
            "stripes at {angle_deg}°: long axis off by {worst:.2}°"
        );
    }
}

#[test]
fn flat_image_gives_isotropic_max_size() {
    let params = MetricParams::default();
    let img = grey_image(300, 200, |_, _| 0.4);
    let (_, metric) = photo_metric(&img, &params);
    let want = params.max_size * metric.diagonal();
    for &c in metric.data() {
        let e = anisopaint::field::Tensor::from_f32(c).eigen();
        assert!((e.l1 - want).abs() < 1e-4 * want, "{e:?} vs {want}");
        assert!((e.l2 - want).abs() < 1e-4 * want, "{e:?} vs {want}");
    }
}

#[test]
fn disc_gives_tangent_long_axes_and_small_cells_at_its_edge() {
    let params = MetricParams::default();
    let (cx, cy, radius) = (128.0, 120.0, 70.0);
    let img = grey_image(256, 240, |x, y| {
        // Anti-aliased disc: a 1 px ramp at the edge.
        let r = ((x - cx).powi(2) + (y - cy).powi(2)).sqrt();
        (radius + 0.5 - r).clamp(0.0, 1.0) * 0.8 + 0.1
    });
    let (_, metric) = photo_metric(&img, &params);
    let flat = metric.sample(DVec2::new(cx, cy)).eigen();
    let mut checked = 0;
    for k in 0..72 {
        let phi = f64::from(k) * 2.0 * PI / 72.0;
        let p = DVec2::new(cx + radius * phi.cos(), cy + radius * phi.sin());
        let e = metric.sample(p).eigen();
        let tangent = phi + PI / 2.0;
        assert!(
            axis_difference_deg(e.angle, tangent) < 2.0,
            "at {:.0}°: long axis {:.1}°",
            phi.to_degrees(),
            e.angle.to_degrees()
        );
        assert!(e.l1 > 2.0 * e.l2, "edge ellipses are elongated: {e:?}");
        assert!(
            e.l2 < 0.5 * flat.l2,
            "edge cells are smaller than flat ones"
        );
        checked += 1;
    }
    assert_eq!(checked, 72);
    assert!(
        (flat.l1 - flat.l2).abs() < 0.05 * flat.l1,
        "centre is isotropic: {flat:?}"
    );
}

#[test]
fn same_look_at_two_resolutions() {
    // The same picture at 400 px and 1600 px: the metric, in fractions of the diagonal, agrees.
    let params = MetricParams::default();
    let picture = |scale: f64| {
        grey_image(
            (400.0 * scale) as u32,
            (300.0 * scale) as u32,
            move |x, y| {
                let (x, y) = (x / scale, y / scale);
                let r = ((x - 200.0).powi(2) + (y - 150.0).powi(2)).sqrt();
                if r < 90.0 {
                    0.8
                } else {
                    0.2
                }
            },
        )
    };
    let (_, small) = photo_metric(&picture(1.0), &params);
    let (_, large) = photo_metric(&picture(4.0), &params);
    for (x, y) in [(100.0, 80.0), (200.0, 60.0), (290.0, 150.0), (200.0, 150.0)] {
        let a = small.sample(DVec2::new(x, y)).eigen();
        let b = large.sample(DVec2::new(4.0 * x, 4.0 * y)).eigen();
        let (ra, rb) = (a.l2 / small.diagonal(), b.l2 / large.diagonal());
        assert!((ra / rb - 1.0).abs() < 0.25, "at ({x}, {y}): {ra} vs {rb}");
    }
}

/// `f` plus white Gaussian grain of deviation `sigma` (0–1 units) per pixel, the same in the
/// three channels (Box–Muller on the sampler's seeded generator).
fn grainy_image(w: u32, h: u32, sigma: f64, f: impl Fn(f64, f64) -> f64) -> DynamicImage {
    let mut rng = anisopaint::sampling::rng::Rng::new(7, 0);
    let mut uniform = move || rng.uniform();
    let img = RgbImage::from_fn(w, h, |x, y| {
        let (u, v) = (uniform().max(1e-12), uniform());
        let grain = (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos();
        let value = f(f64::from(x) + 0.5, f64::from(y) + 0.5) + sigma * grain;
        let v = (value.clamp(0.0, 1.0) * 255.0).round() as u8;
        Rgb([v, v, v])
    });
    DynamicImage::ImageRgb8(img)
}

/// Median of `1 − b/a` and of the short semi-axis `b` over the interior nodes.
fn median_anisotropy_and_size(metric: &TensorField) -> (f64, f64) {
    let (mut anisotropy, mut size): (Vec<f64>, Vec<f64>) = interior_nodes(metric, 20.0)
        .into_iter()
        .map(|p| {
            let e = metric.sample(p).eigen();
            (1.0 - e.l2 / e.l1, e.l2)
        })
        .unzip();
    anisotropy.sort_by(f64::total_cmp);
    size.sort_by(f64::total_cmp);
    (anisotropy[anisotropy.len() / 2], size[size.len() / 2])
}

#[test]
fn grain_alone_gives_round_large_ellipses() {
    let params = MetricParams::default();
    let img = grainy_image(360, 240, 3.0 / 255.0, |_, _| 0.45);
    let (raw, metric) = photo_metric(&img, &params);
    let (anisotropy, size) = median_anisotropy_and_size(&metric);
    let max = params.max_size * metric.diagonal();
    assert!(anisotropy < 0.02, "grain turned the ellipses: {anisotropy}");
    assert!(
        size > 0.8 * max,
        "grain made small ellipses: {size} of {max}"
    );
    // The same tensor read as if it held no noise: the grain is the photo's finest detail.
    let blind = anisopaint::field::metric::metric_from_structure(&raw, &params);
    let (anisotropy, size) = median_anisotropy_and_size(&blind);
    assert!(anisotropy > 0.05 && size < 0.5 * max, "{anisotropy} {size}");
}

#[test]
fn a_disc_under_grain_keeps_its_tangent_ellipses() {
    let params = MetricParams::default();
    let (cx, cy, radius) = (128.0, 120.0, 70.0);
    let img = grainy_image(256, 240, 3.0 / 255.0, |x, y| {
        let r = ((x - cx).powi(2) + (y - cy).powi(2)).sqrt();
        (radius + 0.5 - r).clamp(0.0, 1.0) * 0.3 + 0.35
    });
    let (_, metric) = photo_metric(&img, &params);
    for k in 0..36 {
        let phi = f64::from(k) * 2.0 * PI / 36.0;
        let e = metric
            .sample(DVec2::new(cx + radius * phi.cos(), cy + radius * phi.sin()))
            .eigen();
        assert!(axis_difference_deg(e.angle, phi + PI / 2.0) < 5.0, "{e:?}");
        assert!(e.l1 > 2.0 * e.l2, "edge ellipses stay elongated: {e:?}");
    }
}
