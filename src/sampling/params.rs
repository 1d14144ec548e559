//! The sampler's parameters with the paper's values as defaults (section 5: Δt = 0.2,
//! γ = 0.5, relaxation dart throwing with ρ from 0.9 to 0.75 and ε = 0.01, fill-rate insertion
//! at 0.6, 100 iterations, repair every 8), the force scale and drag derived from a linearised
//! packing, and the checks a metric must pass before any work ([`validate_metric`]).

use super::cellgrid;
use super::force;
use super::lattice::LatticeParams;
use super::seeding::{self, DartParams};
use crate::error::{Error, Result};
use crate::field::TensorField;

/// Default limit on the estimated number of samples ([`SamplerParams::max_samples`]).
pub const DEFAULT_MAX_SAMPLES: usize = 20_000_000;

/// Every parameter of the sampler, with the paper's values as defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct SamplerParams {
    /// Maximum number of relaxation iterations (the paper: 100 suffice, never over 1000; a
    /// lattice seed runs [`LATTICE_ITERATIONS`] of them, see [`Self::schedule`]).
    pub iterations: usize,
    /// Seed of the random numbers (dart throwing, edge jitter).
    pub seed: u64,
    /// Repair the triangulation (and control the population) every this many iterations.
    pub repair_every: usize,
    /// Euler step Δt of eq. 5.
    pub time_step: f64,
    /// `ω·Δt`, where ω is the natural frequency of a particle among hexagonally packed
    /// neighbours; sets how strongly the force spline is scaled (see [`Self::force_scale`]).
    pub stiffness: f64,
    /// Damping ratio ζ of that oscillator; sets the drag `C_drag = 2ζω` (see [`Self::drag`]).
    pub damping_ratio: f64,
    /// No insertion or deletion in the last this many iterations, so the final packing is a
    /// relaxed one.
    pub settle_iterations: usize,
    /// Over the settling iterations the force scale falls linearly to this fraction of its
    /// value (measured: the largest final step drops from 2–7 % to 0.5–1.7 % of a particle's
    /// size, the quality figures stay the same).
    pub settle_force: f64,
    /// Insert a sample into triangles whose fill rate is at most this (paper: 0.6).
    pub insert_fill_rate: f64,
    /// Insert only where the three corners' mean pressure is at most this (0.03: about six
    /// neighbours at `d ≈ 0.97`): a gap among samples that are already pressed together is a
    /// packing defect, not missing area (see [`population`](super::population)).
    pub insert_max_pressure: f64,
    /// Delete samples whose pressure `Σ max(f(d), 0)` exceeds this.
    pub delete_pressure: f64,
    /// Stop when the largest step is below this fraction of the particle's size.
    pub tolerance: f64,
    /// Refuse fields whose estimated sample count exceeds this.
    pub max_samples: usize,
    /// How the interior is seeded.
    pub seeding: Seeding,
    /// Lattice seeding.
    pub lattice: LatticeParams,
    /// Relaxation dart throwing.
    pub darts: DartParams,
}

/// The share of [`SamplerParams::iterations`] a lattice seed runs (see
/// [`SamplerParams::schedule`]).
pub const LATTICE_ITERATIONS: f64 = 0.7;

/// The share of [`SamplerParams::settle_iterations`] a lattice seed settles over (see
/// [`SamplerParams::schedule`]).
pub const LATTICE_SETTLING: f64 = 0.6;

/// How one run relaxes ([`SamplerParams::schedule`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Schedule {
    /// Relaxation iterations at most.
    pub iterations: usize,
    /// Before the settling, the population is controlled (and the triangulation repaired)
    /// every this many iterations; 0 never.
    pub control_every: usize,
    /// While settling, the triangulation is repaired every this many iterations; 0 never.
    pub repair_every: usize,
    /// The last this many iterations settle: no insertion or deletion, the force easing off.
    pub settle_iterations: usize,
}

