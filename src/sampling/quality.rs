//! How well a set of samples is packed, measured independently of how it was made:
//! nearest-neighbour normalised distance (min, 5th percentile, median, mean), coverage (the
//! fraction of the domain inside at least one ellipse) and overlap (inside two or more),
//! measured on a raster fine enough that the smallest ellipse spans several cells, and the
//! anisotropic triangulation's mean quality `4√3·A / Σ l²` in the barycentre metric.

use super::delaunay::AnisotropicDelaunay;
use super::distance::normalised_distance;
use crate::field::{Tensor, TensorField};
use glam::DVec2;
use rayon::prelude::*;

/// Largest raster used for coverage and overlap, in cells.
const MAX_RASTER_CELLS: f64 = 16.0e6;

/// Quality figures of a sampling.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Quality {
    /// Number of samples.
    pub count: usize,
    /// Smallest nearest-neighbour normalised distance.
    pub nn_min: f64,
    /// 5th percentile of the nearest-neighbour normalised distances.
    pub nn_p5: f64,
    /// Median nearest-neighbour normalised distance.
    pub nn_median: f64,
    /// Mean nearest-neighbour normalised distance.
    pub nn_mean: f64,
    /// Fraction of the domain inside at least one ellipse.
    pub coverage: f64,
    /// Fraction of the domain inside at least two ellipses.
    pub overlap: f64,
    /// Mean `4√3·A / Σ l²` of the triangles in their barycentre metric (1 = equilateral).
    pub triangle_quality: f64,
}

