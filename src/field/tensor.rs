//! A symmetric 2x2 tensor `[[xx, xy], [xy, yy]]` with a closed-form eigen-decomposition
//! (paper section 3, eq. 1). The same type holds a structure tensor, a stress tensor (negative
//! eigenvalues allowed) and a metric (positive definite, eigenvalues = semi-axes in pixels).
//!
//! Arithmetic is in `f64` on purpose: the eigen-decomposition of nearly isotropic tensors
//! subtracts close numbers, and the sampler's geometric tests want the headroom. Fields store
//! `f32` and convert on access.

use glam::DVec2;

/// A symmetric 2x2 tensor.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Tensor {
    /// Component (1, 1).
    pub xx: f64,
    /// Components (1, 2) and (2, 1).
    pub xy: f64,
    /// Component (2, 2).
    pub yy: f64,
}

/// Eigen-decomposition of a [`Tensor`]: `t = l1 e1 e1ᵀ + l2 e2 e2ᵀ`, `l1 ≥ l2`, with
/// `e1 = (cos angle, sin angle)` and `e2 = (−sin angle, cos angle)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eigen {
    /// The larger eigenvalue.
    pub l1: f64,
    /// The smaller eigenvalue.
    pub l2: f64,
    /// Angle of the first eigenvector in radians, in (−π/2, π/2].
    pub angle: f64,
}

