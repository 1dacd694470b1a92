//! Disjoint sets over `0..n` with path halving, on reusable storage. Roots are always the lowest
//! index of their set, so set identities do not depend on the order of unions (determinism).

#[derive(Debug, Default, Clone)]
pub(crate) struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    pub(crate) fn reserve(&mut self, n: usize) {
        if self.parent.capacity() < n {
            self.parent.reserve(n - self.parent.len());
        }
    }

    pub(crate) fn bytes(&self) -> usize {
        self.parent.capacity() * 4
    }

    /// Makes `n` singleton sets.
    pub(crate) fn reset(&mut self, n: usize) {
        self.parent.clear();
        self.parent.extend(0..n as u32);
    }

    pub(crate) fn find(&mut self, mut i: u32) -> u32 {
        while self.parent[i as usize] != i {
            let gp = self.parent[self.parent[i as usize] as usize];
            self.parent[i as usize] = gp;
            i = gp;
        }
        i
    }

    pub(crate) fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.parent[hi as usize] = lo;
        }
    }
}
