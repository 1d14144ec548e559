//! The tone the engraving ([`super`]) reads, how its lines ink a tone, and the ink it
//! lays again in the dark tones: the photo's lightness (sRGB-encoded luminance) on a coarse
//! grid blurred over a fifth of a line spacing ([`Tone`]), read at every output pixel with
//! weights found once ([`ToneReader`]); the lines' share of the gap, the paper they leave and
//! their merging ([`LineShares`]); and the ink darkened to keep a tone, tabulated
//! ([`DeeperInk`]).
//! `f32` values, `f64` positions in domain units.

use crate::render::scene::Scene;
use crate::render::support::bilinear::bilinear;
use crate::render::support::colour::{darkened_to, lightness, linear_of};
use glam::DVec2;

/// The photo's lightness (sRGB-encoded luminance, 0 to 1) on a coarse grid, blurred.
pub(crate) struct Tone {
    values: Vec<f32>,
    cols: usize,
    rows: usize,
    /// Domain units per node.
    step: f64,
}

impl Tone {
    /// The tone of `scene`'s photo for lines `d_sep` apart (domain units); `None` without one.
    pub(crate) fn of(scene: &Scene, d_sep: f64) -> Option<Tone> {
        use crate::field::structure::linear_analysis_image;
        let photo = scene.photo?;
        let domain = scene.raster.domain;
        let photo_per_unit = f64::from(photo.width()) / domain.x.max(1e-9);
        // Nodes about a third of a spacing apart (the blur is then a little under a node).
        let factor = ((d_sep * photo_per_unit / 3.0).floor() as usize).max(1);
        let image = linear_analysis_image(photo, factor);
        let mut values: Vec<f32> = image
            .data
            .chunks_exact(3)
            .map(|c| lightness([c[0], c[1], c[2]]))
            .collect();
        let step = factor as f64 / photo_per_unit;
        crate::field::blur::gaussian_blur_parallel_mut(
            &mut values,
            image.width,
            image.height,
            1,
            (TONE_BLUR * d_sep / step) as f32,
        );
        Some(Tone {
            values,
            cols: image.width,
            rows: image.height,
            step,
        })
    }

    /// The tone at `p` (domain units), bilinear, clamped at the grid's edges.
    pub(crate) fn at(&self, p: DVec2) -> f32 {
        let x = (p.x / self.step - 0.5).clamp(0.0, (self.cols - 1) as f64);
        let y = (p.y / self.step - 0.5).clamp(0.0, (self.rows - 1) as f64);
        let (last_c, last_r) = (self.cols as i64 - 1, self.rows as i64 - 1);
        let [v] = bilinear(x, y, |i, j| {
            [self.values[j.min(last_r) as usize * self.cols + i.min(last_c) as usize]]
        });
        v
    }
}

/// The tone read at every pixel of a `width × height` picture: per column the two grid columns
/// and the weight between them, per row the same, found once (a division and clamps per pixel
/// cost 0.3 CPU-s at 12 MP); the lowest node of each grid row, so that a row of pixels whose
/// nodes are all lighter than the ink reads none.
pub(crate) struct ToneReader<'a> {
    tone: &'a Tone,
    columns: Vec<(usize, usize, f32)>,
    rows: Vec<(usize, usize, f32)>,
    node_row_low: Vec<f32>,
}

impl<'a> ToneReader<'a> {
    /// The reader of `tone` at the pixels of a `width × height` picture of `domain`.
    pub(crate) fn new(tone: &'a Tone, domain: DVec2, (width, height): (usize, usize)) -> Self {
        let axis = |n: usize, pixels: usize, extent: f64| -> Vec<(usize, usize, f32)> {
            (0..pixels)
                .map(|k| {
                    let g = ((k as f64 + 0.5) * extent / pixels as f64 / tone.step - 0.5)
                        .clamp(0.0, (n - 1) as f64);
                    let i = g as usize;
                    (i, (i + 1).min(n - 1), (g - i as f64) as f32)
                })
                .collect()
        };
        ToneReader {
            tone,
            columns: axis(tone.cols, width, domain.x),
            rows: axis(tone.rows, height, domain.y),
            node_row_low: tone
                .values
                .chunks(tone.cols)
                .map(|row| row.iter().copied().fold(f32::INFINITY, f32::min))
                .collect(),
        }
    }

    /// Pixel row `y`'s two grid rows and the weight of the second.
    pub(crate) fn row(&self, y: usize) -> (usize, usize, f32) {
        self.rows[y]
    }

    /// The lowest node of the two grid rows `across`.
    pub(crate) fn row_low(&self, &(j0, j1, _): &(usize, usize, f32)) -> f32 {
        self.node_row_low[j0].min(self.node_row_low[j1])
    }

