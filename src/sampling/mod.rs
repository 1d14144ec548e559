//! The anisotropic particle sampler (paper section 5): particles carrying the metric's
//! ellipses are seeded and pushed until the ellipses cover the domain densely, touch, and do
//! not overlap.
//!
//! Order of work in [`sample`]:
//! 1. [`boundary`]: fixed corner and edge samples;
//! 2. [`seeding`]: relaxation dart throwing for the interior, up to the estimated count;
//! 3. [`delaunay`]: the anisotropic Delaunay triangulation, whose one-rings are the only
//!    neighbours a particle feels;
//! 4. iterations of the force spline ([`force`]) with Euler integration of eq. 5 (Δt = 0.2,
//!    force scale and drag from a linearised packing, see [`SamplerParams::force_scale`]),
//!    the triangulation repaired every `k` iterations;
//! 5. [`population`] control at each repair but in the last (settling) iterations: insert into
//!    poorly filled triangles, delete overcrowded samples; while settling, the force scale
//!    eases off so the packing comes to rest;
//! 6. stop when the largest step is a tiny fraction of the local size, or after the maximum
//!    number of iterations.
//!
//! Conventions ([`distance`]): a sample's ellipse is `{p + m(p)·u : |u| = 1}`, its radius along
//! `u` is `1/|m⁻¹u|`, and `d = |y| / (r_a(ŷ) + r_b(ŷ))` (eq. 4), which the seeding and the
//! quality report use. The forces use the exact contact distance of the two ellipses instead
//! ([`distance::contact_distance`]): the same for equal metrics, but in a turning field eq. 4
//! lets the tips of neighbours cross at `d = 1`. Positions and tensors are `f64`.
//! The result is bit-identical for a seed at any rayon thread count: parallel loops write one
//! slot per particle and only `max` is reduced.

pub mod boundary;
pub mod delaunay;
pub mod distance;
pub mod force;
pub mod population;
pub mod quality;
pub mod report;
pub mod rng;
pub mod seeding;

pub use delaunay::{AnisotropicDelaunay, Edges};
pub use force::force_spline;
pub use population::fill_rate;
pub use quality::Quality;
pub use seeding::DartParams;

use crate::error::{Error, Result};
use crate::field::{Tensor, TensorField};
use crate::progress::{Observer, Stage};
use glam::DVec2;
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// Default limit on the estimated number of samples ([`SamplerParams::max_samples`]).
pub const DEFAULT_MAX_SAMPLES: usize = 20_000_000;

/// Every parameter of the sampler, with the paper's values as defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct SamplerParams {
    /// Maximum number of relaxation iterations (the paper: 100 suffice, never over 1000).
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
    /// packing defect, not missing area (see [`population`]).
    pub insert_max_pressure: f64,
    /// Delete samples whose pressure `Σ max(f(d), 0)` exceeds this.
    pub delete_pressure: f64,
    /// Stop when the largest step is below this fraction of the particle's size.
    pub tolerance: f64,
    /// Refuse fields whose estimated sample count exceeds this.
    pub max_samples: usize,
    /// Relaxation dart throwing.
    pub darts: DartParams,
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
        Ok(())
    }
}

/// Counts and timings of a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// The estimated count `∫ dA / (2√3 det m)`.
    pub estimated_count: f64,
    /// Fixed boundary samples.
    pub boundary: usize,
    /// Interior samples accepted by dart throwing.
    pub seeded: usize,
    /// ρ when dart throwing stopped.
    pub final_rho: f64,
    /// Samples inserted by population control.
    pub inserted: usize,
    /// Samples deleted by population control.
    pub deleted: usize,
    /// Lawson flips under the generalised criterion.
    pub flips: u64,
    /// Legalisations stopped by the flip cap.
    pub flip_cap_hits: u64,
    /// Full rebuilds of the triangulation (spade + flips).
    pub rebuilds: usize,
    /// Relaxation iterations done.
    pub iterations: usize,
    /// Largest step of the last iteration relative to the particle's size.
    pub last_step: f64,
    /// Time spent checking the field, placing boundary samples and throwing darts.
    pub seeding_time: Duration,
    /// Time spent on triangulation builds and repairs.
    pub triangulation_time: Duration,
    /// Time spent moving particles (forces, integration, metric look-ups).
    pub relaxation_time: Duration,
    /// Time spent on population control.
    pub population_time: Duration,
}