/// Nearest-neighbour normalised distance of every sample, searched among `candidates(i)`.
fn nearest_distances(
    positions: &[DVec2],
    inverses: &[Tensor],
    candidates: impl Fn(usize) -> Vec<u32> + Sync,
) -> Vec<f64> {
    (0..positions.len())
        .into_par_iter()
        .map(|i| {
            candidates(i)
                .into_iter()
                .filter(|&j| j as usize != i)
                .map(|j| {
                    let j = j as usize;
                    normalised_distance(positions[i], &inverses[i], positions[j], &inverses[j])
                })
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

/// Quality of `positions` with metrics `metrics` over `field`'s domain. Nearest neighbours
/// are searched among each sample's neighbours in `mesh` and theirs (two rings).
#[must_use]
pub fn measure(
    positions: &[DVec2],
    metrics: &[Tensor],
    mesh: &AnisotropicDelaunay,
    field: &TensorField,
) -> Quality {
    let inverses: Vec<Tensor> = metrics
        .iter()
        .map(|m| m.inverse().unwrap_or_default())
        .collect();
    let edges = mesh.edges(positions.len());
    let nn = nearest_distances(positions, &inverses, |i| {
        let mut c: Vec<u32> = edges.at(i).map(|(_, _, n)| n).collect();
        for (_, _, n) in edges.at(i) {
            c.extend(edges.at(n as usize).map(|(_, _, m)| m));
        }
        c
    });
    let (coverage, overlap) = coverage_and_overlap(positions, metrics, field.domain());
    let mut q = summarize(&nn);
    q.count = positions.len();
    q.coverage = coverage;
    q.overlap = overlap;
    q.triangle_quality = mean_triangle_quality(mesh, positions, field);
    q
}

/// Nearest-neighbour figures by brute force over all pairs (for tests and small sets).
#[must_use]
pub fn brute_force_nearest(positions: &[DVec2], metrics: &[Tensor]) -> Vec<f64> {
    let inverses: Vec<Tensor> = metrics
        .iter()
        .map(|m| m.inverse().unwrap_or_default())
        .collect();
    let all: Vec<u32> = (0..positions.len() as u32).collect();
    nearest_distances(positions, &inverses, |_| all.clone())
}

/// Mean quality `4√3·A / Σ l²` (1 for equilateral) of `mesh`'s triangles in the metric of
/// their barycentre.
#[must_use]
pub fn mean_triangle_quality(
    mesh: &AnisotropicDelaunay,
    points: &[DVec2],
    metric: &TensorField,
) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    for [a, b, c] in mesh.triangles() {
        let (a, b, c) = (points[a as usize], points[b as usize], points[c as usize]);
        let q = (a + b + c) / 3.0;
        let Some(inv) = metric.sample(q).inverse() else {
            continue;
        };
        let (a, b, c) = (inv.mul_vec(a), inv.mul_vec(b), inv.mul_vec(c));
        let area = 0.5 * (b - a).perp_dot(c - a).abs();
        let l2 = (b - a).length_squared() + (c - b).length_squared() + (a - c).length_squared();
        if l2 > 0.0 {
            sum += 4.0 * 3f64.sqrt() * area / l2;
            n += 1;
        }
    }
    if n == 0 {
        0.0
    } else {
        sum / n as f64
    }
}

/// Min, 5th percentile, median and mean of nearest-neighbour distances.
#[must_use]
pub fn summarize(nn: &[f64]) -> Quality {
    let mut v: Vec<f64> = nn.iter().copied().filter(|d| d.is_finite()).collect();
    if v.is_empty() {
        return Quality::default();
    }
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    Quality {
        nn_min: v[0],
        nn_p5: at(0.05),
        nn_median: at(0.5),
        nn_mean: v.iter().sum::<f64>() / v.len() as f64,
        ..Quality::default()
    }
}

/// Coverage and overlap on a raster over the domain: each ellipse increments the cells whose
/// centres it contains. Rows are split into bands processed in parallel, each owning its cells.
#[must_use]
pub fn coverage_and_overlap(positions: &[DVec2], metrics: &[Tensor], domain: DVec2) -> (f64, f64) {
    if positions.is_empty() || domain.x <= 0.0 || domain.y <= 0.0 {
        return (0.0, 0.0);
    }
    let smallest = metrics
        .iter()
        .map(|m| m.eigen().l2)
        .filter(|v| *v > 0.0)
        .fold(f64::INFINITY, f64::min);
    // At least 3 raster cells across the smallest short semi-axis, and no coarser than pixels.
    let mut scale = (3.0 / smallest).max(1.0);
    let cells = domain.x * domain.y * scale * scale;
    if cells > MAX_RASTER_CELLS {
        scale *= (MAX_RASTER_CELLS / cells).sqrt();
    }
    let (w, h) = (
        (domain.x * scale).ceil() as usize,
        (domain.y * scale).ceil() as usize,
    );
    let band = 32usize;
    let bands = h.div_ceil(band);
    // Which samples touch which band: one list per band, filled in sample order.
    let mut by_band: Vec<Vec<u32>> = vec![Vec::new(); bands];
    let extents: Vec<DVec2> = metrics
        .iter()
        .map(|m| DVec2::new(m.xx.hypot(m.xy), m.xy.hypot(m.yy)))
        .collect();
    for (i, (p, e)) in positions.iter().zip(&extents).enumerate() {
        let y0 = (((p.y - e.y) * scale).floor().max(0.0) as usize).min(h - 1) / band;
        let y1 = (((p.y + e.y) * scale).floor().max(0.0) as usize).min(h - 1) / band;
        for b in &mut by_band[y0..=y1] {
            b.push(i as u32);
        }
    }
    let inverses: Vec<Tensor> = metrics
        .iter()
        .map(|m| m.inverse().unwrap_or_default())
        .collect();
    let (covered, overlapped) = by_band
        .par_iter()
        .enumerate()
        .map(|(b, ids)| {
            let (r0, r1) = (b * band, ((b + 1) * band).min(h));
            let mut count = vec![0u8; (r1 - r0) * w];
            for &i in ids {
                let (p, e, inv) = (
                    positions[i as usize],
                    extents[i as usize],
                    inverses[i as usize],
                );
                let ry0 = (((p.y - e.y) * scale - 0.5).ceil().max(r0 as f64)) as usize;
                let ry1 = (((p.y + e.y) * scale - 0.5).floor().min((r1 - 1) as f64)) as isize;
                let cx0 = ((p.x - e.x) * scale - 0.5).ceil().max(0.0) as usize;
                let cx1 = ((p.x + e.x) * scale - 0.5).floor().min((w - 1) as f64) as isize;
                if ry1 < 0 || cx1 < 0 {
                    continue;
                }
                for ry in ry0..=ry1 as usize {
                    for cx in cx0..=cx1 as usize {
                        let q = DVec2::new((cx as f64 + 0.5) / scale, (ry as f64 + 0.5) / scale);
                        if inv.mul_vec(q - p).length_squared() <= 1.0 {
                            let c = &mut count[(ry - r0) * w + cx];
                            *c = c.saturating_add(1);
                        }
                    }
                }
            }
            let covered = count.iter().filter(|&&c| c >= 1).count();
            let overlapped = count.iter().filter(|&&c| c >= 2).count();
            (covered, overlapped)
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    let total = (w * h) as f64;
    (covered as f64 / total, overlapped as f64 / total)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coverage_of_known_discs() {
        // One disc of radius 10 in a 100x100 domain: π·100 / 10⁴.
        let (c, o) = coverage_and_overlap(
            &[DVec2::new(50.0, 50.0)],
            &[Tensor::isotropic(10.0)],
            DVec2::splat(100.0),
        );
        assert!((c - std::f64::consts::PI / 100.0).abs() < 2e-3, "{c}");
        assert_eq!(o, 0.0);
        // Two identical discs: all covered area is overlap.
        let (c2, o2) = coverage_and_overlap(
            &[DVec2::new(50.0, 50.0); 2],
            &[Tensor::isotropic(10.0); 2],
            DVec2::splat(100.0),
        );
        assert_eq!(c2, c);
        assert_eq!(o2, c);
    }

    #[test]
    fn summary_figures() {
        let q = summarize(&[1.0, 0.5, 2.0, 1.5, 1.0]);
        assert_eq!((q.nn_min, q.nn_median), (0.5, 1.0));
        assert!((q.nn_mean - 1.2).abs() < 1e-12);
    }
}
