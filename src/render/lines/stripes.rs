//! The share of a pixel that a family of parallel lines ([`stripe_coverage`]) or a single
//! band ([`band_coverage`]) covers, exactly: the hatched looks' lines (paper section 6's hatch
//! textures) and the engraving's, anti-aliased by the area they ink in each pixel's square.
//! Across the lines, that square's footprint is its projection on their normal, a trapezoid:
//! the convolution of two boxes `|n_x|` and `|n_y|` pixels wide (`n` the normal in picture
//! coordinates), so one pixel wide for lines along an axis and a triangle √2 pixels wide at
//! 45°. The lines' ink convolved with it is a second difference of the ink's second
//! antiderivative ([`footprint_mean`]), which is closed-form for evenly spaced lines
//! ([`inked_twice`]) and for one band.
//!
//! A box one pixel wide across lines at 45° is narrower than the pixel they cross: it kept
//! more of the lines' harmonics than the pixel grid can hold, and fine diagonal hatching beat
//! with the grid in bands. Positions are `f64` in periods of the lines.

use crate::render::support::rounding::floor;

/// The share of a pixel inked by lines of period 1 centred on the integers, each `2·half`
/// wide (`0 ≤ half ≤ ½`), where the pixel's centre lies at `w` across them and its square
/// projects onto their normal as the convolution of boxes `foot[0]` and `foot[1]` wide (in
/// periods: the pixel's size times `|n_x|` and `|n_y|`, over the period).
#[must_use]
pub(crate) fn stripe_coverage(w: f64, half: f64, foot: [f64; 2]) -> f32 {
    // Only the place within a period matters (the ink repeats), and near 0 the sums below
    // keep their precision.
    let w = w - floor(w);
    let (wide, narrow) = (foot[0].max(foot[1]).max(1e-9), foot[0].min(foot[1]));
    // Most pixels of a hatching lie wholly in a line or a gap: no integral needed.
    let reach = 0.5 * (wide + narrow);
    let (lo, hi) = (w - reach, w + reach);
    if lo >= half && hi <= 1.0 - half {
        return 0.0;
    }
    if (lo >= -half && hi <= half) || (lo >= 1.0 - half && hi <= 1.0 + half) {
        return 1.0;
    }
    let share = footprint_mean(
        w,
        (wide, narrow),
        |x| inked_once(x, half),
        |x| inked_twice(x, half),
    );
    share.clamp(0.0, 1.0) as f32
}

/// The share of a pixel inked by one band of half width `half` whose middle line lies `d` from
/// the pixel's centre, the pixel's square projecting onto the band's normal as the
/// convolution of boxes `foot[0]` and `foot[1]` wide (the same units as `d`: the pixel's size
/// times `|n_x|` and `|n_y|`).
#[must_use]
pub(crate) fn band_coverage(d: f64, half: f64, foot: [f64; 2]) -> f32 {
    let (wide, narrow) = (foot[0].max(foot[1]).max(1e-9), foot[0].min(foot[1]));
    let reach = 0.5 * (wide + narrow);
    let d = d.abs();
    if d - reach >= half {
        return 0.0;
    }
    if d + reach <= half {
        return 1.0;
    }
    // The band's ink from −∞ to x, and its integral: 0 before the band, a parabola across
    // it, a line of slope 2·half after.
    let once = |x: f64| (x + half).clamp(0.0, 2.0 * half);
    let twice = |x: f64| {
        let inside = (x + half).clamp(0.0, 2.0 * half);
        0.5 * inside * inside + 2.0 * half * (x - half).max(0.0)
    };
    footprint_mean(d, (wide, narrow), once, twice).clamp(0.0, 1.0) as f32
}

/// The mean of an ink profile over a pixel's footprint centred at `w`, the trapezoid of boxes
/// `wide` and `narrow` wide, from the ink's first and second antiderivatives `once` and
/// `twice`: the second difference of `twice` over the trapezoid's corners, or the first
/// difference of `once` over the wider box where the narrower is under [`NARROWEST`] of it.
fn footprint_mean(
    w: f64,
    (wide, narrow): (f64, f64),
    once: impl Fn(f64) -> f64,
    twice: impl Fn(f64) -> f64,
) -> f64 {
    if narrow < NARROWEST * wide {
        (once(w + 0.5 * wide) - once(w - 0.5 * wide)) / wide
    } else {
        let (outer, inner) = (0.5 * (wide + narrow), 0.5 * (wide - narrow));
        (twice(w + outer) - twice(w + inner) - twice(w - inner) + twice(w - outer))
            / (wide * narrow)
    }
}

