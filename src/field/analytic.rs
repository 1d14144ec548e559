//! Analytic tensor fields by name, for tests, demos and tensor-field users (paper Figures 6
//! and 7): `constant`, `circular`, `degenerate-point` and `two-point-load`.
//!
//! A spec is `NAME` or `NAME:key=value,key=value`, e.g. `constant:angle=30,anisotropy=4`.
//! Lengths (`size`) are fractions of the domain diagonal; angles are degrees, measured from
//! the x axis towards y (down). `constant` and `circular` are metrics; `degenerate-point` and
//! `two-point-load` are general tensors (negative eigenvalues) for the anti-symmetric mapping.

use super::grid::TensorField;
use super::tensor::Tensor;
use crate::error::{Error, Result};
use glam::DVec2;
use std::f64::consts::PI;

/// The names [`AnalyticField::parse`] accepts.
pub const ANALYTIC_NAMES: [&str; 4] =
    ["constant", "circular", "degenerate-point", "two-point-load"];

/// A parsed analytic field.
#[derive(Clone, Debug, PartialEq)]
pub enum AnalyticField {
    /// One metric everywhere: semi-axes `size·√anisotropy` along `angle` and
    /// `size/√anisotropy` across (so `size` is the geometric-mean radius).
    Constant {
        /// Direction of the long axis, degrees.
        angle: f64,
        /// Geometric-mean semi-axis, fraction of the diagonal.
        size: f64,
        /// Ratio of the semi-axes, ≥ 1.
        anisotropy: f64,
    },
    /// Long axes tangent to circles about the centre, constant size and anisotropy.
    Circular {
        /// Geometric-mean semi-axis, fraction of the diagonal.
        size: f64,
        /// Ratio of the semi-axes, ≥ 1.
        anisotropy: f64,
    },
    /// `T(x, y) = [[x, y], [y, −x]]` about the centre, scaled to the half-diagonal: one
    /// degenerate (isotropic) point in the centre, eigenvalues `±r`.
    DegeneratePoint,
    /// A compressive and a tensile point load on the top edge of a half plane, each a Flamant
    /// solution `σ_rr = −2P cos θ / (π r)` (other polar components zero), superposed with
    /// opposite signs of `P`. The loads sit at x = 1/3 and 2/3 of the width; a core of radius
    /// `core` (fraction of the diagonal) keeps the field finite on the grid.
    TwoPointLoad {
        /// Core radius, fraction of the diagonal.
        core: f64,
    },
}

impl AnalyticField {
    /// Parses `NAME[:key=value,...]`.
    pub fn parse(spec: &str) -> Result<Self> {
        let (name, args) = spec.split_once(':').unwrap_or((spec, ""));
        let mut kv = Vec::new();
        for item in args.split(',').filter(|s| !s.trim().is_empty()) {
            let (k, v) = item.split_once('=').ok_or_else(|| {
                Error::param(
                    format!("analytic:{name}"),
                    format!("'{item}' is not key=value"),
                )
            })?;
            let value: f64 = v.trim().parse().map_err(|_| {
                Error::param(
                    format!("analytic:{name}.{k}"),
                    format!("'{v}' is not a number"),
                )
            })?;
            if !value.is_finite() {
                return Err(Error::param(
                    format!("analytic:{name}.{k}"),
                    "must be finite",
                ));
            }
            kv.push((k.trim().to_string(), value));
        }
        let mut take = |key: &str, default: f64| -> f64 {
            match kv.iter().position(|(k, _)| k == key) {
                Some(i) => kv.remove(i).1,
                None => default,
            }
        };
        let field = match name {
            "constant" => AnalyticField::Constant {
                angle: take("angle", 0.0),
                size: take("size", 0.02),
                anisotropy: take("anisotropy", 1.0),
            },
            "circular" => AnalyticField::Circular {
                size: take("size", 0.015),
                anisotropy: take("anisotropy", 3.0),
            },
            "degenerate-point" => AnalyticField::DegeneratePoint,
            "two-point-load" => AnalyticField::TwoPointLoad {
                core: take("core", 0.03),
            },
            _ => {
                return Err(Error::param(
                    "analytic field",
                    format!(
                        "unknown name '{name}'; known: {}",
                        ANALYTIC_NAMES.join(", ")
                    ),
                ))
            }
        };
        if let Some((k, _)) = kv.first() {
            return Err(Error::param(
                format!("analytic:{name}"),
                format!("unknown key '{k}'"),
            ));
        }
        field.validate(name)?;
        Ok(field)
    }

    fn validate(&self, name: &str) -> Result<()> {
        let check = |key: &str, ok: bool, what: &str| {
            if ok {
                Ok(())
            } else {
                Err(Error::param(
                    format!("analytic:{name}.{key}"),
                    what.to_string(),
                ))
            }
        };
        match *self {
            AnalyticField::Constant {
                size, anisotropy, ..
            }
            | AnalyticField::Circular { size, anisotropy } => {
                check("size", size > 0.0 && size < 1.0, "must be in (0, 1)")?;
                check(
                    "anisotropy",
                    (1.0..=100.0).contains(&anisotropy),
                    "must be in [1, 100]",
                )
            }
            AnalyticField::TwoPointLoad { core } => {
                check("core", core > 0.0 && core < 1.0, "must be in (0, 1)")
            }
            AnalyticField::DegeneratePoint => Ok(()),
        }
    }

