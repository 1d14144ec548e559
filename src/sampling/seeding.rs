//! Relaxation dart throwing (paper section 5.1, after \[ME92\]) for the interior samples.
//!
//! A candidate is accepted unless its normalised distance to an accepted sample is below ρ.
//! ρ starts at 0.9 and drops by 0.05, down to 0.75, whenever the ratio of accepted to rejected
//! candidates since the last change falls below ε = 0.01; throwing stops at the target count
//! `N ≈ ∫ dA / (2√3 · det m)` (hexagonal packing of the ellipses), or when even ρ = 0.75
//! rejects nearly everything.
//!
//! Candidates are drawn with density proportional to `1/det m`, so every region fills at the
//! same pace and no region waits for the dense ones. Rejection tests never scan all samples:
//! they read the seeding grid of [`cellgrid`](super::cellgrid), where every accepted sample is
//! registered by its ρ-scaled bounding box, and are exact.

use super::cellgrid::{conflict, half_extents, CellGrid};
use super::rng::Rng;
use crate::field::{Tensor, TensorField};
use glam::DVec2;
use rayon::prelude::*;

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

/// The metric of `photo` with `params`' cell sizes (`min_size`, `max_size`) scaled so that
/// about `count` samples fill it. Sizes are corrected twice: the count does not scale
/// exactly with them, as smoothing and gradation scale too. Returns the scaled parameters
/// and the metric.
#[must_use]
pub fn photo_metric_for_count(
    photo: &image::DynamicImage,
    params: &crate::field::MetricParams,
    count: f64,
) -> (crate::field::MetricParams, TensorField) {
    let mut params = params.clone();
    let mut field = crate::field::photo_metric(photo, &params).1;
    for _ in 0..2 {
        let k = (estimate_count(&field) / count.max(1.0)).sqrt();
        params.min_size *= k;
        params.max_size *= k;
        field = crate::field::photo_metric(photo, &params).1;
    }
    (params, field)
}

/// Estimated sample count `∫ dA / (2√3 · det m)` over the grid nodes of `metric`.
#[must_use]
pub fn estimate_count(metric: &TensorField) -> f64 {
    survey(metric, |_| false).estimate
}

/// What one pass over a metric's nodes finds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Survey {
    /// The first node (column, row) in row-major order that the test called bad.
    pub first_bad: Option<(usize, usize)>,
    /// [`estimate_count`] (meaningless when a node is bad).
    pub estimate: f64,
    /// The smallest geometric-mean radius `√det m` over the nodes.
    pub smallest_radius: f64,
    /// Every node holds the first node's tensor (a constant metric, as `analytic:constant`
    /// or a constant `.npy` field gives).
    pub uniform: bool,
}

/// The first node `bad` refuses, the estimated count, the smallest radius and whether every
/// node is the same, in one pass over fixed chunks in parallel: the check, the count and the
/// sampler's grid spacing read the field once instead of three times (the pass is bound by
/// memory: a 1024² field takes 1.5-2 ms on two threads; the sameness test stops at a chunk's
/// first differing node). Each chunk is summed in order, then the chunks' sums in order: the
/// same figures at any thread count.
#[must_use]
pub fn survey(metric: &TensorField, bad: impl Fn(Tensor) -> bool + Sync) -> Survey {
    let area = node_area(metric);
    let first = metric.data().first().copied();
    let chunks: Vec<(Option<usize>, f64, f64, bool)> = metric
        .data()
        .par_chunks(SURVEY_CHUNK)
        .enumerate()
        .map(|(k, chunk)| {
            let (mut sum, mut smallest) = (0.0, f64::INFINITY);
            let uniform = chunk.iter().all(|&c| Some(c) == first);
            for (i, &c) in chunk.iter().enumerate() {
                let t = Tensor::from_f32(c);
                if bad(t) {
                    return (Some(k * SURVEY_CHUNK + i), sum, smallest, uniform);
                }
                let det = t.det();
                sum += area / (2.0 * 3f64.sqrt() * det);
                smallest = smallest.min(det);
            }
            (None, sum, smallest, uniform)
        })
        .collect();
    let cols = metric.cols();
    Survey {
        first_bad: chunks
            .iter()
            .find_map(|c| c.0)
            .map(|i| (i % cols, i / cols)),
        estimate: chunks.iter().map(|c| c.1).sum(),
        smallest_radius: chunks
            .iter()
            .map(|c| c.2)
            .fold(f64::INFINITY, f64::min)
            .sqrt(),
        uniform: chunks.iter().all(|c| c.3),
    }
}

