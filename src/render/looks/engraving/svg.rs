//! The engraving's vector form ([`svg`](crate::render::vector)): its lines as filled outlines whose
//! width follows the raster's, one path per ink.

use crate::render::lines::streamlines::normal_at;
use crate::render::looks::engraving::{engrave_with_inks, EngravingParams};
use crate::render::scene::Scene;
use crate::render::support::colour::linear_of;
use crate::render::vector::path::{hex, path_data};
use std::fmt::Write;

/// Writes the engraving of `scene`: paper, then every line as filled outlines whose width
/// follows the raster's (its two sides as far from the line as its ink reaches on each), one
/// per run of points in one ink: the engraving's, or in the dark tones the darker ink the
/// raster lays there ([`engrave_with_inks`]). The outlines of one ink are the subpaths of one
/// path: a renderer finds the coverage of a path's union at once, so two lines a hair apart
/// ink the pixel between them as the raster does. As separate shapes each was blended over
/// the other, and a pixel both half covered read a quarter paper: the dark tones, whose lines
/// leave slits of paper finer than a pixel, read 6 to 12 levels light (greys 30 and 40 read 42
/// and 51, now 30 and 40).
pub(crate) fn engraved(out: &mut String, scene: &Scene, params: &EngravingParams) {
    let r = scene.raster;
    let scale = r.pixels_per_domain_unit();
    let ppu = scale.x.min(scale.y);
    let _ = writeln!(
        out,
        r#"<rect width="100%" height="100%" fill="{}"/>"#,
        hex(linear_of(params.paper))
    );
    let (e, inks) = engrave_with_inks(scene, params);
    // Path data per ink (`None`: the engraving's own), in a fixed order.
    let mut paths: std::collections::BTreeMap<Option<[u8; 3]>, String> = Default::default();
    let mut outline = Vec::new();
    for ((line, sides), inks) in e.lines.iter().zip(&e.sides).zip(&inks) {
        let pts = &line.points;
        if pts.len() < 2 || sides.iter().all(|&[l, r]| (l + r) * ppu < 0.05) {
            continue;
        }
        // Runs of one ink, each drawn one segment into the next: shapes of two inks that only
        // abut leave a renderer's anti-aliasing seam between them, a speck of paper in a dark
        // area.
        let mut start = 0;
        while start + 1 < pts.len() {
            let ink = inks[start];
            let mut end = start + 1;
            while end + 1 < pts.len() && inks[end] == ink {
                end += 1;
            }
            outline.clear();
            let last = (end + 1).min(pts.len() - 1);
            for i in start..=last {
                let q = (pts[i] + normal_at(pts, i) * sides[i][0]) * scale;
                outline.push([q.x as f32, q.y as f32]);
            }
            for i in (start..=last).rev() {
                let q = (pts[i] - normal_at(pts, i) * sides[i][1]) * scale;
                outline.push([q.x as f32, q.y as f32]);
            }
            path_data(paths.entry(ink).or_default(), &outline, true);
            start = end;
        }
    }
    for (ink, d) in &paths {
        let fill = hex(linear_of(ink.unwrap_or(params.ink)));
        let _ = writeln!(out, r#"<path fill="{fill}" d="{d}"/>"#);
    }
}
