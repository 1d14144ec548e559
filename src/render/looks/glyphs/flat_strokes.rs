//! Brush strokes across flat areas (skies, plain walls, a studio backdrop) laid as a painter
//! lays them: long strokes at one angle, not the round dabs of the metric's ellipses there.
//!
//! Where the photo has no structure the metric is round (paper section 3: no direction, the
//! largest size), and a round brush stroke per sample, each flat at its cell's colour, turned
//! a sky's gentle gradient into rows of overlapping discs, a scaly pattern the photo does not
//! have. Here the stroke of a cell in a flat area becomes [`ASPECT`] times as long as it is
//! wide with the area of its ellipse, along the preset's `flat_angle` turned by up to
//! [`JITTER_DEGREES`] either way per stroke (strokes by hand are never quite parallel).
//!
//! A cell lies in a flat area when neither it nor any cell touching it (in the triangulation) has
//! structure of its own: no channel of the blurred photo under it departs by
//! [`QUIET_STD`](crate::render::cells::quiet_cells::QUIET_STD) levels or more from a gentle plane
//! over the cell (`quiet_colour_cells`: a sky's gradient towards the horizon is flat too). By
//! colour rather than luma, so a texture only the hue shows keeps its own strokes; with the
//! touching cells, so a noisy or sparse texture, whose quiet cells lie scattered among busy ones,
//! is not laid at the one angle. The strokes keep their colours and order; the edge stops and the
//! coarse-to-fine refinement (`edge_stop.rs`, `refine.rs`) treat them as any other.
//!
//! Round strokes are scales elsewhere too: a concrete floor's mottle, a sky's faint wisps or
//! the grain of a plain wall keep the metric round and large (no direction, little detail), but
//! the cells there are not quiet, and rows of discs in nearly one colour covered them. A
//! stroke at least half as large as the field's largest ellipse whose cell differs little from
//! every cell it touches ([`SIMILAR_LEVELS`]) is lengthened towards [`ASPECT`] with its area,
//! along the photo's calm line field (`line_field.rs`, the engraving's: the field's own
//! direction where it holds, the region's where not, the flat angle where none), so a floor is
//! laid in strokes that run with it. Where neighbouring cells differ (gravel, grass, a face's
//! features) the strokes keep their own ellipses.

use crate::field::Tensor;
use crate::render::cells::quiet_cells::quiet_colour_cells;
use crate::render::lines::line_field::Directions;
use crate::render::scene::Scene;
use crate::render::support::colour::{to_srgb, Linear};
use crate::render::support::hash::{salt, site_hash};
use glam::DVec2;

/// A flat area's stroke: this many times as long as it is wide (3 to 5 all read as a sky laid
/// in brushwork; 4 is the middle).
pub const ASPECT: f64 = 4.0;

/// The largest turn, either way, of a flat area's stroke from the flat angle, and of a
/// lengthened stroke from the line field (degrees).
pub const JITTER_DEGREES: f64 = 10.0;

/// Strokes from this share of the field's largest ellipse (by `√(ab)`) up are lengthened where
/// their cell is like its neighbours, fully from [`LARGE_FULLY`] on: the round discs that read
/// as scales are the large ones, where the photo has little detail. Lengthened whatever
/// their neighbours, pebbles and grass would blur into streaks: hence [`SIMILAR_LEVELS`].
const LARGE_FROM: f64 = 0.5;
/// See [`LARGE_FROM`].
const LARGE_FULLY: f64 = 0.8;
/// A cell whose colour differs from each touching cell's by at most this (sRGB levels, the
/// largest channel) is lengthened fully, one differing by twice this not at all: floors,
/// walls and wispy skies go into long strokes, gravel and grass keep their pebbles. (By the
/// mean difference instead of the largest, a wispy sky would keep many of its scales.)
const SIMILAR_LEVELS: f64 = 12.0;

