//! Particle state during relaxation (paper section 5.3): structure-of-arrays of positions,
//! metric determinants, inverse and squared metrics, velocities, motion flags and per-edge
//! forces, boundary samples first, kept in Morton order so loops over particles, their
//! neighbours and the field read memory mostly in order. Insertion appends, deletion and
//! reordering gather every array the same way.

use super::seeding;
use crate::field::{Tensor, TensorField};
use glam::DVec2;
use rayon::prelude::*;

/// Particle state during relaxation, structure-of-arrays, boundary samples first.
pub(super) struct Particles {
    pub(super) positions: Vec<DVec2>,
    /// `det m` of every particle's metric (its size `√det m` squared): the metric itself is
    /// only read through its inverse and its square.
    pub(super) dets: Vec<f64>,
    pub(super) inverses: Vec<Tensor>,
    /// Every metric squared ([`Tensor::squared`]), what the contact distance reads.
    pub(super) squares: Vec<Tensor>,
    pub(super) velocities: Vec<DVec2>,
    /// Force of each triangulation edge on its first vertex (reused).
    pub(super) edge_forces: Vec<DVec2>,
    /// Where each particle's metric was last looked up.
    pub(super) looked_up: Vec<DVec2>,
    /// Where each particle was when the triangulation was last made Delaunay (NaN: never).
    pub(super) meshed_at: Vec<DVec2>,
    /// Motion flags of each particle ([`AWAKE`], [`MOVED`], [`STIRRED`], [`QUIET`]).
    pub(super) motion: Vec<u8>,
    /// The next iteration's flags (reused).
    pub(super) next_motion: Vec<u8>,
    pub(super) fixed: usize,
}

/// The particle is integrated this iteration.
pub(super) const AWAKE: u8 = 1;
/// Its position changed in the last iteration (its edges' forces are stale).
pub(super) const MOVED: u8 = 2;
/// It moved more than [`SLEEP`] of its size in the last iteration (it wakes its neighbours).
pub(super) const STIRRED: u8 = 4;
/// Its last step and the step its force would give next are both under [`SLEEP`].
pub(super) const QUIET: u8 = 8;
/// Steps under this fraction of a particle's size let it sleep: a tenth of the default
/// stopping tolerance.
pub(super) const SLEEP: f64 = 1e-4;

impl Particles {
    pub(super) fn new(positions: Vec<DVec2>, fixed: usize, field: &TensorField) -> Self {
        let metrics: Vec<Tensor> = positions.par_iter().map(|&p| field.sample(p)).collect();
        let inverses = metrics
            .par_iter()
            .map(|m| m.inverse().unwrap_or_default())
            .collect();
        let squares = metrics.par_iter().map(Tensor::squared).collect();
        let dets = metrics.par_iter().map(Tensor::det).collect();
        let velocities = vec![DVec2::ZERO; positions.len()];
        let mut motion = vec![AWAKE | MOVED; positions.len()];
        motion[..fixed].fill(0);
        Particles {
            motion,
            next_motion: Vec::new(),
            looked_up: positions.clone(),
            meshed_at: vec![DVec2::NAN; positions.len()],
            positions,
            dets,
            inverses,
            squares,
            velocities,
            edge_forces: Vec::new(),
            fixed,
        }
    }

    /// Room for exactly `extra` more particles in every array: arrays of a million particles
    /// grown by doubling would hold twice their size for a moment.
    pub(super) fn reserve_exact(&mut self, extra: usize) {
        self.positions.reserve_exact(extra);
        self.looked_up.reserve_exact(extra);
        self.meshed_at.reserve_exact(extra);
        self.dets.reserve_exact(extra);
        self.inverses.reserve_exact(extra);
        self.squares.reserve_exact(extra);
        self.velocities.reserve_exact(extra);
        self.motion.reserve_exact(extra);
    }

    pub(super) fn push(&mut self, p: DVec2, field: &TensorField) {
        let m = field.sample(p);
        self.positions.push(p);
        self.looked_up.push(p);
        self.meshed_at.push(DVec2::NAN);
        self.dets.push(m.det());
        self.inverses.push(m.inverse().unwrap_or_default());
        self.squares.push(m.squared());
        self.velocities.push(DVec2::ZERO);
        self.motion.push(AWAKE | MOVED);
    }

    /// Puts the free particles in Morton (Z-curve) order of their positions, so that loops
    /// over particles, their neighbours and the field read memory mostly in order. Ties keep
    /// the current order, so the result is deterministic.
    /// Returns `new_index`: the new position of every old index.
    pub(super) fn sort_spatially(&mut self, domain: DVec2) -> Vec<u32> {
        // Keys and indices are unique pairs, so the parallel sort gives the one order there is.
        let mut keyed: Vec<(u32, u32)> = (self.fixed..self.positions.len())
            .into_par_iter()
            .map(|i| (seeding::morton_key(self.positions[i], domain), i as u32))
            .collect();
        keyed.par_sort_unstable();
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
    /// Returns every old index's new one (the removed ones' entries are unused).
    pub(super) fn remove(&mut self, gone: &[u32]) -> Vec<u32> {
        let mut k = 0;
        let kept: Vec<u32> = (0..self.positions.len() as u32)
            .filter(|&i| {
                let drop = gone.get(k) == Some(&i);
                k += usize::from(drop);
                !drop
            })
            .collect();
        let mut new_index = vec![u32::MAX; self.positions.len()];
        for (new, &old) in kept.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        if !gone.is_empty() {
            self.keep_in_order(&kept);
        }
        new_index
    }

    /// Keeps the particles `order` lists, in that order, in every per-particle array.
    pub(super) fn keep_in_order(&mut self, order: &[u32]) {
        fn gather<T: Copy + Send + Sync>(v: &mut Vec<T>, order: &[u32]) {
            *v = order.par_iter().map(|&i| v[i as usize]).collect();
        }
        gather(&mut self.positions, order);
        gather(&mut self.velocities, order);
        gather(&mut self.looked_up, order);
        gather(&mut self.meshed_at, order);
        gather(&mut self.dets, order);
        gather(&mut self.inverses, order);
        gather(&mut self.squares, order);
        gather(&mut self.motion, order);
    }
}
