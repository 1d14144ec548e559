//! The anisotropic particle sampler (paper section 5): particles carrying the metric's
//! ellipses are seeded and pushed until the ellipses cover the domain densely, touch, and do
//! not overlap.
//!
//! Order of work in [`sample`]:
//! 1. [`boundary`]: fixed corner and edge samples;
//! 2. the interior's seed: a metric-aligned hexagonal lattice grown as a front ([`lattice`]),
//!    by default from [`params::LATTICE_FROM_COUNT`] estimated samples up (from
//!    [`params::LATTICE_FROM_COUNT_UNIFORM`] for a constant metric), or the paper's
//!    relaxation dart throwing up to the estimated count ([`seeding`]), both testing their
//!    candidates exactly in the [`cellgrid`];
//! 3. [`delaunay`]: the anisotropic Delaunay triangulation, whose one-rings are the only
//!    neighbours a particle feels;
//! 4. iterations of the force spline ([`force`]) with Euler integration of eq. 5 (Δt = 0.2,
//!    force scale and drag from a linearised packing, see [`SamplerParams::force_scale`]),
//!    the triangulation repaired every `k` iterations; particles at rest sleep until a
//!    neighbour moves;
//! 5. [`population`] control at each repair but in the last (settling) iterations: insert into
//!    poorly filled triangles (splitting them), delete overcrowded samples (filling their
//!    holes, `removal.rs`); while settling, the force scale eases off so the packing comes to
//!    rest. A lattice seed, which starts near its end, runs a shorter course with more
//!    frequent control ([`SamplerParams::schedule`]);
//! 6. stop when the largest step is a tiny fraction of the local size, or after the maximum
//!    number of iterations.
//!
//! Conventions ([`distance`]): a sample's ellipse is `{p + m(p)·u : |u| = 1}`, its radius along
//! `u` is `1/|m⁻¹u|`, and `d = |y| / (r_a(ŷ) + r_b(ŷ))` (eq. 4), which the seeding and the
//! quality report use. The forces use a contact distance of the two ellipses instead
//! ([`distance::contact_distance`], Perram–Wertheim's contact function at `λ = ½` plus one
//! Newton step: a lower bound of the exact contact distance, within 0.1 % of it for
//! neighbour-like pairs): the same as eq. 4 for equal metrics, but in a turning field eq. 4
//! lets the tips of neighbours cross at `d = 1`. Positions and tensors are `f64`.
//! The result is bit-identical for a seed at any rayon thread count: parallel loops write one
//! slot per particle and only `max` is reduced.

pub mod boundary;
pub mod cellgrid;
pub mod delaunay;
pub mod distance;
pub mod force;
pub mod lattice;
pub mod params;
mod particles;
pub mod population;
pub mod quality;
mod relax;
pub mod report;
pub mod rng;
pub mod seeding;

pub use delaunay::edges::Edges;
pub use delaunay::AnisotropicDelaunay;
pub use force::force_spline;
pub use params::{validate_metric, SamplerParams, Schedule, Seeding, DEFAULT_MAX_SAMPLES};
pub use population::fill_rate;
pub use quality::Quality;
pub use seeding::DartParams;

use crate::error::Result;
use crate::field::{Tensor, TensorField};
use crate::progress::{Observer, Stage};
use glam::DVec2;
use particles::Particles;
use rayon::prelude::*;
use relax::{
    control_population, rebuild, relax_once, repair, undo_turnovers, Dynamics, REPAIR_DRIFT,
};
use seeding::Survey;
use std::time::{Duration, Instant};

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

