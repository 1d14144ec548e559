//! The force spline `f(d)` of paper section 5.3: piecewise cubic and C¹ over the normalised
//! distance `d`, repelling (`f > 0`) for `0 < d < 1`, zero at `d = 1`, attracting (`f < 0`) for
//! `1 < d < 1 + γ` and zero beyond, bounded at `d → 0`.
//!
//! Repelling piece (Hermite, `t = d ∈ [0, 1]`): `f(0) = 1`, `f'(0) = 0`, `f(1) = 0`,
//! `f'(1) = s`. Attracting piece (`t = d − 1 ∈ [0, γ]`): `k·t·(t − γ)²`, zero with zero slope at
//! `1 + γ`, slope `k·γ²` at 1. C¹ at `d = 1` sets `s = k·γ²`; the depth of the attracting well,
//! `4|k|γ³/27`, is chosen as [`ATTRACTION_DEPTH`] of the largest repulsion.

/// Range of the attracting forces beyond `d = 1` (the paper's γ).
pub const GAMMA: f64 = 0.5;

/// Largest attraction as a fraction of the largest repulsion `f(0) = 1`. Shallow on purpose:
/// in a disordered packing the triangulation links some neighbours at `d ≈ 1.2–1.4`, whose
/// attraction squeezes grain boundaries; measured on constant fields, a depth of 0.1 left the
/// 5th percentile of nearest-neighbour distances at 0.88, a depth of 0.01 at 0.92.
pub const ATTRACTION_DEPTH: f64 = 0.01;

/// `k` of the attracting piece: depth `4|k|γ³/27 = ATTRACTION_DEPTH`.
const K: f64 = -ATTRACTION_DEPTH * 27.0 / (4.0 * GAMMA * GAMMA * GAMMA);

/// Slope of `f` at `d = 1`, shared by both pieces.
pub const SLOPE_AT_ONE: f64 = K * GAMMA * GAMMA;

/// The force spline `f(d)` (NaN for a NaN `d`: the distances it is given never are).
#[inline]
#[must_use]
pub fn force_spline(d: f64) -> f64 {
    // Both pieces vanish outside their own interval (the repelling one is 0 at t = 1, the
    // attracting one at t = 0 and t = γ), so f is their sum at clamped arguments: no branch
    // on d, which falls on either side of 1 about equally often in a packing.
    let t = d.clamp(0.0, 1.0);
    // Hermite basis: h00 = 2t³ − 3t² + 1, h11 = t³ − t².
    let repelling = (2.0 * t - 3.0) * t * t + 1.0 + SLOPE_AT_ONE * (t - 1.0) * t * t;
    let u = (d - 1.0).clamp(0.0, GAMMA);
    let attracting = K * u * (u - GAMMA) * (u - GAMMA);
    repelling + attracting
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_of_the_spline() {
        assert_eq!(force_spline(0.0), 1.0);
        assert_eq!(force_spline(-3.0), 1.0);
        assert!(force_spline(1.0).abs() < 1e-15);
        assert_eq!(force_spline(1.0 + GAMMA), 0.0);
        assert_eq!(force_spline(7.0), 0.0);
        assert_eq!(force_spline(f64::INFINITY), 0.0);
        let mut prev = f64::INFINITY;
        for i in 1..1000 {
            let d = f64::from(i) / 1000.0;
            let f = force_spline(d);
            assert!(f > 0.0 && f < prev, "repelling and decreasing at {d}");
            prev = f;
        }
        for i in 1..500 {
            let d = 1.0 + f64::from(i) / 1000.0;
            assert!(force_spline(d) < 0.0, "attracting at {d}");
        }
        let well = force_spline(1.0 + GAMMA / 3.0);
        assert!((well + ATTRACTION_DEPTH).abs() < 1e-12);
    }

    #[test]
    fn continuous_with_continuous_slope() {
        let h = 1e-7;
        for knot in [1.0, 1.0 + GAMMA] {
            let left = (force_spline(knot - h) - force_spline(knot - 2.0 * h)) / h;
            let right = (force_spline(knot + 2.0 * h) - force_spline(knot + h)) / h;
            assert!(
                (left - right).abs() < 1e-5,
                "slope jumps at {knot}: {left} vs {right}"
            );
            assert!((force_spline(knot - h) - force_spline(knot + h)).abs() < 1e-6);
        }
        // At 0 the slope is zero (bounded, smooth).
        assert!((force_spline(1e-4) - 1.0).abs() < 1e-6);
    }
}
