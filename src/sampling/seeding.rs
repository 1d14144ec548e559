//! Relaxation dart throwing (paper section 5.1, after [ME92]) for the interior samples.
//!
//! A candidate is accepted unless its normalised distance to an accepted sample is below ρ.
//! ρ starts at 0.9 and drops by 0.05, down to 0.75, whenever the ratio of accepted to rejected
//! candidates since the last change falls below ε = 0.01; throwing stops at the target count
//! `N ≈ ∫ dA / (2√3 · det m)` (hexagonal packing of the ellipses), or when even ρ = 0.75
//! rejects nearly everything.
//!
//! Candidates are drawn with density proportional to `1/det m`, so every region fills at the
//! same pace and no region waits for the dense ones. Rejection tests never scan all samples:
//! each accepted sample is registered in the cells of a uniform grid that its bounding disc
//! (radius ρ·a, `a` its long semi-axis) touches, and a candidate looks only at the samples
//! registered in the cells its own disc touches. Two samples closer than ρ in normalised
//! distance have overlapping discs, so they always share a cell: the test is exact.

use super::distance::normalised_distance;
use super::rng::Rng;
use crate::field::{Tensor, TensorField};
use glam::DVec2;

/// Parameters of relaxation dart throwing (the paper's values are the defaults).
#[derive(Clone, Debug, PartialEq)]
pub struct DartParams {
    /// First relative Poisson-disc radius ρ.
    pub rho_start: f64,
    /// Amount ρ drops by.
    pub rho_step: f64,
    /// Smallest ρ.
    pub rho_min: f64,
    /// Threshold ε of the ratio accepted/rejected that lowers ρ.
    pub epsilon: f64,
}

impl Default for DartParams {
    fn default() -> Self {
        DartParams {
            rho_start: 0.9,
            rho_step: 0.05,
            rho_min: 0.75,
            epsilon: 0.01,
        }
    }
}

/// Darts per window over which the ratio accepted/rejected is judged.
const WINDOW: u64 = 2000;

/// Estimated sample count `∫ dA / (2√3 · det m)` over the grid nodes of `metric`.
#[must_use]
pub fn estimate_count(metric: &TensorField) -> f64 {
    let area = node_area(metric);
    metric
        .data()
        .iter()
        .map(|&c| area / (2.0 * 3f64.sqrt() * Tensor::from_f32(c).det()))
        .sum()
}

/// Area of the domain each grid node stands for (the domain may be a little smaller than the
/// grid when the photo's size is not a multiple of the analysis factor).
fn node_area(metric: &TensorField) -> f64 {
    let d = metric.domain();
    d.x * d.y / (metric.cols() * metric.rows()) as f64
}

/// A uniform grid of cells, each holding a linked list of sample indices (flat arrays: one
/// head per cell, one (sample, next) entry per registration).
struct CellGrid {
    cell: f64,
    cols: usize,
    rows: usize,
    head: Vec<u32>,
    entries: Vec<(u32, u32)>,
}

const END: u32 = u32::MAX;

impl CellGrid {
    fn new(domain: DVec2, cell: f64) -> Self {
        let cols = (domain.x / cell).ceil().max(1.0) as usize;
        let rows = (domain.y / cell).ceil().max(1.0) as usize;
        CellGrid {
            cell,
            cols,
            rows,
            head: vec![END; cols * rows],
            entries: Vec::new(),
        }
    }

    /// Cell index ranges touched by the disc of `radius` about `p`.
    fn cells(&self, p: DVec2, radius: f64) -> (usize, usize, usize, usize) {
        let lo = |v: f64, n: usize| ((v / self.cell).floor().max(0.0) as usize).min(n - 1);
        (
            lo(p.x - radius, self.cols),
            lo(p.x + radius, self.cols),
            lo(p.y - radius, self.rows),
            lo(p.y + radius, self.rows),
        )
    }

    fn insert(&mut self, id: u32, p: DVec2, radius: f64) {
        let (x0, x1, y0, y1) = self.cells(p, radius);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let c = y * self.cols + x;
                self.entries.push((id, self.head[c]));
                self.head[c] = (self.entries.len() - 1) as u32;
            }
        }
    }
}

/// Throws darts until `target` interior samples are accepted (or ρ = `rho_min` rejects nearly
/// everything). `fixed` are the boundary samples, already placed. Returns the interior
/// positions and the final ρ.
#[must_use]
pub fn relaxation_dart_throwing(
    metric: &TensorField,
    fixed: &[DVec2],
    target: usize,
    params: &DartParams,
    rng: &mut Rng,
) -> (Vec<DVec2>, f64) {
    let sampler = DensitySampler::new(metric);
    // The long semi-axis, without the angle.
    let long_axis = |t: &Tensor| 0.5 * (t.xx + t.yy) + (0.5 * (t.xx - t.yy)).hypot(t.xy);
    let mut cell = median_long_axis(metric);
    // Keep the grid to a few million cells even for extreme fields.
    let d = metric.domain();
    cell = cell.max((d.x * d.y / 4.0e6).sqrt());
    let mut grid = CellGrid::new(d, cell);

    let mut positions: Vec<DVec2> = Vec::with_capacity(fixed.len() + target);
    let mut inverses: Vec<Tensor> = Vec::with_capacity(fixed.len() + target);
    let mut long: Vec<f64> = Vec::with_capacity(fixed.len() + target);
    let mut rho = params.rho_start;
    for &p in fixed {
        let m = metric.sample(p);
        grid.insert(positions.len() as u32, p, params.rho_start * long_axis(&m));
        positions.push(p);
        inverses.push(m.inverse().unwrap_or_default());
        long.push(long_axis(&m));
    }
    let (mut accepted, mut rejected) = (0u64, 0u64);
    let mut interior = 0usize;
    let max_darts = 400 * target as u64 + 100_000;
    let mut darts = 0u64;
    while interior < target && darts < max_darts {
        darts += 1;
        let c = sampler.draw(rng);
        let m = metric.sample(c);
        let Some(inv) = m.inverse() else { continue };
        let a = long_axis(&m);
        if accepted + rejected == WINDOW {
            if (accepted as f64) < params.epsilon * rejected as f64 {
                if rho <= params.rho_min + 1e-12 {
                    break;
                }
                rho = (rho - params.rho_step).max(params.rho_min);
            }
            accepted = 0;
            rejected = 0;
        }
        if conflicts(&grid, &positions, &inverses, &long, c, &inv, a, rho) {
            rejected += 1;
            continue;
        }
        accepted += 1;
        grid.insert(positions.len() as u32, c, params.rho_start * a);
        positions.push(c);
        inverses.push(inv);
        long.push(a);
        interior += 1;
    }
    (positions.split_off(fixed.len()), rho)
}

