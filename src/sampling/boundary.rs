//! Boundary samples (paper section 5.1, after \[SYI00\]): the four corners, then each edge
//! subdivided so that neighbours sit at normalised distance about 1 along it, jittered and
//! relaxed by 1-D particle movement with the force spline so they are not structured. All of
//! them stay fixed for the rest of the run, which closes the domain: no particle leaves it and
//! no external force is needed.

use super::distance::{normalised_distance, radius_along};
use super::force::force_spline;
use super::rng::Rng;
use crate::field::{Tensor, TensorField};
use glam::DVec2;
use rayon::prelude::*;

/// Iterations of the 1-D relaxation along each edge.
const EDGE_ITERATIONS: usize = 40;

/// Samples along the domain's boundary: corners first, then the edges' interior samples.
/// The four edges are subdivided and relaxed in parallel; the jitter draws from `rng` edge by
/// edge in between, so the samples do not depend on the thread count.
#[must_use]
pub fn boundary_samples(metric: &TensorField, rng: &mut Rng) -> Vec<DVec2> {
    let d = metric.domain();
    let corners = [
        DVec2::ZERO,
        DVec2::new(d.x, 0.0),
        DVec2::new(d.x, d.y),
        DVec2::new(0.0, d.y),
    ];
    let mut out = corners.to_vec();
    let mut sides: Vec<Edge> = (0..4)
        .into_par_iter()
        .map(|i| Edge::subdivided(metric, corners[i], corners[(i + 1) % 4]))
        .collect();
    for side in &mut sides {
        side.jitter(rng);
    }
    sides.par_iter_mut().for_each(|side| side.relax(metric));
    let mut edges: Vec<Vec<DVec2>> = sides.iter().map(Edge::points).collect();
    for (i, &corner) in corners.iter().enumerate() {
        // Edge i leaves corner i; edge i − 1 arrives at it.
        let before = (i + 3) % 4;
        resolve_corner(metric, corner, &mut edges, before, i);
    }
    for e in edges {
        out.extend(e);
    }
    out
}

/// Near a corner, the last sample of one edge and the first of the next can be closer than
/// the edges' own spacing when the ellipses lean across the corner (an anisotropic metric at
/// 30°, say). Fixed samples could never move apart, so the one nearer the corner is dropped
/// while such a pair is closer than [`CORNER_MIN_DISTANCE`].
fn resolve_corner(
    metric: &TensorField,
    corner: DVec2,
    edges: &mut [Vec<DVec2>],
    arriving: usize,
    leaving: usize,
) {
    let inv = |p: DVec2| metric.sample(p).inverse().unwrap_or_default();
    loop {
        // The arriving edge ends at the corner, the leaving edge starts there.
        let (Some(&a), Some(&b)) = (edges[arriving].last(), edges[leaving].first()) else {
            return;
        };
        if normalised_distance(a, &inv(a), b, &inv(b)) >= CORNER_MIN_DISTANCE {
            return;
        }
        if (a - corner).length() < (b - corner).length() {
            edges[arriving].pop();
        } else {
            edges[leaving].remove(0);
        }
    }
}

/// Smallest normalised distance kept between the samples of two edges next to a corner.
const CORNER_MIN_DISTANCE: f64 = 0.9;

/// The interior samples of one edge, as distances `ts` along it from its start `a`.
struct Edge {
    a: DVec2,
    dir: DVec2,
    length: f64,
    ts: Vec<f64>,
}

impl Edge {
    /// The edge from `a` to `b` (corners excluded) subdivided so that neighbours sit at
    /// normalised distance about 1 along it.
    fn subdivided(metric: &TensorField, a: DVec2, b: DVec2) -> Edge {
        let length = (b - a).length();
        let dir = if length > 0.0 {
            (b - a) / length
        } else {
            DVec2::X
        };
        let ts = if length > 0.0 {
            subdivision(metric, a, dir, length)
        } else {
            Vec::new()
        };
        Edge { a, dir, length, ts }
    }

    /// The samples' positions.
    fn points(&self) -> Vec<DVec2> {
        self.ts.iter().map(|&t| self.a + self.dir * t).collect()
    }

    /// Where the two neighbours of sample `i` are (the corners at the ends).
    fn gap(&self, i: usize) -> (f64, f64) {
        let lo = if i == 0 { 0.0 } else { self.ts[i - 1] };
        let hi = if i + 1 == self.ts.len() {
            self.length
        } else {
            self.ts[i + 1]
        };
        (lo, hi)
    }

