//! The textured looks' vector form: hatch and cross-hatch as vector lines clipped to each
//! traced cell, with the raster's directions, spacings and ink coverage (drawable by a pen
//! plotter); stipple as the raster's dots, circles of its radii clipped to each cell; the
//! other textures as their cells' mean tone of ink on paper.

use super::blurred_photo::BlurredPhoto;
use super::hatch_lines::{cross_hatch_layers, LAYER_ANGLES};
use super::stipple::{dab_colour, dot, stipple_radius};
use super::{cell_tones, smoothstep, spacing, texture_frames, Ink, TextureKind, TextureParams};
use crate::render::scene::Scene;
use crate::render::support::colour::{linear_of, mix, Linear};
use crate::render::vector::path::{hex, num, path_data};
use crate::render::vector::{self, LeadInk, Leading, Traced};
use glam::DVec2;
use std::fmt::Write;

/// Writes the body of `p`'s SVG over `scene`.
pub(crate) fn write(out: &mut String, scene: &Scene, p: &TextureParams) {
    match p.kind {
        TextureKind::Hatch | TextureKind::CrossHatch => hatched(out, scene, p),
        TextureKind::Stipple => stippled(out, scene, p),
        _ => {
            let colours = tone_colours(scene, p);
            let lead = linear_of(p.ink.leading());
            let ink = move |_: usize, _: usize| lead;
            let border = (p.border_width > 0.0).then(|| {
                (
                    &ink as LeadInk,
                    Leading::Even(scene.border_px(p.border_width)),
                )
            });
            vector::cells(out, scene, (&colours, None), border);
        }
    }
}

/// A textured cell's colour seen from afar: its ink over paper at the cell's tone.
fn tone_colours(scene: &Scene, p: &TextureParams) -> Vec<Linear> {
    let paper = linear_of(p.paper);
    cell_tones(&scene.colours, p)
        .into_iter()
        .map(|(darkness, ink)| match p.kind {
            // Strokes cover the cell in its own colour.
            TextureKind::Stroke => ink,
            _ => mix(paper, ink, darkness),
        })
        .collect()
}

