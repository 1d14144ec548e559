//! Seeding from a metric-aligned hexagonal lattice, grown as a front (an alternative to the
//! paper's relaxation dart throwing, section 5.1, that starts the relaxation near its end).
//!
//! In the metric's own space, where every ellipse is a unit circle, touching circles pack as a
//! hexagonal lattice of spacing 2. The front grows that lattice outwards from one seed: each
//! accepted sample `p` with metric `m_p = R diag(a, b) Rᵀ` proposes six neighbours
//! `p + (m_p + m_c)·u_k`, `u_k = R(α + θ₀ + kπ/3)·x̂` (α the long axis' angle, `m_c` the metric
//! at the first guess `p + 2 m_p u_k`): at eq. 4's `d = 1` from `p` with both metrics. A
//! proposal is accepted unless it lies outside the domain or closer than ρ (eq. 4) to a sample
//! already there, tested exactly with the dart thrower's grid. Samples are taken first in,
//! first out, so the front is a ring about the seed and meets the fixed boundary last. On a
//! constant field this is the hexagonal packing itself (90.7 % coverage, `N` the estimate); where
//! the field turns or changes size, the lattice bends and the proposals that no longer fit are
//! the defects the relaxation then anneals. Where the front leaves a hole wider than a cell of
//! the grid (a field whose sizes jump), a new front grows from the hole. Last, the seams and the
//! smaller holes are filled: every sample proposes its neighbours once more, accepted at the
//! closer ρ where relaxation dart throwing ends (0.75), so the relaxation starts with nearly its
//! final count; what is left goes to the population control's fill-rate insertion.
//!
//! Sequential and deterministic: one pass over a first-in first-out queue, one grid query per
//! proposal (six per sample), far fewer distance tests than relaxation dart throwing, whose
//! rejections dominate its cost.

use super::cellgrid::{conflict, half_extents, short_semi_axis, CellGrid};
use super::rng::Rng;
use crate::field::{Tensor, TensorField};
use glam::DVec2;
use std::collections::VecDeque;

/// Parameters of lattice seeding.
#[derive(Clone, Debug, PartialEq)]
pub struct LatticeParams {
    /// A proposal closer than this (eq. 4) to an accepted sample is rejected. At 0.95 the
    /// seams where the bent lattice meets itself are seeded a little sparser than at 0.85:
    /// around the singular point of the `circular` field (670 samples) the final overlap fell
    /// from 1.9–2.5 % to 1.7–1.8 %, while coverage on smooth fields moved by 0.2 % at most.
    pub rho: f64,
    /// Angle of the lattice's first row from the ellipse's long axis, measured in the metric's
    /// own space (radians; the lattice repeats every π/3). The default π/6 puts a row across
    /// the long axis, ellipses side by side: on a turning 4:1 field it packed to 0.3–0.5 % more
    /// coverage after relaxation than rows along the long axis (phase 0), tip to tip.
    pub phase: f64,
    /// Once the front stops, every sample proposes its six neighbours again and a proposal is
    /// accepted this close (eq. 4) to the samples already there: the seams where the bent
    /// lattice meets itself, and holes too small for a new front, are filled as densely as
    /// relaxation dart throwing ends (its final ρ). Values at or above `rho` skip the pass.
    /// Coverage / overlap after relaxation, without the fill against with it: the rotating
    /// 4:1 field (11 000 ellipses; the seed grew from 82 to 88 % of the final count) 87.1 /
    /// 0.62 % against 87.9 / 0.79 %; a smooth 3:1 swirl whose sizes vary 2× (14 000) 87.4 /
    /// 0.61 % against 88.0 / 0.75 %; isotropic sizes growing 3× (11 000) 86.9 / 0.41 % against
    /// 87.6 / 0.55 %; `circular` (2 600 and 10 000) +0.2 % with overlap unchanged. At 0.7 the
    /// coverage rose 0.3–0.6 % more, but overlap passed 1 % (rotating field at 4 000: 1.12 %).
    pub fill_rho: f64,
}

impl Default for LatticeParams {
    fn default() -> Self {
        LatticeParams {
            rho: 0.95,
            phase: std::f64::consts::FRAC_PI_6,
            fill_rho: 0.75,
        }
    }
}

/// The samples accepted so far, with the grid that finds their neighbours.
struct Packing<'a> {
    metric: &'a TensorField,
    rho: f64,
    grid: CellGrid,
    positions: Vec<DVec2>,
    inverses: Vec<Tensor>,
    /// Per sample, a bit per lattice direction: that proposal was refused by a sample at
    /// eq. 4's `d` of at least `fill_rho`, off the proposed lattice point, so the fill may
    /// take it.
    near_miss: Vec<u8>,
    /// [`LatticeParams::fill_rho`]: a proposal refused by a sample closer than this would be
    /// refused by the fill too, since that sample stays.
    fill_rho: f64,
}