    /// Moves every sample by up to a sixth of its gap to a neighbour, keeping the order.
    fn jitter(&mut self, rng: &mut Rng) {
        for i in 0..self.ts.len() {
            let (lo, hi) = self.gap(i);
            let jitter = (rng.uniform() - 0.5) / 3.0;
            let span = if jitter < 0.0 {
                self.ts[i] - lo
            } else {
                hi - self.ts[i]
            };
            self.ts[i] += jitter * span;
        }
    }

    /// Moves the samples along the edge under the force spline of their two neighbours
    /// (corners fixed), keeping the order. Each sample's inverse metric is looked up once per
    /// move, not once per pair.
    fn relax(&mut self, metric: &TensorField) {
        let (a, dir, n) = (self.a, self.dir, self.ts.len());
        let inv = |t: f64| metric.sample(a + dir * t).inverse().unwrap_or_default();
        // Inverses at the corners, then at every sample, kept current as the samples move.
        let (inv_start, inv_end) = (inv(0.0), inv(self.length));
        let mut invs: Vec<_> = self.ts.iter().map(|&t| inv(t)).collect();
        for _ in 0..EDGE_ITERATIONS {
            for i in 0..n {
                let (lo, hi) = self.gap(i);
                let inv_lo = if i == 0 { inv_start } else { invs[i - 1] };
                let inv_hi = if i + 1 == n { inv_end } else { invs[i + 1] };
                let ti = self.ts[i];
                let (p, ip) = (a + dir * ti, invs[i]);
                let push = |other: f64, inv_other: &Tensor| {
                    let d = normalised_distance(p, &ip, a + dir * other, inv_other);
                    let span = (ti - other).abs().max(1e-12);
                    force_spline(d) * span / d.max(1e-6)
                };
                // Repulsion from the lower neighbour pushes up, from the upper one down.
                let step = 0.25 * (push(lo, &inv_lo) - push(hi, &inv_hi));
                let t = (ti + step).clamp(lo + 0.25 * (ti - lo), hi - 0.25 * (hi - ti));
                self.ts[i] = t;
                invs[i] = inv(t);
            }
        }
    }
}

/// Distances along the edge from `a` in direction `dir` that cut it at equal normalised arc
/// length `∫ dt / (2 r(t))`, into a whole number of pieces of about 1.
fn subdivision(metric: &TensorField, a: DVec2, dir: DVec2, length: f64) -> Vec<f64> {
    let radius = |t: f64| {
        let inv = metric.sample(a + dir * t).inverse();
        inv.map_or(length, |inv| radius_along(&inv, dir))
    };
    // Normalised arc length by the midpoint rule, steps of a fraction of r.
    let mut cumulative = vec![(0.0, 0.0)];
    let (mut t, mut s) = (0.0f64, 0.0f64);
    while t < length {
        let step = (0.25 * radius(t)).max(1e-3 * length).min(length - t);
        s += step / (2.0 * radius(t + 0.5 * step));
        t += step;
        cumulative.push((t, s));
    }
    let segments = s.round().max(1.0) as usize;
    if segments < 2 {
        return Vec::new();
    }
    // Subdivision at equal normalised arc length.
    let mut ts: Vec<f64> = Vec::with_capacity(segments - 1);
    let mut j = 0;
    for k in 1..segments {
        let target = s * k as f64 / segments as f64;
        while cumulative[j + 1].1 < target {
            j += 1;
        }
        let (t0, s0) = cumulative[j];
        let (t1, s1) = cumulative[j + 1];
        ts.push(t0 + (t1 - t0) * (target - s0) / (s1 - s0).max(1e-300));
    }
    ts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_neighbours_sit_near_distance_one() {
        let metric = TensorField::constant(200, 100, Tensor::from_eigen(0.5, 6.0, 2.0));
        let pts = boundary_samples(&metric, &mut Rng::new(3, 0));
        let inv = metric.node(0, 0).inverse().unwrap();
        // Walk the top edge: corners 0 and 1 plus the samples on y = 0.
        let mut top: Vec<DVec2> = pts.iter().copied().filter(|p| p.y == 0.0).collect();
        top.sort_by(|a, b| a.x.total_cmp(&b.x));
        assert!(top.len() > 10);
        let mut sum = 0.0;
        for w in top.windows(2) {
            let d = normalised_distance(w[0], &inv, w[1], &inv);
            assert!(d > 0.8 && d < 1.25, "{d}");
            sum += d;
        }
        let mean = sum / (top.len() - 1) as f64;
        assert!((mean - 1.0).abs() < 0.05, "{mean}");
        // Every sample is on the boundary.
        let dom = metric.domain();
        assert!(pts
            .iter()
            .all(|p| p.x == 0.0 || p.y == 0.0 || p.x == dom.x || p.y == dom.y));
    }
}
