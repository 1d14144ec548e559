//! The anisotropic Delaunay triangulation of paper section 5.4, as our own half-edge mesh.
//!
//! spade builds the isotropic Delaunay triangulation (`bulk_load`); it has no custom in-circle
//! test and no public flip, so the result is copied into a compact half-edge mesh: triangle `t`
//! owns half-edges `3t, 3t+1, 3t+2` in counter-clockwise order, `origin[h]` is the vertex a
//! half-edge leaves, `twin[h]` the opposite half-edge or [`NONE`] on the hull. Lawson flips then
//! enforce the *generalised* criterion: for the quad of an edge, its four points are mapped by
//! `m(q)⁻¹` with `q` their barycentre (eq. 2) and tested with the exact in-circle predicate of the
//! `robust` crate, the one spade uses. Only strictly convex quads flip. The criterion changes
//! from quad to quad when the metric varies, so flipping may cycle: the number of flips is
//! capped and cap hits are counted. For a constant metric the result is the Delaunay
//! triangulation of the points mapped by `m⁻¹`, which the tests check against spade itself.

pub mod edges;
mod removal;

use crate::field::TensorField;
use glam::DVec2;
use rayon::prelude::*;
use robust::Coord;
use spade::{DelaunayTriangulation, HasPosition, Point2, Triangulation};

/// "No half-edge": the twin of a hull half-edge.
pub const NONE: u32 = u32::MAX;

/// Flips allowed per legalisation, per edge of the mesh, before the cap is hit.
const FLIPS_PER_EDGE: usize = 8;

/// The anisotropic Delaunay triangulation of a set of points (indices into the caller's arrays).
#[derive(Clone, Debug, Default)]
pub struct AnisotropicDelaunay {
    /// The vertex each half-edge leaves.
    pub(super) origin: Vec<u32>,
    /// The opposite half-edge, or [`NONE`] on the hull.
    pub(super) twin: Vec<u32>,
    /// Flips done since the mesh was built (all legalisations).
    pub flips: u64,
    /// Legalisations stopped by the flip cap.
    pub cap_hits: u64,
}

/// spade vertex carrying the caller's index, so the order of `bulk_load` does not matter.
struct Site {
    position: Point2<f64>,
    id: u32,
}

impl HasPosition for Site {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.position
    }
}

#[inline]
pub(super) fn next(h: usize) -> usize {
    if h % 3 == 2 {
        h - 2
    } else {
        h + 1
    }
}

#[inline]
pub(super) fn prev(h: usize) -> usize {
    if h.is_multiple_of(3) {
        h + 2
    } else {
        h - 1
    }
}

fn coord(p: DVec2) -> Coord<f64> {
    Coord { x: p.x, y: p.y }
}

/// Exact orientation: positive when `a, b, c` turn counter-clockwise (y down: clockwise on screen).
#[inline]
pub(super) fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    robust::orient2d(coord(a), coord(b), coord(c))
}

impl AnisotropicDelaunay {
    /// The isotropic Delaunay triangulation of `points` by spade, as a half-edge mesh.
    /// Returns the mesh and the indices of points spade merged away as duplicates (or that had
    /// invalid coordinates); those have no triangle.
    #[must_use]
    pub fn isotropic(points: &[DVec2]) -> (Self, Vec<u32>) {
        let sites: Vec<Site> = points
            .iter()
            .enumerate()
            .map(|(i, p)| Site {
                position: Point2::new(p.x, p.y),
                id: i as u32,
            })
            .collect();
        let Ok(tri) = DelaunayTriangulation::<Site>::bulk_load(sites) else {
            return (Self::default(), (0..points.len() as u32).collect());
        };
        let mut present = vec![false; points.len()];
        for v in tri.vertices() {
            present[v.data().id as usize] = true;
        }
        let missing = (0..points.len() as u32)
            .filter(|&i| !present[i as usize])
            .collect();
        let mut origin = Vec::with_capacity(tri.num_inner_faces() * 3);
        for face in tri.inner_faces() {
            // spade's vertices are counter-clockwise in its y-up convention, which is the
            // same orientation test (positive orient2d) in our y-down coordinates.
            for v in face.vertices() {
                origin.push(v.data().id);
            }
        }
        let twin = compute_twins(&origin, points.len());
        let mut mesh = AnisotropicDelaunay {
            origin,
            twin,
            flips: 0,
            cap_hits: 0,
        };
        mesh.sort_triangles();
        (mesh, missing)
    }