/// The result: samples (boundary ones first), their metrics and triangulation, and stats.
#[derive(Clone, Debug)]
pub struct Sampling {
    /// Sample positions in pixels.
    pub positions: Vec<DVec2>,
    /// The metric at each sample (semi-axes in pixels).
    pub metrics: Vec<Tensor>,
    /// The first `fixed` samples are the boundary's.
    pub fixed: usize,
    /// The anisotropic Delaunay triangulation of the final positions.
    pub mesh: AnisotropicDelaunay,
    /// Counts and timings.
    pub stats: Stats,
}

/// Ellipses larger than this many domain diagonals are refused as nonsense.
const MAX_AXIS_IN_DIAGONALS: f64 = 100.0;

/// Checks that every tensor of `metric` is a usable metric and that the estimated count is
/// within `max_samples`; returns the estimate.
pub fn validate_metric(metric: &TensorField, max_samples: usize) -> Result<f64> {
    let diag = metric.diagonal();
    let bad = metric.first_node_where(|t| {
        !t.is_finite()
            || !t.is_positive_definite()
            || seeding::long_semi_axis(&t) > MAX_AXIS_IN_DIAGONALS * diag
    });
    if let Some((c, r)) = bad {
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
    let estimate = seeding::estimate_count(metric);
    if estimate.is_nan() || estimate > max_samples as f64 {
        return Err(Error::param(
            "metric",
            format!(
                "the field needs about {estimate:.0} samples, over the limit of {max_samples} \
                 (raise it with --max-samples, or use larger ellipses)"
            ),
        ));
    }
    Ok(estimate)
}

/// The metric the sampler works on: the field box-averaged to a node spacing of about two
/// thirds of the smallest ellipse's mean radius. The metric is smooth at that scale (photo
/// metrics are smoothed with a σ of their ellipses' radius), and a field of a few megabytes
/// instead of tens keeps the per-particle look-ups in cache: on a 1024² field they were half
/// of the run.
fn sampling_field(field: &TensorField) -> TensorField {
    let smallest = field
        .data()
        .par_iter()
        .map(|&c| Tensor::from_f32(c).det().sqrt())
        .reduce(|| f64::INFINITY, f64::min);
    let factor = (smallest / (1.5 * field.spacing())).floor();
    let factor = if factor.is_finite() {
        factor.clamp(1.0, 64.0) as usize
    } else {
        1
    };
    field.coarsened(factor)
}

/// Particle state during relaxation, structure-of-arrays, boundary samples first.
struct Particles {
    positions: Vec<DVec2>,
    metrics: Vec<Tensor>,
    inverses: Vec<Tensor>,
    velocities: Vec<DVec2>,
    /// Force of each triangulation edge on its first vertex (reused).
    edge_forces: Vec<DVec2>,
    /// Where each particle's metric was last looked up.
    looked_up: Vec<DVec2>,
    /// Where each particle was when the triangulation was last made Delaunay (NaN: never).
    meshed_at: Vec<DVec2>,
    fixed: usize,
}

impl Particles {
    fn new(positions: Vec<DVec2>, fixed: usize, field: &TensorField) -> Self {
        let metrics: Vec<Tensor> = positions.par_iter().map(|&p| field.sample(p)).collect();
        let inverses = metrics
            .par_iter()
            .map(|m| m.inverse().unwrap_or_default())
            .collect();
        let velocities = vec![DVec2::ZERO; positions.len()];
        Particles {
            looked_up: positions.clone(),
            meshed_at: vec![DVec2::NAN; positions.len()],
            positions,
            metrics,
            inverses,
            velocities,
            edge_forces: Vec::new(),
            fixed,
        }
    }

    fn push(&mut self, p: DVec2, field: &TensorField) {
        let m = field.sample(p);
        self.positions.push(p);
        self.looked_up.push(p);
        self.meshed_at.push(DVec2::NAN);
        self.metrics.push(m);
        self.inverses.push(m.inverse().unwrap_or_default());
        self.velocities.push(DVec2::ZERO);
    }

    /// Puts the free particles in Morton (Z-curve) order of their positions, so that loops
    /// over particles, their neighbours and the field read memory mostly in order. Ties keep
    /// the current order, so the result is deterministic.
    /// Returns `new_index`: the new position of every old index.
    fn sort_spatially(&mut self, domain: DVec2) -> Vec<u32> {
        let mut keyed: Vec<(u32, u32)> = (self.fixed..self.positions.len())
            .map(|i| (seeding::morton_key(self.positions[i], domain), i as u32))
            .collect();
        keyed.sort_unstable();
        let order: Vec<u32> = (0..self.fixed as u32)
            .chain(keyed.iter().map(|&(_, i)| i))
            .collect();
        self.keep_in_order(&order);
        let mut new_index = vec![0u32; order.len()];
        for (new, &old) in order.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        new_index
    }

    /// Removes the samples at the sorted indices `gone` (none of them fixed), keeping order.
    fn remove(&mut self, gone: &[u32]) {
        if gone.is_empty() {
            return;
        }
        let mut k = 0;
        let kept: Vec<u32> = (0..self.positions.len() as u32)
            .filter(|&i| {
                let drop = gone.get(k) == Some(&i);
                k += usize::from(drop);
                !drop
            })
            .collect();
        self.keep_in_order(&kept);
    }

    /// Keeps the particles `order` lists, in that order, in every per-particle array.
    fn keep_in_order(&mut self, order: &[u32]) {
        fn gather<T: Copy>(v: &mut Vec<T>, order: &[u32]) {
            *v = order.iter().map(|&i| v[i as usize]).collect();
        }
        gather(&mut self.positions, order);
        gather(&mut self.velocities, order);
        gather(&mut self.looked_up, order);
        gather(&mut self.meshed_at, order);
        gather(&mut self.metrics, order);
        gather(&mut self.inverses, order);
    }
}

/// Runs the whole sampler on `field` (a metric). Fails before any work when the metric has
/// unusable ellipses or needs more than `params.max_samples` samples.
pub fn sample(full_field: &TensorField, params: &SamplerParams) -> Result<Sampling> {
    sample_observed(full_field, params, &crate::progress::Silent)
}

/// [`sample`], reporting the seeding and each relaxation iteration to `observer`.
pub fn sample_observed(
    full_field: &TensorField,
    params: &SamplerParams,
    observer: &dyn Observer,
) -> Result<Sampling> {
    params.validate()?;
    let start = Instant::now();
    let estimate = validate_metric(full_field, params.max_samples)?;
    observer.begin(Stage::Seeding, None);
    let coarse = sampling_field(full_field);
    let field = &coarse;
    let mut stats = Stats {
        estimated_count: estimate,
        ..Stats::default()
    };
    let mut rng = rng::Rng::new(params.seed, 0);
    let fixed = boundary::boundary_samples(field, &mut rng);
    let target = (estimate - fixed.len() as f64).round().max(0.0) as usize;
    let (interior, rho) =
        seeding::relaxation_dart_throwing(field, &fixed, target, &params.darts, &mut rng);
    stats.boundary = fixed.len();
    stats.seeded = interior.len();
    stats.final_rho = rho;
    stats.seeding_time = start.elapsed();
    observer.end(Stage::Seeding, stats.seeding_time, None);
    let relaxation_start = Instant::now();
    observer.begin(Stage::Relaxation, Some(params.iterations as u64));

    let nfixed = fixed.len();
    let mut all = fixed;
    all.extend(interior);
    let mut particles = Particles::new(all, nfixed, field);
    let mut mesh = rebuild(&mut particles, field, &mut stats);
    let mut edges = mesh.edges(particles.positions.len());
    let dynamics = Dynamics {
        dt: params.time_step,
        scale: params.force_scale(),
        drag: params.drag(),
    };

    // How far some particle has moved since the last repair, in its own size.
    let mut drift = 0.0;
    for it in 0..params.iterations {
        if it > 0 && params.repair_every > 0 && it % params.repair_every == 0 {
            let settling = it + params.settle_iterations > params.iterations;
            mesh = if settling {
                repair(mesh, &mut particles, field, &mut stats)
            } else {
                // Population control reads fill rates and one-rings of the current mesh,
                // which must still be a valid triangulation of the moved particles.
                if !mesh.is_valid_at(&particles.positions) {
                    mesh = rebuild(&mut particles, field, &mut stats);
                }
                control_population(mesh, &mut particles, field, params, &mut stats)
            };
            edges = mesh.edges(particles.positions.len());
        } else if drift > REPAIR_DRIFT {
            mesh = repair(mesh, &mut particles, field, &mut stats);
            edges = mesh.edges(particles.positions.len());
        }
        let t = Instant::now();
        // Over the settling iterations the force scale falls linearly to `settle_force`
        // of its value: the high-frequency ringing of compressed pairs dies out and the
        // packing comes to rest.
        let settle = params.settle_iterations.max(1) as f64;
        let into = ((it + params.settle_iterations) as f64 - params.iterations as f64) / settle;
        let cooling = 1.0 - (1.0 - params.settle_force) * into.clamp(0.0, 1.0);
        let dynamics_now = Dynamics {
            scale: dynamics.scale * cooling,
            ..dynamics
        };
        let step;
        (step, drift) = relax_once(&mut particles, &edges, field, &dynamics_now);
        stats.relaxation_time += t.elapsed();
        stats.iterations = it + 1;
        observer.advance(Stage::Relaxation, stats.iterations as u64);
        stats.last_step = step;
        if step < params.tolerance {
            break;
        }
    }
    // The final triangulation is checked everywhere, not only where particles moved.
    particles.meshed_at.fill(DVec2::NAN);
    mesh = repair(mesh, &mut particles, field, &mut stats);
    // Report every sample with the metric of the field as given.
    let metrics = particles
        .positions
        .par_iter()
        .map(|&p| full_field.sample(p))
        .collect();
    observer.end(
        Stage::Relaxation,
        relaxation_start.elapsed(),
        Some(stats.iterations as u64),
    );
    Ok(Sampling {
        positions: particles.positions,
        metrics,
        fixed: nfixed,
        mesh,
        stats,
    })
}

/// A fresh anisotropic triangulation of the particles; samples spade merged as duplicates
/// are deleted (they cannot take part).
fn rebuild(
    particles: &mut Particles,
    field: &TensorField,
    stats: &mut Stats,
) -> AnisotropicDelaunay {
    let t = Instant::now();
    particles.sort_spatially(field.domain());
    let (mut mesh, missing) = AnisotropicDelaunay::build(&particles.positions, field);
    if !missing.is_empty() {
        particles.remove(&missing);
        stats.deleted += missing.len();
        (mesh, _) = AnisotropicDelaunay::build(&particles.positions, field);
    }
    particles.meshed_at.clone_from(&particles.positions);
    take_flip_counts(&mut mesh, stats);
    stats.rebuilds += 1;
    stats.triangulation_time += t.elapsed();
    mesh
}

/// Moves the mesh's flip and cap-hit counts into the run's stats.
fn take_flip_counts(mesh: &mut AnisotropicDelaunay, stats: &mut Stats) {
    stats.flips += std::mem::take(&mut mesh.flips);
    stats.flip_cap_hits += std::mem::take(&mut mesh.cap_hits);
}

/// Brings the triangulation up to date with moved particles: Lawson flips when every
/// triangle is still counter-clockwise, a rebuild otherwise.
fn repair(
    mut mesh: AnisotropicDelaunay,
    particles: &mut Particles,
    field: &TensorField,
    stats: &mut Stats,
) -> AnisotropicDelaunay {
    if !mesh.is_valid_at(&particles.positions) {
        return rebuild(particles, field, stats);
    }
    let t = Instant::now();
    // Only quads with a particle that moved noticeably since the last repair are checked.
    let moved: Vec<bool> = particles
        .positions
        .iter()
        .zip(&particles.meshed_at)
        .zip(&particles.metrics)
        .map(|((p, at), m)| {
            // A NaN position (never meshed) counts as moved.
            let moved = (*p - *at).length_squared();
            moved.is_nan() || moved > MESH_REFRESH * MESH_REFRESH * m.det()
        })
        .collect();
    mesh.legalize_around(&particles.positions, field, Some(&moved));
    particles.meshed_at.clone_from(&particles.positions);
    take_flip_counts(&mut mesh, stats);
    stats.triangulation_time += t.elapsed();
    mesh
}

/// Inserts into poorly filled triangles and deletes overcrowded samples, and returns the
/// triangulation of the new population: insertions split their triangle in place (then
/// Lawson flips), deletions need a new triangulation.
fn control_population(
    mut mesh: AnisotropicDelaunay,
    particles: &mut Particles,
    field: &TensorField,
    params: &SamplerParams,
    stats: &mut Stats,
) -> AnisotropicDelaunay {
    let t = Instant::now();
    let edges = mesh.edges(particles.positions.len());
    let pressure = population::pressures(&particles.positions, &particles.metrics, &edges);
    let gone = population::deletions(&pressure, particles.fixed, &edges, params.delete_pressure);
    let new = population::insertion_points(
        &mesh,
        &particles.positions,
        &particles.inverses,
        field,
        &population::InsertionRule {
            fill_rate: params.insert_fill_rate,
            max_pressure: params.insert_max_pressure,
            pressure: &pressure,
        },
    );
    stats.deleted += gone.len();
    stats.inserted += new.len();
    for &(triangle, p) in &new {
        mesh.split_triangle(triangle, particles.positions.len() as u32);
        particles.push(p, field);
    }
    stats.population_time += t.elapsed();
    if !gone.is_empty() {
        particles.remove(&gone);
        return rebuild(particles, field, stats);
    }
    if new.is_empty() {
        return repair(mesh, particles, field, stats);
    }
    // Keep memory in spatial order for the next iterations, then restore the criterion.
    let new_index = particles.sort_spatially(field.domain());
    mesh.renumber(&new_index);
    repair(mesh, particles, field, stats)
}

/// Constants of the integration.
#[derive(Clone, Copy)]
struct Dynamics {
    dt: f64,
    scale: f64,
    drag: f64,
}

/// One Euler step of eq. 5 for every free particle: `v ← (v + Δt·F)/(1 + Δt·C_drag)`,
/// `p ← p + Δt·v`,
/// a step never longer than a third of the particle's size `√det m`, positions kept inside the
/// domain. Returns the largest step and the largest distance from where the particle was at the
/// last repair (its drift), both relative to that size.
///
/// The pair force is computed once per triangulation edge (in parallel, one slot per edge),
/// then each particle gathers its edges' forces in a fixed order: no pair is computed twice,
/// nothing is reduced in an order that depends on threads, so the result is the same at any
/// thread count. All edge forces are computed before any particle moves, so positions and
/// metrics are then updated in place.
fn relax_once(
    particles: &mut Particles,
    edges: &Edges,
    field: &TensorField,
    dyn_: &Dynamics,
) -> (f64, f64) {
    let fixed = particles.fixed;
    let domain = field.domain();
    let Particles {
        positions,
        metrics,
        inverses,
        velocities,
        edge_forces,
        looked_up,
        meshed_at,
        ..
    } = particles;
    let (positions_now, metrics_now): (&[DVec2], &[Tensor]) = (positions, metrics);
    edge_forces.resize(edges.ends.len(), DVec2::ZERO);
    edge_forces
        .par_iter_mut()
        .zip(edges.ends.par_iter())
        .for_each(|(f, &[a, b])| {
            let (pa, pb) = (positions_now[a as usize], positions_now[b as usize]);
            let d = distance::contact_distance(
                pa,
                &metrics_now[a as usize],
                pb,
                &metrics_now[b as usize],
            );
            // Force on a: S·f(d)·ŷ·d_opt with ŷ·d_opt = (y/|y|)·(|y|/d) = y/d.
            *f = if d > 0.0 {
                (pa - pb) * (dyn_.scale * force_spline(d) / d)
            } else {
                DVec2::ZERO
            };
        });
    let edge_forces: &[DVec2] = edge_forces;
    // One pass per particle: gather the edge forces, integrate, and look the metric up again
    // when the particle has moved more than a small fraction of its size since the last
    // look-up (the field is smooth at the scale of an ellipse). Only the particle's own slots
    // are written.
    let largest = positions[fixed..]
        .par_iter_mut()
        .zip(velocities[fixed..].par_iter_mut())
        .zip(
            metrics[fixed..]
                .par_iter_mut()
                .zip(inverses[fixed..].par_iter_mut()),
        )
        .zip(looked_up[fixed..].par_iter_mut())
        .zip(meshed_at[fixed..].par_iter())
        .enumerate()
        .map(|(k, ((((pos, v), (m, inv)), at), meshed))| {
            let i = fixed + k;
            let p = *pos;
            let mut force = DVec2::ZERO;
            for (e, first, _) in edges.at(i) {
                force += if first {
                    edge_forces[e]
                } else {
                    -edge_forces[e]
                };
            }
            // Drag taken implicitly: stable for any C_drag·Δt, unlike v·(1 − C_drag·Δt).
            *v = (*v + force * dyn_.dt) / (1.0 + dyn_.drag * dyn_.dt);
            let size = m.det().sqrt();
            let mut step = *v * dyn_.dt;
            let cap = size / 3.0;
            if step.length() > cap {
                step *= cap / step.length();
            }
            let margin = 1e-6 * size.max(1e-3);
            *pos = (p + step).clamp(DVec2::splat(margin), domain - DVec2::splat(margin));
            if (*pos - *at).length_squared() > METRIC_REFRESH * METRIC_REFRESH * size * size {
                *m = field.sample(*pos);
                *inv = m.inverse().unwrap_or_default();
                *at = *pos;
            }
            let size = size.max(1e-12);
            // A NaN `meshed` (never meshed) gives NaN, which `max` ignores.
            ((*pos - p).length() / size, (*pos - *meshed).length() / size)
        })
        .reduce(|| (0.0, 0.0), |a, b| (a.0.max(b.0), a.1.max(b.1)));
    largest
}

/// Between the regular repairs, the triangulation is repaired as soon as some particle has
/// moved this many of its sizes since the last one. Early on, when the seed's particles still travel far, eight
/// iterations can invert triangles, and an inverted mesh must be rebuilt from scratch: on a
/// photo's metric with 8 k samples, four rebuilds of the first 32 iterations (12 ms each) became
/// about sixteen extra repairs (2 ms each), and the flips halved.
const REPAIR_DRIFT: f64 = 1.5;

/// A quad is checked again at a repair once one of its particles has moved this fraction of
/// its size since the previous repair.
const MESH_REFRESH: f64 = 0.02;

/// A particle's metric is looked up again once it has moved this fraction of its size.
const METRIC_REFRESH: f64 = 0.05;