    /// The field's name as written in a spec.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            AnalyticField::Constant { .. } => "constant",
            AnalyticField::Circular { .. } => "circular",
            AnalyticField::DegeneratePoint => "degenerate-point",
            AnalyticField::TwoPointLoad { .. } => "two-point-load",
        }
    }

    /// Whether the field is already a metric (positive definite everywhere).
    #[must_use]
    pub fn is_metric(&self) -> bool {
        matches!(
            self,
            AnalyticField::Constant { .. } | AnalyticField::Circular { .. }
        )
    }

    /// The tensor at `p` (pixels) in a `width × height` domain.
    #[must_use]
    pub fn tensor_at(&self, p: DVec2, width: f64, height: f64) -> Tensor {
        let diag = width.hypot(height);
        let centre = DVec2::new(width, height) * 0.5;
        match *self {
            AnalyticField::Constant {
                angle,
                size,
                anisotropy,
            } => {
                let s = size * diag;
                let root = anisotropy.sqrt();
                Tensor::from_eigen(angle.to_radians(), s * root, s / root)
            }
            AnalyticField::Circular { size, anisotropy } => {
                let s = size * diag;
                let root = anisotropy.sqrt();
                let d = p - centre;
                let tangent = d.y.atan2(d.x) + PI / 2.0;
                Tensor::from_eigen(tangent, s * root, s / root)
            }
            AnalyticField::DegeneratePoint => {
                let d = (p - centre) / (0.5 * diag);
                Tensor::new(d.x, d.y, -d.x)
            }
            AnalyticField::TwoPointLoad { core } => {
                let a = core * diag;
                let flamant = |load: DVec2, force: f64| {
                    let d = p - load;
                    let r2 = d.length_squared() + a * a;
                    // σ = σ_rr e_r e_rᵀ with σ_rr = −2P cos θ/(π r), cos θ = d.y / r, and
                    // e_r e_rᵀ = d dᵀ / r²: σ = −2P d.y d dᵀ / (π r⁴).
                    let k = -2.0 * force * d.y / (PI * r2 * r2);
                    Tensor::new(k * d.x * d.x, k * d.x * d.y, k * d.y * d.y)
                };
                let push = flamant(DVec2::new(width / 3.0, 0.0), 1.0);
                let pull = flamant(DVec2::new(2.0 * width / 3.0, 0.0), -1.0);
                Tensor::new(push.xx + pull.xx, push.xy + pull.xy, push.yy + pull.yy)
            }
        }
    }

    /// The field sampled at every pixel centre of a `width × height` domain.
    #[must_use]
    pub fn field(&self, width: usize, height: usize) -> TensorField {
        let (w, h) = (width as f64, height as f64);
        TensorField::from_fn(width, height, |p| self.tensor_at(p, w, h))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_names_and_keys() {
        assert_eq!(
            AnalyticField::parse("constant:angle=30,anisotropy=4").unwrap(),
            AnalyticField::Constant {
                angle: 30.0,
                size: 0.02,
                anisotropy: 4.0
            }
        );
        assert!(AnalyticField::parse("nope")
            .unwrap_err()
            .to_string()
            .contains("known:"));
        assert!(AnalyticField::parse("constant:colour=3").is_err());
        assert!(AnalyticField::parse("constant:size=-1").is_err());
        assert!(AnalyticField::parse("constant:size=x").is_err());
    }

    #[test]
    fn degenerate_point_is_isotropic_only_at_the_centre() {
        let f = AnalyticField::DegeneratePoint;
        let c = f.tensor_at(DVec2::new(50.0, 50.0), 100.0, 100.0);
        assert_eq!(c.eigen().l1, 0.0);
        let e = f.tensor_at(DVec2::new(90.0, 50.0), 100.0, 100.0).eigen();
        assert!(e.l1 > 0.0 && e.l2 < 0.0 && (e.l1 + e.l2).abs() < 1e-12);
    }

    #[test]
    fn two_point_load_has_compression_and_tension() {
        let f = AnalyticField::TwoPointLoad { core: 0.03 };
        // Below the pushing load: compressive radial stress, along y.
        let push = f.tensor_at(DVec2::new(100.0, 40.0), 300.0, 200.0).eigen();
        assert!(push.l2 < 0.0 && push.l1.abs() < 0.2 * push.l2.abs());
        assert!(push.e2().y.abs() > 0.99);
        // Below the pulling load: tensile.
        let pull = f.tensor_at(DVec2::new(200.0, 40.0), 300.0, 200.0).eigen();
        assert!(pull.l1 > 0.0 && pull.l2.abs() < 0.2 * pull.l1);
        assert!(pull.e1().y.abs() > 0.99);
    }
}
