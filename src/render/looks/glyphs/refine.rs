//! Coarse-to-fine painting of brush strokes (Hertzmann, *Painterly Rendering with Curved Brush
//! Strokes of Multiple Sizes*, 1998): the samples' strokes, sorted broad first, are laid in
//! [`LAYERS`] layers of falling size, a stroke of a later layer only where the canvas as the layers
//! before left it still differs from the photo ([`Refinement`]); then, as the paper's finer
//! brushes, strokes of half and of a quarter a sample's size, at the quarters of a stroke's
//! footprint and at theirs, where the canvas, after the strokes stopped at edges, still differs
//! ([`detail_strokes`]), in the photo's colour at their point. Eyes, nostrils and thin dark lines
//! smaller than a sample's ellipse, which the samples' strokes paint over with the colour of the
//! cell around them, come back as small strokes along the same field.

use crate::field::Tensor;
use crate::render::scene::Scene;
use crate::render::support::colour::{linear_of, Linear};
use glam::DVec2;
use rayon::prelude::*;
use tiny_skia::Pixmap;

/// Coarse-to-fine painting (Hertzmann, *Painterly Rendering with Curved Brush Strokes of
/// Multiple Sizes*, 1998): brush strokes, sorted broad first, are laid in [`LAYERS`] layers of
/// falling size. The first layer is laid whole; a stroke of a later layer is laid only where
/// the canvas as the layers before left it still differs from the photo by more than
/// `refine` (mean sRGB distance, 0 to 1, over five points of the stroke's footprint), so fine
/// strokes go where the picture has detail and broad strokes stay whole where it has none.
pub(crate) struct Refinement<'a> {
    /// The photo as 8-bit RGB (borrowed when it is one already: no 36 MB copy at 12 MP).
    photo: std::borrow::Cow<'a, image::RgbImage>,
    /// Photo pixels per domain unit.
    photo_scale: DVec2,
    /// First glyph index of every layer after the first.
    starts: Vec<usize>,
    threshold: f32,
}

/// Layers of strokes from broad to fine.
pub const LAYERS: usize = 3;

/// The refinement of `n` brush strokes over `scene`'s photo at `threshold` (the look's
/// `refine`), when there is a photo, a positive threshold and a stroke for every layer.
pub(crate) fn refinement<'a>(
    scene: &Scene<'a>,
    threshold: f32,
    n: usize,
) -> Option<Refinement<'a>> {
    let photo = scene.photo?;
    if threshold <= 0.0 || n < LAYERS {
        return None;
    }
    let d = scene.raster.domain;
    Some(Refinement {
        photo: crate::render::support::colour::rgb8(photo),
        photo_scale: DVec2::new(
            f64::from(photo.width()) / d.x,
            f64::from(photo.height()) / d.y,
        ),
        starts: (1..LAYERS).map(|l| l * n / LAYERS).collect(),
        threshold,
    })
}

