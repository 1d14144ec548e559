//! Glyphs (paper section 7.1): an ellipse (or rectangle, or superquadric) per sample, its
//! axes the metric's, drawn anti-aliased with tiny-skia. Placing them at the relaxed samples
//! packs them densely without overlaps; a regular grid or random positions, with the same
//! field and about the same count, give the paper's comparison (Figures 5b-d, 6a-b).
//!
//! Over a photo, glyphs may stand on a wash of their cell's colour (`ground`), their own
//! colours solved so that glyph and wash average to the cell's (`placed`), and kept on their
//! side of the photo's edges (`edge_stop.rs`); brush strokes are laid coarse to fine after
//! Hertzmann (1998), finer strokes only where the canvas still differs from the photo, then
//! strokes half their size where it still does (`refine.rs`).

mod edge_stop;
mod flat_strokes;
mod refine;
pub(crate) mod svg;

use crate::field::blur::round_to_byte;
use crate::field::Tensor;
use crate::render::cells::raster::Raster;
use crate::render::scene::Scene;
use crate::render::support::colour::{anisotropy_colour, linear_of, to_srgb, Linear};
use crate::render::support::hash::salt;
use crate::sampling::rng::Rng;
use edge_stop::{keep_out_across_edges, stop_at_edges};
use glam::DVec2;
use image::RgbImage;
use tiny_skia::{Color, FillRule, Paint, Path, PathBuilder, Pixmap, Rect, Stroke, Transform};

/// Where the glyphs go.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Placement {
    /// At the relaxed samples.
    #[default]
    Relaxed,
    /// On a square grid whose spacing gives about as many glyphs as samples.
    Grid,
    /// Uniformly at random, as many as samples (seeded, deterministic).
    Random,
}

/// The glyph's outline.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Shape {
    /// An ellipse.
    #[default]
    Ellipse,
    /// A rectangle with the ellipse's axes.
    Rectangle,
    /// A superquadric `|x|^p + |y|^p = 1` (p = 2: ellipse; large p: rectangle).
    Superquadric(f32),
    /// A brush stroke: blunt where it starts, tapering to its end, with bristle streaks
    /// along its length (a gradient across it).
    Brush,
}

/// What colour fills a glyph.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GlyphColour {
    /// The cell's colour (the photo under it; the anisotropy map without a photo).
    #[default]
    Cell,
    /// The colour map of the ellipse's anisotropy.
    Anisotropy,
}

/// Parameters of the glyph look.
#[derive(Clone, Debug, PartialEq)]
pub struct GlyphParams {
    /// Placement.
    pub placement: Placement,
    /// Shape.
    pub shape: Shape,
    /// Glyph size relative to the sample's ellipse.
    pub scale: f32,
    /// Fill colour.
    pub colour: GlyphColour,
    /// Outline width in output pixels (0: none).
    pub outline_width: f32,
    /// Outline colour, sRGB.
    pub outline: [u8; 3],
    /// Background colour, sRGB.
    pub background: [u8; 3],
    /// Seed of random placement.
    pub seed: u64,
    /// Paint the cells in their colours first (no borders), so overlapping glyphs such as
    /// brush strokes leave no paper showing.
    pub underpaint: bool,
    /// Without underpainting, how much of its cell's colour the ground under a glyph takes
    /// (0: the plain background; 1: the cell's colour). Over a photo, glyph colours are then
    /// solved so that glyph and ground average to the cell's colour (`placed`).
    pub ground: f32,
    /// Brush strokes over a photo: a stroke finer than the broadest third is laid only where
    /// the canvas still differs from the photo by more than this (mean sRGB distance, 0 to 1),
    /// and so are the detail strokes of half and a quarter the size; 0 lays every stroke and
    /// no detail strokes. See `refine.rs`.
    pub refine: f32,
    /// Brush strokes over a photo at the samples: the direction (degrees from the x axis,
    /// y down) of the long strokes laid across flat areas, where the cells have no structure
    /// (`flat_strokes.rs`). `None`: every stroke keeps its cell's ellipse, round there.
    pub flat_angle: Option<f32>,
}