    /// The tone at pixel `x` of the row `across`, or `None` where its four nodes are all at
    /// least `above` (the blend is too).
    #[inline]
    pub(crate) fn at(
        &self,
        x: usize,
        &(j0, j1, ty): &(usize, usize, f32),
        above: f32,
    ) -> Option<f32> {
        let (i0, i1, tx) = self.columns[x];
        let v = &self.tone.values;
        let cols = self.tone.cols;
        let (a, b) = (v[j0 * cols + i0], v[j0 * cols + i1]);
        let (c, d) = (v[j1 * cols + i0], v[j1 * cols + i1]);
        if a.min(b).min(c).min(d) >= above {
            return None;
        }
        let top = a + (b - a) * tx;
        let bottom = c + (d - c) * tx;
        Some(top + (bottom - top) * ty)
    }
}

/// How the engraving's lines ink a tone (lightness after the tone curve, sRGB-encoded, 0 to 1):
/// the share of its half of the gap a line's side covers ([`Self::cover`]), how much wider it
/// swells to merge with its neighbours ([`Self::widening`]), and the ink it is laid in.
///
/// Over the lighter tones the lines are in the ink, and their share is what gives the tone
/// over the paper: `(paper − t) / (paper − ink)`. Carried on down to the ink's own lightness,
/// that share reached the whole gap there and the lines merged into flat ink already about 13
/// levels above it: a night sky's gradient from 50 down to 30 became lines that stopped along a
/// hard contour, with flat ink beyond. Below [`Self::slits_from`] the paper between the lines
/// instead narrows in proportion to the tone (`SLIT_SHARE · t / paper` of the gap) and the ink
/// darkens to keep the tone (`(t − s·paper) / (1 − s)`, `s` the paper left), so the lines stay
/// visible, closing smoothly towards black, as an engraver's do. The switch is where both give
/// the ink itself, so the tone and the lines are continuous there.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LineShares {
    paper: f32,
    ink: f32,
    /// Below this tone the paper narrows in proportion to it.
    slits_from: f32,
    /// The cover from which the lines swell to merge ([`Self::widening`]).
    merge_from: f64,
}

/// The paper left between the lines below [`LineShares`]' switch, as a share of the gap, per
/// unit of `tone / paper`: at the ink's own lightness (29 of 255 on 240 paper) about 6 % of
/// the gap, at half of it 3 %.
const SLIT_SHARE: f32 = 0.5;

impl LineShares {
    /// The shares of lines in `ink` on `paper` (sRGB).
    pub(crate) fn new(ink: [u8; 3], paper: [u8; 3]) -> Self {
        let (paper, ink) = (lightness(linear_of(paper)), lightness(linear_of(ink)));
        // Where `(paper − t)/(paper − ink) = 1 − SLIT_SHARE·t/paper`; none for an ink as light
        // as the paper, or lighter.
        let slits_from = if paper - ink > 1e-3 && ink > 0.0 {
            ink * paper / (paper - SLIT_SHARE * (paper - ink))
        } else {
            0.0
        };
        // The lines merge only in tones darker than the ink, where the ink can darken to the
        // tone of solid ink; over black ink, from `MERGE_FROM`.
        let merge_from = if slits_from > 0.0 {
            MERGE_FROM.max(f64::from(1.0 - SLIT_SHARE * ink / paper))
        } else {
            MERGE_FROM
        };
        LineShares {
            paper,
            ink,
            slits_from,
            merge_from,
        }
    }

    /// The tone below which the ink darkens ([`Self::ink_lightness`]).
    pub(crate) fn slits_from(&self) -> f32 {
        self.slits_from
    }

    /// The share of its half-gap a line's side inks at tone `t`, before it swells. An ink
    /// lighter than the paper (white lines on black, a scratchboard) inks the light tones.
    pub(crate) fn cover(&self, t: f32) -> f32 {
        let room = self.paper - self.ink;
        if room.abs() <= 1e-3 {
            1.0
        } else if t < self.slits_from {
            1.0 - SLIT_SHARE * t.max(0.0) / self.paper
        } else {
            ((self.paper - t) / room).clamp(0.0, 1.0)
        }
    }

    /// How much wider than its share a line at `cover` is drawn: not at all up to the cover
    /// at the ink's own tone (at least [`MERGE_FROM`]), then smoothly up to `1 + MERGE_WIDEN`
    /// at solid ink. Streamlines are only about `d_sep` apart: where neighbours part, or one
    /// ends, lines at exactly their share leave slivers of paper, and a black area (a night
    /// sky, a dark coat, a silhouette) read as white scratches on black (5 % of a black
    /// horse's pixels lighter than 100). Lines that swell past their share in the darkest
    /// tones merge into solid ink, as an engraver's do.
    pub(crate) fn widening(&self, cover: f32) -> f64 {
        let from = self.merge_from;
        let t = ((f64::from(cover) - from) / (1.0 - from).max(1e-6)).clamp(0.0, 1.0);
        1.0 + MERGE_WIDEN * t * t * (3.0 - 2.0 * t)
    }

