//! The engraving look (after Ostromoukhov, *Digital Facial Engraving*, 1999):
//! long parallel lines that follow the form across the whole picture, evenly spaced
//! ([`crate::render::lines::streamlines`], along the metric's long axes, paper section 3) and
//! swelling and thinning with tone, broken only at strong edges.
//!
//! A line answers for the paper up to half-way to its neighbour on either side. On each side its
//! ink reaches that half-gap times the ink coverage that gives the photo's lightness over it,
//! `(paper − target) / (paper − ink)` with the tone curve `target = 1 − (1 − L)^gamma`, so the
//! picture seen from afar has the photo's tones: light areas paper-white, dark ones nearly solid.
//! From a little above the ink's own lightness down to black the paper left between the lines
//! narrows in proportion to the tone and the ink darkens to keep it, so dark gradients keep their
//! lines instead of merging into flat ink along a contour; only in the darkest tones do the lines
//! swell past their share until neighbours merge into solid ink (`engrave_tone::LineShares`).
//! Taking the two sides apart resolves the tone at half a spacing across the lines (a mast or a
//! wire between two lines shows), and where lines part unevenly the ink follows the wider gap
//! instead of overrunning the narrower one. The tone is the photo's lightness blurred over a fifth
//! of a line spacing (finer than the cells), or `tone` for a field without a photo, less what the
//! outlines laid over the engraving will ink ([`crate::render::lines::outline_share`]). Lines are
//! drawn by the share of each pixel's square they ink (`stripes.rs`: a hairline keeps its share of
//! ink, a diagonal line no staircase), joined round; a line's own segments take the maximum where
//! they overlap, neighbouring lines add up (together they ink the pixels they share), and ink is
//! mixed with the paper in the sRGB encoding, as the hatch looks are (the textured looks). Where
//! the tone is darker than the ink itself, the ink is laid again, darkened to the tone
//! ([`engraving`]), and so it is where the lines leave slits in the dark tones (so greys a little
//! lighter than the ink read as themselves, not as the ink). Coverage is `f32`, geometry `f64` in
//! domain units until it is scaled to output pixels.

pub(crate) mod svg;
mod tone;

use crate::field::blur::round_to_byte;
use crate::render::lines::line_field::Directions;
use crate::render::lines::streamlines::{normal_at, streamlines, LineLayout, Streamline};
use crate::render::lines::stripes::band_coverage;
use crate::render::scene::Scene;
use crate::render::support::colour::BLACK_INK;
use glam::DVec2;
use image::RgbImage;
use rayon::prelude::*;
use tone::{DeeperInk, LineShares, Tone, ToneReader};

/// Parameters of the engraving look.
#[derive(Clone, Debug, PartialEq)]
pub struct EngravingParams {
    /// Spacing of the lines as a fraction of the picture's diagonal.
    pub line_spacing: f32,
    /// The lines are never closer than this many output pixels.
    pub min_spacing_px: f32,
    /// Ink colour, sRGB.
    pub ink: [u8; 3],
    /// Paper colour, sRGB.
    pub paper: [u8; 3],
    /// Tone curve: darkness = (1 − lightness)^gamma; below 1 darkens, above 1 lightens.
    pub gamma: f32,
    /// A line breaks where the photo's lightness changes by more than this (0 to 1) over one
    /// line spacing along it.
    pub edge_break: f32,
    /// Direction of the lines where the field has none (degrees from the x axis, clockwise on
    /// screen as y points down).
    pub flat_angle: f32,
    /// Lightness (0 to 1) of a field without a photo.
    pub tone: f32,
}

impl Default for EngravingParams {
    fn default() -> Self {
        EngravingParams {
            line_spacing: 0.0035,
            min_spacing_px: 2.0,
            ink: BLACK_INK,
            paper: [247, 243, 232],
            gamma: 1.0,
            edge_break: 0.35,
            flat_angle: -45.0,
            tone: 0.6,
        }
    }
}

/// A laid-out engraving: its lines with a width (domain units) at every point.
#[derive(Clone, Debug, Default)]
pub struct Engraving {
    /// The lines.
    pub lines: Vec<Streamline>,
    /// How far the ink reaches from every point of every line to its left (along
    /// [`normal_at`]) and to its right, domain units.
    pub sides: Vec<Vec<[f64; 2]>>,
    /// Separation of the lines, domain units.
    pub d_sep: f64,
}