impl Default for GlyphParams {
    fn default() -> Self {
        GlyphParams {
            placement: Placement::Relaxed,
            shape: Shape::Ellipse,
            scale: 0.95,
            colour: GlyphColour::Cell,
            outline_width: 0.0,
            outline: [30, 30, 30],
            background: [250, 248, 242],
            seed: 0,
            underpaint: false,
            ground: 0.0,
            refine: 0.0,
            flat_angle: None,
        }
    }
}

/// Renders the glyphs of `scene`.
#[must_use]
pub fn glyphs(scene: &Scene, params: &GlyphParams) -> RgbImage {
    painted(scene, params).0
}

/// The glyphs as the picture lays them, in drawing order (centre, metric, colour): every
/// placed glyph, or, where brush strokes are refined coarse to fine, the strokes the canvas
/// chose and then the detail strokes (found by painting the picture). The vector form draws
/// this list, so it shows what the PNG shows.
pub(crate) fn laid(scene: &Scene, params: &GlyphParams) -> Vec<(DVec2, Tensor, Linear)> {
    let glyphs = placed(scene, params);
    // Without a refinement every placed glyph is laid: no picture needs painting to know.
    let refined = params.shape == Shape::Brush
        && refine::refinement(scene, params.refine, glyphs.len()).is_some();
    if refined {
        painted(scene, params).1
    } else {
        glyphs
    }
}

/// The picture of the glyphs of `scene` and the glyphs it laid, in order ([`laid`]).
pub(crate) fn painted(
    scene: &Scene,
    params: &GlyphParams,
) -> (RgbImage, Vec<(DVec2, Tensor, Linear)>) {
    let r = scene.raster;
    let (w, h) = (r.width as u32, r.height as u32);
    let mut pixmap = Pixmap::new(w, h).expect("output size is non-zero");
    let (glyphs, kappa) = placed_and_share(scene, params);
    let mut underpainting = None;
    let washed = !params.underpaint && params.ground > 0.0 && tone_kept(scene, params);
    if params.underpaint {
        // One owning site per pixel, not supersampled, as the wash below: the underpainting
        // shows only between the strokes.
        let flat: Vec<[u8; 3]> = scene.colours.iter().map(|c| c.map(to_srgb)).collect();
        let bg = params.background;
        let centres = Raster {
            supersample: 1,
            ..r
        };
        let mut cells = RgbImage::new(w, h);
        scene
            .cells
            .site_rows(&centres, cells.as_mut(), 3 * w as usize, |_, sites, row| {
                for (px, &site) in row.chunks_exact_mut(3).zip(sites) {
                    px.copy_from_slice(&flat.get(site as usize).copied().unwrap_or(bg));
                }
            });
        for (px, rgb) in pixmap.pixels_mut().iter_mut().zip(cells.pixels()) {
            let [cr, cg, cb] = rgb.0;
            *px = tiny_skia::ColorU8::from_rgba(cr, cg, cb, 255).premultiply();
        }
        underpainting = Some(cells);
    } else if params.ground > 0.0 && tone_kept(scene, params) {
        // One owning site per pixel, not supersampled: the wash shows only between the glyphs.
        // The sites (no runner-up or distance) are handed row by row straight into the canvas
        // (no owner map of the picture).
        let washes: Vec<[u8; 3]> = grounds(scene, params, kappa)
            .into_iter()
            .map(|g| g.map(to_srgb))
            .collect();
        let bg = params.background;
        let centres = Raster {
            supersample: 1,
            ..r
        };
        scene.cells.site_rows(
            &centres,
            pixmap.pixels_mut(),
            w as usize,
            |_, sites, row| {
                for (px, &site) in row.iter_mut().zip(sites) {
                    let [cr, cg, cb] = washes.get(site as usize).copied().unwrap_or(bg);
                    *px = tiny_skia::ColorU8::from_rgba(cr, cg, cb, 255).premultiply();
                }
            },
        );
    } else {
        let bg = params.background;
        pixmap.fill(Color::from_rgba8(bg[0], bg[1], bg[2], 255));
    }
    let DVec2 { x: sx, y: sy } = r.pixels_per_domain_unit();
    let mut line = Paint::default();
    let o = params.outline;
    line.set_color(Color::from_rgba8(o[0], o[1], o[2], 255));
    let refine = (params.shape == Shape::Brush)
        .then(|| refine::refinement(scene, params.refine, glyphs.len()))
        .flatten();
    let mut keep = vec![true; glyphs.len()];
    let mut laid = Vec::with_capacity(glyphs.len());
    for (k, &(p, m, colour)) in glyphs.iter().enumerate() {
        if let Some(r) = &refine {
            if let Some(layer) = r.layer_starting_at(k) {
                r.choose(&pixmap, &glyphs, layer, &mut keep, (sx, sy));
            }
            if !keep[k] {
                continue;
            }
        }
        laid.push((p, m, colour));
        draw_glyph(
            &mut pixmap,
            params,
            &line,
            (p, m, colour),
            k as u32,
            (sx, sy),
        );
    }
    if let (Some(under), Some(_)) = (&underpainting, scene.cells.colour()) {
        stop_at_edges(pixmap.data_mut(), under.as_raw());
    } else if washed && params.placement == Placement::Relaxed && scene.cells.colour().is_some() {
        // Per cell: wash, glyph and the cell's own colour, sRGB levels.
        let levels = |c: Linear| c.map(|v| f32::from(to_srgb(v)));
        let expected: Vec<[[f32; 3]; 3]> = scene
            .colours
            .iter()
            .map(|&c| {
                let (ground, glyph) = ground_and_glyph(params, c, kappa);
                [levels(ground), levels(glyph), levels(c)]
            })
            .collect();
        keep_out_across_edges(scene, &expected, &mut pixmap);
    }
    if let Some(r) = &refine {
        let mut index = glyphs.len() as u32;
        for level in 1..=refine::DETAIL_LEVELS {
            let details = refine::detail_strokes(r, &pixmap, &glyphs, level, (sx, sy));
            for &glyph in &details {
                draw_glyph(&mut pixmap, params, &line, glyph, index, (sx, sy));
                index = index.wrapping_add(1);
            }
            laid.extend(details);
        }
    }
    let rgb = rgba_to_rgb_in_place(pixmap.take());
    let image = RgbImage::from_raw(w, h, rgb).expect("w·h RGB pixels");
    (image, laid)
}