impl Eigen {
    /// The ellipse's anisotropy `1 − b/a` in [0, 1] (`a ≥ b` the semi-axes' magnitudes): 0 for
    /// a circle, towards 1 for a needle; 0 for the zero tensor.
    #[must_use]
    pub fn anisotropy(&self) -> f64 {
        let (a, b) = (self.l1.abs(), self.l2.abs());
        if a > 0.0 {
            (1.0 - b / a).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// Unit eigenvector of `l1`.
    #[must_use]
    pub fn e1(&self) -> DVec2 {
        DVec2::new(self.angle.cos(), self.angle.sin())
    }

    /// Unit eigenvector of `l2`, `e1` turned by +90°.
    #[must_use]
    pub fn e2(&self) -> DVec2 {
        DVec2::new(-self.angle.sin(), self.angle.cos())
    }
}

impl Tensor {
    /// The identity tensor.
    pub const IDENTITY: Tensor = Tensor {
        xx: 1.0,
        xy: 0.0,
        yy: 1.0,
    };

    /// A tensor from its three independent components.
    #[must_use]
    pub const fn new(xx: f64, xy: f64, yy: f64) -> Self {
        Tensor { xx, xy, yy }
    }

    /// `s · I`.
    #[must_use]
    pub const fn isotropic(s: f64) -> Self {
        Tensor::new(s, 0.0, s)
    }

    /// The tensor with eigenvalue `l1` along direction `angle` (radians) and `l2` across it:
    /// `R(angle) diag(l1, l2) R(angle)ᵀ`.
    #[must_use]
    pub fn from_eigen(angle: f64, l1: f64, l2: f64) -> Self {
        let (s, c) = angle.sin_cos();
        let d = l1 - l2;
        Tensor {
            xx: l2 + d * c * c,
            xy: d * c * s,
            yy: l2 + d * s * s,
        }
    }

    /// The outer product `v vᵀ`.
    #[must_use]
    pub fn outer(v: DVec2) -> Self {
        Tensor::new(v.x * v.x, v.x * v.y, v.y * v.y)
    }

    /// Closed-form eigen-decomposition, accurate also for (nearly) equal eigenvalues and for
    /// negative eigenvalues: the half-difference of the eigenvalues is `√(d² + xy²)`, never a
    /// square root of a difference, and the angle comes from `atan2` (0 for isotropic tensors).
    #[must_use]
    pub fn eigen(&self) -> Eigen {
        let mean = 0.5 * (self.xx + self.yy);
        let half_diff = 0.5 * (self.xx - self.yy);
        // f64 squares of f32-sized components cannot overflow, so no libm hypot is needed.
        let radius = (half_diff * half_diff + self.xy * self.xy).sqrt();
        Eigen {
            l1: mean + radius,
            l2: mean - radius,
            angle: 0.5 * self.xy.atan2(half_diff),
        }
    }

    /// Trace `xx + yy`.
    #[must_use]
    pub fn trace(&self) -> f64 {
        self.xx + self.yy
    }

    /// Determinant `xx·yy − xy²`.
    #[must_use]
    pub fn det(&self) -> f64 {
        self.xx * self.yy - self.xy * self.xy
    }

    /// `t²` (for symmetric `t = [[a, b], [b, c]]`: `[[a² + b², b(a + c)], [b(a + c), c² + b²]]`).
    #[must_use]
    pub fn squared(&self) -> Tensor {
        let b2 = self.xy * self.xy;
        Tensor::new(
            self.xx * self.xx + b2,
            self.xy * (self.xx + self.yy),
            self.yy * self.yy + b2,
        )
    }

    /// The inverse, or `None` when the determinant is zero or not finite.
    #[must_use]
    pub fn inverse(&self) -> Option<Tensor> {
        let det = self.det();
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        Some(Tensor::new(self.yy / det, -self.xy / det, self.xx / det))
    }

    /// `t · v`.
    #[must_use]
    pub fn mul_vec(&self, v: DVec2) -> DVec2 {
        DVec2::new(self.xx * v.x + self.xy * v.y, self.xy * v.x + self.yy * v.y)
    }

    /// Positive definite: both eigenvalues strictly positive.
    #[must_use]
    pub fn is_positive_definite(&self) -> bool {
        self.xx > 0.0 && self.det() > 0.0
    }

    /// All three components finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.xx.is_finite() && self.xy.is_finite() && self.yy.is_finite()
    }

    /// Component-wise `a·self + b·other`.
    #[must_use]
    pub fn lerp(&self, other: &Tensor, t: f64) -> Tensor {
        Tensor::new(
            self.xx + (other.xx - self.xx) * t,
            self.xy + (other.xy - self.xy) * t,
            self.yy + (other.yy - self.yy) * t,
        )
    }

    /// Applies `f` to each eigenvalue, keeping the eigenvectors.
    #[must_use]
    pub fn map_eigenvalues(&self, f: impl Fn(f64) -> f64) -> Tensor {
        let e = self.eigen();
        Tensor::from_eigen(e.angle, f(e.l1), f(e.l2))
    }

    /// The components as `f32`, the storage type of fields.
    #[must_use]
    pub fn to_f32(&self) -> [f32; 3] {
        [self.xx as f32, self.xy as f32, self.yy as f32]
    }

    /// A tensor from stored `f32` components.
    #[must_use]
    pub fn from_f32(c: [f32; 3]) -> Tensor {
        Tensor::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::PI;

    fn rel_close(a: &Tensor, b: &Tensor, tol: f64) -> bool {
        let scale = a.xx.abs().max(a.xy.abs()).max(a.yy.abs()).max(1e-300);
        (a.xx - b.xx).abs() <= tol * scale
            && (a.xy - b.xy).abs() <= tol * scale
            && (a.yy - b.yy).abs() <= tol * scale
    }

    #[test]
    fn squared_applies_the_tensor_twice() {
        let t = Tensor::from_eigen(0.4, 5.0, 1.5);
        let sq = t.squared();
        for v in [DVec2::X, DVec2::Y, DVec2::new(0.3, -2.0)] {
            assert!((sq.mul_vec(v) - t.mul_vec(t.mul_vec(v))).length() < 1e-12);
        }
        // Its eigenvalues are the squares: semi-axes 5 and 1.5 give 25 and 2.25.
        let e = sq.eigen();
        assert!((e.l1 - 25.0).abs() < 1e-12 && (e.l2 - 2.25).abs() < 1e-12);
    }

    fn check_decomposition(t: Tensor) -> Result<(), TestCaseError> {
        let e = t.eigen();
        prop_assert!(e.l1 >= e.l2);
        let (e1, e2) = (e.e1(), e.e2());
        prop_assert!((e1.length() - 1.0).abs() < 1e-12);
        prop_assert!((e2.length() - 1.0).abs() < 1e-12);
        prop_assert!(e1.dot(e2).abs() < 1e-12);
        let back = Tensor::outer(e1);
        let back = Tensor::new(
            e.l1 * back.xx + e.l2 * e2.x * e2.x,
            e.l1 * back.xy + e.l2 * e2.x * e2.y,
            e.l1 * back.yy + e.l2 * e2.y * e2.y,
        );
        prop_assert!(rel_close(&t, &back, 1e-5), "{t:?} -> {e:?} -> {back:?}");
        // Each eigenvector really is one: t e = l e.
        let scale = e.l1.abs().max(e.l2.abs()).max(1e-300);
        prop_assert!((t.mul_vec(e1) - e1 * e.l1).length() <= 1e-9 * scale);
        prop_assert!((t.mul_vec(e2) - e2 * e.l2).length() <= 1e-9 * scale);
        Ok(())
    }

    proptest! {
        #[test]
        fn eigen_reconstructs_any_tensor(xx in -1e4..1e4f64, xy in -1e4..1e4f64, yy in -1e4..1e4f64) {
            check_decomposition(Tensor::new(xx, xy, yy))?;
        }

        #[test]
        fn eigen_reconstructs_nearly_isotropic(
            s in -1e3..1e3f64, eps in -1e-6..1e-6f64, angle in -PI..PI,
        ) {
            check_decomposition(Tensor::from_eigen(angle, s + eps, s))?;
        }

        #[test]
        fn from_eigen_round_trips(angle in -PI..PI, l1 in 0.01..1e3f64, ratio in 1.001..100.0f64) {
            let l2 = l1 / ratio;
            let e = Tensor::from_eigen(angle, l1, l2).eigen();
            prop_assert!((e.l1 - l1).abs() <= 1e-9 * l1);
            prop_assert!((e.l2 - l2).abs() <= 1e-9 * l1);
            // Same axis up to sign: compare doubled angles.
            let d = (2.0 * (e.angle - angle)).sin().abs();
            prop_assert!(d < 1e-6, "angle {angle} came back as {}", e.angle);
        }

        #[test]
        fn inverse_is_inverse(angle in -PI..PI, l1 in 0.01..1e3f64, l2 in 0.01..1e3f64) {
            let t = Tensor::from_eigen(angle, l1, l2);
            let inv = t.inverse().unwrap();
            let v = DVec2::new(0.3, -1.7);
            let back = inv.mul_vec(t.mul_vec(v));
            prop_assert!((back - v).length() < 1e-9 * v.length());
            prop_assert!((t.det() - l1 * l2).abs() <= 1e-9 * l1 * l2 + 1e-12 * l1.max(l2).powi(2));
        }
    }

    #[test]
    fn isotropic_and_negative() {
        let e = Tensor::isotropic(2.0).eigen();
        assert_eq!((e.l1, e.l2, e.angle), (2.0, 2.0, 0.0));
        let e = Tensor::new(-3.0, 0.0, 1.0).eigen();
        assert_eq!((e.l1, e.l2), (1.0, -3.0));
        assert!((e.angle.abs() - PI / 2.0).abs() < 1e-12);
        assert!(Tensor::new(0.0, 0.0, 0.0).inverse().is_none());
        assert!(!Tensor::new(1.0, 2.0, 1.0).is_positive_definite());
    }
}