/// How the interior samples are seeded before the relaxation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Seeding {
    /// The lattice from [`LATTICE_FROM_COUNT`] estimated samples up (from
    /// [`LATTICE_FROM_COUNT_UNIFORM`] for a constant metric), darts below: the default.
    Auto,
    /// A metric-aligned hexagonal lattice grown as a front ([`lattice`](super::lattice)):
    /// tight, fast packings of smooth fields; around singular points its seams overlap more
    /// than darts do.
    Lattice,
    /// The paper's relaxation dart throwing ([`super::seeding`]).
    Darts,
}

/// [`Seeding::Auto`] seeds with the lattice from this many estimated samples up. The lattice's
/// defects are seams along which the bent lattice meets itself; their length is set by how much the
/// field turns, not by the count, so their share of the samples falls as the count grows, while
/// dart throwing's rejections grow with it. Measured (coverage / overlap after relaxation, darts
/// against lattice): `circular` at 670 samples 86.8 / 1.5 % against 86.5 / 1.9 %, at 4 000 samples
/// 87.1 / 0.85 % against 88.1 / 0.86 %, at 16 000 86.8 / 0.67 % against 87.1 / 0.47 %; the rotating
/// 4:1 field at 11 000 87.2 / 0.75 % against 87.1 / 0.62 %; a constant 2:1 field at 1 M 86.9 / 0.63
/// % in 32 s against 90.7 / 0.02 % in 9.4 s (all before the lattice's fill pass, which adds 0.2–0.8
/// % coverage on top, see [`LatticeParams::fill_rho`]). Photos at painting sizes (1.5–3 k samples)
/// come out the same either way (`benches/fidelity.sh`).
pub const LATTICE_FROM_COUNT: f64 = 2000.0;

/// [`Seeding::Auto`] seeds a constant metric with the lattice from this many estimated samples
/// up: the lattice is that field's hexagonal packing, and only the rows along the walls need
/// the relaxation. Below it the rows along the walls are a large share of the samples and
/// the lattice packs no better than darts (some fields overlap over 1 %); from it up it covers
/// about two points more.
pub const LATTICE_FROM_COUNT_UNIFORM: f64 = 1200.0;

impl Seeding {
    /// The names the preset key `sampler.seeding` takes.
    pub const NAMES: [&'static str; 3] = ["auto", "lattice", "darts"];

    /// The method's name in presets.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Seeding::Auto => "auto",
            Seeding::Lattice => "lattice",
            Seeding::Darts => "darts",
        }
    }

    /// The method called `name`.
    #[must_use]
    pub fn named(name: &str) -> Option<Self> {
        match name {
            "auto" => Some(Seeding::Auto),
            "lattice" => Some(Seeding::Lattice),
            "darts" => Some(Seeding::Darts),
            _ => None,
        }
    }
}

impl Default for SamplerParams {
    fn default() -> Self {
        SamplerParams {
            iterations: 100,
            seed: 0,
            repair_every: 8,
            time_step: 0.2,
            stiffness: 0.7,
            damping_ratio: 0.3,
            settle_iterations: 24,
            settle_force: 0.1,
            insert_fill_rate: 0.6,
            insert_max_pressure: 0.03,
            delete_pressure: 0.3,
            tolerance: 1e-3,
            max_samples: DEFAULT_MAX_SAMPLES,
            seeding: Seeding::Auto,
            lattice: LatticeParams::default(),
            darts: DartParams::default(),
        }
    }
}

impl SamplerParams {
    /// Natural frequency ω = `stiffness / Δt` of a particle among its neighbours.
    #[must_use]
    pub fn omega(&self) -> f64 {
        self.stiffness / self.time_step
    }