/// Draws one glyph (centre, metric, colour; `k` its index, which seeds its bristles) on
/// `pixmap` at `(sx, sy)` output pixels per domain unit.
fn draw_glyph(
    pixmap: &mut Pixmap,
    params: &GlyphParams,
    line: &Paint,
    (p, m, colour): (DVec2, Tensor, Linear),
    k: u32,
    (sx, sy): (f64, f64),
) {
    let e = m.eigen();
    let (a, b) = (
        e.l1.abs() * f64::from(params.scale),
        e.l2.abs() * f64::from(params.scale),
    );
    if !(a > 0.0 && b > 0.0 && a.is_finite()) {
        return;
    }
    let Some(path) = outline(params.shape, a as f32, b as f32) else {
        return;
    };
    let t = Transform::from_rotate(e.angle.to_degrees() as f32)
        .post_translate(p.x as f32, p.y as f32)
        .post_scale(sx as f32, sy as f32);
    let fill = glyph_paint(params.shape, colour, b as f32, k);
    pixmap.fill_path(&path, &fill, FillRule::Winding, t, None);
    if params.outline_width > 0.0 {
        // The stroke width is given in output pixels: undo the scale for it.
        let s = Stroke {
            width: params.outline_width / ((sx * sy).sqrt() as f32),
            ..Stroke::default()
        };
        pixmap.stroke_path(&path, line, &s, t, None);
    }
}

/// The RGB bytes of opaque RGBA pixels, compacted in the same buffer: a 12 MP canvas is not
/// held twice (48 MB of RGBA beside 36 MB of RGB).
fn rgba_to_rgb_in_place(mut data: Vec<u8>) -> Vec<u8> {
    let n = data.len() / 4;
    // Pixel i moves from 4i to 3i ≤ 4i: every byte is read before it is overwritten.
    // (The whole canvas in one pass: about 30 ms at 12 MP.)
    for i in 0..n {
        data.copy_within(4 * i..4 * i + 3, 3 * i);
    }
    data.truncate(3 * n);
    data.shrink_to_fit();
    data
}