/// The metric the sampler works on: the field box-averaged to a node spacing of about two
/// thirds of the smallest ellipse's mean radius (`survey.smallest_radius`). The metric is
/// smooth at that scale (photo metrics are smoothed with a σ of their ellipses' radius), and a
/// field of a few megabytes instead of tens keeps the per-particle look-ups in cache: on a
/// 1024² field they were half of the run. A uniform field is the same at any spacing (each
/// block's mean is its nodes' one value, exactly); one larger than the cache
/// ([`UNIFORM_COARSENING_FROM`] nodes) is averaged over the largest blocks (a constant field of
/// 4096², 200 MB, becomes 64² nodes with the same samples). Smaller ones keep their grid, which
/// the darts' density sampler draws its cells from.
/// A field that needs no coarsening is borrowed, not copied (a 4096² field is 200 MB).
fn sampling_field<'a>(
    field: &'a TensorField,
    survey: &Survey,
) -> std::borrow::Cow<'a, TensorField> {
    let factor = (survey.smallest_radius / (1.5 * field.spacing())).floor();
    let nodes = field.cols() * field.rows();
    let factor = if survey.uniform && nodes > UNIFORM_COARSENING_FROM {
        MAX_COARSENING
    } else if factor.is_finite() {
        factor.clamp(1.0, MAX_COARSENING as f64) as usize
    } else {
        1
    };
    if factor == 1 {
        std::borrow::Cow::Borrowed(field)
    } else {
        std::borrow::Cow::Owned(field.coarsened(factor))
    }
}

/// The largest block of nodes, per side, [`sampling_field`] averages.
const MAX_COARSENING: usize = 64;

/// Nodes (of three `f32`) over which [`sampling_field`] coarsens a uniform field to the
/// largest blocks: 2¹⁸ nodes are 3 MB, about what the look-ups keep in cache.
const UNIFORM_COARSENING_FROM: usize = 1 << 18;

