//! `floor`, `ceil` and `round` without calls into libm: the baseline x86-64 target has no
//! rounding instruction, and per-pixel code (texture lattices, stipple cells, triangle spans,
//! the LIC's bytes) rounds several times a pixel. Exact for every `|x| < 2⁵²`, which is all a
//! picture's coordinates and values. Also `cube_root` (the cross-hatching's layers, point by
//! point), to within 2·10⁻⁷ of libm's without its call.

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

/// `∛y` for `y ≥ 0` (within 2·10⁻⁷ of it relatively): an estimate from the float's bits
/// (within a few per cent), then two Halley steps `r·(r³ + 2y)/(2r³ + y)` in `f64`, whose
/// error goes as its cube; no libm call. (Three Newton steps in `f32` took a division each:
/// 12 MP crosshatch 3.40 → 3.31 CPU-s.)
#[inline]
#[must_use]
pub fn cube_root(y: f32) -> f32 {
    if y <= 0.0 {
        return 0.0;
    }
    // Dividing the exponent by three (the bits are about 2²³·(log₂ y + 127)).
    let r = f32::from_bits(y.to_bits() / 3 + 709_921_077);
    let (mut r, y) = (f64::from(r), f64::from(y));
    for _ in 0..2 {
        let r3 = r * r * r;
        r *= (r3 + 2.0 * y) / (2.0 * r3 + y);
    }
    r as f32
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

    #[test]
    fn cube_root_is_libms_within_its_precision() {
        for i in 0..=100_000 {
            let y = i as f32 / 100_000.0;
            let (got, want) = (cube_root(y), y.cbrt());
            assert!(
                (got - want).abs() <= 2e-7 * want.max(1e-3),
                "{y}: {got} against {want}"
            );
        }
        assert_eq!(cube_root(0.0), 0.0);
        assert_eq!(cube_root(-1.0), 0.0);
    }
}
