//! The lines of the hatched looks (paper section 6's textured cells, Figures 5f–g): a family
//! of parallel lines in a cell's frame, each pixel inked by the share of its square the lines
//! cover (`stripes.rs`), and the cross-hatching's layers at 0°, 90° and 45° to the cell's long
//! axis, added one by one as the tone darkens. Geometry is `f64` in domain units, coverage `f32`.

use crate::render::lines::stripes::stripe_coverage;
use glam::DVec2;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

/// The angles of the hatch layers to the cell's long axis, in the order they are added (the
/// SVG's line families).
pub(crate) const LAYER_ANGLES: [f64; 3] = [0.0, FRAC_PI_2, FRAC_PI_4];

/// Sine and cosine of [`LAYER_ANGLES`] (as `f64::sin_cos` gives them, which a test checks; no
/// trigonometry per pixel).
pub(crate) const LAYERS: [(f64, f64); 3] = [
    (0.0, 1.0),
    (1.0, 6.123_233_995_736_766e-17),
    (0.707_106_781_186_547_5, std::f64::consts::FRAC_1_SQRT_2),
];

/// Ink coverage of a family of parallel lines at angle `φ` (its sine and cosine) to the long
/// axis through the local point, each of width `darkness × spacing`: the share of the pixel's
/// square they ink (`stripes.rs`), `normal` being their normal in picture coordinates.
/// `offset` is the site's own position across the lines (in domain units, along the same
/// normal), so that lines of neighbouring cells with the same direction and spacing continue
/// into each other.
pub(crate) fn lines(
    local: DVec2,
    (sin, cos): (f64, f64),
    spacing: f64,
    (normal, offset): (DVec2, f64),
    darkness: f32,
    px: f64,
) -> f32 {
    let across = -local.x * sin + local.y * cos + offset;
    let half = 0.5 * f64::from(darkness.clamp(0.0, 1.0));
    let foot = (normal.abs() * (px / spacing)).to_array();
    stripe_coverage(across / spacing, half, foot)
}

/// The widths (shares of the spacing) of the cross-hatching's layers for `darkness`, and how
/// many are laid: the layers come one by one, each from a hairline, the first thickening to
/// [`FIRST_LAYER`], then the second from nothing to its width at [`THIRD_FROM`], then the third,
/// so that `1 − Π(1 − x_i)` is the darkness and no line jumps in width as the tone darkens
/// (layers of one equal width `1 − (1 − d)^(1/k)` would thin every line where a layer comes
/// in, a contour of changed texture across a smooth gradient).
#[must_use]
pub(crate) fn cross_hatch_layers(darkness: f32) -> ([f32; 3], usize) {
    let second_most = 1.0 - (1.0 - THIRD_FROM) / (1.0 - FIRST_LAYER);
    if darkness < FIRST_LAYER {
        ([darkness, 0.0, 0.0], 1)
    } else if darkness < THIRD_FROM {
        let second = 1.0 - (1.0 - darkness) / (1.0 - FIRST_LAYER);
        ([FIRST_LAYER, second, 0.0], 2)
    } else {
        let third = 1.0 - (1.0 - darkness) / (1.0 - THIRD_FROM);
        ([FIRST_LAYER, second_most, third.min(1.0)], 3)
    }
}

/// The darkness at which the cross-hatching's second layer begins, and the first layer's
/// width from there on.
const FIRST_LAYER: f32 = 0.3;

/// The darkness at which the cross-hatching's third layer begins.
const THIRD_FROM: f32 = 0.6;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hatch_layers_are_0_90_and_45_degrees() {
        assert_eq!(LAYER_ANGLES, [0.0, FRAC_PI_2, FRAC_PI_4]);
        for (layer, angle) in LAYERS.iter().zip(LAYER_ANGLES) {
            assert_eq!(*layer, angle.sin_cos());
        }
    }

    #[test]
    fn line_coverage_averages_to_the_darkness() {
        for darkness in [0.1f32, 0.35, 0.8] {
            let n = 10_000;
            let mean: f32 = (0..n)
                .map(|i| {
                    let y = f64::from(i) / f64::from(n) * 10.0;
                    lines(
                        DVec2::new(0.0, y),
                        LAYERS[0],
                        2.5,
                        (DVec2::Y, 0.7),
                        darkness,
                        0.05,
                    )
                })
                .sum::<f32>()
                / n as f32;
            assert!((mean - darkness).abs() < 0.03, "{darkness}: {mean}");
        }
    }

    #[test]
    fn cross_hatch_layers_lay_the_darkness_and_no_line_jumps_in_width() {
        // Every tone is laid (1 − Π(1 − x) = d), and between tones a thousandth apart no
        // layer's width moves by more than 0.005, also where a layer comes in (0.3, 0.6):
        // layers of one equal width thinned the first from 0.3 to 0.16 of the spacing at 0.3.
        let mut last = cross_hatch_layers(0.0).0;
        for i in 1..=1000 {
            let d = i as f32 / 1000.0;
            let (widths, k) = cross_hatch_layers(d);
            let paper: f32 = widths.iter().take(k).map(|x| 1.0 - x).product();
            assert!((1.0 - paper - d).abs() < 1e-5, "{d}: {widths:?}");
            for (x, before) in widths.iter().zip(last) {
                assert!((x - before).abs() < 0.005, "{d}: {widths:?} after {last:?}");
            }
            last = widths;
        }
    }
}
