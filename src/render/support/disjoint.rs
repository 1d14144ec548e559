//! Disjoint sets of indices (union–find), for grouping things that touch: the runs of one cell's
//! pieces ([`crate::render::cells::pieces`]) and the flat cells of one flat area
//! ([`crate::render::looks::texture::frames`]). The lower index of two joined sets becomes the
//! root, so roots follow the indices' order whatever order the joins come in; finding a root halves
//! the path on the way.

/// Sets over the indices `0..n`, each at first alone.
pub(crate) struct DisjointSets {
    parent: Vec<u32>,
}

impl DisjointSets {
    /// `n` sets of one index each.
    pub(crate) fn new(n: usize) -> DisjointSets {
        DisjointSets {
            parent: (0..n as u32).collect(),
        }
    }

    /// The root of `i`'s set: its lowest index.
    pub(crate) fn root(&mut self, mut i: u32) -> u32 {
        while self.parent[i as usize] != i {
            let up = self.parent[self.parent[i as usize] as usize];
            self.parent[i as usize] = up;
            i = up;
        }
        i
    }

    /// Joins the sets of `a` and `b`.
    pub(crate) fn join(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.root(a), self.root(b));
        self.parent[ra.max(rb) as usize] = ra.min(rb);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joined_sets_share_their_lowest_root() {
        let mut sets = DisjointSets::new(6);
        sets.join(4, 2);
        sets.join(5, 4);
        sets.join(3, 1);
        let roots: Vec<u32> = (0..6).map(|i| sets.root(i)).collect();
        assert_eq!(roots, [0, 1, 2, 1, 2, 2]);
        sets.join(5, 3);
        assert!((1..6).all(|i| sets.root(i) == 1));
        assert_eq!(sets.root(0), 0);
    }
}
