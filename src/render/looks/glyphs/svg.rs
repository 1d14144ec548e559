//! The glyph looks' vector form: one `<ellipse>` (or `<rect>`, or a polygon for superquadrics
//! and brush strokes) per glyph with the same axes, angle and colour as the raster picture,
//! over the same ground.

use super::{glyph_cover, grounds, polygon, tone_kept, GlyphParams, Shape};
use crate::field::Tensor;
use crate::render::scene::Scene;
use crate::render::support::colour::{linear_of, Linear};
use crate::render::vector;
use crate::render::vector::path::{hex, num, path_data};
use glam::DVec2;
use std::fmt::Write;

/// Writes the glyphs of `scene`, `laid` as the picture lays them, as vector shapes.
pub(crate) fn write(
    out: &mut String,
    scene: &Scene,
    params: &GlyphParams,
    laid: &[(DVec2, Tensor, Linear)],
) {
    let r = scene.raster;
    let DVec2 { x: sx, y: sy } = r.pixels_per_domain_unit();
    if params.underpaint {
        vector::cells(out, scene, (&scene.colours, None), None);
    } else if params.ground > 0.0 && tone_kept(scene, params) {
        let kappa = glyph_cover(scene, params);
        let ground = grounds(scene, params, kappa);
        vector::cells(out, scene, (&ground, None), None);
    } else {
        vector::paper(out, linear_of(params.background));
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
                path_data(&mut d, &polygon(params.shape, a, b, 48), true);
                let _ = writeln!(
                    out,
                    r#"<path transform="translate({cx} {cy}) rotate({angle})" fill="{fill}" d="{d}"/>"#
                );
            }
        }
    }
    out.push_str("</g>\n");
}
