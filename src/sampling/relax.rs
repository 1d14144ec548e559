//! One relaxation step and the triangulation's upkeep (paper sections 5.3-5.5): the force
//! spline summed over each particle's anisotropic Delaunay edges and integrated by Euler steps
//! of eq. 5 ([`relax_once`]); Lawson repairs and rebuilds of the triangulation as particles
//! move ([`repair`], [`rebuild`]); population control at the repairs ([`control_population`]:
//! fill-rate insertion, pressure deletion).

use super::delaunay::AnisotropicDelaunay;
use super::edges::Edges;
use super::params::SamplerParams;
use super::particles::Particles;
use super::{distance, force_spline, population, Stats};
use crate::field::{Tensor, TensorField};
use glam::DVec2;
use rayon::prelude::*;
use std::time::Instant;

/// A fresh anisotropic triangulation of the particles; samples spade merged as duplicates
/// are deleted (they cannot take part).
pub(super) fn rebuild(
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
pub(super) fn repair(
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
pub(super) fn control_population(
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
pub(super) struct Dynamics {
    pub(super) dt: f64,
    pub(super) scale: f64,
    pub(super) drag: f64,
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
pub(super) fn relax_once(
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
pub(super) const REPAIR_DRIFT: f64 = 1.5;

/// A quad is checked again at a repair once one of its particles has moved this fraction of
/// its size since the previous repair.
const MESH_REFRESH: f64 = 0.02;

/// A particle's metric is looked up again once it has moved this fraction of its size.
const METRIC_REFRESH: f64 = 0.05;