    /// spade's triangulation of `points`, then Lawson flips to the generalised criterion under
    /// `metric`. Returns the mesh and the points spade dropped (duplicates).
    #[must_use]
    pub fn build(points: &[DVec2], metric: &TensorField) -> (Self, Vec<u32>) {
        let (mut mesh, missing) = Self::isotropic(points);
        mesh.legalize(points, metric);
        (mesh, missing)
    }

    /// Number of triangles.
    #[must_use]
    pub fn num_triangles(&self) -> usize {
        self.origin.len() / 3
    }

    /// Vertex indices of triangle `t`, counter-clockwise.
    #[must_use]
    pub fn triangle(&self, t: usize) -> [u32; 3] {
        [
            self.origin[3 * t],
            self.origin[3 * t + 1],
            self.origin[3 * t + 2],
        ]
    }

    /// All triangles, counter-clockwise.
    pub fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.origin.chunks_exact(3).map(|c| [c[0], c[1], c[2]])
    }

    /// The triangle across edge `i` of triangle `t` (the edge from corner `i` to `i + 1`).
    #[must_use]
    pub fn neighbour(&self, t: usize, i: usize) -> Option<usize> {
        let tw = self.twin[3 * t + i];
        (tw != NONE).then_some(tw as usize / 3)
    }

    /// Whether every triangle is counter-clockwise with positive area at `points`.
    #[must_use]
    pub fn is_valid_at(&self, points: &[DVec2]) -> bool {
        self.origin.par_chunks_exact(3).all(|t| {
            orient(
                points[t[0] as usize],
                points[t[1] as usize],
                points[t[2] as usize],
            ) > 0.0
        })
    }

    /// The triangles that are not counter-clockwise with positive area at `points`.
    #[must_use]
    pub fn turned_over_at(&self, points: &[DVec2]) -> Vec<[u32; 3]> {
        self.triangles()
            .filter(|t| {
                orient(
                    points[t[0] as usize],
                    points[t[1] as usize],
                    points[t[2] as usize],
                ) <= 0.0
            })
            .collect()
    }

    /// Lawson flips until every interior edge meets the generalised Delaunay criterion or the
    /// flip cap is hit. Returns the number of flips. The mesh must be valid at `points`.
    pub fn legalize(&mut self, points: &[DVec2], metric: &TensorField) -> usize {
        self.legalize_around(points, metric, None)
    }

    /// [`Self::legalize`] starting only from the edges whose quad has a vertex marked in
    /// `moved` (all edges when `None`). An edge whose four quad vertices have not moved keeps
    /// its verdict, so after small motions this checks a fraction of the mesh; flips still
    /// propagate to wherever they must.
    pub fn legalize_around(
        &mut self,
        points: &[DVec2],
        metric: &TensorField,
        moved: Option<&[bool]>,
    ) -> usize {
        let touches = |h: usize| {
            moved.is_none_or(|m| {
                let g = self.twin[h] as usize;
                [h, next(h), prev(h), prev(g)]
                    .iter()
                    .any(|&k| m[self.origin[k] as usize])
            })
        };
        // Most edges are legal: test them all in parallel first (order kept, so the result
        // does not depend on the thread count); only the illegal ones start the sequential
        // Lawson pass, which pushes the outer edges of every flipped quad again.
        let mut stack: Vec<u32> = (0..self.origin.len() as u32)
            .into_par_iter()
            .filter(|&h| {
                let t = self.twin[h as usize];
                t != NONE
                    && h < t
                    && touches(h as usize)
                    && self.should_flip(h as usize, points, metric)
            })
            .collect();
        let cap = FLIPS_PER_EDGE * (self.origin.len() / 2).max(1);
        let mut flips = 0;
        while let Some(h) = stack.pop() {
            let h = h as usize;
            if self.twin[h] == NONE || !self.should_flip(h, points, metric) {
                continue;
            }
            if flips == cap {
                self.cap_hits += 1;
                break;
            }
            let outer = self.flip(h);
            flips += 1;
            stack.extend_from_slice(&outer);
        }
        self.flips += flips as u64;
        flips
    }

    /// Whether interior edge `h` should flip: its quad is strictly convex and the opposite
    /// vertex lies inside the circumcircle after mapping by `m(q)⁻¹`, `q` the quad's barycentre.
    fn should_flip(&self, h: usize, points: &[DVec2], metric: &TensorField) -> bool {
        let g = self.twin[h] as usize;
        let a = points[self.origin[h] as usize];
        let b = points[self.origin[next(h)] as usize];
        let c = points[self.origin[prev(h)] as usize];
        let d = points[self.origin[prev(g)] as usize];
        // Strictly convex: both triangles of the other diagonal are counter-clockwise.
        if orient(c, a, d) <= 0.0 || orient(d, b, c) <= 0.0 {
            return false;
        }
        let q = (a + b + c + d) * 0.25;
        let Some(inv) = metric.sample(q).inverse() else {
            return false;
        };
        let map = |p: DVec2| coord(inv.mul_vec(p - q));
        robust::incircle(map(a), map(b), map(c), map(d)) > 0.0
    }

    /// Flips interior edge `h` (a→b, triangle a b c; twin b→a, triangle b a d) to c–d and
    /// returns the four outer half-edges of the new quad, to be checked again.
    fn flip(&mut self, h: usize) -> [u32; 4] {
        let g = self.twin[h] as usize;
        let (t1, t2) = (h / 3, g / 3);
        let a = self.origin[h];
        let b = self.origin[next(h)];
        let c = self.origin[prev(h)];
        let d = self.origin[prev(g)];
        let tw_bc = self.twin[next(h)];
        let tw_ca = self.twin[prev(h)];
        let tw_ad = self.twin[next(g)];
        let tw_db = self.twin[prev(g)];
        // t1 = (d, c, a): d→c, c→a, a→d.   t2 = (c, d, b): c→d, d→b, b→c.
        let (h1, h2) = (3 * t1, 3 * t2);
        self.origin[h1..h1 + 3].copy_from_slice(&[d, c, a]);
        self.origin[h2..h2 + 3].copy_from_slice(&[c, d, b]);
        self.link(h1, h2 as u32);
        self.link(h1 + 1, tw_ca);
        self.link(h1 + 2, tw_ad);
        self.link(h2 + 1, tw_db);
        self.link(h2 + 2, tw_bc);
        [h1 as u32 + 1, h1 as u32 + 2, h2 as u32 + 1, h2 as u32 + 2]
    }

    pub(super) fn link(&mut self, h: usize, other: u32) {
        self.twin[h] = other;
        if other != NONE {
            self.twin[other as usize] = h as u32;
        }
    }

    /// Room for exactly `extra` more [`Self::split_triangle`]s.
    pub fn reserve_splits(&mut self, extra: usize) {
        self.origin.reserve_exact(6 * extra);
        self.twin.reserve_exact(6 * extra);
    }

    /// Inserts vertex `v`, which lies strictly inside triangle `t`, by splitting `t` into three
    /// (a b v, b c v, c a v). The mesh is a valid triangulation afterwards but not yet
    /// Delaunay: call [`Self::legalize`].
    pub fn split_triangle(&mut self, t: usize, v: u32) {
        let [a, b, c] = self.triangle(t);
        let h = 3 * t;
        let (tw_ab, tw_bc, tw_ca) = (self.twin[h], self.twin[h + 1], self.twin[h + 2]);
        let t1 = self.num_triangles();
        let (h1, h2) = (3 * t1, 3 * t1 + 3);
        // t: a→b, b→v, v→a.   t1: b→c, c→v, v→b.   t2: c→a, a→v, v→c.
        self.origin[h..h + 3].copy_from_slice(&[a, b, v]);
        self.origin.extend_from_slice(&[b, c, v, c, a, v]);
        self.twin.extend_from_slice(&[NONE; 6]);
        self.link(h, tw_ab);
        self.link(h1, tw_bc);
        self.link(h2, tw_ca);
        self.link(h + 1, h1 as u32 + 2);
        self.link(h1 + 1, h2 as u32 + 2);
        self.link(h2 + 1, h as u32 + 2);
    }

    /// Renames every vertex `v` to `new_index[v]` (after the caller reorders its points), then
    /// puts the triangles in the order of their smallest vertex, so that with spatially sorted
    /// vertices the loops over triangles and edges read memory mostly in order.
    pub fn renumber(&mut self, new_index: &[u32]) {
        self.origin
            .par_iter_mut()
            .for_each(|o| *o = new_index[*o as usize]);
        self.sort_triangles();
    }

    /// Reorders triangles by their smallest vertex index (ties by triangle), keeping each
    /// triangle's corner order and remapping twins.
    pub fn sort_triangles(&mut self) {
        let n = self.num_triangles();
        let key = |t: usize| {
            let [a, b, c] = self.triangle(t);
            a.min(b).min(c) as usize
        };
        // A counting sort by the key, stable, so ties keep the triangle order.
        let keys = self.origin.iter().max().map_or(0, |&v| v as usize + 1);
        let mut start = vec![0u32; keys + 1];
        for t in 0..n {
            start[key(t) + 1] += 1;
        }
        for i in 1..start.len() {
            start[i] += start[i - 1];
        }
        let mut order = vec![0u32; n];
        let mut new_of_old = vec![0u32; n];
        for t in 0..n {
            let slot = &mut start[key(t)];
            order[*slot as usize] = t as u32;
            new_of_old[t] = *slot;
            *slot += 1;
        }
        let map = |h: u32| {
            if h == NONE {
                NONE
            } else {
                3 * new_of_old[h as usize / 3] + h % 3
            }
        };
        let mut origin = vec![0u32; self.origin.len()];
        let mut twin = vec![NONE; self.twin.len()];
        origin
            .par_chunks_exact_mut(3)
            .zip(twin.par_chunks_exact_mut(3))
            .zip(order.par_iter())
            .for_each(|((o, t), &old)| {
                for k in 0..3 {
                    o[k] = self.origin[3 * old as usize + k];
                    t[k] = map(self.twin[3 * old as usize + k]);
                }
            });
        self.origin = origin;
        self.twin = twin;
    }

    /// Checks the mesh invariants: twins are mutual and reversed, every triangle is
    /// counter-clockwise with positive area, every present vertex is used, and the Euler
    /// characteristic of a triangulated disc holds (V − E + F = 1). For tests and fuzzing.
    pub fn sanity_check(&self, points: &[DVec2], missing: &[u32]) -> Result<(), String> {
        if !self.origin.len().is_multiple_of(3) || self.twin.len() != self.origin.len() {
            return Err("half-edge arrays have inconsistent lengths".into());
        }
        let mut used = vec![false; points.len()];
        let mut hull = 0usize;
        for h in 0..self.origin.len() {
            let a = self.origin[h] as usize;
            if a >= points.len() {
                return Err(format!("half-edge {h} starts at unknown vertex {a}"));
            }
            used[a] = true;
            let t = self.twin[h];
            if t == NONE {
                hull += 1;
                continue;
            }
            let t = t as usize;
            if self.twin[t] as usize != h {
                return Err(format!("twin of twin of {h} is not {h}"));
            }
            if self.origin[t] != self.origin[next(h)] || self.origin[next(t)] != self.origin[h] {
                return Err(format!("half-edge {h} and its twin {t} are not reversed"));
            }
        }
        for (t, [a, b, c]) in self.triangles().enumerate() {
            let o = orient(points[a as usize], points[b as usize], points[c as usize]);
            if o <= 0.0 {
                return Err(format!(
                    "triangle {t} ({a}, {b}, {c}) is not counter-clockwise"
                ));
            }
        }
        let mut is_missing = vec![false; points.len()];
        for &m in missing {
            is_missing[m as usize] = true;
        }
        for (v, (&u, &m)) in used.iter().zip(&is_missing).enumerate() {
            if u == m {
                return Err(format!("vertex {v}: used {u}, reported missing {m}"));
            }
        }
        let v = used.iter().filter(|&&u| u).count() as i64;
        let f = self.num_triangles() as i64;
        let e = ((self.origin.len() + hull) / 2) as i64;
        if v - e + f != 1 {
            return Err(format!(
                "Euler characteristic V − E + F = {v} − {e} + {f} ≠ 1"
            ));
        }
        Ok(())
    }
}

