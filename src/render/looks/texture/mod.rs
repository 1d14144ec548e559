//! Textured cells (paper section 6, Figures 5f-g and 6d-f): every raster point is mapped into
//! the local frame of the site that owns it, rotated by the inverse eigenvector matrix of the
//! site's metric and scaled by its semi-axes, so that one texture tile spans one cell and its
//! lines run along the field.
//!
//! In that frame `s` runs along the long axis and `t` across, both ±1 on the site's ellipse.
//! Textures give ink coverage; tone mapping makes darker cells denser (thicker hatch lines,
//! more cross-hatch layers, bigger stipples; image textures are thresholded like a halftone
//! screen), and the texture's contrast fades where the metric is isotropic and no direction
//! is defined (paper Figure 6), keeping the mean tone, unless the preset names a
//! `flat_angle`: then such cells are hatched at that angle, their lines running on from cell to
//! cell (`texture_frames`). The coverage is solved so that paper
//! and ink average to the cell's lightness ([`cell_tones`]), and paper and ink are mixed in the
//! sRGB encoding, so the picture seen from afar (or reduced by a viewer, or blurred by an
//! evaluator) has the photo's tones; the rest of the shading is `f32` in linear light.

mod blurred_photo;
mod dot_order;
mod frames;
mod hatch_lines;
mod local_tone;
pub mod stipple;
pub(crate) mod svg;

use crate::render::cells::quiet_cells::quiet_cells;
use crate::render::cells::voronoi::Owner;
use crate::render::scene::{Average, Scene};
use crate::render::support::bilinear::bilinear;
use crate::render::support::colour::BLACK_INK;
use crate::render::support::colour::{
    darkened_to, encoded, lightness, linear_of, mix, mix_encoded, Linear,
};
use crate::render::support::hash::{salt, site_hash, GOLDEN_U32};
use crate::render::support::rounding::floor;
pub use blurred_photo::INK_BLUR;
use blurred_photo::{BlurredPhoto, ToneGrid};
use dot_order::dots_at;
use frames::{cell_frames, FlatHatching, Frame};
use glam::DVec2;
use hatch_lines::{cross_hatch_layers, lines, LAYERS};
use image::{GrayImage, RgbImage};
use local_tone::LocalTone;
use stipple::{dab_at, next_render, stipple_radius, Dab};

/// Which texture fills the cells.
#[derive(Clone, Debug, PartialEq)]
pub enum TextureKind {
    /// Parallel lines along the field.
    Hatch,
    /// Up to three layers of lines (along, across, diagonal), added as the tone darkens.
    CrossHatch,
    /// One tapered line along the field per cell (looks like tensor LIC).
    Line,
    /// A brush stroke along the field in the cell's colour, with bristle streaks.
    Stroke,
    /// Dots on a jittered lattice in the cell's frame, growing with the tone.
    Stipple,
    /// A greyscale image tile (dark = ink) spanning each cell, thresholded by tone.
    Image(GrayImage),
}

/// The colour of the ink.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ink {
    /// A fixed sRGB colour.
    Fixed([u8; 3]),
    /// The cell's own colour, darkened by this factor (0 to 1).
    Cell(f32),
    /// The photo's colour under the point, blurred (σ of [`INK_BLUR`] of the diagonal) and
    /// darkened by this factor: colour changes within a cell; the cell colour without a photo.
    Pixel(f32),
}

impl Ink {
    /// The colour of the leading between cells: the ink itself when it is fixed, else one
    /// dark grey ([`LEADING_GREY`]) for every cell.
    #[must_use]
    pub fn leading(&self) -> [u8; 3] {
        match self {
            Ink::Fixed(rgb) => *rgb,
            Ink::Cell(_) | Ink::Pixel(_) => LEADING_GREY,
        }
    }
}

/// The leading of textured cells whose ink changes from cell to cell: a neutral dark grey
/// that reads as an outline beside any of them.
pub const LEADING_GREY: [u8; 3] = [30, 30, 30];