impl Refinement<'_> {
    /// The layer that starts at glyph `k`, if one does (layers after the first).
    pub(crate) fn layer_starting_at(&self, k: usize) -> Option<usize> {
        self.starts.iter().position(|&s| s == k)
    }

    /// Decides which strokes of `layer` are laid, from the canvas before it (in parallel;
    /// the decisions do not depend on each other, so neither on the thread count).
    pub(crate) fn choose(
        &self,
        canvas: &Pixmap,
        glyphs: &[(DVec2, Tensor, Linear)],
        layer: usize,
        keep: &mut [bool],
        scale: (f64, f64),
    ) {
        let start = self.starts[layer];
        let end = self.starts.get(layer + 1).copied().unwrap_or(glyphs.len());
        keep[start..end]
            .par_iter_mut()
            .zip(&glyphs[start..end])
            .for_each(|(keep, (p, m, _))| {
                *keep = self.error(canvas, *p, m, scale) > self.threshold
            });
    }

    /// Mean sRGB distance (0 to 1) between canvas and photo at the centre of a stroke at `p`
    /// with metric `m` and at half its semi-axes either side.
    fn error(&self, canvas: &Pixmap, p: DVec2, m: &Tensor, scale: (f64, f64)) -> f32 {
        let total: f32 = footprint(p, m)
            .iter()
            .map(|&q| srgb_distance(canvas_at(canvas, q, scale), self.photo_at(q)))
            .sum();
        total / 5.0
    }

    /// Whether a detail stroke of `colour` at `p` with metric `m` is laid: the canvas differs
    /// from the photo there by more than the threshold ([`Self::error`]), the stroke's colour
    /// would bring that difference down by half the threshold, and at none of the footprint's
    /// points would its colour be further from the photo than the canvas is (by more than
    /// [`DETAIL_SLACK`]): a stroke that would cross an edge into a region of another colour is
    /// not laid, so details do not smear the edges the strokes stopped at.
    fn takes_detail(
        &self,
        canvas: &Pixmap,
        p: DVec2,
        m: &Tensor,
        colour: [u8; 3],
        scale: (f64, f64),
    ) -> bool {
        let (mut now, mut then) = (0.0, 0.0);
        for q in footprint(p, m) {
            let photo = self.photo_at(q);
            let (before, after) = (
                srgb_distance(canvas_at(canvas, q, scale), photo),
                srgb_distance(colour, photo),
            );
            if after > before + DETAIL_SLACK {
                return false;
            }
            (now, then) = (now + before / 5.0, then + after / 5.0);
        }
        now > self.threshold && then < now - 0.5 * self.threshold
    }

    /// The photo's pixel under `q` (domain units).
    fn photo_at(&self, q: DVec2) -> [u8; 3] {
        let px = ((q.x * self.photo_scale.x) as i64).clamp(0, i64::from(self.photo.width()) - 1);
        let py = ((q.y * self.photo_scale.y) as i64).clamp(0, i64::from(self.photo.height()) - 1);
        self.photo.get_pixel(px as u32, py as u32).0
    }

    /// The photo's mean sRGB colour over the 3 × 3 pixels around `p` (domain units).
    fn photo_mean(&self, p: DVec2) -> [u8; 3] {
        let (w, h) = (
            i64::from(self.photo.width()),
            i64::from(self.photo.height()),
        );
        let (cx, cy) = (
            (p.x * self.photo_scale.x) as i64,
            (p.y * self.photo_scale.y) as i64,
        );
        let mut sum = [0u32; 3];
        for dy in -1..=1 {
            for dx in -1..=1 {
                let x = (cx + dx).clamp(0, w - 1) as u32;
                let y = (cy + dy).clamp(0, h - 1) as u32;
                let c = self.photo.get_pixel(x, y).0;
                for k in 0..3 {
                    sum[k] += u32::from(c[k]);
                }
            }
        }
        sum.map(|v| ((v + 4) / 9) as u8)
    }
}

/// A detail stroke's ellipse relative to the stroke it refines (per axis).
const DETAIL_SIZE: f64 = 0.5;

/// Levels of detail strokes, each [`DETAIL_SIZE`] the size of the one before.
pub(crate) const DETAIL_LEVELS: u32 = 2;

/// Detail strokes of `level` (1, 2, …) for `glyphs` (centre, metric, colour) on `canvas` as
/// the strokes before left it. A glyph's ellipse is cut in quarters (half its semi-axes either
/// side along and across), each quarter again at the next level: at `level` a glyph has
/// `4^level` candidates with its metric scaled by `DETAIL_SIZE^level`, each laid where
/// [`Refinement::takes_detail`]. Their colour is the photo's, a 3 × 3 pixel mean at the point.
/// In glyph order, then candidate order: the same strokes at any thread count.
#[must_use]
pub(crate) fn detail_strokes(
    refine: &Refinement,
    canvas: &Pixmap,
    glyphs: &[(DVec2, Tensor, Linear)],
    level: u32,
    scale: (f64, f64),
) -> Vec<(DVec2, Tensor, Linear)> {
    glyphs
        .par_iter()
        .flat_map_iter(|&(p, m, _)| {
            let e = m.eigen();
            let (u, v) = (e.e1() * e.l1.abs(), e.e2() * e.l2.abs());
            let small = m.map_eigenvalues(|l| l * DETAIL_SIZE.powi(level as i32));
            (0..1u32 << (2 * level)).filter_map(move |code| {
                // Two bits per level: the side along, the side across.
                let q = (1..=level).fold(p, |q, l| {
                    let bits = code >> (2 * (l - 1));
                    let half = DETAIL_SIZE.powi(l as i32);
                    let along = if bits & 1 == 0 { half } else { -half };
                    let across = if bits & 2 == 0 { half } else { -half };
                    q + u * along + v * across
                });
                let colour = refine.photo_mean(q);
                refine
                    .takes_detail(canvas, q, &small, colour, scale)
                    .then(|| (q, small, linear_of(colour)))
            })
        })
        .collect()
}