    /// The lightness of the ink at tone `t`: below [`Self::slits_from`], darker than the ink,
    /// so that with the paper the swollen lines leave it reads as `t` (`t` itself where they
    /// merge); `None` where it is the ink's own.
    fn ink_lightness(&self, t: f32) -> Option<f32> {
        if t >= self.slits_from {
            return None;
        }
        let t = t.max(0.0);
        let cover = self.cover(t);
        let slit = (1.0 - f64::from(cover) * self.widening(cover)).max(0.0) as f32;
        Some(((t - slit * self.paper) / (1.0 - slit)).clamp(0.0, self.ink))
    }
}

/// The coverage from which lines widen to merge ([`LineShares::widening`]) at the least.
/// From 0.93 the lines keep the photo's edges about as well as unmerged lines while the
/// darkest tones read as solid; from lower, the faint lights of dark skies would drown.
const MERGE_FROM: f64 = 0.93;

/// The widening of a line at solid ink ([`LineShares::widening`]): half its share more (a
/// whole share more closed the last slivers but merged more of the darkest detail: Hubble's
/// recall 0.256).
const MERGE_WIDEN: f64 = 0.5;

/// The ink laid where the tone is below [`LineShares::slits_from`]: the ink's colour scaled in
/// linear light to [`LineShares::ink_lightness`], tabulated over those tones (a power per dark
/// pixel cost 0.3 CPU-s on a 12 MP photo with a dark tenth; the table is within a hundredth of
/// a level of it).
pub(crate) struct DeeperInk {
    /// Tones at least this light (before the tone curve: its inverse at the switch, with a
    /// margin for rounding) take the ink itself.
    pub(crate) darker_below: f32,
    /// The ink (sRGB values, 0 to 255) at [`DEEPER_STEPS`] + 1 tones evenly from 0 to
    /// `darker_below`, `None` at those that take the ink itself.
    table: Vec<Option<[f32; 3]>>,
}

/// Steps of [`DeeperInk`]'s table.
const DEEPER_STEPS: usize = 1024;

impl DeeperInk {
    /// The ink `ink` darkened for the tones `shares` darken it at, through the tone curve of
    /// `gamma`.
    pub(crate) fn new(ink: [u8; 3], shares: &LineShares, gamma: f32) -> Self {
        use crate::field::structure::{linear_to_srgb, srgb_to_linear};
        let ink = linear_of(ink);
        let luminance = crate::render::support::colour::luminance(ink);
        let gamma = gamma.max(1e-3);
        let darker_below = 1.0 - (1.0 - shares.slits_from()).powf(1.0 / gamma) + 1e-3;
        let table = (0..=DEEPER_STEPS)
            .map(|s| {
                let l = darker_below * s as f32 / DEEPER_STEPS as f32;
                let target = 1.0 - (1.0 - l.clamp(0.0, 1.0)).powf(gamma);
                let lighter = shares.ink_lightness(target)?;
                (luminance > 0.0).then(|| {
                    darkened_to(ink, srgb_to_linear(lighter)).map(|v| 255.0 * linear_to_srgb(v))
                })
            })
            .collect();
        DeeperInk {
            darker_below,
            table,
        }
    }

    /// The ink (sRGB values, 0 to 255) at the tone of lightness `l` (before the tone curve),
    /// where it is darker than the ink itself; `None` elsewhere. Between two entries of the
    /// table, their blend; next to a `None`, the nearer entry.
    #[inline]
    pub(crate) fn at(&self, l: f32) -> Option<[f32; 3]> {
        // Most of a picture is lighter than the switch.
        if l.is_nan() || l >= self.darker_below {
            return None;
        }
        let g = (l.max(0.0) / self.darker_below) * DEEPER_STEPS as f32;
        let i = (g as usize).min(DEEPER_STEPS - 1);
        let t = g - i as f32;
        match (self.table[i], self.table[i + 1]) {
            (Some(a), Some(b)) => Some(std::array::from_fn(|k| a[k] + (b[k] - a[k]) * t)),
            (a, b) => {
                if t < 0.5 {
                    a
                } else {
                    b
                }
            }
        }
    }
}

/// σ of the tone's blur as a share of the line spacing: the width follows detail along a line
/// down to about this scale (across the lines the spacing itself is the limit).
const TONE_BLUR: f64 = 0.2;
