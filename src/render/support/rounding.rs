//! `floor`, `ceil` and `round` without calls into libm: the baseline x86-64 target has no
//! rounding instruction, and per-pixel code (texture lattices, stipple cells, triangle spans,
//! the LIC's bytes) rounds several times a pixel. Exact for every `|x| < 2⁵²`, which is all a
//! picture's coordinates and values.

/// `x.floor()`, exact for `|x| < 2⁶³`.
#[inline]
#[must_use]
pub fn floor(x: f64) -> f64 {
    let t = x as i64 as f64;
    if t > x {
        t - 1.0
    } else {
        t
    }
}

/// `x.ceil()`, exact for `|x| < 2⁶³`.
#[inline]
#[must_use]
pub fn ceil(x: f64) -> f64 {
    -floor(-x)
}

/// `x.round()` (halves away from zero) up to the sign of a zero result, exact for
/// `|x| < 2⁵²` (where `x` minus its integer part is exact).
#[inline]
#[must_use]
pub fn round(x: f64) -> f64 {
    let t = x as i64 as f64;
    let frac = x - t;
    if frac >= 0.5 {
        t + 1.0
    } else if frac <= -0.5 {
        t - 1.0
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_is_the_floor() {
        for x in [
            -2.5,
            -2.0,
            -1e-300,
            -0.0,
            0.0,
            0.3,
            1.0,
            7.999_999_999,
            1e15 + 0.5,
            -1e15 - 0.5,
        ] {
            assert_eq!(floor(x), f64::floor(x), "{x}");
            assert_eq!(ceil(x), f64::ceil(x), "{x}");
        }
    }

    #[test]
    fn round_is_the_round() {
        let mut values = vec![
            0.5 - f64::EPSILON / 4.0,
            1e15 + 0.5,
            -1e15 - 0.5,
            4.5e15 + 0.5,
        ];
        for i in -2600..=2600 {
            let x = f64::from(i) / 10.0;
            values.extend([x, x.next_up(), x.next_down(), x + 0.05]);
        }
        for x in values {
            // Equal as numbers: -0.0 == 0.0.
            assert_eq!(round(x), f64::round(x), "{x}");
        }
    }
}