/// The lines of `scene` engraved with `params`, and their widths.
#[must_use]
pub fn engrave(scene: &Scene, params: &EngravingParams) -> Engraving {
    let d_sep = line_separation(scene, params);
    engrave_in(scene, params, Tone::of(scene, d_sep).as_ref(), d_sep)
}

/// [`engrave`], and per point of every line the ink laid again there for the vector form: the
/// raster's darker ink ([`engraving`]) at the tone under the point, in [`SVG_INK_LEVELS`] steps
/// of tone from black to where the ink darkens, `None` where the tone takes the ink itself.
/// A line's run of points at one level is one filled shape of that ink.
#[must_use]
pub fn engrave_with_inks(
    scene: &Scene,
    params: &EngravingParams,
) -> (Engraving, Vec<Vec<Option<[u8; 3]>>>) {
    let d_sep = line_separation(scene, params);
    let tone = Tone::of(scene, d_sep);
    let e = engrave_in(scene, params, tone.as_ref(), d_sep);
    let shares = LineShares::new(params.ink, params.paper);
    let deeper = DeeperInk::new(params.ink, &shares, params.gamma);
    let step = deeper.darker_below / SVG_INK_LEVELS as f32;
    let inks = e
        .lines
        .par_iter()
        .map(|line| {
            line.points
                .iter()
                .map(|&p| {
                    let l = tone.as_ref().map_or(params.tone, |t| t.at(p));
                    if l.is_nan() || l >= deeper.darker_below {
                        return None;
                    }
                    // The middle of the level's range of tones.
                    let level = (l.max(0.0) / step).floor().min(SVG_INK_LEVELS as f32 - 1.0);
                    deeper
                        .at((level + 0.5) * step)
                        .map(|c| c.map(|v| v.round().clamp(0.0, 255.0) as u8))
                })
                .collect()
        })
        .collect();
    (e, inks)
}

/// Steps of tone in which the SVG lays the engraving's darker ink ([`engrave_with_inks`]).
pub const SVG_INK_LEVELS: usize = 8;

/// The separation of the lines in domain units: `line_spacing` of the picture's diagonal, at
/// least `min_spacing_px` output pixels.
fn line_separation(scene: &Scene, params: &EngravingParams) -> f64 {
    (f64::from(params.line_spacing) * scene.raster.domain.length())
        .max(f64::from(params.min_spacing_px) / scene.pixels_per_unit)
}

/// [`engrave`] with the lines `d_sep` apart over `tone` (the photo's, or none: `params.tone`).
fn engrave_in(
    scene: &Scene,
    params: &EngravingParams,
    tone: Option<&Tone>,
    d_sep: f64,
) -> Engraving {
    let domain = scene.raster.domain;
    let lightness_at = |p: DVec2| tone.map_or(params.tone, |t| t.at(p));
    let layout = LineLayout {
        d_sep,
        flat_angle: f64::from(params.flat_angle).to_radians(),
        edge_break: if tone.is_some() {
            params.edge_break
        } else {
            f32::INFINITY
        },
    };
    let directions = if tone.is_some() {
        Directions::of_photo(scene.field, layout.flat_angle, d_sep)
    } else {
        Directions::new(scene.field, layout.flat_angle, d_sep)
    };
    let lines = streamlines(
        &directions,
        &lightness_at,
        domain,
        &layout,
        scene.cells.positions(),
    );
    let shares = LineShares::new(params.ink, params.paper);
    // The ink that gives lightness `l` over a share of paper: its coverage, widened to merge.
    // Less where the outlines laid over the engraving will ink some of that tone.
    let ink_over = |l: f32, share: f64, at: DVec2| {
        let target = 1.0 - (1.0 - l.clamp(0.0, 1.0)).powf(params.gamma);
        let mut cover = shares.cover(target);
        if let Some(outlines) = scene.outline_share {
            cover = outlines.leave_out(cover, at);
        }
        f64::from(cover) * share * shares.widening(cover)
    };
    let sides = lines
        .par_iter()
        .map(|line| {
            (0..line.points.len())
                .map(|i| {
                    let (p, [left, right]) = (line.points[i], line.halves[i]);
                    let n = normal_at(&line.points, i);
                    // Each side's ink answers for the tone over its own half of the gap (read
                    // at a quarter and three quarters across it): a light or dark feature
                    // between two lines (a mast, a wire) moves the facing sides of both, one
                    // under a line thins it, resolved at half a spacing across the lines.
                    let over =
                        |v: DVec2| 0.5 * (lightness_at(p + v * 0.25) + lightness_at(p + v * 0.75));
                    [
                        ink_over(over(n * left), left, p + n * (0.5 * left)),
                        ink_over(over(-n * right), right, p - n * (0.5 * right)),
                    ]
                })
                .collect()
        })
        .collect();
    Engraving {
        lines,
        sides,
        d_sep,
    }
}