/// A proposal within this many short semi-axes (of the sample proposing it) of a sample
/// already there lands on a taken lattice point: most of a grown lattice's proposals (on the
/// rotating 4:1 field, 65 000 of 95 000). Eq. 4's `d` to that sample is then under 0.5 (at
/// most the smallest `fill_rho`) unless the ellipses there are under half the proposer's
/// size, so the exact test would refuse it too, for the front and the fill (the seeds came
/// out the same on the rotating field and photos), and it is refused without the metric
/// look-up and the distance tests. Refusing is always safe: no overlap can come of it.
const TAKEN: f64 = 0.25;

/// Every lattice direction of [`Packing::grow`], as bits.
const ALL_DIRECTIONS: u8 = 0b11_1111;

/// What became of a proposal.
enum Proposal {
    /// Accepted, with its metric.
    Added(Tensor),
    /// Outside the domain, or refused by a sample closer than the fill's ρ (its lattice
    /// point taken): the fill would refuse it too.
    Refused,
    /// Refused by a sample at `d` of at least the fill's ρ: a seam the fill may close.
    NearMiss,
}

impl Packing<'_> {
    /// Adds a sample at `p` with metric `m` without any test.
    fn add(&mut self, p: DVec2, m: &Tensor) {
        self.grid
            .insert(self.positions.len() as u32, p, half_extents(m), self.rho);
        self.positions.push(p);
        self.inverses.push(m.inverse().unwrap_or_default());
        self.near_miss.push(0);
    }

    /// Adds a sample at `p` unless it is outside the domain or closer than ρ to one already
    /// there. `short` is the proposing sample's short semi-axis: a sample within
    /// [`TAKEN`]`·short` of `p` has taken its lattice point, found without the metric at `p`.
    fn try_add(&mut self, p: DVec2, short: f64) -> Proposal {
        let domain = self.metric.domain();
        if !(p.x > 0.0 && p.y > 0.0 && p.x < domain.x && p.y < domain.y) {
            return Proposal::Refused;
        }
        if self.grid.any_closer(p, TAKEN * short) {
            return Proposal::Refused;
        }
        let m = self.metric.sample(p);
        let Some(inv) = m.inverse() else {
            return Proposal::Refused;
        };
        match conflict(
            &self.grid,
            &self.inverses,
            p,
            &inv,
            half_extents(&m),
            self.rho,
        ) {
            Some(d) if d < self.fill_rho => Proposal::Refused,
            Some(_) => Proposal::NearMiss,
            None => {
                self.add(p, &m);
                Proposal::Added(m)
            }
        }
    }

    /// Grows the lattice from the samples in `front` (index, position, metric, the lattice
    /// directions to propose as bits) until no proposal fits. Samples the front adds propose
    /// all six.
    fn grow(&mut self, front: &mut VecDeque<(usize, DVec2, Tensor, u8)>, phase: f64) {
        // The six directions relative to the long axis, turned onto it per sample.
        let turns: [DVec2; 6] = std::array::from_fn(|k| {
            let (s, c) = (phase + std::f64::consts::FRAC_PI_3 * k as f64).sin_cos();
            DVec2::new(c, s)
        });
        while let Some((k, p, m, directions)) = front.pop_front() {
            let axis = long_axis_direction(&m);
            let short = short_semi_axis(&m);
            for (bit, turn) in turns.into_iter().enumerate() {
                if directions & (1 << bit) == 0 {
                    continue;
                }
                let u = axis.rotate(turn);
                let reach = m.mul_vec(u);
                // Eq. 4's d = 1 with both ellipses: the second one's radius taken at the guess.
                let guess = p + 2.0 * reach;
                let q = p + reach + self.metric.sample(guess).mul_vec(u);
                match self.try_add(q, short) {
                    Proposal::Added(mq) => {
                        front.push_back((self.positions.len() - 1, q, mq, ALL_DIRECTIONS));
                    }
                    Proposal::NearMiss => self.near_miss[k] |= 1 << bit,
                    Proposal::Refused => {}
                }
            }
        }
    }

    /// Adds a seed at `s` and grows the lattice from it.
    fn grow_from(&mut self, s: DVec2, phase: f64) -> bool {
        // A seed has no proposer: no lattice point of its own to find taken.
        let Proposal::Added(m) = self.try_add(s, 0.0) else {
            return false;
        };
        let mut front = VecDeque::from([(self.positions.len() - 1, s, m, ALL_DIRECTIONS)]);
        self.grow(&mut front, phase);
        true
    }
}