/// Bristle streaks of a brush stroke: this many across its width.
const BRISTLES: usize = 7;

/// The paint of glyph `k`: its colour, and for brush strokes a gradient across the stroke
/// (local y from −b to b) whose stops are the colour lightened or darkened per bristle.
fn glyph_paint(shape: Shape, colour: Linear, b: f32, k: u32) -> Paint<'static> {
    let mut paint = Paint::default();
    let srgb = |c: Linear| {
        let [r, g, b] = c.map(to_srgb);
        Color::from_rgba8(r, g, b, 255)
    };
    if shape != Shape::Brush {
        paint.set_color(srgb(colour));
        return paint;
    }
    let stops: Vec<tiny_skia::GradientStop> = (0..BRISTLES)
        .map(|i| {
            let shade = 1.0
                + 0.3
                    * (crate::render::support::hash::site_hash(
                        k.wrapping_mul(31) + i as u32,
                        salt::GLYPH_BRISTLE,
                    ) - 0.5);
            let c = colour.map(|v| (v * shade).clamp(0.0, 1.0));
            tiny_skia::GradientStop::new(i as f32 / (BRISTLES - 1) as f32, srgb(c))
        })
        .collect();
    match tiny_skia::LinearGradient::new(
        tiny_skia::Point::from_xy(0.0, -b),
        tiny_skia::Point::from_xy(0.0, b),
        stops,
        tiny_skia::SpreadMode::Pad,
        Transform::identity(),
    ) {
        Some(shader) => paint.shader = shader,
        None => paint.set_color(srgb(colour)),
    }
    paint
}

/// Whether glyph colours are solved for the photo's tone: glyphs in the photo's colours over
/// a background or ground (an underpainting already has the tone).
pub(crate) fn tone_kept(scene: &Scene, params: &GlyphParams) -> bool {
    scene.photo.is_some() && !params.underpaint && params.colour == GlyphColour::Cell
}

/// The ground under the glyph of a cell of colour `c`: the background, `ground` of the way to
/// `c` in the sRGB encoding.
fn ground_colour(params: &GlyphParams, c: Linear) -> Linear {
    let bg = linear_of(params.background);
    std::array::from_fn(|k| encoded_mix(bg[k], c[k], params.ground))
}

/// Where [`tone_kept`], the ground under the glyph of a cell of colour `c` and the glyph's
/// colour, which average to `c` seen from afar when the glyphs cover a share `kappa` of the
/// picture: the ground is [`ground_colour`] and the glyph `(c − (1 − κ)·ground) / κ`, in the
/// sRGB encoding, channel by channel. Where that glyph would be darker than black (a cell
/// darker than its ground allows: a black sky, whose wash 15 % towards the paper left a grey
/// mesh between black glyphs), the glyph is black and the ground takes the rest,
/// `c / (1 − κ)`; where it would be lighter than white, likewise.
pub(crate) fn ground_and_glyph(params: &GlyphParams, c: Linear, kappa: f32) -> (Linear, Linear) {
    let g = ground_colour(params, c);
    let enc = |v: f32| f32::from(to_srgb(v));
    let mut ground = g;
    let glyph = std::array::from_fn(|k| {
        let (ce, ge) = (enc(c[k]), enc(g[k]));
        let e = (ce - (1.0 - kappa) * ge) / kappa;
        let inked = e.clamp(0.0, 255.0);
        if inked != e {
            let rest = (ce - kappa * inked) / (1.0 - kappa);
            ground[k] = crate::render::support::colour::to_linear(round_to_byte(rest));
        }
        crate::render::support::colour::to_linear(round_to_byte(e))
    });
    (ground, glyph)
}

/// The grounds under the glyphs of every cell ([`ground_and_glyph`]), the glyphs covering a
/// share `kappa` of the picture ([`glyph_cover`]).
pub(crate) fn grounds(scene: &Scene, params: &GlyphParams, kappa: f32) -> Vec<Linear> {
    scene
        .colours
        .iter()
        .map(|&c| ground_and_glyph(params, c, kappa).0)
        .collect()
}

/// The share of the picture the glyphs of `scene` cover ([`glyph_share`]).
pub(crate) fn glyph_cover(scene: &Scene, params: &GlyphParams) -> f32 {
    glyph_share(scene, &placed_unordered(scene, params), params)
}

