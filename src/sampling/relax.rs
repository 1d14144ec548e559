//! One relaxation step and the triangulation's upkeep (paper sections 5.3-5.5): the force
//! spline summed over each particle's anisotropic Delaunay edges and integrated by Euler steps
//! of eq. 5 ([`relax_once`], where particles at rest sleep); Lawson repairs and rebuilds of
//! the triangulation as particles move ([`repair`], [`rebuild`]; moves that turned a triangle
//! over are taken back first, [`undo_turnovers`]); population control at the repairs
//! ([`control_population`]: fill-rate insertion, pressure deletion).

use super::delaunay::edges::Edges;
use super::delaunay::AnisotropicDelaunay;
use super::params::SamplerParams;
use super::particles::{Particles, AWAKE, MOVED, QUIET, SLEEP, STIRRED};
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

/// Takes back the motion since the triangulation was last made Delaunay (where it was valid)
/// of the corners of every triangle the particles' motion turned over, round after round as
/// neighbours' triangles turn back too (at most [`UNDO_ROUNDS`]); whether the mesh is then
/// valid. Smooth fields rarely turn a triangle over (one build in a run on the rotating 4:1
/// field, one to three on photos); a field whose orientation has singular points at full
/// anisotropy (ellipses along a random vector field's direction) keeps doing it near them, and
/// taking the motion back spares a rebuild of the whole triangulation each time.
pub(super) fn undo_turnovers(mesh: &AnisotropicDelaunay, particles: &mut Particles) -> bool {
    for _ in 0..UNDO_ROUNDS {
        let turned = mesh.turned_over_at(&particles.positions);
        if turned.is_empty() {
            return true;
        }
        for v in turned.into_iter().flatten() {
            let v = v as usize;
            let back = particles.meshed_at[v];
            // Never meshed (inserted since): nowhere to go back to.
            if !back.is_finite() {
                return false;
            }
            particles.positions[v] = back;
            particles.velocities[v] = DVec2::ZERO;
            particles.motion[v] |= AWAKE | MOVED;
        }
    }
    mesh.is_valid_at(&particles.positions)
}

/// Rounds of [`undo_turnovers`] before a rebuild.
const UNDO_ROUNDS: usize = 8;

/// Moves the mesh's flip and cap-hit counts into the run's stats.
fn take_flip_counts(mesh: &mut AnisotropicDelaunay, stats: &mut Stats) {
    stats.flips += std::mem::take(&mut mesh.flips);
    stats.flip_cap_hits += std::mem::take(&mut mesh.cap_hits);
}

/// Brings the triangulation up to date with moved particles: Lawson flips when every
/// triangle is still counter-clockwise (or is again once [`undo_turnovers`] took back the
/// moves that turned some over), a rebuild otherwise.
pub(super) fn repair(
    mut mesh: AnisotropicDelaunay,
    particles: &mut Particles,
    field: &TensorField,
    stats: &mut Stats,
) -> AnisotropicDelaunay {
    if !mesh.is_valid_at(&particles.positions) && !undo_turnovers(&mesh, particles) {
        return rebuild(particles, field, stats);
    }
    let t = Instant::now();
    // Only quads with a particle that moved noticeably since the last repair are checked.
    let moved: Vec<bool> = particles
        .positions
        .iter()
        .zip(&particles.meshed_at)
        .zip(&particles.dets)
        .map(|((p, at), det)| {
            // A NaN position (never meshed) counts as moved.
            let moved = (*p - *at).length_squared();
            moved.is_nan() || moved > MESH_REFRESH * MESH_REFRESH * det
        })
        .collect();
    mesh.legalize_around(&particles.positions, field, Some(&moved));
    particles.meshed_at.clone_from(&particles.positions);
    take_flip_counts(&mut mesh, stats);
    stats.triangulation_time += t.elapsed();
    mesh
}