/// The [`LatticeParams::phase`] that lays a row of the lattice of the constant metric `m`
/// along the domain's walls that are longest in the metric's own space (the horizontal ones,
/// `domain.x` long, or the vertical ones): the wall's fixed samples then sit on the lattice
/// as a row of it, where a lattice at another angle meets them in notches that the relaxation
/// fills with compressed samples. In the metric's space a wall along `d` runs along `m⁻¹d`;
/// the lattice's rows run at `α + phase + kπ/3`, `α` the long axis's angle. Measured after
/// relaxation, the default phase against this one:
/// - constant fields of about 1 450 samples (700×600), coverage / overlap / p5 of the nearest
///   distances: 2:1, 90.3 % / 0.64 % / 0.927 against 89.3 % / 0.20 % / 0.963; 4:1, 90.0 % /
///   0.94 % / 0.911 against 89.7 % / 0.52 % / 0.931;
/// - 24 constant fields of 1 450 and 5 700 samples (800×600, anisotropy 1.5, 3 and 5 at 0°,
///   20°, 45° and 70°): p5 +0.007 and overlap −0.09 points on average, coverage −0.14 points
///   (from +0.8 to −2.2: where the aligned rows leave fewer samples); coverage ≥ 88 %,
///   overlap ≤ 1 % and p5 ≥ 0.93 together on 18 fields against 15. At 0° the default already
///   lies along the walls.
#[must_use]
pub fn wall_phase(m: &Tensor, domain: DVec2) -> Option<f64> {
    let inv = m.inverse()?;
    let (along_x, along_y) = (inv.mul_vec(DVec2::X), inv.mul_vec(DVec2::Y));
    let wall = if along_x.length() * domain.x >= along_y.length() * domain.y {
        along_x
    } else {
        along_y
    };
    let alpha = m.eigen().angle;
    let phase = (wall.y.atan2(wall.x) - alpha).rem_euclid(std::f64::consts::FRAC_PI_3);
    phase.is_finite().then_some(phase)
}

/// Grows the lattice from a seed near the domain's centre (placed by `rng`) around the `fixed`
/// boundary samples; where the front leaves a hole larger than a grid cell (the median long
/// semi-axis), a new front grows from the hole's centre; last, the seams are filled at
/// [`LatticeParams::fill_rho`]. `expected` (the estimated interior count) sizes the buffers.
/// Returns the interior positions.
#[must_use]
pub fn lattice_seeding(
    metric: &TensorField,
    fixed: &[DVec2],
    expected: usize,
    params: &LatticeParams,
    rng: &mut Rng,
) -> Vec<DVec2> {
    let mut packing = Packing {
        metric,
        rho: params.rho,
        fill_rho: params.fill_rho,
        grid: CellGrid::for_field(metric, fixed.len() + expected),
        positions: Vec::with_capacity(fixed.len() + expected + expected / 8),
        inverses: Vec::new(),
        near_miss: Vec::new(),
    };
    packing.inverses.reserve(packing.positions.capacity());
    packing.near_miss.reserve(packing.positions.capacity());
    for &p in fixed {
        packing.add(p, &metric.sample(p));
    }
    let domain = metric.domain();
    let centre = domain * DVec2::new(0.4 + 0.2 * rng.uniform(), 0.4 + 0.2 * rng.uniform());
    let mut seeds = vec![centre];
    // A hole that cannot take a seed stays empty; stop when a pass adds nothing.
    while !seeds.is_empty() {
        let before = packing.positions.len();
        for &s in &seeds {
            packing.grow_from(s, params.phase);
        }
        if packing.positions.len() == before {
            break;
        }
        seeds = packing.grid.empty_cells().collect();
    }
    // The seams and the holes too small for a front: the proposals that met a seam are made
    // again, accepted at the closer `fill_rho` (every other proposal landed on a taken lattice
    // point or outside, and would again: the same seeds as proposing all six, with 40 % of the
    // distance tests on the rotating 4:1 field).
    if params.fill_rho < packing.rho {
        packing.rho = params.fill_rho;
        let mut front: VecDeque<(usize, DVec2, Tensor, u8)> = (fixed.len()
            ..packing.positions.len())
            .filter(|&k| packing.near_miss[k] != 0)
            .map(|k| {
                let p = packing.positions[k];
                (k, p, metric.sample(p), packing.near_miss[k])
            })
            .collect();
        packing.grow(&mut front, params.phase);
    }
    packing.positions.split_off(fixed.len())
}

