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

/// Contact distance of two samples at `pa`, `pb` with metrics `ma`, `mb`: about the factor `d`
/// such that the two ellipses, both scaled by `d` about their centres, touch, so `d < 1` when
/// they overlap anywhere, not only along the connecting line as with
/// [`normalised_distance`].
///
/// Perram and Wertheim's contact function gives that factor exactly as
/// `d² = max over λ ∈ [0, 1] of λ(1 − λ)·yᵀ C(λ)⁻¹ y` with `C(λ) = (1 − λ)·m_a² + λ·m_b²`.
/// This evaluates it at `λ = ½` and after one Newton step from there: the maximum is at `½`
/// for equal metrics (then `d` equals eq. 4's distance), and the function is flat and smooth
/// around it, so for neighbours, whose metrics differ a little, one step lands on it (tested
/// against a brute-force contact: within 0.1 % for sizes within 1.5× and axes within 30°).
/// Anywhere it is a lower bound of the exact contact distance, so it never lets two ellipses
/// overlap unnoticed. Coincident samples have `d = 0`.
#[inline]
#[must_use]
pub fn contact_distance(pa: DVec2, ma: &Tensor, pb: DVec2, mb: &Tensor) -> f64 {
    contact_distance_of_squares(pa, &ma.squared(), pb, &mb.squared())
}

/// [`contact_distance`] from the squared metrics `m_a²`, `m_b²` ([`Tensor::squared`]), which
/// the relaxation keeps per particle instead of squaring them again for every edge.
#[inline]
#[must_use]
pub fn contact_distance_of_squares(pa: DVec2, a2: &Tensor, pb: DVec2, b2: &Tensor) -> f64 {
    let y = pa - pb;
    let (a, b) = ((a2.xx, a2.xy, a2.yy), (b2.xx, b2.xy, b2.yy));
    // yᵀ adj(C) y and det C for C = C(λ) = (1 − λ)·A + λ·B: N(λ) = n0 + n1·λ,
    // D(λ) = d0 + d1·λ + d2·λ².
    let adj_form = |c: (f64, f64, f64)| c.2 * y.x * y.x - 2.0 * c.1 * y.x * y.y + c.0 * y.y * y.y;
    let (na, nb) = (adj_form(a), adj_form(b));
    let delta = (b.0 - a.0, b.1 - a.1, b.2 - a.2);
    let d0 = a.0 * a.2 - a.1 * a.1;
    let d1 = a.0 * delta.2 + a.2 * delta.0 - 2.0 * a.1 * delta.1;
    let d2 = delta.0 * delta.2 - delta.1 * delta.1;
    let f = |l: f64| l * (1.0 - l) * (na + (nb - na) * l) / (d0 + l * (d1 + l * d2));
    let half = f(0.5);
    // Coincident samples give 0, a degenerate C gives NaN: both count as touching centres.
    if half.is_nan() || half <= 0.0 {
        return 0.0;
    }
    // One Newton step on (log F)' = N'/N − D'/D + (1 − 2λ)/(λ − λ²) from λ = ½, where the last
    // term and its slope are 0 and −8.
    let (n, dn) = (0.5 * (na + nb), nb - na);
    let (d, dd) = (d0 + 0.5 * d1 + 0.25 * d2, d1 + d2);
    // Near ½, log F rises by at most about φ²/16 (the slope there is about −8), so `d` by
    // φ²/32: under NEWTON_SKIP_PHI that is below 1e-4 of `d`, and the step is skipped (the
    // neighbours of a smooth field, most pairs, differ that little). `n` and `d` are positive
    // here (`F(½) = n/(4d) > 0`), so `|φ| < s` is tested as `|dn·d − dd·n| < s·n·d`, without
    // dividing.
    if (dn * d - dd * n).abs() < NEWTON_SKIP_PHI * n * d {
        return half.sqrt();
    }
    let phi = dn / n - dd / d;
    let slope = -8.0 - (dn / n).powi(2) - (2.0 * d2 * d - dd * dd) / (d * d);
    let step = (0.5 - phi / slope).clamp(0.05, 0.95);
    // F(λ) ≤ max F for every λ, so the larger of the two is the better lower bound.
    half.max(f(step)).sqrt()
}