/// Renders the engraving of `scene`. Where the tone is darker than the ink itself, or the lines
/// leave slits of paper in the dark tones, the ink is laid again, darkened to keep the tone (down
/// to black for a black photo, `LineShares`), as the hatchings' cell tones do: in one ink, a black
/// coat, a night sky or a silhouette read as the ink's brown-black, 20 to 30 levels lighter than
/// the photo (astronaut, 19 % of its pixels under 32: +23 levels).
#[must_use]
pub fn engraving(scene: &Scene, params: &EngravingParams) -> RgbImage {
    let d_sep = line_separation(scene, params);
    let tone = Tone::of(scene, d_sep);
    let e = engrave_in(scene, params, tone.as_ref(), d_sep);
    let r = scene.raster;
    let cover = coverage(&e, r.width, r.height, r.domain);
    let (paper, ink) = (params.paper.map(f32::from), params.ink.map(f32::from));
    let shares = LineShares::new(params.ink, params.paper);
    let deeper = DeeperInk::new(params.ink, &shares, params.gamma);
    let reader = tone
        .as_ref()
        .map(|t| ToneReader::new(t, r.domain, (r.width, r.height)));
    let mut out = vec![0u8; 3 * r.width * r.height];
    out.par_chunks_mut(3 * r.width)
        .zip(cover.par_chunks(r.width))
        .enumerate()
        .for_each(|(y, (row, cov))| {
            for (px, &c) in row.chunks_exact_mut(3).zip(cov) {
                for k in 0..3 {
                    px[k] = round_to_byte(paper[k] + (ink[k] - paper[k]) * c);
                }
            }
            // Then the ink laid again, in rows where some tone read is darker than the ink
            // (most rows' are not: the plain loop above stays as fast as without it).
            let across = reader.as_ref().map(|t| t.row(y));
            let dark_row = match (&reader, &across) {
                (Some(t), Some(a)) => t.row_low(a) < deeper.darker_below,
                _ => params.tone < deeper.darker_below,
            };
            if !dark_row {
                return;
            }
            for (x, (px, &c)) in row.chunks_exact_mut(3).zip(cov).enumerate() {
                if c <= 0.0 {
                    continue;
                }
                let l = match (&reader, &across) {
                    (Some(t), Some(a)) => t.at(x, a, deeper.darker_below),
                    _ => Some(params.tone),
                };
                if let Some(darker) = l.and_then(|l| deeper.at(l)) {
                    for k in 0..3 {
                        px[k] = round_to_byte(paper[k] + (darker[k] - paper[k]) * c);
                    }
                }
            }
        });
    RgbImage::from_raw(r.width as u32, r.height as u32, out).expect("w·h RGB pixels")
}

/// The middle of a line's ink and its half-width at every point, from how far it reaches on
/// either side (`sides`, along [`normal_at`] and against it).
fn ink_bands(points: &[DVec2], sides: &[[f64; 2]]) -> (Vec<DVec2>, Vec<f64>) {
    (0..points.len())
        .map(|i| {
            let [left, right] = sides[i];
            (
                points[i] + normal_at(points, i) * (0.5 * (left - right)),
                0.5 * (left + right),
            )
        })
        .unzip()
}

/// Rows of output per band of the parallel rasterisation.
const BAND_ROWS: usize = 16;

/// A piece of a line between two of its points, in output pixels, with the half-widths of the
/// ink at both ends.
struct Segment {
    a: DVec2,
    b: DVec2,
    ra: f64,
    rb: f64,
    line: u32,
}

