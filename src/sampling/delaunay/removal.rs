//! Removing vertices from the anisotropic Delaunay triangulation (paper section 5.5's
//! population control deletes overcrowded samples): each removed vertex's star becomes a hole,
//! filled by clipping ears of its ring of neighbours (exact orientation tests), and Lawson flips
//! from the edges around the holes restore the generalised criterion, as after an insertion.
//! A fresh build of the whole mesh for each round that deleted a sample or two would cost up
//! to a fifth of a run.

use super::{next, orient, prev, AnisotropicDelaunay, NONE};
use crate::field::TensorField;
use glam::DVec2;

impl AnisotropicDelaunay {
    /// Removes the interior vertices `gone` (sorted), each star's hole triangulated by ear clipping
    /// and then made legal by Lawson flips from the edges around the holes, as
    /// [`Self::legalize_around`] does: the local counterpart of a fresh build without them. Vertex
    /// indices are kept (the gone ones are no longer used: renumber after removing the points).
    /// Returns `false`, with the mesh unchanged, when one of them lies on the hull, neighbours
    /// another, or its hole has no ear to clip at `points` (degenerate): then rebuild.
    pub fn remove_vertices(
        &mut self,
        gone: &[u32],
        points: &[DVec2],
        metric: &TensorField,
    ) -> bool {
        if gone.is_empty() {
            return true;
        }
        // One outgoing half-edge of every vertex to remove.
        let mut is_gone = vec![false; points.len()];
        for &v in gone {
            is_gone[v as usize] = true;
        }
        let mut start = vec![NONE; points.len()];
        for (h, &o) in self.origin.iter().enumerate() {
            if is_gone[o as usize] && start[o as usize] == NONE {
                start[o as usize] = h as u32;
            }
        }
        // Every hole must be fillable, and no removed vertex a neighbour of another (its star
        // would change under the other's fill), before any is touched.
        let fillable = |v: u32| {
            self.hole_plan(start[v as usize], points)
                .is_some_and(|plan| plan.ring.iter().all(|&a| !is_gone[a as usize]))
        };
        if !gone.iter().all(|&v| fillable(v)) {
            return false;
        }
        let mut ring_vertex = vec![false; points.len()];
        let mut dead = vec![false; self.num_triangles()];
        for &v in gone {
            // Planned again: a hole filled before may have been across a side of this one,
            // which then has a new triangle outside it (the ring and the ears are the same).
            let plan = self
                .hole_plan(start[v as usize], points)
                .expect("checked above");
            self.fill_hole(&plan, &mut dead);
            for &a in &plan.ring {
                ring_vertex[a as usize] = true;
            }
        }
        self.drop_triangles(&dead);
        self.legalize_around(points, metric, Some(&ring_vertex));
        true
    }

    /// The star of the vertex half-edge `h0` leaves (`NONE`: not in the mesh) and an ear
    /// triangulation of its hole, or `None` on the hull or without an ear.
    fn hole_plan(&self, h0: u32, points: &[DVec2]) -> Option<HolePlan> {
        if h0 == NONE {
            return None;
        }
        let (mut slots, mut ring, mut outer) = (Vec::new(), Vec::new(), Vec::new());
        let mut h = h0 as usize;
        loop {
            // Triangle (v, a, b): h = v→a, next(h) = a→b, prev(h) = b→v.
            slots.push(h / 3);
            ring.push(self.origin[next(h)]);
            outer.push(self.twin[next(h)]);
            let back = self.twin[prev(h)];
            // (No star of a valid mesh comes near 64 triangles; a broken one cannot loop.)
            if back == NONE || slots.len() > 64 {
                return None;
            }
            h = back as usize;
            if h == h0 as usize {
                break;
            }
        }
        let ears = ear_clipping(&ring, points)?;
        Some(HolePlan {
            slots,
            ring,
            outer,
            ears,
        })
    }

