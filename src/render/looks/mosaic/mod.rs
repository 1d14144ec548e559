//! The mosaic look (paper Figure 5e): every generalized Voronoi cell filled with its mean photo
//! colour, borders where the owner changes, optional relief and colour jitter.
//!
//! Borders are anti-aliased from the distance difference: the distance in pixels from a point
//! to the border between its owner `i` and the runner-up `j` is about
//! `(δ_j − δ_i) / |∇δ_j − ∇δ_i|` (first order, measured by the scene), so borders keep an
//! even width in pixels whatever the cell's stretch; cells smaller than those that cover most
//! of the picture take leading narrowed in proportion ([`leading_widths`], shared with the
//! SVG), so small type and fine detail stay readable. The glass is lifted by the share of the
//! cell its leading covers (`lit_through_leading`), so the picture seen from afar keeps the
//! photo's tones; the leading is never lighter than half the darker glass beside it
//! ([`Glass::leads`]), so dark glass is not crossed by a grey web. Relief lights each cell as
//! a dome `1 − δ_i²` over its ellipse from the upper left (GEGL's mosaic has a bevel of the
//! same kind), its slope linear in the position, from one vector per cell (`dome_tilts`).
//! Shading is `f32` in linear light.

pub(crate) mod svg;

use crate::render::scene::{Average, Scene};
use crate::render::support::colour::{mix, Linear};
use crate::render::support::hash::{salt, site_hash};
use crate::render::vector::Gradient;
use glam::DVec2;
use image::RgbImage;

/// Parameters of the mosaic look.
#[derive(Clone, Debug, PartialEq)]
pub struct MosaicParams {
    /// Border width in pixels of a picture of up to a 1500 px diagonal (a one-megapixel
    /// photo's); a larger picture widens it with its diagonal
    /// ([`Scene::border_px`](crate::render::scene::Scene::border_px)). 0: no borders.
    pub border_width: f32,
    /// Border colour, sRGB.
    pub border_colour: [u8; 3],
    /// Strength of the relief shading, 0 (flat) to 1.
    pub relief: f32,
    /// Random brightness change per cell, 0 to 1 (fraction of the colour).
    pub jitter: f32,
}

impl Default for MosaicParams {
    fn default() -> Self {
        MosaicParams {
            border_width: 1.5,
            border_colour: [40, 36, 32],
            relief: 0.0,
            jitter: 0.0,
        }
    }
}

impl MosaicParams {
    /// Cell `site`'s colour `c` with its brightness jitter (`jitter` is the largest change,
    /// as a fraction of the colour; the same for the raster and the SVG).
    #[must_use]
    pub fn jittered(&self, c: Linear, site: u32) -> Linear {
        if self.jitter <= 0.0 {
            return c;
        }
        let k = 1.0 + self.jitter * (2.0 * site_hash(site, salt::MOSAIC_JITTER) - 1.0);
        c.map(|v| (v * k).clamp(0.0, 1.0))
    }
}

/// Renders the mosaic of `scene`.
#[must_use]
pub fn mosaic(scene: &Scene, params: &MosaicParams) -> RgbImage {
    let width = scene.border_px(params.border_width);
    let tilts = (params.relief > 0.0).then(|| dome_tilts(scene));
    let Glass {
        leading,
        colours,
        leads,
    } = glass(scene, params, width);
    // The cell's colour with its relief at `p`: lit where the dome faces the light.
    let inside = |p: DVec2, site: u32| {
        let (site, c) = (site as usize, colours[site as usize]);
        match &tilts {
            Some(tilts) => lit(
                c,
                params.relief,
                p - scene.cells.positions()[site],
                tilts[site],
            ),
            None => c,
        }
    };
    // Pixels the cell map settles have no border near: no ink (`Owner::border_coverage` is 0).
    scene.shade_settled_by_site(
        (width, Average::Linear),
        |p, o| {
            let c = inside(p, o.site);
            if width > 0.0 {
                let second = leading.get(o.second as usize).copied().unwrap_or(width);
                let w = leading[o.site as usize].min(second);
                let cover = o.border_coverage(w);
                if cover <= 0.0 {
                    return c;
                }
                mix(c, lead_between(&leads, o.site, o.second), cover)
            } else {
                c
            }
        },
        inside,
    )
}