/// [`contact_distance`] takes its Newton step only when `|φ|`, the slope of `log F` at `λ = ½`,
/// is at least this: below it the step would raise `d` by less than `φ²/32 < 1e-4` of itself.
const NEWTON_SKIP_PHI: f64 = 0.056;

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

    /// Brute-force contact distance: bisect on the scale at which the scaled ellipses share a
    /// point, tested on a fine sampling of a's boundary against b's inside.
    fn brute_contact(pa: DVec2, ma: &Tensor, pb: DVec2, mb: &Tensor) -> f64 {
        let ib = mb.inverse().unwrap();
        let overlap = |s: f64| {
            (0..20_000).any(|k| {
                let t = f64::from(k) / 20_000.0 * 2.0 * PI;
                let x = pa + ma.mul_vec(DVec2::new(t.cos(), t.sin())) * s;
                ib.mul_vec(x - pb).length() <= s
            })
        };
        let (mut lo, mut hi) = (0.0, 100.0);
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if overlap(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        // Scaled by `hi` they touch, which is what a contact distance of `hi` means.
        hi
    }

    #[test]
    fn contact_distance_bounds_the_exact_contact_from_below() {
        // (angle, semi-axes of a; angle, semi-axes of b; direction of b from a), degrees.
        let neighbours = [
            (0.0, 4.0, 1.0, 30.0, 4.0, 1.0, 90.0),
            (10.0, 3.0, 1.5, 40.0, 2.5, 1.2, 75.0),
            (-20.0, 4.0, 1.0, -35.0, 5.0, 1.3, 10.0),
            (45.0, 2.0, 2.0, 45.0, 2.5, 2.5, 200.0),
            (60.0, 6.0, 1.5, 80.0, 5.0, 1.2, 150.0),
        ];
        let strangers = [
            (0.0, 4.0, 1.0, 90.0, 4.0, 1.0, 30.0),
            (-20.0, 20.0, 1.0, 25.0, 5.0, 1.0, 0.0),
            (0.0, 1.0, 1.0, 0.0, 8.0, 8.0, 45.0),
        ];
        let all = neighbours
            .iter()
            .map(|c| (c, 0.001))
            .chain(strangers.iter().map(|c| (c, 1.0)));
        for (&(aa, a1, a2, ab, b1, b2, dir), tolerance) in all {
            let ma = Tensor::from_eigen(f64::to_radians(aa), a1, a2);
            let mb = Tensor::from_eigen(f64::to_radians(ab), b1, b2);
            let u = DVec2::new(f64::to_radians(dir).cos(), f64::to_radians(dir).sin());
            let (pa, pb) = (DVec2::new(1.0, 2.0), DVec2::new(1.0, 2.0) + u * 5.0);
            let d = contact_distance(pa, &ma, pb, &mb);
            let exact = brute_contact(pa, &ma, pb, &mb);
            assert!(d <= exact * (1.0 + 1e-4), "{d} above the exact {exact}");
            assert!(d >= exact * (1.0 - tolerance), "{d} vs exact {exact}");
            let (ia, ib) = (ma.inverse().unwrap(), mb.inverse().unwrap());
            assert!(exact <= normalised_distance(pa, &ia, pb, &ib) * (1.0 + 1e-4));
            assert!((contact_distance(pb, &mb, pa, &ma) - d).abs() < 1e-12 * d);
        }
    }

    proptest! {
        #[test]
        fn contact_distance_equals_the_line_distance_for_equal_metrics(
            angle in -PI..PI, dir in -PI..PI, a in 0.5..20.0f64, r in 1.0..20.0f64,
            len in 0.1..100.0f64,
        ) {
            let m = Tensor::from_eigen(angle, a * r, a);
            let inv = m.inverse().unwrap();
            let y = DVec2::new(dir.cos(), dir.sin()) * len;
            let line = normalised_distance(y, &inv, DVec2::ZERO, &inv);
            let contact = contact_distance(y, &m, DVec2::ZERO, &m);
            prop_assert!((line - contact).abs() < 1e-9 * line);
        }

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