/// Parameters of the textured looks.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureParams {
    /// The texture.
    pub kind: TextureKind,
    /// Lines (or dot rows) across a cell's short axis.
    pub lines_per_cell: f32,
    /// Lines never come closer than this many output pixels (small cells get fewer lines).
    pub min_spacing_px: f32,
    /// Ink colour.
    pub ink: Ink,
    /// Paper colour, sRGB.
    pub paper: [u8; 3],
    /// Tone curve: darkness = (1 − lightness)^gamma; below 1 darkens, above 1 lightens.
    pub gamma: f32,
    /// Anisotropy `1 − b/a` at which the texture reaches full contrast; below it the
    /// texture fades towards flat tone.
    pub fade_anisotropy: f32,
    /// Width of cell borders (0: none), in pixels of a picture of up to a 1500 px diagonal,
    /// widened with a larger picture's diagonal as the mosaic's leading is.
    pub border_width: f32,
    /// Hatch and cross-hatch: the direction (degrees from the x axis, y down) of the lines in
    /// cells rounder than `fade_anisotropy`, which then keep full contrast instead of fading:
    /// flat areas get even hatching that runs on from cell to cell. `None`: they fade (the
    /// paper's Figure 6).
    pub flat_angle: Option<f32>,
    /// Hatch and cross-hatch over a photo: one tone per cell (the paper's) instead of the
    /// photo's tone point by point (`local_tone.rs`).
    pub cell_tone: bool,
}

impl TextureParams {
    /// Defaults that suit `kind`.
    #[must_use]
    pub fn for_kind(kind: TextureKind) -> Self {
        let base = TextureParams {
            kind: TextureKind::Hatch,
            lines_per_cell: 4.0,
            min_spacing_px: 3.0,
            ink: Ink::Fixed(BLACK_INK),
            paper: [247, 243, 232],
            gamma: 1.0,
            fade_anisotropy: 0.25,
            border_width: 0.0,
            flat_angle: None,
            cell_tone: false,
        };
        match kind {
            TextureKind::Stroke => TextureParams {
                kind,
                lines_per_cell: 7.0,
                min_spacing_px: 1.5,
                ink: Ink::Cell(0.0),
                fade_anisotropy: 0.0,
                ..base
            },
            TextureKind::Line => TextureParams {
                kind,
                ink: Ink::Pixel(0.35),
                ..base
            },
            TextureKind::Stipple => TextureParams {
                kind,
                lines_per_cell: 3.0,
                fade_anisotropy: 0.0,
                ..base
            },
            _ => TextureParams { kind, ..base },
        }
    }
}

/// Every cell of `scene` framed for texturing ([`cell_frames`]): with
/// [`TextureParams::flat_angle`], hatch and cross-hatch cells rounder than `fade_anisotropy`,
/// or with no structure of their own (`quiet_cells.rs`), are hatched at that angle, one
/// spacing per flat area (cells touching in the triangulation), no larger than lines
/// [`FLAT_SPACING`] of the picture's diagonal apart need (a flat area is hatched finely and
/// evenly, not in the coarse lines of its large cells).
pub(crate) fn texture_frames(scene: &Scene, p: &TextureParams) -> Vec<Frame> {
    let hatched = matches!(p.kind, TextureKind::Hatch | TextureKind::CrossHatch);
    let diagonal = scene.raster.domain.length();
    let flat = p.flat_angle.filter(|_| hatched).map(|angle| FlatHatching {
        angle: f64::from(angle).to_radians(),
        below: p.fade_anisotropy,
        largest: FLAT_SPACING * diagonal * f64::from(p.lines_per_cell) / 2.0,
    });
    // Every pair of touching cells once.
    let neighbours: Vec<[u32; 2]> = match flat {
        Some(_) => scene.cells.mesh().edges(scene.cells.positions().len()).ends,
        None => Vec::new(),
    };
    let quiet = flat.and_then(|_| quiet_cells(&scene.cells));
    cell_frames(scene.cells.metrics(), &neighbours, flat, quiet.as_deref())
}