/// The leading's colour on the border between cells `a` and `b` (`b` may be
/// [`NONE`](crate::render::cells::voronoi::NONE)): the
/// darker of their [`Glass::leads`], channel by channel. The raster and the SVG both draw this.
#[must_use]
pub(crate) fn lead_between(leads: &[Linear], a: u32, b: u32) -> Linear {
    let own = leads[a as usize];
    leads
        .get(b as usize)
        .map_or(own, |other| std::array::from_fn(|i| own[i].min(other[i])))
}

/// The lightest the leading is beside a cell, as a share of the cell's light (linear): lead
/// came is opaque and reads darker than any glass. The preset's leading (`#2a2521`, 16 % grey)
/// is lighter than dark glass, and would draw a grey web over black areas and a light grout
/// over a dim photo (a black helmet as a mesh, a night sky as a net on black).
const LEAD_UNDER_GLASS: f32 = 0.5;

/// What the raster and the SVG paint of every cell of a mosaic.
pub struct Glass {
    /// The width of the cell's leading in output pixels ([`leading_widths`]).
    pub leading: Vec<f32>,
    /// Its glass: the photo's colour lifted for that leading (`lit_through_leading`) and
    /// jittered ([`MosaicParams::jittered`]).
    pub colours: Vec<Linear>,
    /// Its leading's colour: the preset's, but no lighter than `LEAD_UNDER_GLASS` of the
    /// cell's photo colour, channel by channel in linear light (a border takes the darker of
    /// its two cells', `lead_between`).
    pub leads: Vec<Linear>,
}

/// The [`Glass`] of every cell of `scene` for borders `width` pixels wide.
#[must_use]
pub fn glass(scene: &Scene, params: &MosaicParams, width: f32) -> Glass {
    let leading = leading_widths(scene, width);
    let lead = crate::render::support::colour::linear_of(params.border_colour);
    let leads: Vec<Linear> = scene
        .colours
        .iter()
        .map(|c| std::array::from_fn(|i| lead[i].min(LEAD_UNDER_GLASS * c[i])))
        .collect();
    let colours = lit_through_leading(scene, &leading, &leads)
        .into_iter()
        .enumerate()
        .map(|(i, c)| params.jittered(c, i as u32))
        .collect();
    Glass {
        leading,
        colours,
        leads,
    }
}

/// Per cell, the width of the leading round it in output pixels: `width` for cells at least
/// as large (short semi-axis) as the cell under the picture's median pixel, narrowed in
/// proportion for smaller ones down to `THINNEST` of it; a border takes the narrower of its
/// two cells'. A mosaicist sets small tesserae with thin grout: at the full width, the leading
/// of cells as small as a letter's stroke (printed text, fine fur, branches) was as dark and as
/// wide as the strokes themselves, and text became unreadable. The reference is the cells that
/// cover most of the picture (the median by area, not by count, which the many small cells of
/// a detail would pull down), so the width a preset or user asks for is what the picture
/// mostly shows; on a thumbnail, whose cells are only a few pixels across, narrowed with
/// them (`FULL_WIDTH_FROM_SEMI_AXIS_PX`).
#[must_use]
pub fn leading_widths(scene: &Scene, width: f32) -> Vec<f32> {
    // (short semi-axis, area ∝ a·b) per cell.
    let axes: Vec<(f64, f64)> = scene
        .cells
        .metrics()
        .iter()
        .map(|m| {
            let e = m.eigen();
            let (a, b) = (e.l1.abs(), e.l2.abs());
            (a.min(b), a * b)
        })
        .collect();
    let reference = median_by_area(&axes);
    // A thumbnail's cells are a few pixels across: its leading narrows with them, but stays
    // a line.
    let shrink = (reference * scene.pixels_per_unit / FULL_WIDTH_FROM_SEMI_AXIS_PX).min(1.0);
    let width = (width * shrink as f32).max(width.min(1.0));
    axes.iter()
        .map(|&(b, _)| width * (b / reference).clamp(THINNEST, 1.0) as f32)
        .collect()
}

