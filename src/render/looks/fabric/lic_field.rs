//! The field the LIC of the fabric and LIC looks ([`fabric`](super), paper section
//! 7.3) follows, tabulated once at every pixel of its grid ([`LicGrid`]): the long axis of the
//! metric (or of a photo's line field) as a quantised angle and the convolution kernel's
//! half-length. The fabric's kernel follows the local ellipse: the dots of its noise sit a
//! sample apart along a thread, so a kernel of the local long semi-axes joins them into
//! fibres wherever the cells are large (a sky's), where one from the picture's median cell
//! left a lattice of soft crosses. Angles are bytes (0.7° steps), kernels bytes of grid
//! pixels, positions `f64`.

use super::lic_grid::LicGrid;
use crate::field::{Tensor, TensorField};
use glam::DVec2;
use rayon::prelude::*;

/// Unit direction in output pixels of the long axis of `t` (a tensor sampled in the domain),
/// up to sign. From `[[a, b], [b, c]]` directly: the long axis is at half the angle of
/// `(a − c, 2b)`, and the half-angle formulas give it without `atan2` or an eigen
/// decomposition.
fn long_direction(t: &Tensor, to_domain: DVec2) -> DVec2 {
    let (c2, s2) = (t.xx - t.yy, 2.0 * t.xy);
    let n = (c2 * c2 + s2 * s2).sqrt();
    let d = if n > 0.0 {
        let c = c2 / n;
        let cos = (0.5 * (1.0 + c)).max(0.0).sqrt();
        let sin = (0.5 * (1.0 - c)).max(0.0).sqrt().copysign(s2);
        DVec2::new(cos, sin)
    } else {
        // Isotropic: any direction; keep x so streamlines stay straight.
        DVec2::X
    };
    // Back to output pixels (non-square scaling bends directions).
    (d / to_domain).normalize_or_zero()
}

/// `atan2(y, x)` in [−π, π] by a minimax polynomial for `atan` on [0, 1] after folding into
/// one octant (error under 2·10⁻⁵ rad, a 600th of an [`ANGLE_STEPS`] step, and far cheaper
/// than libm's `atan2` at every output pixel); 0 at the origin.
fn fast_atan2(y: f64, x: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, PI};
    let (ax, ay) = (x.abs(), y.abs());
    if ax == 0.0 && ay == 0.0 {
        return 0.0;
    }
    let (z, steep) = if ay > ax {
        (ax / ay, true)
    } else {
        (ay / ax, false)
    };
    let z2 = z * z;
    let atan_z = z
        * (0.999_977_26
            + z2 * (-0.332_623_47
                + z2 * (0.193_543_46
                    + z2 * (-0.116_432_87 + z2 * (0.052_653_32 + z2 * -0.011_721_20)))));
    // The first quadrant's angle, mirrored into the quadrant of (x, y).
    let first = if steep { FRAC_PI_2 - atan_z } else { atan_z };
    let upper = if x < 0.0 { PI - first } else { first };
    if y < 0.0 {
        -upper
    } else {
        upper
    }
}

/// The angle in [0, π] of the axis along `d` (`d` and `−d` alike).
fn half_turn_angle(d: DVec2) -> f64 {
    let a = fast_atan2(d.y, d.x);
    if a < 0.0 {
        a + std::f64::consts::PI
    } else {
        a
    }
}

/// Steps of the quantised direction angle over half a turn (0.7° each).
const ANGLE_STEPS: usize = 256;

/// Which eigenvector field a LIC pass follows.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Axis {
    Long,
    Short,
}

/// The convolution kernel's half-length, in pixels of the LIC's grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Kernel {
    /// The same everywhere (white noise: the kernel is the grain's smoothing length).
    Fixed(u8),
    /// `axes` of the metric's long semi-axes at the pixel, within `least..=most`.
    Local { axes: f64, least: u8, most: u8 },
}

/// The field a LIC follows, tabulated at every pixel centre of its grid: the long axis's
/// direction as an angle in [0, π) quantised to [`ANGLE_STEPS`] (one byte serves both passes:
/// the short axis is a quarter turn away) and the kernel's half-length there. Streamlines look
/// both up at the pixel they are in instead of sampling the tensor field at every step (a
/// step is then a table look-up; the field is smooth at the scale of the ellipses, many
/// pixels).
pub(crate) struct LicField {
    /// Quantised angles, one per pixel, row-major.
    angle: Vec<u8>,
    table: Vec<DVec2>,
    /// Kernel half-lengths, one per pixel, row-major; `None`: [`Self::fixed`] everywhere.
    kernels: Option<Vec<u8>>,
    fixed: u8,
}

