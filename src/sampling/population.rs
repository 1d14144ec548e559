//! Automatic insert and delete operations (paper section 5.5).
//!
//! Insert: per triangle of the anisotropic Delaunay triangulation, the [`fill_rate`] is the
//! area of the three corner sectors of the corners' ellipses over the triangle's area
//! (hexagonal packing: `π/(2√3) ≈ 0.907`), the paper's isotropic-space measure computed with
//! exact elliptical sectors (see [`fill_rate`]).
//! A new sample goes to `q` when the fill rate is at most the threshold (0.6 in the paper) and
//! there is room for it ([`INSERT_MIN_DISTANCE`]), unless the corners are already pressed
//! together ([`InsertionRule::max_pressure`]): in a curved or turning field a perfect packing
//! does not exist, and the relaxation leaves gaps at its defects that no sample fits into
//! (measured on the `degenerate-point` field: without this rule, insertion went on at every
//! repair, 46 insertions in 100 iterations, 63 in 400, and overlap rose from 2.0 % to 3.9 %).
//! At most one insertion touches each sample per round, so two neighbouring empty triangles do
//! not both receive one.
//!
//! Delete: a sample is overcrowded when the repelling forces on it, summed over its neighbours
//! (its *pressure*, `Σ max(f(d), 0)`), exceed a threshold. The most pressed go first, and a
//! sample next to one deleted in the same round is spared. Boundary samples are never deleted.
//! The default threshold, 0.3, is about six neighbours at `d ≈ 0.88`: it never fires in a
//! constant field and thins the knots of a singular one (the centre of `circular`).

use super::delaunay::edges::Edges;
use super::delaunay::AnisotropicDelaunay;
use super::distance::{contact_distance_of_squares, normalised_distance};
use super::force::force_spline;
use crate::field::{Tensor, TensorField};
use glam::DVec2;

/// The optimal fill rate of hexagonally packed discs, `π / (2√3)`.
pub const OPTIMAL_FILL_RATE: f64 = std::f64::consts::PI / (2.0 * 1.732_050_807_568_877_2);

/// Fill rate of the triangle `p` whose corners carry the inverse metrics `inv`: the area of the
/// three corner sectors of the corners' ellipses over the triangle's area.
///
/// The paper measures this in the isotropic space of `m(q)⁻¹`, `q` the barycentre, where it
/// approximates each corner's ellipse by a disc. Here the sectors are exact instead: mapped by
/// `m_i⁻¹` the ellipse of corner `i` is the unit disc, so its sector between the two edges has
/// area `½·det(m_i)·θ_i`, with `θ_i` the angle between `m_i⁻¹e₁` and `m_i⁻¹e₂`. Ratios of areas
/// do not depend on the linear map they are measured in, so this is the same fill rate as in
/// the isotropic space of `m(q)⁻¹`, without the disc approximation, which overstated how much
/// of a corner a long ellipse turned across the triangle fills (and without a field look-up).
#[must_use]
pub fn fill_rate(p: [DVec2; 3], inv: [Tensor; 3]) -> f64 {
    sector_share(p, inv, |u, v| u.perp_dot(v).abs().atan2(u.dot(v)))
}

/// A lower bound of [`fill_rate`] without its arc tangents: each corner's angle `θ` is bounded
/// below by `x + x³/6` with `x = sin θ` when it is acute (the first terms of `arcsin`'s series,
/// all of whose terms are positive) and by `π/2` when it is not. For a hexagonal triangle it
/// reads 0.84 of the exact 0.907, so most triangles of a packing are cleared by it alone.
#[must_use]
pub fn fill_rate_lower_bound(p: [DVec2; 3], inv: [Tensor; 3]) -> f64 {
    let share = sector_share(p, inv, |u, v| {
        if u.dot(v) < 0.0 {
            return std::f64::consts::FRAC_PI_2;
        }
        let x = u.perp_dot(v).abs() / (u.length_squared() * v.length_squared()).sqrt();
        // NaN (a zero edge) counts as no angle at all.
        if x.is_nan() {
            0.0
        } else {
            x + x * x * x / 6.0
        }
    });
    // Rounding could lift the bound a few ulps over the exact value; this margin keeps it
    // below.
    share * (1.0 - 1e-9)
}