/// The unit direction of a metric's long axis (x̂ for a circle), without an angle.
fn long_axis_direction(m: &Tensor) -> DVec2 {
    let half_diff = 0.5 * (m.xx - m.yy);
    let radius = (half_diff * half_diff + m.xy * m.xy).sqrt();
    // (l1 − yy, xy) with l1 − yy = half_diff + radius, or (xy, l1 − xx) when that is tiny.
    let v = if half_diff >= 0.0 {
        DVec2::new(half_diff + radius, m.xy)
    } else {
        DVec2::new(m.xy, radius - half_diff)
    };
    v.try_normalize().unwrap_or(DVec2::X)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::distance::normalised_distance;

    #[test]
    fn wall_phase_lays_a_row_along_the_longer_wall() {
        for (angle, long, short, domain) in [
            (0.3, 6.0, 2.0, DVec2::new(800.0, 600.0)),
            (-1.1, 9.0, 1.8, DVec2::new(300.0, 900.0)),
            (2.0, 4.0, 4.0, DVec2::new(500.0, 500.0)),
        ] {
            let m = Tensor::from_eigen(angle, long, short);
            let phase = wall_phase(&m, domain).unwrap();
            assert!((0.0..std::f64::consts::FRAC_PI_3).contains(&phase));
            let inv = m.inverse().unwrap();
            let (x, y) = (inv.mul_vec(DVec2::X), inv.mul_vec(DVec2::Y));
            let wall = if x.length() * domain.x >= y.length() * domain.y {
                x
            } else {
                y
            };
            // The lattice's three row directions in the metric's own space, as the front
            // proposes them: one runs along the wall.
            let along = (0..3).any(|k| {
                let row = DVec2::from_angle(
                    m.eigen().angle + phase + f64::from(k) * std::f64::consts::FRAC_PI_3,
                );
                row.perp_dot(wall.normalize()).abs() < 1e-9
            });
            assert!(along, "{angle}: {phase}");
        }
    }

    #[test]
    fn long_axis_direction_matches_the_eigenvector() {
        for angle in [-1.5, -0.7, 0.0, 0.3, 1.2, 1.57] {
            let m = Tensor::from_eigen(angle, 5.0, 2.0);
            let d = long_axis_direction(&m);
            let e = DVec2::new(f64::cos(angle), f64::sin(angle));
            assert!(d.dot(e).abs() > 1.0 - 1e-12, "{angle}: {d}");
        }
        assert_eq!(long_axis_direction(&Tensor::isotropic(3.0)), DVec2::X);
    }

    #[test]
    fn constant_field_grows_the_hexagonal_packing() {
        let m = Tensor::from_eigen(0.5, 6.0, 2.0);
        let metric = TensorField::constant(300, 240, m);
        let estimate = 300.0 * 240.0 / (2.0 * 3f64.sqrt() * 12.0);
        let params = LatticeParams::default();
        let mut rng = Rng::new(3, 0);
        let pts = lattice_seeding(&metric, &[], 1000, &params, &mut rng);
        // A hexagonal packing has the estimated count, less the half-ellipses cut by the edges.
        let n = pts.len() as f64;
        assert!(
            n > 0.9 * estimate && n < 1.02 * estimate,
            "{n} vs {estimate}"
        );
        // Every sample's nearest neighbour is at d = 1 (touching), up to rounding.
        let inv = m.inverse().unwrap();
        for (i, &p) in pts.iter().enumerate().step_by(7) {
            let nearest = pts
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, &q)| normalised_distance(p, &inv, q, &inv))
                .fold(f64::INFINITY, f64::min);
            assert!((nearest - 1.0).abs() < 1e-6, "sample {i}: {nearest}");
        }
    }

    #[test]
    fn nothing_closer_than_rho_in_a_turning_field() {
        let metric = TensorField::from_fn(200, 150, |p| {
            Tensor::from_eigen(p.x / 50.0, 3.0 + p.y / 30.0, 2.0)
        });
        let estimate = crate::sampling::seeding::estimate_count(&metric);
        // The front alone (no fill): the seams where the bent lattice meets itself hold fewer
        // samples than the packing (this field turns by a radian every 50 px), but the front
        // reaches the whole domain.
        let front_only = LatticeParams {
            fill_rho: 1.0,
            ..LatticeParams::default()
        };
        let pts = lattice_seeding(&metric, &[], 1000, &front_only, &mut Rng::new(9, 0));
        let share = pts.len() as f64 / estimate;
        assert!(share > 0.7, "front: {share} of the estimate");
        crate::sampling::seeding::tests::assert_no_pair_closer(&metric, &pts, front_only.rho);
        // With the fill, the seams take samples down to its ρ and no closer.
        let params = LatticeParams::default();
        let filled = lattice_seeding(&metric, &[], 1000, &params, &mut Rng::new(9, 0));
        let filled_share = filled.len() as f64 / estimate;
        assert!(
            filled_share > share + 0.05 && filled_share < 1.05,
            "filled: {filled_share} of the estimate, front alone {share}"
        );
        assert_eq!(filled[..pts.len()], pts[..], "the fill only adds");
        crate::sampling::seeding::tests::assert_no_pair_closer(&metric, &filled, params.fill_rho);
    }
}