/// Writes hatched cells as vector lines, as [`textured`](super::textured) draws
/// them: per cell, lines along its long axis (cross-hatch: one to three layers by tone) at
/// its spacing, on the same lines as the raster so they continue into neighbouring cells,
/// clipped to the traced cell. Where the metric is nearly isotropic the raster fades the
/// lines towards flat tone; here the cell gets that flat tint and thinner lines over it, so
/// the mean tone is kept. Pen plotters can draw the result.
fn hatched(out: &mut String, scene: &Scene, p: &TextureParams) {
    let traced = Traced::new(scene);
    let r = scene.raster;
    let DVec2 { x: sx, y: sy } = r.pixels_per_domain_unit();
    let px = 1.0 / scene.pixels_per_unit;
    let paper = linear_of(p.paper);
    vector::paper(out, paper);
    let tones = cell_tones(&scene.colours, p);
    let frames = texture_frames(scene, p);
    let (mut d, mut lines) = (String::new(), String::new());
    for (i, &(darkness, ink)) in tones.iter().enumerate() {
        if traced.rings[i].is_empty() || darkness <= 0.0 {
            continue;
        }
        let frame = frames[i];
        let tint = darkness * (1.0 - smoothstep(p.fade_anisotropy, frame.anisotropy));
        // Lines over the tint so that tint + (1 − tint)·w = darkness.
        let w = ((darkness - tint) / (1.0 - tint).max(1e-6)).clamp(0.0, 1.0);
        traced.cell_path(i, &mut d);
        if tint > 0.005 {
            let _ = writeln!(
                out,
                r#"<path fill="{}" d="{d}"/>"#,
                hex(mix(paper, ink, tint))
            );
        }
        // The raster's layers (`cross_hatch_layers`) at the cell's tone, each its own width.
        let (widths, k) = match p.kind {
            TextureKind::CrossHatch => cross_hatch_layers(w),
            _ => ([w, 0.0, 0.0], 1),
        };
        let spacing = spacing(frame.b, p, px);
        let mut clipped = false;
        for (&phi, &x) in LAYER_ANGLES.iter().zip(&widths).take(k) {
            let width = f64::from(x) * spacing * (sx * sy).sqrt();
            if width < 0.05 {
                continue;
            }
            lines.clear();
            family(
                &mut lines,
                &traced.rings[i],
                frame.angle + phi,
                spacing,
                (sx, sy),
            );
            if lines.is_empty() {
                continue;
            }
            if !clipped {
                let _ = writeln!(out, r#"<clipPath id="c{i}"><path d="{d}"/></clipPath>"#);
                clipped = true;
            }
            let _ = writeln!(
                out,
                r#"<path clip-path="url(#c{i})" fill="none" stroke="{}" stroke-width="{}" d="{lines}"/>"#,
                hex(ink),
                num(width as f32)
            );
        }
    }
    leading(out, &traced, scene, p);
}

/// Writes stippled cells as vector dots: per cell, the raster's jittered lattice in the cell's
/// frame, every dot a circle of the raster's radius for the cell's tone (so the dots ink the
/// same share of paper) laid in the raster's order, clipped to the traced cell, in the cell's
/// ink; pointillist dots ([`Ink::Pixel`]) each in the blurred photo's colour at its centre,
/// with the raster's per-dot colour ([`dab_colour`]).
fn stippled(out: &mut String, scene: &Scene, p: &TextureParams) {
    let traced = Traced::new(scene);
    let r = scene.raster;
    let DVec2 { x: sx, y: sy } = r.pixels_per_domain_unit();
    let k = (sx * sy).sqrt();
    let px = 1.0 / scene.pixels_per_unit;
    vector::paper(out, linear_of(p.paper));
    let tones = cell_tones(&scene.colours, p);
    let frames = texture_frames(scene, p);
    let blurred = match (p.ink, scene.photo) {
        (Ink::Pixel(_), Some(photo)) => Some(BlurredPhoto::new(photo)),
        _ => None,
    };
    let (mut d, mut dots, mut order) = (String::new(), String::new(), Vec::new());
    for (i, &(darkness, ink)) in tones.iter().enumerate() {
        if traced.rings[i].is_empty() || darkness <= 0.0 {
            continue;
        }
        let f = frames[i];
        let s = spacing(f.b, p, px);
        let radius = s * stipple_radius(darkness);
        if radius * k < 0.05 {
            continue;
        }
        let site = scene.cells.positions()[i];
        let (sin, cos) = f.angle.sin_cos();
        // The cell's extent in lattice periods of its own frame.
        let (mut lo, mut hi) = (glam::DVec2::splat(f64::MAX), glam::DVec2::splat(f64::MIN));
        for q in traced.rings[i].iter().flatten() {
            let v = glam::DVec2::new(f64::from(q[0]) / sx, f64::from(q[1]) / sy) - site;
            let local = glam::DVec2::new(cos * v.x + sin * v.y, -sin * v.x + cos * v.y) / s;
            (lo, hi) = (lo.min(local), hi.max(local));
        }
        // The cell's dots, lowest first: later circles lie over earlier ones as the raster's
        // dabs do.
        order.clear();
        for cy in (lo.y.floor() as i64 - 1)..=(hi.y.ceil() as i64) {
            for cx in (lo.x.floor() as i64 - 1)..=(hi.x.ceil() as i64) {
                let (above, c) = dot(i as u32, glam::DVec2::new(cx as f64, cy as f64));
                order.push((above, c * s));
            }
        }
        order.sort_by_key(|&(above, _)| above);
        dots.clear();
        for &(_, c) in &order {
            let q = site + glam::DVec2::new(cos * c.x - sin * c.y, sin * c.x + cos * c.y);
            let _ = write!(
                dots,
                r#"<circle cx="{}" cy="{}" r="{}""#,
                num((q.x * sx) as f32),
                num((q.y * sy) as f32),
                num((radius * k) as f32)
            );
            if let (Ink::Pixel(darken), Some(photo)) = (p.ink, &blurred) {
                let dab = dab_colour(i as u32, c, photo.at(q), darken);
                let _ = write!(dots, r#" fill="{}""#, hex(dab));
            }
            dots.push_str("/>");
        }
        traced.cell_path(i, &mut d);
        let _ = writeln!(
            out,
            r#"<clipPath id="c{i}"><path d="{d}"/></clipPath><g clip-path="url(#c{i})" fill="{}">{dots}</g>"#,
            hex(ink)
        );
    }
    leading(out, &traced, scene, p);
}

/// The leading of a textured look over its traced cells: one width, in the ink's leading
/// colour, where the preset asks for a border.
fn leading(out: &mut String, traced: &Traced, scene: &Scene, p: &TextureParams) {
    if p.border_width > 0.0 {
        let lead = linear_of(p.ink.leading());
        traced.write_leading(
            out,
            &move |_, _| lead,
            Leading::Even(scene.border_px(p.border_width)),
        );
    }
}

/// Appends the lines `n·q = k·spacing` (n the normal of direction `angle`, q in domain units)
/// that cross the bounding box of `rings` (output pixels), as segments in output pixels.
fn family(d: &mut String, rings: &[Vec<[f32; 2]>], angle: f64, spacing: f64, scale: (f64, f64)) {
    let (sin, cos) = angle.sin_cos();
    let (n, t) = ((-sin, cos), (cos, sin));
    let (mut n_range, mut t_range) = ((f64::MAX, f64::MIN), (f64::MAX, f64::MIN));
    for q in rings.iter().flatten() {
        let (x, y) = (f64::from(q[0]) / scale.0, f64::from(q[1]) / scale.1);
        let (a, b) = (n.0 * x + n.1 * y, t.0 * x + t.1 * y);
        n_range = (n_range.0.min(a), n_range.1.max(a));
        t_range = (t_range.0.min(b), t_range.1.max(b));
    }
    let (first, last) = (
        (n_range.0 / spacing).floor() as i64,
        (n_range.1 / spacing).ceil() as i64,
    );
    if last - first > 400 {
        return;
    }
    for k in first..=last {
        let c = k as f64 * spacing;
        let point = |along: f64| {
            let (x, y) = (n.0 * c + t.0 * along, n.1 * c + t.1 * along);
            [(x * scale.0) as f32, (y * scale.1) as f32]
        };
        path_data(
            d,
            &[point(t_range.0 - spacing), point(t_range.1 + spacing)],
            false,
        );
    }
}