    /// Scale `S` of the force: a neighbour at `y` pushes with `S·f(d)·d_opt·ŷ`, `d_opt = |y|/d`,
    /// so forces, and steps, are proportional to the local spacing (paper 5.3). Linearised about
    /// `d = 1`, a particle among hexagonally packed neighbours feels the stiffness
    /// `k = S·|f'(1)|·Σ cos²θ = 3·S·|f'(1)|`; `S` is chosen so that `√k = ω`.
    ///
    /// How ω·Δt = 0.7 and ζ = 0.3 were chosen, by measurement on constant fields (1.5 k and
    /// 5.8 k samples, 100 iterations), the degenerate-point field and photos: the softer system
    /// of the first version (4x less stiff, critically damped) left the 5th percentile of
    /// nearest-neighbour distances at 0.84; ω·Δt = 0.6–0.8 with ζ = 0.15–0.3 reached 0.92 with
    /// coverage 0.875–0.88 and overlap under 1 %: a little inertia lets particles slip past each
    /// other into hexagonal order. Stronger damping (ζ = 0.7 or 1) packed as tightly but lost
    /// one to two points of coverage on constant fields. The drag is applied implicitly,
    /// `v ← (v + F·Δt)/(1 + C_drag·Δt)`, which is stable for any drag (the explicit
    /// `v·(1 − C_drag·Δt)` flips sign once `C_drag·Δt > 1`). The spline is about five times
    /// steeper at `d = 0.9` than at `d = 1`, so compressed pairs ring faster than ω; that jitter
    /// helps the packing order itself, and [`Self::settle_force`] calms it at the end.
    #[must_use]
    pub fn force_scale(&self) -> f64 {
        self.omega().powi(2) / (3.0 * force::SLOPE_AT_ONE.abs())
    }

    /// The relaxation's course for a run seeded by `seeding`: the iterations, repairs and
    /// settling as given for relaxation dart throwing (and `Auto`, which is resolved before).
    /// A lattice seed starts near its end, with about nine tenths of the final count, and
    /// what it lacks are the small holes of its seams: it runs [`LATTICE_ITERATIONS`] of the
    /// iterations, controls its population twice as often (each round fills the holes the
    /// last one's insertions have opened up), and settles over [`LATTICE_SETTLING`] of the
    /// settling iterations, repaired as often as ever there: it packs as tightly as the
    /// paper's course (`benches/packing.py`) in about four fifths of the time. Dart-thrown seeds
    /// keep the paper's course: on them (photos, small fields) the shorter one raises the
    /// overlap.
    #[must_use]
    pub fn schedule(&self, seeding: Seeding) -> Schedule {
        let given = Schedule {
            iterations: self.iterations,
            control_every: self.repair_every,
            repair_every: self.repair_every,
            settle_iterations: self.settle_iterations,
        };
        if seeding != Seeding::Lattice {
            return given;
        }
        let share = |n: usize, of: f64| (n as f64 * of).round() as usize;
        Schedule {
            iterations: share(self.iterations, LATTICE_ITERATIONS),
            control_every: self.repair_every.div_ceil(2),
            settle_iterations: share(self.settle_iterations, LATTICE_SETTLING),
            ..given
        }
    }

    /// Drag `C_drag = 2ζω` of eq. 5 (applied implicitly, see [`Self::force_scale`]).
    #[must_use]
    pub fn drag(&self) -> f64 {
        2.0 * self.damping_ratio * self.omega()
    }