/// Below this ratio of its two widths, the trapezoid is taken as a box of the wider (to within
/// this it is one): the second difference divides by the narrower width, and near zero loses
/// its precision.
const NARROWEST: f64 = 0.02;

/// `∫₀ˣ ink`: the ink from 0 to `x` of lines of half width `half` centred on the integers.
#[inline]
fn inked_once(x: f64, half: f64) -> f64 {
    let n = floor(x);
    let r = x - n;
    n * 2.0 * half + r.min(half) + (r - (1.0 - half)).max(0.0)
}

/// `∫₀ˣ inked_once`: over whole periods `n`, `half·n²` (each period `k` adds `2·half·k +
/// half`); within the last, `2·half·n·r` and the integral of the ink up to `r`.
#[inline]
fn inked_twice(x: f64, half: f64) -> f64 {
    let n = floor(x);
    let r = x - n;
    let first = r.min(half);
    let middle = (r - half).max(0.0);
    let last = (r - (1.0 - half)).max(0.0);
    half * n * n + 2.0 * half * n * r + 0.5 * first * first + half * middle + 0.5 * last * last
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The share of a unit pixel centred at `(cx, cy)` inked by lines of period `period`
    /// along the normal `(nx, ny)`, half width `half` periods, counted on a fine grid.
    fn brute(cx: f64, cy: f64, (nx, ny): (f64, f64), period: f64, half: f64) -> f64 {
        let n = 400;
        let mut inked = 0;
        for i in 0..n {
            for j in 0..n {
                let x = cx - 0.5 + (f64::from(i) + 0.5) / f64::from(n);
                let y = cy - 0.5 + (f64::from(j) + 0.5) / f64::from(n);
                let w = (x * nx + y * ny) / period;
                let r = w - w.floor();
                if r < half || r >= 1.0 - half {
                    inked += 1;
                }
            }
        }
        f64::from(inked) / f64::from(n * n)
    }

    #[test]
    fn coverage_is_the_inked_area_of_the_pixel_square() {
        use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};
        for angle in [0.0f64, 0.3, FRAC_PI_4, 1.2, 2.0, FRAC_PI_2] {
            let (ny, nx) = angle.sin_cos();
            for (period, half) in [(2.2, 0.3), (3.0, 0.1), (7.5, 0.45), (1.3, 0.25)] {
                for (cx, cy) in [(10.5, 3.5), (101.5, 57.5), (4.5, 8.5)] {
                    let w = (cx * nx + cy * ny) / period;
                    let foot = [nx.abs() / period, ny.abs() / period];
                    let got = f64::from(stripe_coverage(w, half, foot));
                    let want = brute(cx, cy, (nx, ny), period, half);
                    assert!(
                        (got - want).abs() < 0.01,
                        "angle {angle} period {period} half {half} at ({cx}, {cy}): {got} vs {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_band_covers_the_area_of_the_pixel_square_it_inks() {
        // One band: the lines' formula with a period so long that only one line is near.
        for angle in [0.0f64, 0.4, 0.9, 1.3, 2.5] {
            let (ny, nx) = angle.sin_cos();
            for (half, cx, cy) in [
                (0.3, 0.5, 0.5),
                (1.2, 1.5, -0.5),
                (0.05, 0.5, 0.5),
                (0.7, 2.5, 0.5),
            ] {
                let period = 1000.0;
                let d = cx * nx + cy * ny;
                let got = f64::from(band_coverage(d, half, [nx.abs(), ny.abs()]));
                let want = brute(cx, cy, (nx, ny), period, half / period);
                assert!(
                    (got - want).abs() < 0.01,
                    "{angle} {half} ({cx}, {cy}): {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn the_second_antiderivative_is_continuous_and_integrates_the_first() {
        for half in [0.0, 0.1, 0.37, 0.5] {
            for k in -3..3 {
                let x = f64::from(k);
                assert!((inked_twice(x - 1e-9, half) - inked_twice(x + 1e-9, half)).abs() < 1e-8);
            }
            let h = 1e-4;
            for i in 0..200 {
                let x = -2.0 + f64::from(i) * 0.0213;
                let slope = (inked_twice(x + h, half) - inked_twice(x - h, half)) / (2.0 * h);
                assert!((slope - inked_once(x, half)).abs() < 1e-6, "{half} at {x}");
            }
        }
    }
}