/// Lays the strokes of `scene`'s flat areas along `angle` (radians from the x axis, y down),
/// and lengthens its large round strokes among similar cells along the photo's line field:
/// `glyphs` are the samples' strokes in cell order (centre, metric, colour); those of cells in
/// a flat area take a metric [`ASPECT`] times as long as wide with their own area, the large
/// round ones up to that. Without the colour term's cell map (a field, or a picture not at the
/// photo's size) nothing changes.
pub(crate) fn lay_long_strokes(scene: &Scene, glyphs: &mut [(DVec2, Tensor, Linear)], angle: f64) {
    let Some(quiet) = quiet_colour_cells(&scene.cells) else {
        return;
    };
    // Every pair of touching cells once.
    let touching = scene.cells.mesh().edges(scene.cells.positions().len()).ends;
    let flat = flat_areas(&quiet, &touching);
    let lengthen = lengthening(scene, glyphs, &touching);
    let directions = Directions::at_cell_scale(scene.field, angle, glyphs.len());
    for (i, (p, m, _)) in glyphs.iter_mut().enumerate() {
        let jitter = JITTER_DEGREES.to_radians()
            * (2.0 * f64::from(site_hash(i as u32, salt::FLAT_STROKE)) - 1.0);
        let e = m.eigen();
        let (long, short) = (e.l1.abs().max(e.l2.abs()), e.l1.abs().min(e.l2.abs()));
        let radius = (long * short).sqrt();
        if flat.get(i).copied().unwrap_or(false) {
            let stretch = ASPECT.sqrt();
            *m = Tensor::from_eigen(angle + jitter, radius * stretch, radius / stretch);
            continue;
        }
        let aspect = 1.0 + (ASPECT - 1.0) * lengthen.get(i).copied().unwrap_or(0.0);
        if short > 0.0 && long < aspect * short {
            let u = directions.at(*p);
            let stretch = aspect.sqrt();
            *m = Tensor::from_eigen(u.y.atan2(u.x) + jitter, radius * stretch, radius / stretch);
        }
    }
}

/// Per stroke of `glyphs` (in cell order), how far towards [`ASPECT`] it is lengthened (0 to
/// 1): by its size against the field's largest ellipse ([`LARGE_FROM`], [`LARGE_FULLY`]) times
/// how little its cell's colour differs from the most different touching cell's
/// ([`SIMILAR_LEVELS`]; `touching`: the pairs of touching cells).
fn lengthening(
    scene: &Scene,
    glyphs: &[(DVec2, Tensor, Linear)],
    touching: &[[u32; 2]],
) -> Vec<f64> {
    let largest = scene
        .field
        .data()
        .iter()
        .map(|t| {
            (f64::from(t[0]) * f64::from(t[2]) - f64::from(t[1]).powi(2))
                .abs()
                .sqrt()
        })
        .fold(f64::MIN_POSITIVE, f64::max);
    let n = scene.colours.len();
    let levels: Vec<[f64; 3]> = scene
        .colours
        .iter()
        .map(|c| c.map(|v| f64::from(to_srgb(v))))
        .collect();
    let mut unlike = vec![0.0_f64; n];
    for &[a, b] in touching {
        let (a, b) = (a as usize, b as usize);
        let d = (0..3)
            .map(|k| (levels[a][k] - levels[b][k]).abs())
            .fold(0.0, f64::max);
        unlike[a] = unlike[a].max(d);
        unlike[b] = unlike[b].max(d);
    }
    glyphs
        .iter()
        .zip(&unlike)
        .map(|((_, m, _), &d)| {
            let size = m.det().abs().sqrt() / largest;
            let large = ((size - LARGE_FROM) / (LARGE_FULLY - LARGE_FROM)).clamp(0.0, 1.0);
            let similar = (2.0 - d / SIMILAR_LEVELS).clamp(0.0, 1.0);
            large * similar
        })
        .collect()
}