    /// Writes `plan`'s ears into the first of its star's triangle slots, linked to each other
    /// and to the triangles around the hole, and marks the two slots left over in `dead`.
    fn fill_hole(&mut self, plan: &HolePlan, dead: &mut [bool]) {
        let k = plan.ring.len();
        // The ears' corners into the slots, then every ear edge's twin: the triangle outside
        // the hole for a side of it, the other ear for a diagonal.
        for (e, &[i, j, l]) in plan.ears.iter().enumerate() {
            let h = 3 * plan.slots[e];
            self.origin[h..h + 3].copy_from_slice(&[plan.ring[i], plan.ring[j], plan.ring[l]]);
        }
        for (e, ear) in plan.ears.iter().enumerate() {
            for c in 0..3 {
                let (i, j) = (ear[c], ear[(c + 1) % 3]);
                let h = 3 * plan.slots[e] + c;
                if j == (i + 1) % k {
                    // A side of the hole: the triangle outside it.
                    self.link(h, plan.outer[i]);
                } else if let Some(g) = plan.ears.iter().enumerate().find_map(|(f, other)| {
                    (0..3)
                        .find(|&d| other[d] == j && other[(d + 1) % 3] == i)
                        .map(|d| 3 * plan.slots[f] + d)
                }) {
                    self.link(h, g as u32);
                }
            }
        }
        for &t in &plan.slots[plan.ears.len()..] {
            dead[t] = true;
            self.origin[3 * t..3 * t + 3].fill(NONE);
            self.twin[3 * t..3 * t + 3].fill(NONE);
        }
    }

    /// Drops the triangles marked `dead` (unlinked), keeping the others' order.
    fn drop_triangles(&mut self, dead: &[bool]) {
        let mut new_of_old = vec![NONE; dead.len()];
        let mut kept = 0u32;
        for (t, &d) in dead.iter().enumerate() {
            if !d {
                new_of_old[t] = kept;
                kept += 1;
            }
        }
        let map = |h: u32| {
            if h == NONE {
                NONE
            } else {
                3 * new_of_old[h as usize / 3] + h % 3
            }
        };
        let mut w = 0;
        for t in (0..dead.len()).filter(|&t| !dead[t]) {
            for c in 0..3 {
                self.origin[3 * w + c] = self.origin[3 * t + c];
                self.twin[3 * w + c] = map(self.twin[3 * t + c]);
            }
            w += 1;
        }
        self.origin.truncate(3 * w);
        self.twin.truncate(3 * w);
    }
}

/// A vertex's star and how its hole is filled: the star's triangle slots (counter-clockwise
/// from the first), the ring of neighbours (triangle `i` is `(v, ring[i], ring[i + 1])`), the
/// half-edge outside each side `ring[i] → ring[i + 1]` of the hole, and the ears as ring
/// indices, counter-clockwise.
struct HolePlan {
    slots: Vec<usize>,
    ring: Vec<u32>,
    outer: Vec<u32>,
    ears: Vec<[usize; 3]>,
}