/// Twins by matching each half-edge a→b with the half-edge b→a among b's outgoing half-edges.
fn compute_twins(origin: &[u32], num_vertices: usize) -> Vec<u32> {
    let mut start = vec![0u32; num_vertices + 1];
    for &o in origin {
        start[o as usize + 1] += 1;
    }
    for i in 1..start.len() {
        start[i] += start[i - 1];
    }
    let mut fill = start.clone();
    let mut outgoing = vec![0u32; origin.len()];
    for (h, &o) in origin.iter().enumerate() {
        outgoing[fill[o as usize] as usize] = h as u32;
        fill[o as usize] += 1;
    }
    let mut twin = vec![NONE; origin.len()];
    for h in 0..origin.len() {
        let (a, b) = (origin[h], origin[next(h)]);
        let range = start[b as usize] as usize..start[b as usize + 1] as usize;
        for &g in &outgoing[range] {
            if origin[next(g as usize)] == a {
                twin[h] = g;
                break;
            }
        }
    }
    twin
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::field::Tensor;
    use crate::sampling::rng::Rng;
    use std::collections::BTreeSet;

    pub(in crate::sampling) fn random_points(n: usize, seed: u64) -> Vec<DVec2> {
        let mut r = Rng::new(seed, 0);
        (0..n)
            .map(|_| DVec2::new(r.uniform() * 100.0, r.uniform() * 80.0))
            .collect()
    }

    pub(in crate::sampling) fn edge_set(
        tris: impl Iterator<Item = [u32; 3]>,
    ) -> BTreeSet<(u32, u32)> {
        let mut s = BTreeSet::new();
        for [a, b, c] in tris {
            for (x, y) in [(a, b), (b, c), (c, a)] {
                s.insert((x.min(y), x.max(y)));
            }
        }
        s
    }

    #[test]
    fn isotropic_metric_keeps_spades_triangulation() {
        let pts = random_points(500, 1);
        let metric = TensorField::constant(10, 8, Tensor::isotropic(2.0));
        let (iso, missing) = AnisotropicDelaunay::isotropic(&pts);
        let (mut aniso, _) = AnisotropicDelaunay::build(&pts, &metric);
        assert!(missing.is_empty());
        iso.sanity_check(&pts, &missing).unwrap();
        aniso.sanity_check(&pts, &missing).unwrap();
        assert_eq!(edge_set(iso.triangles()), edge_set(aniso.triangles()));
        assert_eq!(aniso.legalize(&pts, &metric), 0);
    }

    #[test]
    fn constant_anisotropic_metric_equals_spade_on_mapped_points() {
        for (angle, ratio, seed) in [(30.0f64, 4.0, 2), (-70.0, 8.0, 3), (0.0, 3.0, 4)] {
            let pts = random_points(800, seed);
            let m = Tensor::from_eigen(angle.to_radians(), 2.0 * ratio, 2.0);
            let metric = TensorField::constant(4, 4, m);
            let (mesh, missing) = AnisotropicDelaunay::build(&pts, &metric);
            mesh.sanity_check(&pts, &missing).unwrap();
            assert_eq!(mesh.cap_hits, 0);
            assert!(mesh.flips > 0);
            let inv = m.inverse().unwrap();
            let mapped: Vec<DVec2> = pts.iter().map(|&p| inv.mul_vec(p)).collect();
            let (oracle, _) = AnisotropicDelaunay::isotropic(&mapped);
            assert_eq!(
                edge_set(mesh.triangles()),
                edge_set(oracle.triangles()),
                "{angle}°"
            );
        }
    }

    #[test]
    fn edges_are_the_symmetric_one_rings() {
        let pts = random_points(200, 5);
        let metric = TensorField::constant(4, 4, Tensor::from_eigen(0.3, 5.0, 1.0));
        let (mesh, _) = AnisotropicDelaunay::build(&pts, &metric);
        let edges = mesh.edges(pts.len());
        let set = edge_set(mesh.triangles());
        assert_eq!(edges.ends.len(), set.len());
        let mut count = 0;
        for v in 0..pts.len() {
            for (e, first, n) in edges.at(v) {
                let [a, b] = edges.ends[e];
                assert_eq!(
                    (if first { a } else { b }, if first { b } else { a }),
                    (v as u32, n)
                );
                assert!(set.contains(&((v as u32).min(n), (v as u32).max(n))));
                assert!(edges.at(n as usize).any(|(_, _, back)| back == v as u32));
                count += 1;
            }
        }
        assert_eq!(count, 2 * set.len());
    }

    #[test]
    fn split_then_legalize_equals_a_fresh_build() {
        let mut pts = random_points(300, 9);
        let metric = TensorField::constant(4, 4, Tensor::from_eigen(-0.4, 3.0, 1.0));
        let (mut mesh, _) = AnisotropicDelaunay::build(&pts, &metric);
        // Insert at the barycentres of a few triangles that share no vertex.
        let mut used = vec![false; pts.len()];
        for t in 0..mesh.num_triangles() {
            let [a, b, c] = mesh.triangle(t);
            if [a, b, c].iter().any(|&v| used[v as usize]) || t % 7 != 0 {
                continue;
            }
            for v in [a, b, c] {
                used[v as usize] = true;
            }
            let q = (pts[a as usize] + pts[b as usize] + pts[c as usize]) / 3.0;
            pts.push(q);
            used.push(true);
            mesh.split_triangle(t, pts.len() as u32 - 1);
        }
        mesh.sanity_check(&pts, &[]).unwrap();
        mesh.legalize(&pts, &metric);
        mesh.sanity_check(&pts, &[]).unwrap();
        let (fresh, _) = AnisotropicDelaunay::build(&pts, &metric);
        assert_eq!(edge_set(mesh.triangles()), edge_set(fresh.triangles()));
    }

    #[test]
    fn duplicates_are_reported_missing() {
        let mut pts = random_points(50, 6);
        pts.push(pts[7]);
        let (mesh, missing) = AnisotropicDelaunay::isotropic(&pts);
        assert_eq!(missing.len(), 1);
        mesh.sanity_check(&pts, &missing).unwrap();
    }

    #[test]
    fn sanity_check_catches_broken_meshes() {
        let pts = random_points(60, 7);
        let (mesh, missing) = AnisotropicDelaunay::isotropic(&pts);
        let mut broken = mesh.clone();
        let h = broken.twin.iter().position(|&t| t != NONE).unwrap();
        broken.twin[h] = NONE;
        assert!(broken.sanity_check(&pts, &missing).is_err());
        let mut moved = pts.clone();
        let [a, b, _] = mesh.triangle(0);
        moved.swap(a as usize, b as usize);
        assert!(mesh.sanity_check(&moved, &missing).is_err());
    }
}