/// Per cell, its photo colour lifted so that the cell with its leading reads, from afar, as
/// the photo's colour, as far as white allows. Unlifted, the leading darkened every tone by its
/// share of the cell: a flat grey of 200 read 182, 120 read 110.
///
/// What a look from afar averages is the sRGB encoding `E`. Along a border of width `w` the
/// ink ramps over the cell's side as [`Owner::border_coverage`] does, mixed in linear light, so a
/// unit of border length darkens the cell by `I(c) = ∫ E(c) − E(mix(c, lead, cov(x))) dx`
/// (8 midpoints). The cell's area `A` and perimeter `P` are estimated from its ellipse: in a
/// packing each sample's cell is about the hexagon round it, of area `2√3·a·b` and perimeter
/// `4√3/(2π)` of the ellipse's (Ramanujan's). The lifted `c'` solves
/// `E(c') − (P/A)·I(c') = E(c)` per channel, by three fixed-point steps from `c`; where that
/// would take a channel past white, every channel gets the same share of its lift.
#[must_use]
fn lit_through_leading(scene: &Scene, leading: &[f32], leads: &[Linear]) -> Vec<Linear> {
    use crate::field::structure::{linear_to_srgb, srgb_to_linear};
    use rayon::prelude::*;
    let ppu = scene.pixels_per_unit;
    scene
        .colours
        .par_iter()
        .zip(scene.cells.metrics().par_iter())
        .zip(leading.par_iter().zip(leads.par_iter()))
        .map(|((&c, m), (&w, &lead))| {
            let e = m.eigen();
            let (a, b) = (e.l1.abs() * ppu, e.l2.abs() * ppu);
            let area = 2.0 * 3f64.sqrt() * a * b;
            if !(area > 0.0 && w > 0.0) {
                return c;
            }
            let h = ((a - b) / (a + b)).powi(2);
            let ellipse =
                std::f64::consts::PI * (a + b) * (1.0 + 3.0 * h / (10.0 + (4.0 - 3.0 * h).sqrt()));
            let perimeter = ellipse * 4.0 * 3f64.sqrt() / (2.0 * std::f64::consts::PI);
            let per_area = (perimeter / area).min(MAX_PERIMETER_PER_AREA) as f32;
            // The ink's reach into the cell, and the darkening of one unit of border length.
            let reach = 0.5 * w + 0.5;
            let darkening = |v: f32, l: f32| {
                let steps = 8;
                let dx = reach / steps as f32;
                let inked: f32 = (0..steps)
                    .map(|i| {
                        let x = (i as f32 + 0.5) * dx;
                        let cov = (0.5 * w - x + 0.5).clamp(0.0, 1.0);
                        linear_to_srgb(v + (l - v) * cov)
                    })
                    .sum();
                (steps as f32 * linear_to_srgb(v) - inked) * dx
            };
            // Every channel is lifted by the same share of the lift it needs, the largest
            // that keeps them all under white: a channel clamped alone would turn light skin white
            // (240, 210, 190 → 255, 255, 240), where this keeps its hue (255, 225, 207).
            let target = c.map(linear_to_srgb);
            let mut v = c;
            for _ in 0..3 {
                let lift: [f32; 3] = std::array::from_fn(|k| per_area * darkening(v[k], lead[k]));
                let share = (0..3)
                    .filter(|&k| lift[k] > 0.0)
                    .map(|k| ((1.0 - target[k]) / lift[k]).max(0.0))
                    .fold(1.0f32, f32::min);
                v = std::array::from_fn(|k| srgb_to_linear(target[k] + share * lift[k]));
            }
            v
        })
        .collect()
}

/// Per cell, the mosaic's relief as a linear gradient: the dome's shading is linear in the
/// position but for its clamps ([`lit`]), so stops along its slope at the site and one and a
/// half long semi-axes either side give it across the cell (viewers blend the stops in sRGB,
/// the raster shades in linear light). `None` without relief.
#[must_use]
pub(crate) fn relief_ramps(
    scene: &Scene,
    p: &MosaicParams,
    colours: &[Linear],
) -> Option<Vec<Option<Gradient>>> {
    if p.relief <= 0.0 {
        return None;
    }
    let scale = scene.raster.pixels_per_domain_unit();
    let tilts = dome_tilts(scene);
    let cells = scene.cells.positions().iter().zip(scene.cells.metrics());
    let ramps = cells
        .zip(colours.iter().zip(&tilts))
        .map(|((&site, m), (&c, &tilt))| {
            let e = m.eigen();
            let reach = RAMP_REACH * e.l1.abs().max(e.l2.abs());
            let d = tilt.normalize_or_zero() * reach;
            (d != DVec2::ZERO).then(|| Gradient {
                ends: [(site - d) * scale, (site + d) * scale],
                colours: [-d, DVec2::ZERO, d].map(|d| lit(c, p.relief, d, tilt)),
            })
        })
        .collect();
    Some(ramps)
}

