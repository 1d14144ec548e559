//! Vector output (SVG) of a look. Glyph looks become one `<ellipse>` (or `<rect>`, or
//! polygon for superquadrics) per glyph with the same axes, angle and colour as the raster
//! picture. Cell looks become the generalized Voronoi cells (paper section 6) as polygons
//! traced from the label map at the output size and simplified ([`super::trace`]), filled
//! with the cell colour (the mean photo colour for the mosaic; the mosaic's leading is one
//! stroked path of all borders). Hatch and cross-hatch become vector lines clipped to each
//! cell, with the raster's directions, spacings and ink coverage (drawable by a pen plotter);
//! stipple becomes the raster's dots as circles of its radii, clipped to each cell; the
//! engraving its lines as filled outlines whose width follows the tone; the other textured
//! looks become their cells' mean tone of ink on paper. The outlines over a photo's look are
//! traced from where they ink at least half a pixel ([`outlines`](super::svg_outlines::outlines)).
//! Fabric and LIC are images of noise and have no vector form.
//!
//! Coordinates are output pixels with one decimal; colours are sRGB hex.

use super::blurred_photo::BlurredPhoto;
use super::colour::{linear_of, mix, to_srgb, Linear};
use super::glyphs::{GlyphParams, Shape};
use super::hatch_lines::{cross_hatch_layers, LAYER_ANGLES};
use super::look::Look;
use super::raster::label_map;
use super::scene::Scene;
use super::stipple::{dab_colour, dot, stipple_radius};
use super::svg_path::{hex, hex_of_srgb, num, path_data};
use super::texture::{
    cell_tones, smoothstep, spacing, texture_frames, Ink, TextureKind, TextureParams,
};
use super::trace::{rings, simplify, Borders};
use crate::error::Result;
use crate::field::Tensor;
use glam::DVec2;
use std::fmt::Write;

/// Largest distance of a traced border from the pixel staircase it simplifies, in output
/// pixels.
pub const TRACE_TOLERANCE_PX: f32 = 0.7;

/// The SVG document of `look` over `scene`, or an error for looks without a vector form.
pub fn svg(look: &Look, scene: &Scene) -> Result<String> {
    svg_of_laid(look, scene, None)
}