/// Whether a candidate at `c` is closer than `rho` (normalised) to any registered sample.
#[allow(clippy::too_many_arguments)]
fn conflicts(
    grid: &CellGrid,
    positions: &[DVec2],
    inverses: &[Tensor],
    long: &[f64],
    c: DVec2,
    inv: &Tensor,
    a: f64,
    rho: f64,
) -> bool {
    let (x0, x1, y0, y1) = grid.cells(c, rho * a);
    for y in y0..=y1 {
        for x in x0..=x1 {
            let mut e = grid.head[y * grid.cols + x];
            while e != END {
                let (id, next) = grid.entries[e as usize];
                let id = id as usize;
                let p = positions[id];
                // Cheap bound first: the discs of radius ρ·a must overlap.
                if (p - c).length_squared() < (rho * (a + long[id])).powi(2)
                    && normalised_distance(c, inv, p, &inverses[id]) < rho
                {
                    return true;
                }
                e = next;
            }
        }
    }
    false
}

/// Median long semi-axis of the field (a sample of its nodes), the grid's cell size.
fn median_long_axis(metric: &TensorField) -> f64 {
    let step = (metric.data().len() / 4096).max(1);
    let mut v: Vec<f64> = metric
        .data()
        .iter()
        .step_by(step)
        .map(|&c| Tensor::from_f32(c).eigen().l1)
        .filter(|v| v.is_finite() && *v > 0.0)
        .collect();
    if v.is_empty() {
        return 1.0;
    }
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// `n` points drawn independently with density proportional to `1/det m`: the "random
/// placement" baseline the relaxed samples are compared with.
#[must_use]
pub fn random_positions(metric: &TensorField, n: usize, rng: &mut Rng) -> Vec<DVec2> {
    let sampler = DensitySampler::new(metric);
    (0..n).map(|_| sampler.draw(rng)).collect()
}

/// Draws points with density proportional to `1/det m` over the domain: a grid node by its
/// cumulative weight, then a uniform point within the node's cell.
struct DensitySampler {
    cumulative: Vec<f64>,
    cols: usize,
    cell: DVec2,
}

impl DensitySampler {
    fn new(metric: &TensorField) -> Self {
        let mut total = 0.0;
        let cumulative = metric
            .data()
            .iter()
            .map(|&c| {
                total += 1.0 / Tensor::from_f32(c).det();
                total
            })
            .collect();
        let d = metric.domain();
        DensitySampler {
            cumulative,
            cols: metric.cols(),
            cell: DVec2::new(d.x / metric.cols() as f64, d.y / metric.rows() as f64),
        }
    }

    fn draw(&self, rng: &mut Rng) -> DVec2 {
        let total = *self.cumulative.last().unwrap_or(&0.0);
        let u = rng.uniform() * total;
        let i = self
            .cumulative
            .partition_point(|&c| c <= u)
            .min(self.cumulative.len() - 1);
        let (c, r) = (i % self.cols, i / self.cols);
        DVec2::new(
            (c as f64 + rng.uniform()) * self.cell.x,
            (r as f64 + rng.uniform()) * self.cell.y,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimate_of_a_constant_field() {
        let m = Tensor::from_eigen(0.4, 6.0, 2.0);
        let metric = TensorField::constant(300, 200, m);
        let want = 300.0 * 200.0 / (2.0 * 3f64.sqrt() * 12.0);
        assert!((estimate_count(&metric) - want).abs() < 1e-6 * want);
    }

    #[test]
    fn accepted_darts_respect_rho_exactly() {
        let metric = TensorField::from_fn(200, 150, |p| {
            Tensor::from_eigen(p.x / 50.0, 3.0 + p.y / 30.0, 2.0)
        });
        let params = DartParams::default();
        let (pts, rho) = relaxation_dart_throwing(&metric, &[], 2000, &params, &mut Rng::new(9, 0));
        assert!(pts.len() > 300);
        let inv: Vec<Tensor> = pts
            .iter()
            .map(|&p| metric.sample(p).inverse().unwrap())
            .collect();
        // Brute force over all pairs: nothing closer than the final ρ.
        for i in 0..pts.len() {
            for j in 0..i {
                let d = normalised_distance(pts[i], &inv[i], pts[j], &inv[j]);
                assert!(d >= rho - 1e-9, "{i} {j}: {d} < {rho}");
            }
        }
    }
}
