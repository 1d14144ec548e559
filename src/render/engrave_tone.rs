//! The tone the engraving ([`super::engrave`]) reads and the ink it lays again where that tone
//! is darker than its ink: the photo's lightness (sRGB-encoded luminance) on a coarse grid
//! blurred over a fifth of a line spacing ([`Tone`]), read at every output pixel with weights
//! found once ([`ToneReader`]), and the ink darkened to a tone, tabulated ([`DeeperInk`]).
//! `f32` values, `f64` positions in domain units.

use super::colour::{bilinear, lightness, linear_of};
use super::scene::Scene;
use glam::DVec2;

/// The photo's lightness (sRGB-encoded luminance, 0 to 1) on a coarse grid, blurred.
pub(super) struct Tone {
    values: Vec<f32>,
    cols: usize,
    rows: usize,
    /// Domain units per node.
    step: f64,
}

impl Tone {
    /// The tone of `scene`'s photo for lines `d_sep` apart (domain units); `None` without one.
    pub(super) fn of(scene: &Scene, d_sep: f64) -> Option<Tone> {
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
    pub(super) fn at(&self, p: DVec2) -> f32 {
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
pub(super) struct ToneReader<'a> {
    tone: &'a Tone,
    columns: Vec<(usize, usize, f32)>,
    rows: Vec<(usize, usize, f32)>,
    node_row_low: Vec<f32>,
}

impl<'a> ToneReader<'a> {
    /// The reader of `tone` at the pixels of a `width × height` picture of `domain`.
    pub(super) fn new(tone: &'a Tone, domain: DVec2, (width, height): (usize, usize)) -> Self {
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
    pub(super) fn row(&self, y: usize) -> (usize, usize, f32) {
        self.rows[y]
    }

    /// The lowest node of the two grid rows `across`.
    pub(super) fn row_low(&self, &(j0, j1, _): &(usize, usize, f32)) -> f32 {
        self.node_row_low[j0].min(self.node_row_low[j1])
    }

    /// The tone at pixel `x` of the row `across`, or `None` where its four nodes are all at
    /// least `above` (the blend is too).
    #[inline]
    pub(super) fn at(
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

/// The ink laid again where the tone is darker than the ink: the ink's colour scaled in linear
/// light to the tone's lightness, tabulated over the tones darker than the ink (a power per
/// dark pixel cost 0.3 CPU-s on a 12 MP photo with a dark tenth; the table is within a
/// hundredth of a level of it).
pub(super) struct DeeperInk {
    /// Tones at least this light (the tone curve's inverse at the ink's lightness, with a
    /// margin for rounding) are not darker than the ink.
    pub(super) darker_below: f32,
    /// The ink (sRGB values, 0 to 255) at [`DEEPER_STEPS`] + 1 tones evenly from 0 to
    /// `darker_below`, `None` at those not darker than the ink.
    table: Vec<Option<[f32; 3]>>,
}

/// Steps of [`DeeperInk`]'s table.
const DEEPER_STEPS: usize = 1024;

impl DeeperInk {
    pub(super) fn new(ink: [u8; 3], gamma: f32) -> Self {
        use crate::field::structure::{linear_to_srgb, srgb_to_linear};
        let ink = linear_of(ink);
        let (ink_lightness, luminance) = (lightness(ink), super::colour::luminance(ink));
        let gamma = gamma.max(1e-3);
        let darker_below = 1.0 - (1.0 - ink_lightness).powf(1.0 / gamma) + 1e-3;
        let table = (0..=DEEPER_STEPS)
            .map(|s| {
                let l = darker_below * s as f32 / DEEPER_STEPS as f32;
                let target = 1.0 - (1.0 - l.clamp(0.0, 1.0)).powf(gamma);
                (target < ink_lightness && luminance > 0.0).then(|| {
                    let k = (srgb_to_linear(target) / luminance).clamp(0.0, 1.0);
                    ink.map(|v| 255.0 * linear_to_srgb(v * k))
                })
            })
            .collect();
        DeeperInk {
            darker_below,
            table,
        }
    }

    /// The ink (sRGB values, 0 to 255) that reads as the tone of lightness `l` through the tone
    /// curve, where that is darker than the ink; `None` elsewhere. Between two entries of the
    /// table, their blend; next to a `None`, the nearer entry.
    #[inline]
    pub(super) fn at(&self, l: f32) -> Option<[f32; 3]> {
        // Most of a picture is lighter than the ink.
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
