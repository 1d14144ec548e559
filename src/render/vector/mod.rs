//! Vector output (SVG): what every look's vector form is made of. A document of the output's
//! size (`document`); the cells (paper section 6) as polygons traced from the label map at
//! the output size and simplified ([`trace`]), filled with one colour or a linear gradient each
//! and their borders stroked as leading (`cells`, `Traced`); path data and colours
//! (`path`); the outlines over a photo's look, traced from where they ink at least half a
//! pixel ([`outlines`]). Each look writes its own body in its folder (`looks/*/svg.rs`).
//!
//! Coordinates are output pixels with one decimal; colours are sRGB hex.

pub mod outlines;
pub(crate) mod path;
pub mod trace;

use crate::render::cells::raster::{label_map, Raster};
use crate::render::scene::Scene;
use crate::render::support::colour::{to_srgb, Linear};
use glam::DVec2;
use path::{hex, hex_of_srgb, num, path_data};
use std::fmt::Write;
use trace::{rings, simplify, Borders};

/// Largest distance of a traced border from the pixel staircase it simplifies, in output
/// pixels.
pub const TRACE_TOLERANCE_PX: f32 = 0.7;

/// An SVG document of `raster`'s size whose body `body` writes.
pub(crate) fn document(raster: &Raster, body: impl FnOnce(&mut String)) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        // `xlink` for the embedded photo's `xlink:href`, which SVG 1.1 renderers (Inkscape
        // 0.92, librsvg before 2.52) read where they ignore SVG 2's plain `href`.
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#,
        w = raster.width,
        h = raster.height
    );
    let _ = writeln!(
        out,
        "<!-- anisopaint {}: generalized Voronoi cells / glyphs of anisotropic samples -->",
        env!("CARGO_PKG_VERSION")
    );
    body(&mut out);
    out.push_str("</svg>\n");
    out
}

/// Writes a background of `colour` over the whole picture.
pub(crate) fn paper(out: &mut String, colour: Linear) {
    let _ = writeln!(
        out,
        r#"<rect width="100%" height="100%" fill="{}"/>"#,
        hex(colour)
    );
}

/// A cell filled with a linear gradient of three stops (a mosaic cell's relief).
pub(crate) struct Gradient {
    /// The gradient's ends, in output pixels.
    pub ends: [DVec2; 2],
    /// The colour at the first end, half way and at the second end.
    pub colours: [Linear; 3],
}

/// The cells of a scene as simplified polygons: the border chains (for the leading) and
/// every cell's rings.
pub(crate) struct Traced {
    borders: Borders,
    simplified: Vec<Vec<[f32; 2]>>,
    /// Every cell's rings, in output pixels.
    pub rings: Vec<Vec<Vec<[f32; 2]>>>,
}

impl Traced {
    /// The cells of `scene`, traced.
    pub fn new(scene: &Scene) -> Self {
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
    pub fn cell_path(&self, i: usize, d: &mut String) {
        d.clear();
        for ring in &self.rings[i] {
            path_data(d, ring, true);
        }
    }

    /// The borders between two cells (not the picture's edge) stroked in `ink` at `leading`'s
    /// width: one path per width and colour.
    pub fn write_leading(&self, out: &mut String, ink: LeadInk, leading: Leading) {
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
pub(crate) type LeadInk<'a> = &'a dyn Fn(usize, usize) -> Linear;

/// How wide the leading between cells is, in output pixels.
#[derive(Clone, Copy)]
pub(crate) enum Leading<'a> {
    /// One width everywhere.
    Even(f32),
    /// Per cell; a border takes the narrower of its two cells' (the mosaic's
    /// `leading_widths`).
    PerCell(&'a [f32]),
}

/// Writes the cells of `scene` filled with `colours` (or, where `ramps` gives a cell one, with
/// that gradient: a relief), and the borders stroked with `(colour, leading)` when
/// given.
pub(crate) fn cells(
    out: &mut String,
    scene: &Scene,
    (colours, ramps): (&[Linear], Option<&[Option<Gradient>]>),
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