/// The share of the picture `glyphs` cover, as ellipses of their metrics' axes (the union:
/// where they overlap, the paper between them shows as much as if they did not), kept within
/// [0.3, 0.97]. Counted at the points of a grid over the domain of at most
/// [`SHARE_POINTS`] points. The sum of their areas, which it was, counts overlaps twice: a
/// packing's glyphs covering 0.86 of a flat grey summed to 0.95, and every tone came out
/// lighter than the photo's, a dark grey of 35 as 39.
fn glyph_share(scene: &Scene, glyphs: &[(DVec2, Tensor, Linear)], params: &GlyphParams) -> f32 {
    let d = scene.field.domain();
    let step = ((d.x * d.y) / SHARE_POINTS).sqrt().max(1e-9);
    let (nx, ny) = ((d.x / step).ceil() as usize, (d.y / step).ceil() as usize);
    let mut covered = vec![false; nx * ny];
    let scale = f64::from(params.scale);
    for (p, m, _) in glyphs {
        let Some(inverse) = m.inverse() else {
            continue;
        };
        // The ellipse's extent along x and y: the square roots of the diagonal of m².
        let m2 = m.squared();
        let reach = DVec2::new(m2.xx.sqrt(), m2.yy.sqrt()) * scale;
        let index = |v: f64, n: usize| (v / step - 0.5).clamp(0.0, n as f64 - 1.0);
        let (lo, hi) = (*p - reach, *p + reach);
        let (x0, x1) = (index(lo.x, nx).ceil() as usize, index(hi.x, nx) as usize);
        let (y0, y1) = (index(lo.y, ny).ceil() as usize, index(hi.y, ny) as usize);
        for j in y0..=y1 {
            for i in x0..=x1 {
                let q = DVec2::new((i as f64 + 0.5) * step, (j as f64 + 0.5) * step);
                if inverse.mul_vec(q - *p).length_squared() <= scale * scale {
                    covered[j * nx + i] = true;
                }
            }
        }
    }
    let share = covered.iter().filter(|&&c| c).count() as f64 / covered.len().max(1) as f64;
    (share as f32).clamp(0.3, 0.97)
}

/// Points of the grid [`glyph_share`] counts on: the share to within a few thousandths.
const SHARE_POINTS: f64 = 1_000_000.0;

/// `a + (b − a)·t` in the sRGB encoding (how paint and paper average seen from afar).
fn encoded_mix(a: f32, b: f32, t: f32) -> f32 {
    let enc = |v: f32| f32::from(to_srgb(v));
    let e = enc(a) + (enc(b) - enc(a)) * t;
    crate::render::support::colour::to_linear(round_to_byte(e))
}

/// Glyph centres, metrics and colours for the placement, in drawing order: brush strokes
/// broad first and details over them (ties keep the sample order), others as placed.
///
/// Where [`tone_kept`], a glyph's colour is solved so that it and the ground around it
/// average to the cell's colour seen from afar ([`ground_and_glyph`], with `κ` the share of
/// the picture the glyphs cover).
pub(crate) fn placed(scene: &Scene, params: &GlyphParams) -> Vec<(DVec2, Tensor, Linear)> {
    placed_and_share(scene, params).0
}

/// [`placed`], and the share of the picture the glyphs cover ([`glyph_share`]).
fn placed_and_share(scene: &Scene, params: &GlyphParams) -> (Vec<(DVec2, Tensor, Linear)>, f32) {
    let mut glyphs = placed_unordered(scene, params);
    let kappa = glyph_share(scene, &glyphs, params);
    if tone_kept(scene, params) {
        for (_, _, c) in &mut glyphs {
            *c = ground_and_glyph(params, *c, kappa).1;
        }
    }
    let at_samples = params.placement == Placement::Relaxed && scene.photo.is_some();
    if let (Shape::Brush, true, Some(angle)) = (params.shape, at_samples, params.flat_angle) {
        flat_strokes::lay_long_strokes(scene, &mut glyphs, f64::from(angle).to_radians());
    }
    if params.shape == Shape::Brush {
        let area = |m: &Tensor| m.det().abs();
        glyphs.sort_by(|a, b| area(&b.1).total_cmp(&area(&a.1)));
    }
    (glyphs, kappa)
}