/// Nodes per parallel chunk of [`survey`].
const SURVEY_CHUNK: usize = 1 << 14;

/// Area of the domain each grid node stands for (the domain may be a little smaller than the
/// grid when the photo's size is not a multiple of the analysis factor).
fn node_area(metric: &TensorField) -> f64 {
    let d = metric.domain();
    d.x * d.y / (metric.cols() * metric.rows()) as f64
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
    let mut grid = CellGrid::for_field(metric, fixed.len() + target);

    let mut positions: Vec<DVec2> = Vec::with_capacity(fixed.len() + target);
    let mut inverses: Vec<Tensor> = Vec::with_capacity(fixed.len() + target);
    let mut rho = params.rho_start;
    for &p in fixed {
        let m = metric.sample(p);
        grid.insert(
            positions.len() as u32,
            p,
            half_extents(&m),
            params.rho_start,
        );
        positions.push(p);
        inverses.push(m.inverse().unwrap_or_default());
    }
    let (mut accepted, mut rejected) = (0u64, 0u64);
    let interior = |positions: &Vec<DVec2>| positions.len() - fixed.len();
    let max_darts = 400 * target as u64 + 100_000;
    let mut darts = 0u64;
    // Darts are drawn in batches and thrown in Morton order within a batch, so the grid and
    // the field are read mostly in order. A batch is small next to the target count (at most a
    // sixteenth), so its darts rarely compete with each other and the order does not show.
    //
    // Each batch is first tested in parallel against the samples accepted before it (the
    // look-ups and most rejections happen there); then, in order, a dart that conflicted
    // already is rejected (samples are only ever added, so it still conflicts), and the others
    // are tested again against everything, those accepted earlier in the batch included. This
    // accepts exactly the darts a purely sequential pass would, at any thread count. If ρ falls
    // within a batch, the rest of the batch is tested sequentially (an earlier conflict at the
    // larger ρ proves nothing at the smaller one).
    let batch_size = (target / 16).clamp(64, 4096);
    let mut batch: Vec<(u32, DVec2)> = Vec::with_capacity(batch_size);
    let mut tested: Vec<Option<Dart>> = Vec::with_capacity(batch_size);
    let domain = metric.domain();
    'throwing: while interior(&positions) < target && darts < max_darts {
        batch.clear();
        batch.extend((0..batch_size).map(|_| {
            let c = sampler.draw(rng);
            (morton_key(c, domain), c)
        }));
        batch.sort_unstable_by_key(|&(k, _)| k);
        let rho_batch = rho;
        batch
            .par_iter()
            .map(|&(_, c)| {
                let m = metric.sample(c);
                m.inverse().map(|inv| {
                    let half = half_extents(&m);
                    let conflict = conflict(&grid, &inverses, c, &inv, half, rho_batch).is_some();
                    Dart {
                        inv,
                        half,
                        conflict,
                    }
                })
            })
            .collect_into_vec(&mut tested);
        for (&(_, c), dart) in batch.iter().zip(&tested) {
            if interior(&positions) >= target {
                break 'throwing;
            }
            darts += 1;
            let Some(dart) = dart else { continue };
            if accepted + rejected == WINDOW {
                if (accepted as f64) < params.epsilon * rejected as f64 {
                    if rho <= params.rho_min + 1e-12 {
                        break 'throwing;
                    }
                    rho = (rho - params.rho_step).max(params.rho_min);
                }
                accepted = 0;
                rejected = 0;
            }
            let known_conflict = dart.conflict && rho == rho_batch;
            if known_conflict || conflict(&grid, &inverses, c, &dart.inv, dart.half, rho).is_some()
            {
                rejected += 1;
                continue;
            }
            accepted += 1;
            grid.insert(positions.len() as u32, c, dart.half, params.rho_start);
            positions.push(c);
            inverses.push(dart.inv);
        }
    }
    (positions.split_off(fixed.len()), rho)
}

