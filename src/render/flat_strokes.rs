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
//! A cell lies in a flat area when neither it nor any cell touching it (in the triangulation)
//! has structure of its own: no channel of the blurred photo under it varies by
//! [`QUIET_STD`](super::quiet_cells::QUIET_STD) levels or more (`quiet_colour_cells`). By
//! colour rather than luma, so a texture only the hue shows keeps its own strokes; with the
//! touching cells, so a noisy or sparse texture, whose quiet cells lie scattered among busy
//! ones, keeps its dabs rather than turning into streaks. The strokes keep their colours and
//! order; the edge stops and the coarse-to-fine refinement (`edge_stop.rs`, `refine.rs`)
//! treat them as any other.
//!
//! Measured with `tone.py` on 22 held-out pictures (seed 7), strokes: PSNR 39.41 → 39.77 dB,
//! SSIM 0.9709 → 0.9720, edge recall 0.8998 → 0.8992; skies and plain backgrounds (camera,
//! clock, horse, logo, page, moon) +0.8 to +1.9 dB, a rocket's night sky +0.3 dB, a noisy
//! micrograph (cell) −0.14 dB (recall 0.789 → 0.781), no other picture below −0.02 dB.

use super::colour::{salt, site_hash, Linear};
use super::quiet_cells::quiet_colour_cells;
use super::scene::Scene;
use crate::field::Tensor;
use glam::DVec2;

/// A flat area's stroke: this many times as long as it is wide. Measured (`tone.py`, 22
/// pictures): 3, 4 and 5 give 39.71, 39.77 and 39.81 dB; by eye all three read as a sky laid
/// in brushwork, 4 kept as the middle.
pub const ASPECT: f64 = 4.0;

/// The largest turn, either way, of a flat area's stroke from the flat angle (degrees).
pub const JITTER_DEGREES: f64 = 10.0;

/// Lays the strokes of `scene`'s flat areas along `angle` (radians from the x axis, y down):
/// `glyphs` are the samples' strokes in cell order (centre, metric, colour); those of cells
/// in a flat area take a metric [`ASPECT`] times as long as wide with their own area. Without
/// the colour term's cell map (a field, or a picture not at the photo's size) nothing changes.
pub(super) fn lay_flat(scene: &Scene, glyphs: &mut [(DVec2, Tensor, Linear)], angle: f64) {
    let Some(flat) = flat_areas(scene) else {
        return;
    };
    let stretch = ASPECT.sqrt();
    for (i, (_, m, _)) in glyphs.iter_mut().enumerate() {
        if !flat.get(i).copied().unwrap_or(false) {
            continue;
        }
        let e = m.eigen();
        let radius = (e.l1 * e.l2).abs().sqrt();
        let jitter = JITTER_DEGREES.to_radians()
            * (2.0 * f64::from(site_hash(i as u32, salt::FLAT_STROKE)) - 1.0);
        *m = Tensor::from_eigen(angle + jitter, radius * stretch, radius / stretch);
    }
}

/// Per cell of `scene`, whether it lies in a flat area: it and every cell touching it quiet
/// ([`quiet_colour_cells`]).
fn flat_areas(scene: &Scene) -> Option<Vec<bool>> {
    let quiet = quiet_colour_cells(&scene.cells)?;
    let mut flat = quiet.clone();
    let n = scene.cells.positions().len();
    for [a, b] in scene.cells.mesh().edges(n).ends {
        let (a, b) = (a as usize, b as usize);
        if !(quiet[a] && quiet[b]) {
            flat[a] = false;
            flat[b] = false;
        }
    }
    Some(flat)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::{photo_metric, MetricParams};
    use crate::render::cells::{CellParams, CellSites};
    use crate::sampling::{self, SamplerParams};
    use image::{DynamicImage, Rgb, RgbImage};

    /// Three areas across a 180 × 120 photo: a sky's gentle gradient (x < 70, 100 → 108
    /// levels of blue top to bottom), a checker of 2 px squares of two colours of one Rec. 601
    /// luma (a texture only the hue shows, the same mean colour in every cell), and dark dots
    /// of 2 × 2 px every 12 px on the sky (a sparse texture: cells between the dots are as
    /// quiet as the sky's).
    fn photo() -> RgbImage {
        RgbImage::from_fn(180, 120, |x, y| {
            if x < 70 {
                let b = 100 + (8 * y / 120) as u8;
                Rgb([40, 60, b])
            } else if x < 110 {
                // Luma 0.299 r + 0.587 g + 0.114 b = 120 for both.
                if (x / 2 + y / 2) % 2 == 0 {
                    Rgb([60, 154, 100])
                } else {
                    Rgb([200, 83, 100])
                }
            } else if x % 12 < 2 && y % 12 < 2 {
                Rgb([30, 40, 60])
            } else {
                Rgb([40, 60, 104])
            }
        })
    }

    #[test]
    fn strokes_of_flat_areas_lie_along_the_angle_and_the_rest_keep_their_ellipses() {
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
        lay_flat(&scene, &mut after, angle);
        let (mut sky, mut others) = (0, 0);
        for ((p, m, c), (q, n, d)) in before.iter().zip(&after) {
            assert_eq!((p, c), (q, d), "strokes keep their places and colours");
            let (e, f) = (m.eigen(), n.eigen());
            let radius = e.l1.abs().min(e.l2.abs()).max(1.0);
            if p.x + 4.0 * radius < 70.0 {
                // Deep in the sky: four times as long as wide, the same area, within the
                // jitter of the angle.
                sky += 1;
                assert!((f.l1 / f.l2 - ASPECT).abs() < 1e-9, "{p}: {f:?}");
                assert!(
                    (f.l1 * f.l2 - e.l1 * e.l2).abs() < 1e-9 * e.l1 * e.l2,
                    "{p}"
                );
                let turn = (f.angle - angle).abs().to_degrees();
                assert!(turn <= JITTER_DEGREES + 1e-9, "{p}: turned {turn}°");
            } else if p.x - 4.0 * radius > 70.0 && p.x < 180.0 && p.y > 0.0 && p.y < 120.0 {
                // The hue's checker (as quiet as the sky in luma) and the dots, but for the
                // border's fixed samples, whose tiny cells may miss every dot.
                others += 1;
                assert_eq!(m, n, "{p} has structure: its own ellipse");
            }
        }
        assert!(
            sky >= 10 && others >= 10,
            "{sky} sky and {others} other strokes"
        );
    }
}