/// The three corner sectors' area over the triangle's, each corner's angle between its two
/// edges mapped by its `m_i⁻¹` (`u`, `v`) given by `angle(u, v)` (the exact one or a bound);
/// infinite for a degenerate triangle.
fn sector_share(p: [DVec2; 3], inv: [Tensor; 3], angle: impl Fn(DVec2, DVec2) -> f64) -> f64 {
    let area = 0.5 * (p[1] - p[0]).perp_dot(p[2] - p[0]).abs();
    if area <= 0.0 {
        return f64::INFINITY;
    }
    let mut covered = 0.0;
    for i in 0..3 {
        let u = inv[i].mul_vec(p[(i + 1) % 3] - p[i]);
        let v = inv[i].mul_vec(p[(i + 2) % 3] - p[i]);
        // The sector's area is ½·θ·det(m_i), and det(m_i) = 1 / det(m_i⁻¹).
        covered += 0.5 * angle(u, v) / inv[i].det();
    }
    covered / area
}

/// When a triangle receives a new sample.
#[derive(Clone, Copy, Debug)]
pub struct InsertionRule<'a> {
    /// Fill rate at or below which a triangle is a hole (paper: 0.6).
    pub fill_rate: f64,
    /// Largest mean [`pressures`] of the triangle's corners: above it, the hole is a defect
    /// of a packing already pressed together and is left to the relaxation.
    pub max_pressure: f64,
    /// Pressure of every sample.
    pub pressure: &'a [f64],
}

/// Triangles that are holes by the `rule` and their barycentres, at most one touching each
/// sample per round, in triangle order (deterministic).
#[must_use]
pub fn insertion_points(
    mesh: &AnisotropicDelaunay,
    positions: &[DVec2],
    inverses: &[Tensor],
    metric: &TensorField,
    rule: &InsertionRule,
) -> Vec<(usize, DVec2)> {
    use rayon::prelude::*;
    let pressure = rule.pressure;
    // Which triangles are holes: in parallel (the fill rates are most of the work), in order.
    let holes: Vec<u32> = (0..mesh.num_triangles() as u32)
        .into_par_iter()
        .filter(|&t| {
            let [a, b, c] = mesh.triangle(t as usize).map(|v| v as usize);
            let p = [positions[a], positions[b], positions[c]];
            let inv = [inverses[a], inverses[b], inverses[c]];
            let crowded = (pressure[a] + pressure[b] + pressure[c]) / 3.0 > rule.max_pressure;
            !crowded
                && fill_rate_lower_bound(p, inv) <= rule.fill_rate
                && fill_rate(p, inv) <= rule.fill_rate
                && has_room(p, inv, metric)
        })
        .collect();
    // Then, in triangle order, at most one insertion touching each sample.
    let mut touched = vec![false; positions.len()];
    let mut out = Vec::new();
    for t in holes {
        let [a, b, c] = mesh.triangle(t as usize).map(|v| v as usize);
        if touched[a] || touched[b] || touched[c] {
            continue;
        }
        touched[a] = true;
        touched[b] = true;
        touched[c] = true;
        out.push((
            t as usize,
            (positions[a] + positions[b] + positions[c]) / 3.0,
        ));
    }
    out
}

/// Whether a sample at the barycentre of the triangle would keep a normalised distance of at
/// least [`INSERT_MIN_DISTANCE`] from the three corners.
fn has_room(p: [DVec2; 3], inv: [Tensor; 3], metric: &TensorField) -> bool {
    let q = (p[0] + p[1] + p[2]) / 3.0;
    let Some(inv_q) = metric.sample(q).inverse() else {
        return false;
    };
    (0..3).all(|i| normalised_distance(q, &inv_q, p[i], &inv[i]) >= INSERT_MIN_DISTANCE)
}

/// Smallest normalised distance an inserted sample may have to the triangle's corners. The
/// fill rate alone also fires in gaps that are large but too narrow for a sample (four samples
/// in a square at `d ≈ 1.15`): inserting there overcrowds the packing (measured: 6 % more
/// samples than fit, nearest-neighbour median 0.92); at 0.65 the count settles near the
/// hexagonal estimate.
pub const INSERT_MIN_DISTANCE: f64 = 0.65;

/// Pressure `Σ max(f(d), 0)` of every sample over its triangulation neighbours, with the
/// contact distance the forces use (from the squared metrics, [`Tensor::squared`]): the spline
/// is evaluated once per edge, then gathered per sample in a fixed order.
#[must_use]
pub fn pressures(positions: &[DVec2], squares: &[Tensor], edges: &Edges) -> Vec<f64> {
    use rayon::prelude::*;
    let per_edge: Vec<f64> = edges
        .ends
        .par_iter()
        .map(|&[a, b]| {
            let (a, b) = (a as usize, b as usize);
            force_spline(contact_distance_of_squares(
                positions[a],
                &squares[a],
                positions[b],
                &squares[b],
            ))
            .max(0.0)
        })
        .collect();
    (0..positions.len())
        .into_par_iter()
        .map(|i| edges.at(i).map(|(e, _, _)| per_edge[e]).sum())
        .collect()
}