/// The widest spacing of flat hatching, as a share of the picture's diagonal: 4.5 px at a
/// one-megapixel photo's 1 500, near its detail's, so a plain reads as its tone (wider, a
/// blurred leaf, an evening sky or a dim facade become zebra stripes hiding the forms).
pub const FLAT_SPACING: f64 = 0.003;

/// Every cell's ink coverage and ink colour. The tone curve sets the lightness the cell should
/// read as, `1 − (1 − L)^gamma` of its own lightness `L`; the coverage is the share of ink
/// that gives that lightness between the paper's and the ink's,
/// `(paper − target) / (paper − ink)` (all perceived lightness, the sRGB encoding of the
/// luminance, which is what ink on paper averages to at a distance, since the
/// shading mixes paper and ink in that encoding too): a cell as light as the paper or lighter
/// takes no ink, and coloured dots cover as much as their own colour needs. A cell darker than
/// the ink itself is covered and inked again (a second layer over the first, as a pen goes
/// over a solid black), its ink darkened to the target, down to black for a black photo. A
/// fixed ink lighter than the paper (white on black) covers `(target − paper) / (ink − paper)`.
#[must_use]
pub fn cell_tones(colours: &[Linear], params: &TextureParams) -> Vec<(f32, Linear)> {
    let paper = lightness(linear_of(params.paper));
    colours
        .iter()
        .map(|&colour| {
            let target = 1.0 - (1.0 - lightness(colour)).clamp(0.0, 1.0).powf(params.gamma);
            let mut ink = match params.ink {
                Ink::Fixed(rgb) => linear_of(rgb),
                Ink::Cell(k) | Ink::Pixel(k) => colour.map(|v| v * (1.0 - k)),
            };
            let room = paper - lightness(ink);
            if room < -1e-3 && matches!(params.ink, Ink::Fixed(_)) {
                // Chalk on a blackboard: the share of ink that lifts the paper to the tone.
                return (((target - paper) / -room).clamp(0.0, 1.0), ink);
            }
            // A tone as light as the paper or lighter is bare paper: ink in the photo's own
            // colour would be as light as the tone, lighter than the paper, and cover the cell
            // whole, a speckle of jittered near-white dots on a white ground.
            if target >= paper {
                return (0.0, ink);
            }
            if target < lightness(ink) && crate::render::support::colour::luminance(ink) > 0.0 {
                ink = darkened_to(ink, crate::field::structure::srgb_to_linear(target));
                // The ink is the tone: covered whole. (Its lightness read back through the
                // 8-bit encoding can be a level off the target, which gave a coverage just
                // short of 1 and single white pixels of paper in black areas.)
                return (1.0, ink);
            }
            let cover = if room > 1e-3 {
                ((paper - target) / room).clamp(0.0, 1.0)
            } else {
                1.0
            };
            // Paper left that lightens the cell by less than one level of the 8-bit encoding
            // (the lightnesses are read through it: a near-black cell whose ink reads a level
            // under its target came out 0.997 covered) is no tone anyone can see, but the gaps
            // of a dot lattice gather it into specks of bare paper, white stars in a black sky:
            // the cell is covered.
            let cover = if (1.0 - cover) * room < 1.0 / 255.0 {
                1.0
            } else {
                cover
            };
            (cover, ink)
        })
        .collect()
}