fn placed_unordered(scene: &Scene, params: &GlyphParams) -> Vec<(DVec2, Tensor, Linear)> {
    let cells = &scene.cells;
    let colour_of = |i: usize, m: &Tensor| match params.colour {
        GlyphColour::Cell => scene.colours[i],
        GlyphColour::Anisotropy => anisotropy_colour(m),
    };
    let n = cells.positions().len();
    let positions: Vec<DVec2> = match params.placement {
        Placement::Relaxed => {
            return (0..n)
                .map(|i| {
                    let m = cells.metrics()[i];
                    (cells.positions()[i], m, colour_of(i, &m))
                })
                .collect();
        }
        Placement::Grid => {
            let d = scene.field.domain();
            let spacing = (d.x * d.y / n.max(1) as f64).sqrt();
            let (cols, rows) = (
                (d.x / spacing).ceil() as usize,
                (d.y / spacing).ceil() as usize,
            );
            (0..rows)
                .flat_map(|j| {
                    (0..cols).map(move |i| {
                        DVec2::new((i as f64 + 0.5) * spacing, (j as f64 + 0.5) * spacing)
                    })
                })
                .filter(|p| p.x < d.x && p.y < d.y)
                .collect()
        }
        Placement::Random => {
            let mut rng = Rng::new(params.seed, 2);
            let d = scene.field.domain();
            (0..n)
                .map(|_| DVec2::new(rng.uniform() * d.x, rng.uniform() * d.y))
                .collect()
        }
    };
    let photo = scene.photo.map(crate::render::support::colour::rgb8);
    positions
        .into_iter()
        .map(|p| {
            let m = scene.field.sample(p);
            // Off the samples there is no cell colour: the photo's pixel under the glyph, or
            // the anisotropy map.
            let c = match (&photo, params.colour) {
                (Some(img), GlyphColour::Cell) => {
                    let x = (p.x as u32).min(img.width() - 1);
                    let y = (p.y as u32).min(img.height() - 1);
                    linear_of(img.get_pixel(x, y).0)
                }
                _ => anisotropy_colour(&m),
            };
            (p, m, c)
        })
        .collect()
}

/// The glyph outline for semi-axes `a` (along x) and `b`, centred at the origin.
fn outline(shape: Shape, a: f32, b: f32) -> Option<Path> {
    match shape {
        Shape::Ellipse => PathBuilder::from_oval(Rect::from_xywh(-a, -b, 2.0 * a, 2.0 * b)?),
        Shape::Rectangle => Some(PathBuilder::from_rect(Rect::from_xywh(
            -a,
            -b,
            2.0 * a,
            2.0 * b,
        )?)),
        Shape::Superquadric(_) | Shape::Brush => {
            let points = polygon(shape, a, b, 64);
            let mut pb = PathBuilder::new();
            pb.move_to(points[0][0], points[0][1]);
            for p in &points[1..] {
                pb.line_to(p[0], p[1]);
            }
            pb.close();
            pb.finish()
        }
    }
}

/// `steps` points around the outline of `shape` with semi-axes `a` (along x) and `b`, for
/// the shapes drawn as polygons: a superquadric `|x/a|^p + |y/b|^p = 1`, or a brush stroke
/// (an ellipse whose half-width shrinks from the blunt start at x = −a to 55 % at the end).
#[must_use]
pub fn polygon(shape: Shape, a: f32, b: f32, steps: usize) -> Vec<[f32; 2]> {
    (0..steps)
        .map(|k| {
            let th = k as f32 / steps as f32 * std::f32::consts::TAU;
            let (c, s) = (th.cos(), th.sin());
            match shape {
                Shape::Superquadric(p) => {
                    let p = p.max(0.5);
                    [
                        a * c.signum() * c.abs().powf(2.0 / p),
                        b * s.signum() * s.abs().powf(2.0 / p),
                    ]
                }
                Shape::Brush => [a * c, b * s * (1.0 - 0.45 * (c + 1.0) * 0.5)],
                Shape::Ellipse | Shape::Rectangle => [a * c, b * s],
            }
        })
        .collect()
}