/// Ink coverage (0 to 1) of every output pixel, row-major. Within a line the coverage of its
/// segments is the largest (they overlap at every joint); the coverages of different lines add
/// up (neighbouring lines in a dark area share the pixels between them, and together ink them
/// fully), capped at 1.
fn coverage(e: &Engraving, width: usize, height: usize, domain: DVec2) -> Vec<f32> {
    let scale = DVec2::new(width as f64 / domain.x, height as f64 / domain.y);
    let ppu = scale.x.min(scale.y);
    let mut segments: Vec<Segment> = Vec::new();
    for (id, (line, sides)) in e.lines.iter().zip(&e.sides).enumerate() {
        // The ink's middle and half-width at every point: the two sides' reaches, centred.
        let (middle, radius) = ink_bands(&line.points, sides);
        for i in 0..line.points.len().saturating_sub(1) {
            let (ra, rb) = (radius[i] * ppu, radius[i + 1] * ppu);
            if ra.max(rb) > 1e-3 {
                segments.push(Segment {
                    a: middle[i] * scale,
                    b: middle[i + 1] * scale,
                    ra,
                    rb,
                    line: id as u32,
                });
            }
        }
    }
    let bands = height.div_ceil(BAND_ROWS);
    let mut in_band: Vec<Vec<u32>> = vec![Vec::new(); bands];
    for (k, s) in segments.iter().enumerate() {
        let reach = s.ra.max(s.rb) + 1.0;
        let y0 = ((s.a.y.min(s.b.y) - reach).floor().max(0.0) as usize) / BAND_ROWS;
        let y1 = ((s.a.y.max(s.b.y) + reach).ceil().max(0.0) as usize / BAND_ROWS).min(bands - 1);
        for band in in_band.iter_mut().take(y1 + 1).skip(y0) {
            band.push(k as u32);
        }
    }
    // The bands add into it: filled by writing (see `buffer`).
    let mut cover = crate::render::support::buffer::filled(width * height, 0.0f32);
    cover
        .par_chunks_mut(BAND_ROWS * width)
        .zip(&in_band)
        .enumerate()
        .for_each_init(
            || (Vec::new(), Vec::new()),
            |(line, own), (band, (rows, list))| {
                // Per band, not per pixel: the line last drawn at each pixel and its coverage there
                // (buffers reused from band to band).
                line.clear();
                line.resize(rows.len(), u32::MAX);
                own.clear();
                own.resize(rows.len(), 0.0);
                let mut last = BandLayer {
                    line,
                    own,
                    others: rows,
                    width,
                    y_start: band * BAND_ROWS,
                };
                for &k in list {
                    last.stamp(&segments[k as usize]);
                }
                for (o, own) in last.others.iter_mut().zip(last.own.iter()) {
                    *o = (*o + own).min(1.0);
                }
            },
        );
    cover
}

/// One band's coverage while it is drawn: `others` holds the lines finished at each pixel,
/// `own` the coverage of the line being drawn there (`line`).
struct BandLayer<'a> {
    line: &'a mut [u32],
    own: &'a mut [f32],
    others: &'a mut [f32],
    width: usize,
    y_start: usize,
}

impl BandLayer<'_> {
    /// Draws segment `s` into the band's rows.
    fn stamp(&mut self, s: &Segment) {
        let (a, b) = (s.a, s.b);
        let reach = s.ra.max(s.rb) + 1.0;
        let y_end = self.y_start + self.others.len() / self.width;
        let x0 = (a.x.min(b.x) - reach).floor().max(0.0) as usize;
        let x1 = ((a.x.max(b.x) + reach).ceil().max(0.0) as usize).min(self.width);
        let y0 = ((a.y.min(b.y) - reach).floor().max(0.0) as usize).max(self.y_start);
        let y1 = ((a.y.max(b.y) + reach).ceil().max(0.0) as usize).min(y_end);
        let ab = b - a;
        let len2 = ab.length_squared().max(1e-12);
        // The pixel's square projected across the segment: boxes |n_x| and |n_y| wide.
        let foot = ab.perp().normalize_or(DVec2::Y).abs().to_array();
        let r_max = s.ra.max(s.rb);
        for y in y0..y1 {
            let base = (y - self.y_start) * self.width;
            for x in x0..x1 {
                let c = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                let t = ((c - a).dot(ab) / len2).clamp(0.0, 1.0);
                let d = (c - (a + ab * t)).length();
                if d - r_max >= std::f64::consts::FRAC_1_SQRT_2 {
                    // Beyond the reach of any pixel's square (half its diagonal).
                    continue;
                }
                let r = s.ra + (s.rb - s.ra) * t;
                // The share of the pixel's square that a band of half-width r at distance d
                // inks across the segment (at a round end, the same footprint).
                let v = band_coverage(d, r, foot);
                if v <= 0.0 {
                    continue;
                }
                let i = base + x;
                if self.line[i] == s.line {
                    self.own[i] = self.own[i].max(v);
                } else {
                    self.others[i] += self.own[i];
                    self.line[i] = s.line;
                    self.own[i] = v;
                }
            }
        }
    }
}