/// How far either side of its site a cell's relief gradient runs, in long semi-axes: past
/// the glass of most cells, where the gradient's last colour goes on.
const RAMP_REACH: f64 = 1.5;

/// The largest perimeter over area (per output pixel) [`lit_through_leading`] counts: a cell
/// narrower than a few pixels is mostly leading, and lifting its colour to white would not
/// bring its tone back.
const MAX_PERIMETER_PER_AREA: f64 = 0.4;

/// The short semi-axis (output pixels) of the cells covering most of the picture from which
/// the leading takes the width asked for; on smaller cells it narrows in proportion, but not
/// under a pixel (thinner, it reads as a grey smudge, not a line). The cell count does not
/// grow with the picture, so a thumbnail's cells are a few pixels across, and the preset's
/// 1.5 px covered most of them: at 160 × 120 pixels it took 0.36 of the picture's tone (0.24
/// now; 0.09 at 1200 × 900), and a fundus thumbnail of 102 × 102 pixels (cells of 1.3 pixels'
/// short semi-axis) came out 21 levels darker than the photo (13 now). Pictures from about
/// 0.1 MP up have cells at least this large and keep the width asked for.
const FULL_WIDTH_FROM_SEMI_AXIS_PX: f64 = 3.0;

/// The narrowest leading as a share of the full width: thinner, a border between two tiny
/// cells was no line at all.
const THINNEST: f64 = 0.4;

/// The short semi-axis of the cell holding the median of the area, cells in order of size.
fn median_by_area(axes: &[(f64, f64)]) -> f64 {
    let mut sorted = axes.to_vec();
    sorted.sort_by(|x, y| x.0.total_cmp(&y.0));
    let half = 0.5 * sorted.iter().map(|c| c.1).sum::<f64>();
    let mut covered = 0.0;
    for &(b, area) in &sorted {
        covered += area;
        if covered >= half {
            return b;
        }
    }
    sorted.last().map_or(1.0, |c| c.0)
}

/// Per cell, the vector `Q l r` that gives how squarely the dome faces the light at offset `d`
/// from the site, `2 d · Q l r`: the dome `h = 1 − δ²` has `∇h = −2δ∇δ = −2 Q d`
/// (`∇δ = Q d / δ`, `Q = m⁻ᵀm⁻¹`), its surface faces the light `l` (from the upper left) by
/// `−∇h · l`, and `r = √det m` is the cell's mean radius. The dome is the ellipse's alone, for
/// edge-following cells too: scaled by the owner's distance with the colour term over `δ`,
/// as it once was, a grained pixel unlike its cell's mean got a slope several times the
/// dome's and showed as a dark or light speck in the glass. A dot product per pixel, and the
/// owner's distances are not needed.
fn dome_tilts(scene: &Scene) -> Vec<DVec2> {
    let light = DVec2::new(-1.0, -1.0).normalize();
    scene
        .cells
        .metrics()
        .iter()
        .map(|m| {
            let q = m.inverse().unwrap_or_default().squared();
            q.mul_vec(light) * m.det().sqrt()
        })
        .collect()
}

/// Glass of colour `c` lit by a relief of strength `relief` at offset `d` from its site, the
/// cell's tilt ([`dome_tilts`]) `tilt`: how squarely the dome faces the light there,
/// `2 d · tilt`, brightens or darkens it by half the relief per unit (the side towards the
/// upper left lit, the other in shade; the sign was once the other way, which lit the domes
/// from the lower right, and they read as dishes). The raster and the SVG's gradients both
/// light the glass with it.
#[must_use]
pub(crate) fn lit(c: Linear, relief: f32, d: DVec2, tilt: DVec2) -> Linear {
    let facing = (2.0 * d.dot(tilt)) as f32;
    let k = (1.0 + relief * 0.5 * facing).clamp(0.0, 2.0);
    c.map(|v| (v * k).clamp(0.0, 1.0))
}