/// Triangulates the simple counter-clockwise polygon `ring` (a removed vertex's neighbours) by
/// clipping ears: a corner whose triangle with its two neighbours is counter-clockwise and holds
/// no other corner, tested exactly. `None` when no ear is left (a degenerate hole).
fn ear_clipping(ring: &[u32], points: &[DVec2]) -> Option<Vec<[usize; 3]>> {
    let at = |i: usize| points[ring[i] as usize];
    let mut left: Vec<usize> = (0..ring.len()).collect();
    let mut ears = Vec::with_capacity(ring.len().saturating_sub(2));
    while left.len() > 3 {
        let n = left.len();
        let ear = (0..n).find(|&c| {
            let (a, b, d) = (left[(c + n - 1) % n], left[c], left[(c + 1) % n]);
            orient(at(a), at(b), at(d)) > 0.0
                && left.iter().all(|&o| {
                    o == a
                        || o == b
                        || o == d
                        || orient(at(a), at(b), at(o)) < 0.0
                        || orient(at(b), at(d), at(o)) < 0.0
                        || orient(at(d), at(a), at(o)) < 0.0
                })
        })?;
        ears.push([left[(ear + n - 1) % n], left[ear], left[(ear + 1) % n]]);
        left.remove(ear);
    }
    if left.len() == 3 && orient(at(left[0]), at(left[1]), at(left[2])) > 0.0 {
        ears.push([left[0], left[1], left[2]]);
        Some(ears)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{edge_set, random_points};
    use super::*;
    use crate::field::Tensor;
    use std::collections::BTreeSet;

    #[test]
    fn removing_vertices_equals_a_fresh_build_without_them() {
        for (seed, angle) in [(11u64, -0.4f64), (12, 1.1), (13, 0.0)] {
            let pts = random_points(400, seed);
            let metric = TensorField::constant(4, 4, Tensor::from_eigen(angle, 3.0, 1.0));
            let (mut mesh, _) = AnisotropicDelaunay::build(&pts, &metric);
            let hull: BTreeSet<u32> = (0..mesh.origin.len())
                .filter(|&h| mesh.twin[h] == NONE)
                .flat_map(|h| [mesh.origin[h], mesh.origin[next(h)]])
                .collect();
            // Every fifth vertex off the hull, skipping neighbours of one already taken.
            let edges = mesh.edges(pts.len());
            let mut blocked = vec![false; pts.len()];
            let mut gone = Vec::new();
            for v in (0..pts.len()).step_by(5) {
                if blocked[v] || hull.contains(&(v as u32)) {
                    continue;
                }
                gone.push(v as u32);
                for (_, _, n) in edges.at(v) {
                    blocked[n as usize] = true;
                }
            }
            assert!(gone.len() > 40, "{} removed", gone.len());
            assert!(mesh.remove_vertices(&gone, &pts, &metric));
            mesh.sanity_check(&pts, &gone).unwrap();
            // The oracle: a fresh build of the points that stay, in their original numbering.
            let kept: Vec<u32> = (0..pts.len() as u32)
                .filter(|v| gone.binary_search(v).is_err())
                .collect();
            let kept_points: Vec<DVec2> = kept.iter().map(|&v| pts[v as usize]).collect();
            let (fresh, _) = AnisotropicDelaunay::build(&kept_points, &metric);
            let renamed = fresh.triangles().map(|t| t.map(|v| kept[v as usize]));
            assert_eq!(edge_set(mesh.triangles()), edge_set(renamed), "seed {seed}");
        }
    }

    #[test]
    fn neighbours_are_not_removed_in_place() {
        let pts = random_points(100, 15);
        let metric = TensorField::constant(4, 4, Tensor::isotropic(1.0));
        let (mut mesh, _) = AnisotropicDelaunay::build(&pts, &metric);
        let edges = mesh.edges(pts.len());
        // An edge between two vertices off the hull.
        let hull: BTreeSet<u32> = (0..mesh.origin.len())
            .filter(|&h| mesh.twin[h] == NONE)
            .flat_map(|h| [mesh.origin[h], mesh.origin[next(h)]])
            .collect();
        let &[a, b] = edges
            .ends
            .iter()
            .find(|[a, b]| !hull.contains(a) && !hull.contains(b))
            .unwrap();
        let before = (mesh.origin.clone(), mesh.twin.clone());
        assert!(!mesh.remove_vertices(&[a, b], &pts, &metric));
        assert_eq!((mesh.origin.clone(), mesh.twin.clone()), before);
    }

    #[test]
    fn a_hull_vertex_is_not_removed_in_place() {
        let pts = random_points(100, 14);
        let metric = TensorField::constant(4, 4, Tensor::isotropic(1.0));
        let (mut mesh, _) = AnisotropicDelaunay::build(&pts, &metric);
        let h = mesh.twin.iter().position(|&t| t == NONE).unwrap();
        let on_hull = mesh.origin[h];
        let before = (mesh.origin.clone(), mesh.twin.clone());
        assert!(!mesh.remove_vertices(&[on_hull], &pts, &metric));
        assert_eq!((mesh.origin.clone(), mesh.twin.clone()), before);
    }
}