/// [`svg`], with the glyphs the raster picture laid when it was painted already
/// ([`super::glyphs::painted`]), so they are not found twice.
pub(super) fn svg_of_laid(
    look: &Look,
    scene: &Scene,
    laid: Option<Vec<(DVec2, Tensor, Linear)>>,
) -> Result<String> {
    look.check_vector_form()?;
    let r = scene.raster;
    let mut out = String::new();
    let _ = writeln!(
        out,
        // `xlink` for the embedded photo's `xlink:href`, which SVG 1.1 renderers (Inkscape
        // 0.92, librsvg before 2.52) read where they ignore SVG 2's plain `href`.
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#,
        w = r.width,
        h = r.height
    );
    let _ = writeln!(
        out,
        "<!-- anisopaint {}: generalized Voronoi cells / glyphs of anisotropic samples -->",
        env!("CARGO_PKG_VERSION")
    );
    match look {
        Look::Mosaic(p) => {
            let glass = super::mosaic::glass(scene, p, scene.border_px(p.border_width));
            let ink =
                |l: usize, r: usize| super::mosaic::lead_between(&glass.leads, l as u32, r as u32);
            let border = (p.border_width > 0.0)
                .then_some((&ink as LeadInk, Leading::PerCell(&glass.leading)));
            let colours = glass.colours;
            let ramps = super::mosaic::relief_ramps(scene, p, &colours);
            cells(&mut out, scene, (&colours, ramps.as_deref()), border);
        }
        Look::Texture(p) if matches!(p.kind, TextureKind::Hatch | TextureKind::CrossHatch) => {
            hatched(&mut out, scene, p);
        }
        Look::Texture(p) if p.kind == TextureKind::Stipple => stippled(&mut out, scene, p),
        Look::Texture(p) => {
            let colours = tone_colours(scene, p);
            let lead = linear_of(p.ink.leading());
            let ink = move |_: usize, _: usize| lead;
            let border = (p.border_width > 0.0).then(|| {
                (
                    &ink as LeadInk,
                    Leading::Even(scene.border_px(p.border_width)),
                )
            });
            cells(&mut out, scene, (&colours, None), border);
        }
        Look::Glyphs(p) => {
            let laid = laid.unwrap_or_else(|| super::glyphs::laid(scene, p));
            glyphs(&mut out, scene, p, &laid);
        }
        Look::Engraving(p) => super::svg_engraved::engraved(&mut out, scene, p),
        // Refused above.
        Look::Fabric(_) => {}
    }
    out.push_str("</svg>\n");
    Ok(out)
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

/// The cells of a scene as simplified polygons: the border chains (for the leading) and
/// every cell's rings.
struct Traced {
    borders: Borders,
    simplified: Vec<Vec<[f32; 2]>>,
    rings: Vec<Vec<Vec<[f32; 2]>>>,
}

impl Traced {
    fn new(scene: &Scene) -> Self {
        let r = scene.raster;
        let labels = label_map(&scene.cells, &r);
        let borders = Borders::trace(&labels, r.width, r.height);
        let simplified: Vec<Vec<[f32; 2]>> = borders
            .chains
            .iter()
            .map(|c| simplify(&c.points, TRACE_TOLERANCE_PX))
            .collect();
        let rings = rings(&borders, &simplified, scene.colours.len());
        Traced {
            borders,
            simplified,
            rings,
        }
    }

    /// Path data of cell `i`'s rings.
    fn cell_path(&self, i: usize, d: &mut String) {
        d.clear();
        for ring in &self.rings[i] {
            path_data(d, ring, true);
        }
    }

    /// The borders between two cells (not the picture's edge) stroked in `ink` at `leading`'s
    /// width: one path per width and colour.
    fn write_leading(&self, out: &mut String, ink: LeadInk, leading: Leading) {
        // Paths by width in tenths of a pixel (as `num` writes it), narrowest first, then by
        // colour (a fixed order).
        let mut paths: std::collections::BTreeMap<(u32, [u8; 3]), String> = Default::default();
        for (chain, s) in self.borders.chains.iter().zip(&self.simplified) {
            if chain.left >= 0 && chain.right >= 0 {
                let (left, right) = (chain.left as usize, chain.right as usize);
                let width = match leading {
                    Leading::Even(w) => w,
                    Leading::PerCell(w) => w[left].min(w[right]),
                };
                let key = (
                    (width * 10.0).round().max(0.0) as u32,
                    ink(left, right).map(to_srgb),
                );
                path_data(paths.entry(key).or_default(), s, false);
            }
        }
        for ((key, ink), d) in paths.iter().filter(|((key, _), _)| *key > 0) {
            let ink = hex_of_srgb(*ink);
            let _ = writeln!(
                out,
                r#"<path fill="none" stroke="{ink}" stroke-width="{}" stroke-linejoin="round" stroke-linecap="round" d="{d}"/>"#,
                num(*key as f32 / 10.0)
            );
        }
    }
}

/// The leading's colour along a border between cells `left` and `right` (linear light).
type LeadInk<'a> = &'a dyn Fn(usize, usize) -> Linear;

/// How wide the leading between cells is, in output pixels.
#[derive(Clone, Copy)]
enum Leading<'a> {
    /// One width everywhere.
    Even(f32),
    /// Per cell; a border takes the narrower of its two cells' (the mosaic's
    /// [`leading_widths`](super::mosaic::leading_widths)).
    PerCell(&'a [f32]),
}

/// Writes the cells of `scene` filled with `colours` (or, where `ramps` gives a cell one, with
/// that gradient: the mosaic's relief), and the borders stroked with `(colour, leading)` when
/// given.
fn cells(
    out: &mut String,
    scene: &Scene,
    (colours, ramps): (&[Linear], Option<&[Option<super::mosaic::Ramp>]>),
    border: Option<(LeadInk, Leading)>,
) {
    let traced = Traced::new(scene);
    // Without leading, a hairline of the cell's own colour hides the seams anti-aliasing
    // leaves between abutting polygons.
    let seam = if border.is_none() {
        r#" stroke-width="0.5" stroke-linejoin="round""#
    } else {
        ""
    };
    let _ = writeln!(out, r#"<g stroke="none"{seam}>"#);
    let mut d = String::new();
    for (i, &colour) in colours.iter().enumerate() {
        if traced.rings[i].is_empty() {
            continue;
        }
        traced.cell_path(i, &mut d);
        let mut c = hex(colour);
        if let Some(ramp) = ramps.and_then(|r| r[i].as_ref()) {
            let [from, to] = ramp.ends.map(|v| [num(v.x as f32), num(v.y as f32)]);
            let [c0, c1, c2] = ramp.colours.map(hex);
            let _ = writeln!(
                out,
                "<linearGradient id=\"r{i}\" gradientUnits=\"userSpaceOnUse\" x1=\"{}\" \
                 y1=\"{}\" x2=\"{}\" y2=\"{}\"><stop offset=\"0\" stop-color=\"{c0}\"/>\
                 <stop offset=\"0.5\" stop-color=\"{c1}\"/><stop offset=\"1\" \
                 stop-color=\"{c2}\"/></linearGradient>",
                from[0], from[1], to[0], to[1]
            );
            c = format!("url(#r{i})");
        }
        if border.is_none() {
            let _ = writeln!(out, r#"<path fill="{c}" stroke="{c}" d="{d}"/>"#);
        } else {
            let _ = writeln!(out, r#"<path fill="{c}" d="{d}"/>"#);
        }
    }
    out.push_str("</g>\n");
    if let Some((colour, leading)) = border {
        traced.write_leading(out, colour, leading);
    }
}

/// Writes hatched cells as vector lines, as [`textured`](super::texture::textured) draws
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
    let _ = writeln!(
        out,
        r#"<rect width="100%" height="100%" fill="{}"/>"#,
        hex(paper)
    );
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
    if p.border_width > 0.0 {
        let lead = linear_of(p.ink.leading());
        traced.write_leading(
            out,
            &move |_, _| lead,
            Leading::Even(scene.border_px(p.border_width)),
        );
    }
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
    let _ = writeln!(
        out,
        r#"<rect width="100%" height="100%" fill="{}"/>"#,
        hex(linear_of(p.paper))
    );
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

/// Writes the glyphs of `scene`, `laid` as the picture lays them, as vector shapes.
fn glyphs(out: &mut String, scene: &Scene, params: &GlyphParams, laid: &[(DVec2, Tensor, Linear)]) {
    let r = scene.raster;
    let DVec2 { x: sx, y: sy } = r.pixels_per_domain_unit();
    if params.underpaint {
        cells(out, scene, (&scene.colours, None), None);
    } else if params.ground > 0.0 && super::glyphs::tone_kept(scene, params) {
        let kappa = super::glyphs::glyph_cover(scene, params);
        let ground = super::glyphs::grounds(scene, params, kappa);
        cells(out, scene, (&ground, None), None);
    } else {
        let _ = writeln!(
            out,
            r#"<rect width="100%" height="100%" fill="{}"/>"#,
            hex(linear_of(params.background))
        );
    }
    if params.outline_width > 0.0 {
        let _ = writeln!(
            out,
            r#"<g stroke="{}" stroke-width="{}">"#,
            hex(linear_of(params.outline)),
            params.outline_width
        );
    } else {
        out.push_str("<g>\n");
    }
    for &(p, m, colour) in laid {
        let e = m.eigen();
        let scale = f64::from(params.scale);
        let (a, b) = (e.l1.abs() * scale, e.l2.abs() * scale);
        if !(a > 0.0 && b > 0.0 && a.is_finite()) {
            continue;
        }
        // Domain to output pixels: a uniform scale when the aspect is kept (it is, up to
        // rounding), so the ellipse stays an ellipse with scaled axes.
        let k = (sx * sy).sqrt();
        let (cx, cy) = (num((p.x * sx) as f32), num((p.y * sy) as f32));
        let (a, b) = (num((a * k) as f32), num((b * k) as f32));
        let angle = num(e.angle.to_degrees() as f32);
        let fill = hex(colour);
        match params.shape {
            Shape::Ellipse => {
                let _ = writeln!(
                    out,
                    r#"<ellipse cx="{cx}" cy="{cy}" rx="{a}" ry="{b}" transform="rotate({angle} {cx} {cy})" fill="{fill}"/>"#
                );
            }
            Shape::Rectangle => {
                let _ = writeln!(
                    out,
                    r#"<rect x="-{a}" y="-{b}" width="{w}" height="{h}" transform="translate({cx} {cy}) rotate({angle})" fill="{fill}"/>"#,
                    w = num(2.0 * (e.l1.abs() * scale * k) as f32),
                    h = num(2.0 * (e.l2.abs() * scale * k) as f32),
                );
            }
            Shape::Superquadric(_) | Shape::Brush => {
                let a = (e.l1.abs() * scale * k) as f32;
                let b = (e.l2.abs() * scale * k) as f32;
                let mut d = String::new();
                path_data(
                    &mut d,
                    &super::glyphs::polygon(params.shape, a, b, 48),
                    true,
                );
                let _ = writeln!(
                    out,
                    r#"<path transform="translate({cx} {cy}) rotate({angle})" fill="{fill}" d="{d}"/>"#
                );
            }
        }
    }
    out.push_str("</g>\n");
}