/// Renders `scene` with textured cells.
#[must_use]
pub fn textured(scene: &Scene, params: &TextureParams) -> RgbImage {
    let frames = texture_frames(scene, params);
    // Per cell, once: tone and ink (a power per raster point would cost more than the texture).
    let tones = cell_tones(&scene.colours, params);
    // Stipple radii (lattice periods) per cell, once: a table search per raster point cost 5 %.
    let radii: Vec<f64> = match params.kind {
        TextureKind::Stipple => tones.iter().map(|&(d, _)| stipple_radius(d)).collect(),
        _ => Vec::new(),
    };
    let paper = linear_of(params.paper);
    let border_width = scene.border_px(params.border_width);
    let px = 1.0 / scene.pixels_per_unit;
    // Hatched cells over a photo take their tone point by point (`local_tone.rs`).
    let local_tone = match (&params.kind, scene.photo) {
        (TextureKind::Hatch | TextureKind::CrossHatch, Some(_)) if !params.cell_tone => {
            Some(LocalTone::new(&cell_tones(&LocalTone::greys(), params)))
        }
        _ => None,
    };
    let blurred = match (params.ink, scene.photo) {
        (Ink::Pixel(_), Some(photo)) => Some(BlurredPhoto::new(photo)),
        _ => None,
    };
    let tone_grid = match (&local_tone, scene.photo) {
        (Some(tone), Some(photo)) => Some(ToneGrid::new(photo, tone, scene.outline_share)),
        _ => None,
    };
    // Per cell, once: how much of the texture shows (flat cells take their tone) and the
    // texture's period.
    let amps: Vec<f32> = frames
        .iter()
        .map(|f| smoothstep(params.fade_anisotropy, f.anisotropy))
        .collect();
    let periods: Vec<f64> = frames.iter().map(|f| spacing(f.b, params, px)).collect();
    // The paper encoded once, and bare paper as `mix_encoded` gives it for no coverage.
    let paper_encoded = encoded(paper);
    let bare = mix_encoded(paper_encoded, paper, 0.0);
    let render = next_render();
    let colour = |p: DVec2, o: &Owner| {
        let site = o.site;
        let f = frames[site as usize];
        let d = p - scene.cells.positions()[site as usize];
        // Domain units along the long (x) and short (y) axes.
        let local = DVec2::new(f.cos * d.x + f.sin * d.y, -f.sin * d.x + f.cos * d.y);
        let colour = scene.colours[site as usize];
        let (mut darkness, cell_ink) = tones[site as usize];
        if let Some(grid) = &tone_grid {
            darkness = grid.at(p);
        }
        // The ink, read from the photo only where some is laid.
        let ink = || match (params.ink, &blurred) {
            (Ink::Pixel(k), Some(b)) => b.at(p).map(|v| v * (1.0 - k)),
            _ => cell_ink,
        };
        let radius = radii.get(site as usize).copied().unwrap_or(0.0);
        // Stipple: the dots at the point (the uppermost and the one under it), found once.
        let (period, solid) = (periods[site as usize], darkness >= 1.0);
        let dots = (params.kind == TextureKind::Stipple)
            .then(|| dots_at(local, site, period, (radius, solid), px));
        // Pointillist dots (stipple in the photo's colours): each one dab of the photo's colour
        // at its centre (its frame turned back into the picture's), cut by the photo's edges;
        // at the rim of the uppermost, the dab under it shows.
        let plain_ink = ink;
        let dab_over = |centre: DVec2, b: &BlurredPhoto, k: f32, here: Linear| {
            let dab = dab_at(render, site, centre, || {
                let world =
                    DVec2::new(f.cos, f.sin) * centre.x + DVec2::new(-f.sin, f.cos) * centre.y;
                let under = b.at(scene.cells.positions()[site as usize] + world);
                Dab::new(site, centre, under, k)
            });
            dab.colour_over(here)
        };
        let ink = || match (dots, params.ink, &blurred) {
            (Some(dots), Ink::Pixel(k), Some(b)) => {
                let here = b.at(p);
                dots.ink(|centre| dab_over(centre, b, k, here))
            }
            _ => plain_ink(),
        };
        let mut c = if let TextureKind::Stroke = params.kind {
            stroke(local, &f, site, colour, params, px)
        } else {
            let cover = match dots {
                // A tone of solid ink leaves no paper in the gaps of the dots' lattice (their
                // radius inks every point of the table's sampling of it, not every pixel).
                Some(_) if solid => 1.0,
                Some(dots) => dots.cover(),
                None => {
                    let centre = scene.cells.positions()[site as usize];
                    coverage(local, centre, &f, darkness, params, px)
                }
            };
            let mut cover = darkness + amps[site as usize] * (cover - darkness);
            if let (Some(widths), TextureKind::Stipple) = (&scene.thin_widths, &params.kind) {
                // A cell narrower than about one and a half periods of the dot lattice cannot
                // show its tone with dots (a thin line would catch a few dots, or none): it
                // takes its flat tone instead, fully from half a period wide. Hatch lines run
                // along the cell's long axis, so a thin cell still catches one along its length.
                let period = periods[site as usize];
                let thin = ((1.5 * period - widths[site as usize]) / period).clamp(0.0, 1.0);
                cover += (darkness - cover) * thin as f32;
            }
            if cover == 0.0 {
                bare
            } else if cover >= 1.0 {
                // All ink: `mix_encoded` would give the ink through the 8-bit encoding, which
                // the shading rounds to the same byte.
                ink()
            } else {
                mix_encoded(paper_encoded, ink(), cover)
            }
        };
        if border_width > 0.0 {
            let border = o.border_coverage(border_width);
            if border > 0.0 {
                c = mix(c, ink(), border);
            }
        }
        c
    };
    // Settled pixels have no border near (their owner's `border_px` is infinite): the same
    // colour, without the owner search, and without measuring the owner's `δ` or `D`, which the
    // colour does not read (only the site and the border distance).
    // Ink on paper is averaged as it is mixed, in the encoding; a stroke's paint as light.
    let average = match params.kind {
        TextureKind::Stroke => Average::Linear,
        _ => Average::Encoded,
    };
    scene.shade_settled_by_site((border_width, average), colour, |p, site| {
        colour(
            p,
            &Owner {
                site,
                ..Owner::NOBODY
            },
        )
    })
}

