//! The distance measure of paper section 5.2, with the conventions every other part uses:
//!
//! - a sample's ellipse is `{ p + m(p)·u : |u| = 1 }`, so `m`'s eigenvalues are its semi-axes;
//! - its radius in a unit direction `u` is `r(u) = 1 / |m⁻¹ u|` (the paper's eq. 3 prints
//!   `|m u|`, which is the radius only along the axes; its text and Figure 1 mean the distance
//!   to the ellipse's surface, which is this);
//! - the normalised distance of samples `a`, `b` with `y = p_a − p_b` is
//!   `d = |y| / (r_a(ŷ) + r_b(ŷ))` (eq. 4): `d = 1` means the ellipses touch along `y`.
//!
//! Functions take the *inverse* metric, which samples cache, so no inversion happens in hot
//! loops. `f64` throughout.

use crate::field::Tensor;
use glam::DVec2;

/// Radius of the ellipse with inverse metric `inv` in the direction of `y` (any length > 0):
/// `|y| / |m⁻¹ y|`, which equals `1 / |m⁻¹ ŷ|`.
#[inline]
#[must_use]
pub fn radius_along(inv: &Tensor, y: DVec2) -> f64 {
    y.length() / inv.mul_vec(y).length()
}

/// Normalised distance `d = |y| / (r_a(ŷ) + r_b(ŷ))` of two samples at `pa`, `pb` with
/// inverse metrics `inv_a`, `inv_b`. Coincident samples have `d = 0`.
#[inline]
#[must_use]
pub fn normalised_distance(pa: DVec2, inv_a: &Tensor, pb: DVec2, inv_b: &Tensor) -> f64 {
    let y = pa - pb;
    // |y| / (|y|/|A y| + |y|/|B y|) = 1 / (1/|A y| + 1/|B y|).
    let (ay, by) = (inv_a.mul_vec(y).length(), inv_b.mul_vec(y).length());
    if ay == 0.0 || by == 0.0 {
        return 0.0;
    }
    ay * by / (ay + by)
}

/// Whether `p` lies inside (or on) the ellipse of a sample at `centre` with inverse metric
/// `inv`: `|m⁻¹ (p − centre)| ≤ 1`.
#[inline]
#[must_use]
pub fn inside_ellipse(p: DVec2, centre: DVec2, inv: &Tensor) -> bool {
    inv.mul_vec(p - centre).length_squared() <= 1.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::PI;

    #[test]
    fn radius_along_the_axes_and_between() {
        // Semi-axes 4 along x, 1 along y.
        let inv = Tensor::from_eigen(0.0, 4.0, 1.0).inverse().unwrap();
        assert!((radius_along(&inv, DVec2::X) - 4.0).abs() < 1e-12);
        assert!((radius_along(&inv, DVec2::Y * 3.0) - 1.0).abs() < 1e-12);
        // At 45°: the point t(1,1) on x²/16 + y² = 1 has t = 4/√17, radius t√2.
        let r45 = radius_along(&inv, DVec2::new(1.0, 1.0));
        assert!((r45 - 4.0 * 2f64.sqrt() / 17f64.sqrt()).abs() < 1e-12);
        // |m u| would give √((16 + 1)/2) ≈ 2.92, which is not on the ellipse.
        assert!((r45 - (8.5f64).sqrt()).abs() > 0.5);
    }

    proptest! {
        #[test]
        fn touching_ellipses_have_distance_one(
            angle_a in -PI..PI, angle_b in -PI..PI, dir in -PI..PI,
            a1 in 0.5..20.0f64, ra in 1.0..6.0f64, b1 in 0.5..20.0f64, rb in 1.0..6.0f64,
        ) {
            let ma = Tensor::from_eigen(angle_a, a1 * ra, a1);
            let mb = Tensor::from_eigen(angle_b, b1 * rb, b1);
            let (ia, ib) = (ma.inverse().unwrap(), mb.inverse().unwrap());
            let u = DVec2::new(dir.cos(), dir.sin());
            // Place b so that the two surfaces meet on the line through the centres.
            let gap = radius_along(&ia, u) + radius_along(&ib, u);
            let pa = DVec2::new(3.0, -2.0);
            let pb = pa - u * gap;
            prop_assert!((normalised_distance(pa, &ia, pb, &ib) - 1.0).abs() < 1e-9);
            prop_assert!((normalised_distance(pb, &ib, pa, &ia) - 1.0).abs() < 1e-9);
            // The surface point of a along -u lies on its ellipse.
            let surface = pa - u * radius_along(&ia, u);
            prop_assert!((ia.mul_vec(surface - pa).length() - 1.0).abs() < 1e-9);
            prop_assert!(inside_ellipse(pa - u * 0.99 * radius_along(&ia, u), pa, &ia));
        }
    }
}