/// The five points a stroke's difference from the photo is read at: its centre and half its
/// semi-axes either side along and across.
fn footprint(p: DVec2, m: &Tensor) -> [DVec2; 5] {
    let e = m.eigen();
    let (u, v) = (e.e1() * (0.5 * e.l1.abs()), e.e2() * (0.5 * e.l2.abs()));
    [p, p + u, p - u, p + v, p - v]
}

/// The canvas's pixel under `q` (domain units; `(sx, sy)` canvas pixels per unit).
fn canvas_at(canvas: &Pixmap, q: DVec2, (sx, sy): (f64, f64)) -> [u8; 3] {
    let cx = ((q.x * sx) as i64).clamp(0, i64::from(canvas.width()) - 1) as u32;
    let cy = ((q.y * sy) as i64).clamp(0, i64::from(canvas.height()) - 1) as u32;
    canvas
        .pixel(cx, cy)
        .map_or([0; 3], |c| [c.red(), c.green(), c.blue()])
}

/// Distance of two sRGB colours, 0 to 1 (Euclidean over channels, over its largest value).
fn srgb_distance(a: [u8; 3], b: [u8; 3]) -> f32 {
    let d2: f32 = (0..3)
        .map(|k| (f32::from(a[k]) - f32::from(b[k])).powi(2))
        .sum();
    d2.sqrt() / (255.0 * 3f32.sqrt())
}

/// How much further from the photo than the canvas a detail stroke may be at one of its
/// points ([`Refinement::takes_detail`]).
const DETAIL_SLACK: f32 = 0.02;

#[cfg(test)]
mod tests {
    use super::*;
    use tiny_skia::Color;

    /// A photo with a flat left half and stripes one pixel wide on the right.
    fn photo() -> image::RgbImage {
        image::RgbImage::from_fn(64, 32, |x, _| {
            if x < 32 || x % 2 == 0 {
                image::Rgb([200, 120, 60])
            } else {
                image::Rgb([20, 20, 90])
            }
        })
    }

    /// A canvas painted the flat colour all over, as broad strokes would leave it.
    fn broad_canvas() -> Pixmap {
        let mut canvas = Pixmap::new(64, 32).unwrap();
        canvas.fill(Color::from_rgba8(200, 120, 60, 255));
        canvas
    }