    /// Checks the ranges the integration needs to be stable.
    pub fn validate(&self) -> Result<()> {
        let bad =
            |key: &str, why: &str| Err(Error::param(format!("sampler.{key}"), why.to_string()));
        if !(self.time_step > 0.0 && self.time_step.is_finite()) {
            return bad("time_step", "must be positive");
        }
        if !(self.stiffness > 0.0 && self.stiffness <= 1.0) {
            return bad(
                "stiffness",
                "ω·Δt must be in (0, 1] for a stable integration",
            );
        }
        if !(self.damping_ratio >= 0.0 && self.damping_ratio <= 2.0) {
            return bad("damping_ratio", "must be in [0, 2]");
        }
        if !(self.settle_force > 0.0 && self.settle_force <= 1.0) {
            return bad("settle_force", "must be in (0, 1]");
        }
        if !(0.0..=1.0).contains(&self.insert_fill_rate) {
            return bad("insert_fill_rate", "must be in [0, 1]");
        }
        if self.insert_max_pressure.is_nan() || self.insert_max_pressure < 0.0 {
            return bad("insert_max_pressure", "must be zero or positive");
        }
        if self.delete_pressure.is_nan() || self.delete_pressure <= 0.0 {
            return bad("delete_pressure", "must be positive");
        }
        if self.iterations > 100_000 {
            return bad("iterations", "at most 100000");
        }
        // Closer than half the contact distance, a lattice would pile samples on each other.
        for (key, rho) in [
            ("lattice.rho", self.lattice.rho),
            ("lattice.fill_rho", self.lattice.fill_rho),
        ] {
            if !(0.5..=1.0).contains(&rho) {
                return bad(key, "must be in [0.5, 1]");
            }
        }
        Ok(())
    }
}

/// Ellipses larger than this many domain diagonals are refused as nonsense.
const MAX_AXIS_IN_DIAGONALS: f64 = 100.0;

/// Checks that every tensor of `metric` is a usable metric and that the estimated count is
/// within `max_samples`; returns the survey (the estimate, the smallest radius).
pub fn validate_metric(metric: &TensorField, max_samples: usize) -> Result<seeding::Survey> {
    let limit = MAX_AXIS_IN_DIAGONALS * metric.diagonal();
    // A positive definite metric's long semi-axis is below its trace: the eigenvalue is
    // computed only when the trace is over the limit.
    let found = seeding::survey(metric, |t| {
        !t.is_finite()
            || !t.is_positive_definite()
            || (t.xx + t.yy > limit && cellgrid::long_semi_axis(&t) > limit)
    });
    if let Some((c, r)) = found.first_bad {
        let e = metric.node(c, r).eigen();
        let p = metric.node_position(c, r);
        return Err(Error::param(
            "metric",
            format!(
                "the ellipse at pixel ({:.0}, {:.0}) has semi-axes {:.3e} and {:.3e}: every \
                 semi-axis must be finite, positive and at most {MAX_AXIS_IN_DIAGONALS} domain diagonals",
                p.x - 0.5,
                p.y - 0.5,
                e.l1,
                e.l2
            ),
        ));
    }
    let estimate = found.estimate;
    if estimate.is_nan() || estimate > max_samples as f64 {
        return Err(Error::param(
            "metric",
            format!(
                "the field needs about {estimate:.0} samples, over the limit of {max_samples} \
                 (raise it with --max-samples, or use larger ellipses)"
            ),
        ));
    }
    Ok(found)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lattice_seed_runs_a_shorter_course_with_more_frequent_control() {
        let p = SamplerParams::default();
        let given = Schedule {
            iterations: 100,
            control_every: 8,
            repair_every: 8,
            settle_iterations: 24,
        };
        for seeding in [Seeding::Darts, Seeding::Auto] {
            assert_eq!(p.schedule(seeding), given);
        }
        let lattice = Schedule {
            iterations: 70,
            control_every: 4,
            repair_every: 8,
            settle_iterations: 14,
        };
        assert_eq!(p.schedule(Seeding::Lattice), lattice);
        // Given values are scaled (an odd cadence rounds up).
        let odd = SamplerParams {
            iterations: 300,
            repair_every: 5,
            ..p.clone()
        };
        assert_eq!(
            (
                odd.schedule(Seeding::Lattice).iterations,
                odd.schedule(Seeding::Lattice).control_every
            ),
            (210, 3)
        );
        let never = SamplerParams {
            repair_every: 0,
            ..p
        };
        assert_eq!(never.schedule(Seeding::Lattice).control_every, 0);
    }
}
