//! The edges of the anisotropic Delaunay triangulation (paper section 5.4) as the relaxation
//! reads them: every edge once with its two ends, and per vertex its one-ring in compressed
//! rows, so the force of each pair is computed once and gathered per particle in a fixed
//! order (the same result at any thread count).

use super::{AnisotropicDelaunay, NONE};

/// The edges of a mesh: `ends[e]` are edge `e`'s vertices; the edges at vertex `v` are
/// `incident[offsets[v]..offsets[v + 1]]`, each `e << 1 | side` with side 0 when `v` is
/// `ends[e][0]` and 1 when it is `ends[e][1]`.
#[derive(Clone, Debug, Default)]
pub struct Edges {
    /// The two vertices of each edge.
    pub ends: Vec<[u32; 2]>,
    /// Row starts into `incident`, one per vertex plus one.
    pub offsets: Vec<u32>,
    /// Edge index and side, per vertex.
    pub incident: Vec<u32>,
}

impl Edges {
    /// The edge structure of `ends` over `num_vertices` vertices.
    #[must_use]
    pub fn from_ends(ends: Vec<[u32; 2]>, num_vertices: usize) -> Edges {
        let mut offsets = vec![0u32; num_vertices + 1];
        for [a, b] in &ends {
            offsets[*a as usize + 1] += 1;
            offsets[*b as usize + 1] += 1;
        }
        for i in 1..offsets.len() {
            offsets[i] += offsets[i - 1];
        }
        let mut fill = offsets.clone();
        let mut incident = vec![0u32; 2 * ends.len()];
        for (e, [a, b]) in ends.iter().enumerate() {
            for (side, v) in [(0u32, *a), (1, *b)] {
                incident[fill[v as usize] as usize] = (e as u32) << 1 | side;
                fill[v as usize] += 1;
            }
        }
        Edges {
            ends,
            offsets,
            incident,
        }
    }

    /// The edges at vertex `v` (its one-ring) as (edge index, whether `v` is the edge's first
    /// end, the other vertex), in a fixed order.
    pub fn at(&self, v: usize) -> impl Iterator<Item = (usize, bool, u32)> + '_ {
        self.incident[self.offsets[v] as usize..self.offsets[v + 1] as usize]
            .iter()
            .map(|&x| {
                let e = (x >> 1) as usize;
                let [a, b] = self.ends[e];
                if x & 1 == 0 {
                    (e, true, b)
                } else {
                    (e, false, a)
                }
            })
    }

    /// The edges at vertex `v` as (edge index, whether `v` is the edge's first end), in the
    /// order of [`Self::at`], without looking up the other vertex.
    pub fn sides_at(&self, v: usize) -> impl Iterator<Item = (usize, bool)> + '_ {
        self.incident[self.offsets[v] as usize..self.offsets[v + 1] as usize]
            .iter()
            .map(|&x| ((x >> 1) as usize, x & 1 == 0))
    }
}

impl AnisotropicDelaunay {
    /// Every edge once, as its two end vertices, and for every vertex the edges it ends
    /// (compressed rows, its one-ring): force loops compute each pair once and gather per
    /// particle.
    #[must_use]
    pub fn edges(&self, num_vertices: usize) -> Edges {
        // Half-edge h stands for its edge when it is on the hull or the lower-numbered of its
        // twin pair: about half of them, at random, so both passes below count and place
        // without branching on it (a mispredicted branch per half-edge cost a fifth of the
        // time). They are read triangle by triangle: the next corner needs no modulo.
        let triangle_edges = |t: usize| {
            let o = &self.origin[3 * t..3 * t + 3];
            let tw = &self.twin[3 * t..3 * t + 3];
            std::array::from_fn::<_, 3, _>(|i| {
                let h = (3 * t + i) as u32;
                let keep = tw[i] == NONE || h < tw[i];
                let (a, b) = (o[i], o[(i + 1) % 3]);
                (keep, [a.min(b), a.max(b)])
            })
        };
        // Grouped by their lower vertex (a counting sort, in half-edge order within a
        // group): with spatially sorted vertices, a loop over edges reads in order.
        let mut start = vec![0u32; num_vertices + 1];
        for t in 0..self.num_triangles() {
            for (keep, [a, _]) in triangle_edges(t) {
                start[a as usize + 1] += u32::from(keep);
            }
        }
        for i in 1..start.len() {
            start[i] += start[i - 1];
        }
        // One slot more, where the half-edges that are not kept are written.
        let count = start[num_vertices] as usize;
        let mut ends = vec![[0u32; 2]; count + 1];
        for t in 0..self.num_triangles() {
            for (keep, e) in triangle_edges(t) {
                let slot = &mut start[e[0] as usize];
                ends[if keep { *slot as usize } else { count }] = e;
                *slot += u32::from(keep);
            }
        }
        ends.truncate(count);
        Edges::from_ends(ends, num_vertices)
    }
}