impl LicField {
    /// The table over `grid` of the long axis of `directions` (the metric, or a line field's
    /// direction tensors) and the kernel `kernel` asks for, from the metric `field`'s ellipses.
    pub(crate) fn new(
        (directions, field): (&TensorField, &TensorField),
        grid: &LicGrid,
        kernel: Kernel,
    ) -> Self {
        let (w, to_domain) = (grid.w, grid.to_domain);
        let step = std::f64::consts::PI / ANGLE_STEPS as f64;
        let mut angle = vec![0u8; w * grid.h];
        let mut kernels = match kernel {
            Kernel::Fixed(_) => None,
            Kernel::Local { .. } => Some(vec![0u8; w * grid.h]),
        };
        let per_unit = grid.pixels_per_unit();
        // A field's streamlines follow its own axes: its tensor at a pixel is sampled once.
        let same = std::ptr::eq(directions, field);
        // Output pixels are square in the domain (the usual case): directions need no rescaling.
        let square = to_domain.x == to_domain.y;
        let rows = angle.par_chunks_mut(w).enumerate();
        let fill = |(y, row): (usize, &mut [u8]), mut kernel_row: Option<&mut [u8]>| {
            for (x, a) in row.iter_mut().enumerate() {
                let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                let t = directions.sample(p * to_domain);
                let theta = if square {
                    // The long axis lies at half the angle of (a − c, 2b): no square roots.
                    let half = 0.5 * fast_atan2(2.0 * t.xy, t.xx - t.yy);
                    if half < 0.0 {
                        half + std::f64::consts::PI
                    } else {
                        half
                    }
                } else {
                    half_turn_angle(long_direction(&t, to_domain))
                };
                // θ ≥ 0: `+ 0.5` and truncation round (no libm call per pixel).
                *a = ((theta / step + 0.5) as usize % ANGLE_STEPS) as u8;
                if let (Some(k), Kernel::Local { axes, least, most }) = (&mut kernel_row, kernel) {
                    let m = if same { t } else { field.sample(p * to_domain) };
                    let long = m.eigen().l1.abs() * per_unit;
                    k[x] = ((axes * long)
                        .round()
                        .clamp(f64::from(least), f64::from(most))) as u8;
                }
            }
        };
        match &mut kernels {
            Some(k) => rows
                .zip(k.par_chunks_mut(w))
                .for_each(|(row, k)| fill(row, Some(k))),
            None => rows.for_each(|row| fill(row, None)),
        }
        let table = (0..ANGLE_STEPS)
            .map(|k| DVec2::from_angle(k as f64 * step))
            .collect();
        let fixed = match kernel {
            Kernel::Fixed(k) => k,
            Kernel::Local { least, .. } => least,
        };
        LicField {
            angle,
            table,
            kernels,
            fixed,
        }
    }

    /// Unit direction of `axis` at pixel `i` (row-major), up to sign.
    #[inline]
    pub(crate) fn at_pixel(&self, i: usize, axis: Axis) -> DVec2 {
        let d = self.table[usize::from(self.angle[i])];
        if axis == Axis::Long {
            d
        } else {
            d.perp()
        }
    }

    /// The kernel's half-length at pixel `i` (row-major), at least 1.
    #[inline]
    pub(crate) fn kernel_at(&self, i: usize) -> usize {
        usize::from(self.kernels.as_ref().map_or(self.fixed, |k| k[i]).max(1))
    }

    /// The longest kernel half-length anywhere (how far a band's streamlines reach).
    pub(crate) fn kernel_most(&self) -> usize {
        let most = match &self.kernels {
            Some(k) => k.par_iter().copied().max().unwrap_or(self.fixed),
            None => self.fixed,
        };
        usize::from(most.max(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn local_kernels_follow_the_long_semi_axis_within_their_bounds() {
        // 200 × 100 px: long semi-axes of 4 px on the left half, 20 px along 30° on the
        // right; the grid is the output's own pixels.
        let field = TensorField::from_fn(200, 100, |p| {
            if p.x < 100.0 {
                Tensor::from_eigen(0.0, 4.0, 2.0)
            } else {
                Tensor::from_eigen(std::f64::consts::FRAC_PI_6, 20.0, 10.0)
            }
        });
        let grid = LicGrid::for_output(200, 100, field.domain());
        let local = Kernel::Local {
            axes: 1.2,
            least: 10,
            most: 30,
        };
        let table = LicField::new((&field, &field), &grid, local);
        let at = |x: usize, y: usize| table.kernel_at(y * 200 + x);
        // 1.2 · 4 = 4.8 is raised to the least, 1.2 · 20 = 24 kept, away from the seam.
        assert_eq!((at(20, 50), at(180, 50)), (10, 24));
        assert_eq!(table.kernel_most(), 24);
        let capped = Kernel::Local {
            axes: 2.0,
            least: 10,
            most: 30,
        };
        assert_eq!(
            LicField::new((&field, &field), &grid, capped).kernel_at(50 * 200 + 180),
            30
        );
        let fixed = LicField::new((&field, &field), &grid, Kernel::Fixed(12));
        assert_eq!((fixed.kernel_at(0), fixed.kernel_most()), (12, 12));
        // The directions as before: 0° on the left, 30° (the long axis) on the right.
        let right = table.at_pixel(50 * 200 + 180, Axis::Long);
        assert!((right.y.atan2(right.x) - std::f64::consts::FRAC_PI_6).abs() < 0.01);
        assert!(table.at_pixel(50 * 200 + 20, Axis::Short).x.abs() < 1e-9);
    }

    #[test]
    fn half_turn_angle_is_the_axis_angle() {
        for k in 0..3600 {
            let a = f64::from(k) * std::f64::consts::TAU / 3600.0;
            let d = DVec2::from_angle(a) * 3.0;
            let want = d.y.atan2(d.x).rem_euclid(std::f64::consts::PI);
            let got = half_turn_angle(d);
            // Equal up to the error bound, or at both ends of the half turn (one axis).
            let err = (got - want).abs();
            assert!(
                err < 2e-5 || (err - std::f64::consts::PI).abs() < 2e-5,
                "{a}: {got} vs {want}"
            );
        }
        assert_eq!(half_turn_angle(DVec2::ZERO), 0.0);
        for k in 0..=3600 {
            let a = f64::from(k) * std::f64::consts::TAU / 3600.0 - std::f64::consts::PI;
            let (y, x) = (2.5 * a.sin(), 2.5 * a.cos());
            assert!((fast_atan2(y, x) - y.atan2(x)).abs() < 2e-5, "{a}");
        }
    }
}