/// Interior samples (index ≥ `fixed`) to delete: pressure above `threshold`, most pressed
/// first, never two neighbours in one round. Returned sorted by index.
#[must_use]
pub fn deletions(pressure: &[f64], fixed: usize, edges: &Edges, threshold: f64) -> Vec<u32> {
    let mut candidates: Vec<u32> = (fixed..pressure.len())
        .filter(|&i| pressure[i] > threshold)
        .map(|i| i as u32)
        .collect();
    candidates.sort_by(|&a, &b| {
        pressure[b as usize]
            .total_cmp(&pressure[a as usize])
            .then(a.cmp(&b))
    });
    let mut spared = vec![false; pressure.len()];
    let mut out = Vec::new();
    for c in candidates {
        let c = c as usize;
        if spared[c] {
            continue;
        }
        out.push(c as u32);
        for (_, _, n) in edges.at(c) {
            spared[n as usize] = true;
        }
    }
    out.sort_unstable();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hexagonal_triangle_has_the_optimal_fill_rate() {
        // Unit discs at the corners of an equilateral triangle of side 2, in a metric
        // with semi-axes 3 and 1 at 20°: mapped to isotropic space it is the ideal case.
        let m = Tensor::from_eigen(20f64.to_radians(), 3.0, 1.0);
        let iso = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(1.0, 3f64.sqrt()),
        ];
        let p = iso.map(|v| m.mul_vec(v) + DVec2::new(4.0, 4.0));
        let inv = m.inverse().unwrap();
        let fill = fill_rate(p, [inv; 3]);
        assert!((fill - OPTIMAL_FILL_RATE).abs() < 1e-9, "{fill}");
        // Twice as far apart: a quarter of that.
        let far = iso.map(|v| m.mul_vec(v * 2.0) + DVec2::new(2.0, 2.0));
        assert!((fill_rate(far, [inv; 3]) - OPTIMAL_FILL_RATE / 4.0).abs() < 1e-9);
    }

    proptest::proptest! {
        #[test]
        fn the_lower_bound_is_below_the_fill_rate(
            corners in proptest::array::uniform6(-10.0f64..10.0),
            axes in proptest::array::uniform6(0.2f64..5.0),
            angles in proptest::array::uniform3(-3.2f64..3.2),
        ) {
            let p = [0, 1, 2].map(|i| DVec2::new(corners[2 * i], corners[2 * i + 1]));
            let inv = [0, 1, 2].map(|i| {
                let (a, b) = (axes[2 * i].max(axes[2 * i + 1]), axes[2 * i].min(axes[2 * i + 1]));
                Tensor::from_eigen(angles[i], a, b).inverse().unwrap()
            });
            let (bound, exact) = (fill_rate_lower_bound(p, inv), fill_rate(p, inv));
            proptest::prop_assert!(bound <= exact, "{bound} > {exact}");
            if exact.is_finite() {
                // Never below half the exact value (x + x³/6 ≥ 0.5·arcsin x, and π/2 ≥ θ/2).
                proptest::prop_assert!(bound >= 0.5 * exact, "{bound} ≪ {exact}");
            }
        }
    }

    #[test]
    fn the_lower_bound_is_close_for_a_hexagonal_triangle() {
        let m = Tensor::from_eigen(0.3, 4.0, 1.5);
        let iso = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(1.0, 3f64.sqrt()),
        ];
        let p = iso.map(|v| m.mul_vec(v));
        let inv = [m.inverse().unwrap(); 3];
        let bound = fill_rate_lower_bound(p, inv);
        // 3·(x + x³/6) with x = sin 60°, over 3·π/3.
        let expected =
            OPTIMAL_FILL_RATE * (0.75f64.sqrt() * (1.0 + 0.125)) / (std::f64::consts::PI / 3.0);
        assert!((bound - expected).abs() < 1e-6 && bound > 0.84, "{bound}");
    }

    #[test]
    fn deletions_spare_neighbours() {
        // Path 0 - 1 - 2 - 3, pressures make 1 and 2 candidates; only the higher goes.
        let edges = Edges::from_ends(vec![[0, 1], [1, 2], [2, 3]], 4);
        let pressure = [0.0, 3.0, 4.0, 0.0];
        assert_eq!(deletions(&pressure, 0, &edges, 1.0), vec![2]);
        assert_eq!(deletions(&pressure, 3, &edges, 1.0), Vec::<u32>::new());
    }
}