/// `0` at 0, `1` from `edge` on, smooth between (`edge ≤ 0`: always 1).
pub(crate) fn smoothstep(edge: f32, x: f32) -> f32 {
    if edge <= 0.0 {
        return 1.0;
    }
    let t = (x / edge).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Spacing of lines in domain units for a cell of short semi-axis `b`.
pub(crate) fn spacing(b: f64, params: &TextureParams, px: f64) -> f64 {
    (2.0 * b / f64::from(params.lines_per_cell.max(0.1))).max(f64::from(params.min_spacing_px) * px)
}

/// Ink coverage of the ink textures at a local point of a cell whose site is at `centre` (the
/// stipple's dots are found by [`dots_at`], which also gives their centres).
fn coverage(
    local: DVec2,
    centre: DVec2,
    f: &Frame,
    darkness: f32,
    p: &TextureParams,
    px: f64,
) -> f32 {
    // The normal, in picture coordinates, of lines at an angle of sine `sin` and cosine `cos`
    // to the long axis, and the site's position across them.
    let across = |(sin, cos): (f64, f64)| {
        let (s, c) = (f.sin * cos + f.cos * sin, f.cos * cos - f.sin * sin);
        let normal = DVec2::new(-s, c);
        (normal, normal.dot(centre))
    };
    match &p.kind {
        TextureKind::Hatch => {
            let along = LAYERS[0];
            lines(
                local,
                along,
                spacing(f.b, p, px),
                across(along),
                darkness,
                px,
            )
        }
        TextureKind::CrossHatch => {
            let (widths, k) = cross_hatch_layers(darkness);
            let s = spacing(f.b, p, px);
            let mut paper_left = 1.0;
            for (&layer, &x) in LAYERS.iter().zip(&widths).take(k) {
                paper_left *= 1.0 - lines(local, layer, s, across(layer), x, px);
                // A layer that inks the whole pixel leaves nothing for the next.
                if paper_left == 0.0 {
                    break;
                }
            }
            1.0 - paper_left
        }
        TextureKind::Line => {
            let s = (local.x / f.a).clamp(-1.0, 1.0);
            let half = f64::from(darkness) * 0.8 * f.b * (1.0 - s * s).sqrt();
            ((half - local.y.abs()) / px + 0.5).clamp(0.0, 1.0) as f32
        }
        // The caller finds the dots with their centres (`dots_at`); its flat tone here.
        TextureKind::Stipple => darkness,
        TextureKind::Image(img) => {
            let u = (local.x / f.a + 1.0) * 0.5;
            let v = (local.y / f.b + 1.0) * 0.5;
            let value = 1.0 - sample_wrapped(img, u, v);
            ((value - (1.0 - darkness)) / 0.15 + 0.5).clamp(0.0, 1.0)
        }
        TextureKind::Stroke => darkness,
    }
}

/// The brush-stroke colour at a local point: the cell's colour with bristle streaks along the
/// field, a little darker towards the stroke's sides and ends.
fn stroke(
    local: DVec2,
    f: &Frame,
    site: u32,
    colour: Linear,
    p: &TextureParams,
    px: f64,
) -> Linear {
    let s = spacing(f.b, p, px);
    // Value noise across the stroke: random per bristle, blended smoothly between bristles
    // (no hard steps, which would alias inside a cell).
    let u = local.y / s + f64::from(site_hash(site, salt::STROKE_PHASE)) * 16.0;
    let k = floor(u);
    let t = (u - k) as f32;
    let bristle = |k: f64| {
        site_hash(
            site ^ (k as i64 as u32).wrapping_mul(GOLDEN_U32),
            salt::STROKE_BRISTLE,
        ) - 0.5
    };
    let t = t * t * (3.0 - 2.0 * t);
    let streak = bristle(k) + (bristle(k + 1.0) - bristle(k)) * t;
    let along = (local.x / f.a).abs().min(1.5) as f32;
    let across = (local.y / f.b).abs().min(1.5) as f32;
    let shade = 1.0 + 0.22 * streak - 0.12 * along * along - 0.08 * across * across;
    colour.map(|v| (v * shade).clamp(0.0, 1.0))
}

/// The engraving tile of `styles/textures/engraving.png`, made here so that it can be made
/// again: three lines across the tile (the cell's short axis) that swell in the middle of the
/// cell and thin out towards its ends, stored as a threshold map (a dark pixel inks already in
/// light cells, a light one only in dark cells), as the image textures expect.
#[must_use]
pub fn engraving_tile(size: u32) -> GrayImage {
    const LINES: f64 = 3.0;
    GrayImage::from_fn(size, size, |x, y| {
        let u = (f64::from(x) + 0.5) / f64::from(size);
        let v = (f64::from(y) + 0.5) / f64::from(size);
        // 1 on a line's centre, 0 halfway between lines.
        let across = 1.0 - (2.0 * (v * LINES).fract() - 1.0).abs();
        // Lines swell towards the middle of the cell along its long axis.
        let swell = 0.7 + 0.3 * (std::f64::consts::PI * u).sin();
        let ink = (across * swell).clamp(0.0, 1.0);
        image::Luma([(255.0 * (1.0 - ink)).round() as u8])
    })
}

/// Bilinear look-up of `img` (0..1 grey) at `(u, v)` in tile units, wrapping around.
fn sample_wrapped(img: &GrayImage, u: f64, v: f64) -> f32 {
    let (w, h) = (i64::from(img.width()), i64::from(img.height()));
    let x = (u - floor(u)) * w as f64 - 0.5;
    let y = (v - floor(v)) * h as f64 - 0.5;
    let [grey] = bilinear(x, y, |xi, yi| {
        let pixel = img.get_pixel(xi.rem_euclid(w) as u32, yi.rem_euclid(h) as u32);
        [f32::from(pixel.0[0]) / 255.0]
    });
    grey
}