/// Inserts into poorly filled triangles and deletes overcrowded samples (`edges` are `mesh`'s),
/// and returns the triangulation of the new population: insertions split their triangle in
/// place, deletions fill their star's hole (a new triangulation only where a hole cannot be
/// filled), then Lawson flips.
pub(super) fn control_population(
    mut mesh: AnisotropicDelaunay,
    edges: &Edges,
    particles: &mut Particles,
    field: &TensorField,
    params: &SamplerParams,
    stats: &mut Stats,
) -> AnisotropicDelaunay {
    let t = Instant::now();
    let pressure = population::pressures(&particles.positions, &particles.squares, edges);
    let gone = population::deletions(&pressure, particles.fixed, edges, params.delete_pressure);
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
    particles.reserve_exact(new.len());
    mesh.reserve_splits(new.len());
    for &(triangle, p) in &new {
        mesh.split_triangle(triangle, particles.positions.len() as u32);
        particles.push(p, field);
    }
    stats.population_time += t.elapsed();
    let mut kept_index = None;
    if !gone.is_empty() {
        let t = Instant::now();
        let removed = mesh.remove_vertices(&gone, &particles.positions, field);
        take_flip_counts(&mut mesh, stats);
        stats.triangulation_time += t.elapsed();
        if !removed {
            particles.remove(&gone);
            return rebuild(particles, field, stats);
        }
        kept_index = Some(particles.remove(&gone));
    } else if new.is_empty() {
        return repair(mesh, particles, field, stats);
    }
    // Keep memory in spatial order for the next iterations (one renumbering of the mesh for
    // the removal and the sort together), then restore the criterion.
    let sorted = particles.sort_spatially(field.domain());
    let new_index = match kept_index {
        Some(kept) => kept
            .iter()
            .map(|&k| sorted.get(k as usize).copied().unwrap_or(u32::MAX))
            .collect(),
        None => sorted,
    };
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

/// One Euler step of eq. 5 for every awake free particle: `v ← (v + Δt·F)/(1 + Δt·C_drag)`,
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
///
/// Particles at rest sleep: one whose step and whose next step (from its velocity and force)
/// are both under [`SLEEP`] of its size is not integrated until a neighbour moves more than
/// that. An edge's force is computed again only when one of its ends moved, or when the edges
/// are `fresh` (a new or repaired triangulation). Where the packing is already in equilibrium,
/// as over most of a lattice seed, an iteration then costs little more than reading the flags.
pub(super) fn relax_once(
    particles: &mut Particles,
    edges: &Edges,
    field: &TensorField,
    dyn_: &Dynamics,
    fresh: bool,
) -> (f64, f64) {
    let fixed = particles.fixed;
    let domain = field.domain();
    let Particles {
        positions,
        dets,
        inverses,
        squares,
        velocities,
        edge_forces,
        looked_up,
        meshed_at,
        motion,
        next_motion,
        ..
    } = particles;
    let (positions_now, squares_now, motion_now): (&[DVec2], &[Tensor], &[u8]) =
        (positions, squares, motion);
    update_edge_forces(
        edge_forces,
        edges,
        (positions_now, squares_now, motion_now),
        dyn_.scale,
        fresh,
    );
    let edge_forces: &[DVec2] = edge_forces;
    // One pass per particle: gather the edge forces, integrate, and look the metric up again
    // when the particle has moved more than a small fraction of its size since the last
    // look-up (the field is smooth at the scale of an ellipse). Only the particle's own slots
    // are written.
    let largest = positions[fixed..]
        .par_iter_mut()
        .zip(velocities[fixed..].par_iter_mut())
        .zip(
            dets[fixed..]
                .par_iter_mut()
                .zip(inverses[fixed..].par_iter_mut())
                .zip(squares[fixed..].par_iter_mut()),
        )
        .zip(looked_up[fixed..].par_iter_mut())
        .zip(
            meshed_at[fixed..]
                .par_iter()
                .zip(motion[fixed..].par_iter_mut()),
        )
        .enumerate()
        .map(
            |(k, ((((pos, v), ((det, inv), sq)), at), (meshed, flags)))| {
                let i = fixed + k;
                let p = *pos;
                let size = det.sqrt().max(1e-12);
                if *flags & AWAKE == 0 {
                    *flags &= !(MOVED | STIRRED);
                    return (0.0, (p - *meshed).length() / size);
                }
                let mut force = DVec2::ZERO;
                for (e, first) in edges.sides_at(i) {
                    if first {
                        force += edge_forces[e];
                    } else {
                        force -= edge_forces[e];
                    }
                }
                // Drag taken implicitly: stable for any C_drag·Δt, unlike v·(1 − C_drag·Δt).
                *v = (*v + force * dyn_.dt) / (1.0 + dyn_.drag * dyn_.dt);
                let mut step = *v * dyn_.dt;
                let (cap, length) = (size / 3.0, step.length());
                if length > cap {
                    step *= cap / length;
                }
                let margin = 1e-6 * size.max(1e-3);
                *pos = (p + step).clamp(DVec2::splat(margin), domain - DVec2::splat(margin));
                let moved = (*pos - p).length() / size;
                let next = (*v + force * dyn_.dt).length() * dyn_.dt / size;
                *flags = AWAKE
                    | if *pos != p { MOVED } else { 0 }
                    | if moved > SLEEP { STIRRED } else { 0 }
                    | if moved < SLEEP && next < SLEEP {
                        QUIET
                    } else {
                        0
                    };
                if (*pos - *at).length_squared() > METRIC_REFRESH * METRIC_REFRESH * size * size {
                    let m = field.sample(*pos);
                    *det = m.det();
                    *inv = m.inverse().unwrap_or_default();
                    *sq = m.squared();
                    *at = *pos;
                }
                // A NaN `meshed` (never meshed) gives NaN, which `max` ignores.
                (moved, (*pos - *meshed).length() / size)
            },
        )
        .reduce(|| (0.0, 0.0), |a, b| (a.0.max(b.0), a.1.max(b.1)));
    wake(motion, next_motion, velocities, edges, fixed);
    largest
}

/// The force along every edge, `S·f(d)·y/d` on its first end (`scale` = S), from the particles'
/// `(positions, squared metrics, motion flags)`; with `fresh` unset, only edges with an end
/// that moved are computed again (the others' forces stand). The buffer is made anew, exactly
/// sized, when the edges changed in number (a million particles have three million edges, and
/// a grown buffer would double).
fn update_edge_forces(
    edge_forces: &mut Vec<DVec2>,
    edges: &Edges,
    (positions, squares, motion): (&[DVec2], &[Tensor], &[u8]),
    scale: f64,
    fresh: bool,
) {
    if edge_forces.len() != edges.ends.len() {
        *edge_forces = vec![DVec2::ZERO; edges.ends.len()];
    }
    edge_forces
        .par_iter_mut()
        .zip(edges.ends.par_iter())
        .for_each(|(f, &[a, b])| {
            let (a, b) = (a as usize, b as usize);
            if !fresh && (motion[a] | motion[b]) & MOVED == 0 {
                return;
            }
            let (pa, pb) = (positions[a], positions[b]);
            let d = distance::contact_distance_of_squares(pa, &squares[a], pb, &squares[b]);
            // Force on a: S·f(d)·ŷ·d_opt with ŷ·d_opt = (y/|y|)·(|y|/d) = y/d.
            *f = if d > 0.0 {
                (pa - pb) * (scale * force_spline(d) / d)
            } else {
                DVec2::ZERO
            };
        });
}

/// Who is awake next (into `motion`, through the scratch `next_motion`): the restless, and
/// whoever has a neighbour that moved. A free particle that falls asleep keeps no velocity.
fn wake(
    motion: &mut Vec<u8>,
    next_motion: &mut Vec<u8>,
    velocities: &mut [DVec2],
    edges: &Edges,
    fixed: usize,
) {
    let motion_now: &[u8] = motion;
    next_motion.resize(motion_now.len(), 0);
    next_motion[fixed..]
        .par_iter_mut()
        .zip(velocities[fixed..].par_iter_mut())
        .enumerate()
        .for_each(|(k, (next, v))| {
            let i = fixed + k;
            let flags = motion_now[i];
            let stirred = edges
                .at(i)
                .any(|(_, _, j)| motion_now[j as usize] & STIRRED != 0);
            *next = if flags & QUIET == 0 || stirred {
                flags | AWAKE
            } else {
                *v = DVec2::ZERO;
                flags & !AWAKE
            };
        });
    std::mem::swap(motion, next_motion);
}

/// Between the regular repairs, the triangulation is repaired as soon as some particle has moved
/// this many of its sizes since the last one. Early on, when the seed's particles still travel far,
/// eight iterations can invert triangles, and an inverted mesh must be rebuilt from scratch: on a
/// photo's metric with 8 k samples, four rebuilds of the first 32 iterations (12 ms each) became
/// about sixteen extra repairs (2 ms each), and the flips halved.
pub(super) const REPAIR_DRIFT: f64 = 1.5;

/// A quad is checked again at a repair once one of its particles has moved this fraction of
/// its size since the previous repair.
const MESH_REFRESH: f64 = 0.02;

/// A particle's metric is looked up again once it has moved this fraction of its size.
const METRIC_REFRESH: f64 = 0.05;
