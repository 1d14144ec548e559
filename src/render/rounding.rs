//! `floor` and `ceil` without calls into libm: the baseline x86-64 target has no rounding
//! instruction, and per-pixel code (texture lattices, stipple cells, triangle spans) rounds
//! several times a pixel. Exact for every `|x| < 2⁶³`, which is all a picture's coordinates.

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
}