/// Per cell, whether it lies in a flat area: it and every cell touching it (`touching`, each
/// pair once) `quiet` by colour about a gentle ramp ([`quiet_colour_cells`]).
fn flat_areas(quiet: &[bool], touching: &[[u32; 2]]) -> Vec<bool> {
    let mut flat = quiet.to_vec();
    for &[a, b] in touching {
        let (a, b) = (a as usize, b as usize);
        if !(quiet[a] && quiet[b]) {
            flat[a] = false;
            flat[b] = false;
        }
    }
    flat
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::{photo_metric, MetricParams};
    use crate::render::cells::{CellParams, CellSites};
    use crate::sampling::{self, SamplerParams};
    use image::{DynamicImage, Rgb, RgbImage};

    /// Three areas across a 180 × 120 photo: a sky's gradient (x < 60, blue 40 → 220 top to
    /// bottom: 1.5 levels a pixel, a plane of 3–4 levels' spread over a cell and
    /// nothing about it), a mottled grey floor (blocks of 3 px, ±6 levels hashed: a spread
    /// of 3.7 levels in every cell, cells alike), and a steep ramp (x ≥ 130, red rising 3.5
    /// levels a pixel: a colour wheel's hues, a plane of 8–9 levels over a cell, and cells
    /// some 30 levels apart).
    fn photo() -> RgbImage {
        RgbImage::from_fn(180, 120, |x, y| {
            if x < 60 {
                Rgb([40, 60, 40 + (3 * y / 2) as u8])
            } else if x < 130 {
                let hash = (x / 3).wrapping_mul(2_654_435_761) ^ (y / 3).wrapping_mul(40_503);
                let v = 114 + (hash.wrapping_mul(2_246_822_519) >> 16) % 13;
                Rgb([v as u8; 3])
            } else {
                Rgb([(7 * (x - 130) / 2) as u8, 60, 104])
            }
        })
    }

    #[test]
    fn strokes_of_flat_areas_lie_along_the_angle_and_like_cells_are_lengthened() {
        let photo = DynamicImage::ImageRgb8(photo());
        // Cells of about one size everywhere (radius 4–5 px), each of some 50 pixels.
        let metric = MetricParams {
            min_size: 0.02,
            max_size: 0.025,
            ..MetricParams::default()
        };
        let (_, field) = photo_metric(&photo, &metric);
        let s = sampling::sample(&field, &SamplerParams::default()).unwrap();
        let params = CellParams::default();
        let read = CellSites::photo_read(Some(&photo), &params);
        let sites =
            CellSites::with_photo_read(s.positions, s.metrics, s.mesh, &field, read, &params);
        let scene = Scene::new(sites.cells(), &field, Some(&photo), 180, 120, 1);
        let before: Vec<(DVec2, Tensor, Linear)> = (0..scene.colours.len())
            .map(|i| {
                let c = scene.cells.positions()[i];
                (c, scene.cells.metrics()[i], scene.colours[i])
            })
            .collect();
        let angle = 20f64.to_radians();
        let mut after = before.clone();
        lay_long_strokes(&scene, &mut after, angle);
        let (mut sky, mut floor, mut steep) = (0, 0, 0);
        for ((p, m, c), (q, n, d)) in before.iter().zip(&after) {
            assert_eq!((p, c), (q, d), "strokes keep their places and colours");
            let (e, f) = (m.eigen(), n.eigen());
            let margin = 3.0 * e.l1.abs().min(e.l2.abs()).max(1.0);
            let inside = p.y > margin && p.y < 120.0 - margin;
            let area_kept = (f.l1 * f.l2 - e.l1 * e.l2).abs() < 1e-9 * e.l1 * e.l2;
            if inside && p.x + margin < 60.0 {
                // In the sky: four times as long as wide, the same area, within the jitter of
                // the angle.
                sky += 1;
                assert!((f.l1 / f.l2 - ASPECT).abs() < 1e-9, "{p}: {f:?}");
                assert!(area_kept, "{p}");
                let turn = (f.angle - angle).abs().to_degrees();
                assert!(turn <= JITTER_DEGREES + 1e-9, "{p}: turned {turn}°");
            } else if inside && p.x - margin > 60.0 && p.x + margin < 130.0 {
                // The floor: structure (not flat), but cells alike and large: lengthened.
                floor += 1;
                assert!(f.l1 / f.l2 > 2.0, "{p}: {e:?} → {f:?}");
                assert!(area_kept, "{p}");
            } else if inside && p.x - margin > 130.0 && p.x + margin < 180.0 {
                // The steep ramp is structure, and its cells differ: their own ellipses.
                steep += 1;
                assert_eq!(m, n, "{p} has structure: its own ellipse");
            }
        }
        // Small strokes among alike cells are dabs of detail, not scales: the floor's strokes
        // at 0.4 of their size keep their ellipses.
        let on_floor = |p: &DVec2| p.x > 70.0 && p.x < 120.0 && p.y > 10.0 && p.y < 110.0;
        let mut small = before.clone();
        for (p, m, _) in &mut small {
            if on_floor(p) {
                *m = Tensor::new(0.4 * m.xx, 0.4 * m.xy, 0.4 * m.yy);
            }
        }
        let mut small_after = small.clone();
        lay_long_strokes(&scene, &mut small_after, angle);
        for ((p, m, _), (_, n, _)) in small.iter().zip(&small_after) {
            if on_floor(p) {
                assert_eq!(m, n, "{p}: a small stroke keeps its ellipse");
            }
        }
        assert!(
            sky >= 10 && floor >= 5 && steep >= 10,
            "{sky} sky, {floor} floor and {steep} steep strokes"
        );
    }
}