/// A dart after the parallel test: its inverse metric, bounding box, and whether it
/// conflicted with the samples accepted before its batch.
struct Dart {
    inv: Tensor,
    half: DVec2,
    conflict: bool,
}

/// Morton (Z-curve) key of `p` in `domain`, 16 bits per axis.
#[must_use]
pub fn morton_key(p: DVec2, domain: DVec2) -> u32 {
    let q = |v: f64, extent: f64| ((v / extent).clamp(0.0, 1.0) * 65535.0) as u32;
    let spread = |mut v: u32| {
        v &= 0xffff;
        v = (v | (v << 8)) & 0x00ff_00ff;
        v = (v | (v << 4)) & 0x0f0f_0f0f;
        v = (v | (v << 2)) & 0x3333_3333;
        (v | (v << 1)) & 0x5555_5555
    };
    spread(q(p.x, domain.x)) | (spread(q(p.y, domain.y)) << 1)
}

/// `n` points drawn independently with density proportional to `1/det m`: the "random
/// placement" baseline the relaxed samples are compared with.
#[must_use]
pub fn random_positions(metric: &TensorField, n: usize, rng: &mut Rng) -> Vec<DVec2> {
    let sampler = DensitySampler::new(metric);
    (0..n).map(|_| sampler.draw(rng)).collect()
}

/// Draws points with density proportional to `1/det m` over the domain: a grid node by
/// Walker's alias method (constant time, one table look-up), then a uniform point within the
/// node's cell.
struct DensitySampler {
    /// Probability of keeping node `i` rather than taking `alias[i]`.
    keep: Vec<f32>,
    alias: Vec<u32>,
    cols: usize,
    cell: DVec2,
}

impl DensitySampler {
    fn new(metric: &TensorField) -> Self {
        let weights: Vec<f64> = metric
            .data()
            .iter()
            .map(|&c| 1.0 / Tensor::from_f32(c).det())
            .collect();
        let n = weights.len();
        let total: f64 = weights.iter().sum();
        // Vose's construction: scaled weights, then pair each small one with a large one.
        let mut scaled: Vec<f64> = weights.iter().map(|w| w * n as f64 / total).collect();
        let mut keep = vec![1.0f32; n];
        let mut alias: Vec<u32> = (0..n as u32).collect();
        let (mut small, mut large): (Vec<u32>, Vec<u32>) =
            (0..n as u32).partition(|&i| scaled[i as usize] < 1.0);
        while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
            keep[s as usize] = scaled[s as usize] as f32;
            alias[s as usize] = l;
            scaled[l as usize] -= 1.0 - scaled[s as usize];
            if scaled[l as usize] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        let d = metric.domain();
        DensitySampler {
            keep,
            alias,
            cols: metric.cols(),
            cell: DVec2::new(d.x / metric.cols() as f64, d.y / metric.rows() as f64),
        }
    }