/// Replaces `edges` with `mesh`'s, dropping the old ones first: at a million samples each set
/// is tens of megabytes.
fn renew_edges(edges: &mut Edges, mesh: &AnisotropicDelaunay, vertices: usize) {
    drop(std::mem::take(edges));
    *edges = mesh.edges(vertices);
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
    let survey = validate_metric(full_field, params.max_samples)?;
    let estimate = survey.estimate;
    observer.begin(Stage::Seeding, None);
    let coarse = sampling_field(full_field, &survey);
    let field: &TensorField = &coarse;
    let mut stats = Stats {
        estimated_count: estimate,
        ..Stats::default()
    };
    let mut rng = rng::Rng::new(params.seed, 0);
    let fixed = boundary::boundary_samples(field, &mut rng);
    let target = (estimate - fixed.len() as f64).round().max(0.0) as usize;
    let seeding = seeding_for(params.seeding, &survey);
    let (interior, rho) = seed_interior(field, &fixed, target, seeding, &survey, params, &mut rng);
    stats.boundary = fixed.len();
    stats.seeded = interior.len();
    stats.final_rho = rho;
    stats.seeding_time = start.elapsed();
    observer.end(Stage::Seeding, stats.seeding_time, None);
    let relaxation_start = Instant::now();
    let schedule = params.schedule(seeding);
    observer.begin(Stage::Relaxation, Some(schedule.iterations as u64));

    let nfixed = fixed.len();
    let mut all = fixed;
    all.extend(interior);
    let mut particles = Particles::new(all, nfixed, field);
    let mut mesh = rebuild(&mut particles, field, &mut stats);
    let mut edges = mesh.edges(particles.positions.len());
    // The edges changed since the edge forces were computed.
    let mut fresh = true;
    let dynamics = Dynamics {
        dt: params.time_step,
        scale: params.force_scale(),
        drag: params.drag(),
    };

    // How far some particle has moved since the last repair, in its own size.
    let mut drift = 0.0;
    for it in 0..schedule.iterations {
        let settling = it + schedule.settle_iterations > schedule.iterations;
        let every = if settling {
            schedule.repair_every
        } else {
            schedule.control_every
        };
        let due = it > 0 && every > 0 && it % every == 0;
        if due || drift > REPAIR_DRIFT {
            let control = due && !settling;
            let state = (&mut particles, &mut edges, &mut stats);
            mesh = maintained(mesh, state, field, params, control);
            fresh = true;
        }
        let t = Instant::now();
        let dynamics_now = cooled(dynamics, &schedule, params.settle_force, it);
        let step;
        (step, drift) = relax_once(&mut particles, &edges, field, &dynamics_now, fresh);
        fresh = false;
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

/// `mesh` made right again for the moved particles, and `edges` renewed from it: with
/// `control`, the population controlled (on a mesh that must still triangulate the moved
/// particles: turned triangles taken back, else rebuilt, since fill rates and one-rings are
/// read from it); otherwise repaired where particles moved.
fn maintained(
    mesh: AnisotropicDelaunay,
    (particles, edges, stats): (&mut Particles, &mut Edges, &mut Stats),
    field: &TensorField,
    params: &SamplerParams,
    control: bool,
) -> AnisotropicDelaunay {
    let mesh = if control {
        let mut mesh = mesh;
        if !mesh.is_valid_at(&particles.positions) && !undo_turnovers(&mesh, particles) {
            mesh = rebuild(particles, field, stats);
            renew_edges(edges, &mesh, particles.positions.len());
        }
        // `edges` are the current mesh's: the relaxation moves particles, not edges.
        control_population(mesh, edges, particles, field, params, stats)
    } else {
        repair(mesh, particles, field, stats)
    };
    renew_edges(edges, &mesh, particles.positions.len());
    mesh
}

/// The seeding `chosen` resolves to for a metric of `survey`: `Auto` takes the lattice for
/// large fields (and smaller constant ones, whose lattice is their packing), darts below.
fn seeding_for(chosen: Seeding, survey: &seeding::Survey) -> Seeding {
    let estimate = survey.estimate;
    match chosen {
        Seeding::Auto
            if estimate >= params::LATTICE_FROM_COUNT
                || (survey.uniform && estimate >= params::LATTICE_FROM_COUNT_UNIFORM) =>
        {
            Seeding::Lattice
        }
        Seeding::Auto => Seeding::Darts,
        chosen => chosen,
    }
}

/// About `target` interior samples seeded by `seeding` among the `fixed` boundary samples, and
/// the closest a seed sample may be to another (ρ).
fn seed_interior(
    field: &TensorField,
    fixed: &[DVec2],
    target: usize,
    seeding: Seeding,
    survey: &seeding::Survey,
    params: &SamplerParams,
    rng: &mut rng::Rng,
) -> (Vec<DVec2>, f64) {
    match seeding {
        Seeding::Darts | Seeding::Auto => {
            seeding::relaxation_dart_throwing(field, fixed, target, &params.darts, rng)
        }
        Seeding::Lattice => {
            // A constant metric's lattice lies along the walls (see `lattice::wall_phase`).
            let wall = survey
                .uniform
                .then(|| lattice::wall_phase(&field.node(0, 0), field.domain()))
                .flatten();
            let lattice = lattice::LatticeParams {
                phase: wall.unwrap_or(params.lattice.phase),
                ..params.lattice.clone()
            };
            let interior = lattice::lattice_seeding(field, fixed, target, &lattice, rng);
            // The closest a seed sample may be: the fill's ρ when it ran.
            (interior, params.lattice.rho.min(params.lattice.fill_rho))
        }
    }
}

/// `dynamics` at iteration `it` of `schedule`: over the settling iterations the force scale
/// falls linearly to `settle_force` of its value, so the high-frequency ringing of compressed
/// pairs dies out and the packing comes to rest.
fn cooled(dynamics: Dynamics, schedule: &Schedule, settle_force: f64, it: usize) -> Dynamics {
    let settle = schedule.settle_iterations.max(1) as f64;
    let into = ((it + schedule.settle_iterations) as f64 - schedule.iterations as f64) / settle;
    let cooling = 1.0 - (1.0 - settle_force) * into.clamp(0.0, 1.0);
    Dynamics {
        scale: dynamics.scale * cooling,
        ..dynamics
    }
}