    /// A refinement of `photo` (one pixel per domain unit) with layers from `starts`, at the
    /// strokes preset's threshold.
    fn refinement_of(photo: image::RgbImage, starts: Vec<usize>) -> Refinement<'static> {
        Refinement {
            photo: std::borrow::Cow::Owned(photo),
            photo_scale: DVec2::ONE,
            starts,
            threshold: 0.06,
        }
    }

    #[test]
    fn finer_strokes_go_only_where_the_canvas_still_differs_from_the_photo() {
        let r = refinement_of(photo(), vec![1, 3]);
        let m = Tensor::from_eigen(0.0, 3.0, 1.5);
        let grey = [0.5; 3];
        // One broad stroke, then two fine ones on the flat half and two on the stripes.
        let glyphs = [
            (DVec2::new(16.0, 16.0), m, grey),
            (DVec2::new(8.0, 8.0), m, grey),
            (DVec2::new(20.0, 24.0), m, grey),
            (DVec2::new(44.0, 8.0), m, grey),
            (DVec2::new(52.0, 24.0), m, grey),
        ];
        let canvas = broad_canvas();
        let mut keep = vec![true; glyphs.len()];
        r.choose(&canvas, &glyphs, 0, &mut keep, (1.0, 1.0));
        r.choose(&canvas, &glyphs, 1, &mut keep, (1.0, 1.0));
        assert_eq!(keep, [true, false, false, true, true]);
        // A blank canvas differs from the photo everywhere: every stroke is laid.
        let blank = Pixmap::new(64, 32).unwrap();
        let mut keep = vec![false; glyphs.len()];
        keep[0] = true;
        r.choose(&blank, &glyphs, 0, &mut keep, (1.0, 1.0));
        r.choose(&blank, &glyphs, 1, &mut keep, (1.0, 1.0));
        assert!(keep.iter().all(|&k| k));
    }

    #[test]
    fn detail_strokes_go_to_what_the_strokes_painted_over_and_stop_at_edges() {
        // The photo: ground A, a dark 6 × 6 spot at (18..24, 12..18), colour B from x = 40 on.
        // The canvas: A with the spot painted over, a wrong colour W on 40 ≤ x < 46 (strokes
        // that did not stop at the edge), then B.
        let (a, b, w, dark) = ([200, 120, 60], [30, 90, 160], [0, 200, 0], [20, 20, 20]);
        let photo = image::RgbImage::from_fn(64, 32, |x, y| {
            image::Rgb(if x >= 40 {
                b
            } else if (18..24).contains(&x) && (12..18).contains(&y) {
                dark
            } else {
                a
            })
        });
        let mut canvas = Pixmap::new(64, 32).unwrap();
        canvas.fill(Color::from_rgba8(a[0], a[1], a[2], 255));
        for (x, width, c) in [(40.0, 6.0, w), (46.0, 18.0, b)] {
            let rect = tiny_skia::Rect::from_xywh(x, 0.0, width, 32.0).unwrap();
            let mut paint = tiny_skia::Paint::default();
            paint.set_color(Color::from_rgba8(c[0], c[1], c[2], 255));
            canvas.fill_rect(rect, &paint, tiny_skia::Transform::identity(), None);
        }
        let r = refinement_of(photo, vec![1, 2]);
        let m = Tensor::from_eigen(0.0, 8.0, 4.0);
        let grey = [0.5; 3];
        let glyphs = [
            (DVec2::new(22.0, 16.0), m, grey),
            (DVec2::new(8.0, 8.0), m, grey),
            (DVec2::new(42.0, 16.0), m, grey),
            (DVec2::new(54.0, 16.0), m, grey),
        ];
        let mut laid = Vec::new();
        for level in 1..=DETAIL_LEVELS {
            laid.extend(detail_strokes(&r, &canvas, &glyphs, level, (1.0, 1.0)));
        }
        // Dark strokes on the spot and strokes of B over W, none of them reaching back over
        // the edge at x = 40 (they would smear B, or a mix, over A); nothing anywhere else (a
        // stroke that would change nothing, A beside the spot, is not laid either).
        let on_spot = |p: DVec2| (18.0..24.0).contains(&p.x) && (12.0..18.0).contains(&p.y);
        assert!(laid.iter().any(|(p, _, _)| on_spot(*p)), "{laid:?}");
        assert!(laid.iter().any(|(p, _, _)| p.x > 40.0), "{laid:?}");
        for (p, m, c) in &laid {
            if on_spot(*p) {
                // Dark, or at the spot's rim a mix of the spot and A, at most half as light.
                let ground = linear_of(a);
                assert!(
                    (0..3).all(|k| c[k] < 0.5 * ground[k]),
                    "a light stroke on the spot: {c:?}"
                );
            } else {
                assert_eq!(*c, linear_of(b), "{p}");
                assert!(p.x - m.eigen().l1 / 2.0 >= 40.0, "{p}, {m:?}");
            }
        }
        // The same glyphs on a canvas that is the photo: nothing to add.
        let mut exact = Pixmap::new(64, 32).unwrap();
        for (px, q) in exact.pixels_mut().iter_mut().zip(r.photo.pixels()) {
            *px = tiny_skia::ColorU8::from_rgba(q.0[0], q.0[1], q.0[2], 255).premultiply();
        }
        for level in 1..=DETAIL_LEVELS {
            assert!(detail_strokes(&r, &exact, &glyphs, level, (1.0, 1.0)).is_empty());
        }
    }
}