    fn draw(&self, rng: &mut Rng) -> DVec2 {
        let n = self.keep.len();
        let u = rng.uniform() * n as f64;
        let i = (u as usize).min(n - 1);
        let i = if (u - i as f64) < f64::from(self.keep[i]) {
            i
        } else {
            self.alias[i] as usize
        };
        let (c, r) = (i % self.cols, i / self.cols);
        DVec2::new(
            (c as f64 + rng.uniform()) * self.cell.x,
            (r as f64 + rng.uniform()) * self.cell.y,
        )
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::sampling::cellgrid::{long_semi_axis, short_semi_axis};
    use crate::sampling::distance::normalised_distance;

    #[test]
    fn estimate_of_a_constant_field() {
        let m = Tensor::from_eigen(0.4, 6.0, 2.0);
        let metric = TensorField::constant(300, 200, m);
        let want = 300.0 * 200.0 / (2.0 * 3f64.sqrt() * 12.0);
        assert!((estimate_count(&metric) - want).abs() < 1e-6 * want);
    }

    #[test]
    fn survey_finds_the_first_bad_node_the_count_and_the_smallest_radius() {
        // Sizes vary across the field; 600 x 100 nodes span four chunks.
        let metric = TensorField::from_fn(600, 100, |p| {
            Tensor::from_eigen(p.y / 40.0, 2.0 + p.x / 100.0, 1.0 + p.y / 200.0)
        });
        let nodes: Vec<Tensor> = (0..100)
            .flat_map(|r| (0..600).map(move |c| (c, r)))
            .map(|(c, r)| metric.node(c, r))
            .collect();
        let brute_count: f64 = nodes
            .iter()
            .map(|t| 1.0 / (2.0 * 3f64.sqrt() * t.det()))
            .sum();
        let brute_smallest = nodes
            .iter()
            .map(|t| t.det().sqrt())
            .fold(f64::MAX, f64::min);
        let found = survey(&metric, |_| false);
        assert_eq!(found.first_bad, None);
        assert!((found.estimate - brute_count).abs() < 1e-9 * brute_count);
        assert!((found.smallest_radius - brute_smallest).abs() < 1e-12);
        // Bad nodes from the second chunk on: the one first in row order is reported.
        let bad = |t: Tensor| short_semi_axis(&t) > 1.25 && long_semi_axis(&t) > 5.0;
        let first = (0..nodes.len()).find(|&i| bad(nodes[i])).unwrap();
        assert!(
            first > SURVEY_CHUNK,
            "the test wants a bad node past the first chunk"
        );
        assert_eq!(
            survey(&metric, bad).first_bad,
            Some((first % 600, first / 600))
        );
    }

    #[test]
    fn density_sampler_follows_inverse_determinant() {
        // Left half: ellipses of area 4x those on the right, so 1/4 of the density.
        let metric = TensorField::from_fn(40, 10, |p| {
            Tensor::isotropic(if p.x < 20.0 { 2.0 } else { 1.0 })
        });
        let sampler = DensitySampler::new(&metric);
        let mut rng = Rng::new(4, 0);
        let n = 200_000;
        let left = (0..n).filter(|_| sampler.draw(&mut rng).x < 20.0).count();
        let want = n as f64 * 0.25 / 1.25;
        assert!((left as f64 - want).abs() < 0.02 * want, "{left} vs {want}");
    }

    #[test]
    fn accepted_darts_respect_rho_exactly() {
        let metric = TensorField::from_fn(200, 150, |p| {
            Tensor::from_eigen(p.x / 50.0, 3.0 + p.y / 30.0, 2.0)
        });
        let params = DartParams::default();
        let (pts, rho) = relaxation_dart_throwing(&metric, &[], 2000, &params, &mut Rng::new(9, 0));
        assert!(pts.len() > 300);
        assert_no_pair_closer(&metric, &pts, rho);
    }

    /// Brute force over all pairs: no two of `pts` closer than `rho` (eq. 4).
    pub(in crate::sampling) fn assert_no_pair_closer(
        metric: &TensorField,
        pts: &[DVec2],
        rho: f64,
    ) {
        let inv: Vec<Tensor> = pts
            .iter()
            .map(|&p| metric.sample(p).inverse().unwrap())
            .collect();
        for i in 0..pts.len() {
            for j in 0..i {
                let d = normalised_distance(pts[i], &inv[i], pts[j], &inv[j]);
                assert!(d >= rho - 1e-9, "{i} {j}: {d} < {rho}");
            }
        }
    }
}
