//! The factorisation the pivoting solves with, kept across solves: `A` with the rows held at a
//! bound replaced by identity rows (their diagonal kept), so the pattern never changes.
//!
//! A system is often several independent islands at once (the joints of every split island in
//! one system), and a pivot moves rows of one of them. So the factorisation is kept with the
//! values' stamp and the held set it was made for: the same values and set reuse it whole, and
//! a changed set refactorises only the connected components whose rows changed (a component's
//! elimination touches only its own blocks).

use super::factor::factorise;
use super::sets::Bound;
use super::system::System;

/// The kept factorisation (module docs).
#[derive(Debug, Default, Clone)]
pub(crate) struct HeldFactor {
    /// `L`, over the system's pattern and layout.
    pub(crate) factor: Vec<f64>,
    /// Stamp of the values `factor` was made from (0: none) and the held set it was made for.
    stamp: u64,
    state: Vec<Bound>,
    /// Whether a pivot was regularised in the factorisation of each component.
    singular: Vec<bool>,
    /// Each block position's connected component, for the pattern of `component_stamp`.
    component: Vec<u32>,
    component_stamp: u64,
    /// Scratch: components to refactorise, positions to refactorise.
    dirty: Vec<bool>,
    positions: Vec<bool>,
}

impl HeldFactor {
    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        self.factor.capacity() * 8
            + self.state.capacity()
            + self.singular.capacity()
            + self.component.capacity() * 4
            + self.dirty.capacity()
            + self.positions.capacity()
    }

    /// Makes `factor` the factorisation of `sys` with the rows of `state` held, reusing what it
    /// can (module docs). Pivots not above `tiny` become `floor`; returns whether any component
    /// had one.
    pub(crate) fn update(
        &mut self,
        sys: &System<'_>,
        state: &[Bound],
        tiny: f64,
        floor: f64,
    ) -> bool {
        let blocks = sys.pattern.len();
        let same_values = sys.stamp != 0 && self.stamp == sys.stamp;
        if same_values && self.state.as_slice() == state {
            return self.singular.iter().any(|&s| s);
        }
        if sys.stamp == 0 || self.component_stamp != sys.stamp {
            self.find_components(sys);
            self.component_stamp = sys.stamp;
        }
        let components = self.singular.len();
        self.dirty.clear();
        self.dirty.resize(components, !same_values);
        if same_values {
            for k in 0..blocks {
                let (first, size) = sys.layout.rows(k);
                if self.state[first..first + size] != state[first..first + size] {
                    self.dirty[self.component[k] as usize] = true;
                }
            }
        } else {
            self.factor.resize(sys.layout.values(), 0.0);
        }
        self.positions.clear();
        self.positions
            .extend((0..blocks).map(|k| self.dirty[self.component[k] as usize]));
        self.load(sys, state);
        let singular = factorise(
            sys.pattern,
            sys.layout,
            &mut self.factor,
            tiny,
            floor,
            Some(&self.positions),
        );
        for (c, s) in self.singular.iter_mut().enumerate() {
            if self.dirty[c] {
                *s = false;
            }
        }
        // A regularised pivot is reported for every component refactorised this time.
        if singular {
            for (c, s) in self.singular.iter_mut().enumerate() {
                *s |= self.dirty[c];
            }
        }
        self.stamp = sys.stamp;
        self.state.clear();
        self.state.extend_from_slice(state);
        self.singular.iter().any(|&s| s)
    }

    /// Copies the values of the positions to refactorise into `factor`, with held rows and
    /// columns cleared to identity rows.
    fn load(&mut self, sys: &System<'_>, state: &[Bound]) {
        let is_held = |i: usize| state[i] != Bound::Free;
        for k in 0..sys.pattern.len() {
            if !self.positions[k] {
                continue;
            }
            let (fk, sk) = sys.layout.rows(k);
            let d = sys.layout.offset(k);
            for r in 0..sk {
                for c in 0..sk {
                    let v = sys.a[d + r * sk + c];
                    let held = is_held(fk + r) || is_held(fk + c);
                    self.factor[d + r * sk + c] = if !held || r == c { v } else { 0.0 };
                }
            }
            for (e, &a) in sys.pattern.later(k).iter().enumerate() {
                let (fa, sa) = sys.layout.rows(a as usize);
                let at = sys.layout.offset(sys.pattern.off_slot(k, e));
                for r in 0..sa {
                    for c in 0..sk {
                        let held = is_held(fa + r) || is_held(fk + c);
                        self.factor[at + r * sk + c] =
                            if held { 0.0 } else { sys.a[at + r * sk + c] };
                    }
                }
            }
        }
    }

    /// Labels each block position with its connected component (union-find over the pattern's
    /// couplings), numbered from 0 in order of first position.
    fn find_components(&mut self, sys: &System<'_>) {
        let n = sys.pattern.len();
        // `component` first serves as the union-find parents.
        self.component.clear();
        self.component.extend(0..n as u32);
        fn root(parent: &mut [u32], mut k: u32) -> u32 {
            while parent[k as usize] != k {
                let up = parent[parent[k as usize] as usize];
                parent[k as usize] = up;
                k = up;
            }
            k
        }
        for k in 0..n {
            for &a in sys.pattern.later(k) {
                let (x, y) = (
                    root(&mut self.component, k as u32),
                    root(&mut self.component, a),
                );
                if x != y {
                    self.component[x.max(y) as usize] = x.min(y);
                }
            }
        }
        // Every position to its root (the smallest position of its set: roots come first, so
        // each ancestor is already resolved), then roots get consecutive numbers in order.
        for k in 0..n {
            let r = root(&mut self.component, k as u32);
            self.component[k] = r;
        }
        const LABEL: u32 = 1 << 31;
        let mut count = 0u32;
        for k in 0..n {
            let r = self.component[k] as usize;
            self.component[k] = if r == k {
                count += 1;
                (count - 1) | LABEL
            } else {
                self.component[r]
            };
        }
        for c in &mut self.component {
            *c &= !LABEL;
        }
        self.singular.clear();
        self.singular.resize(count as usize, false);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::sparse::factor::tests::{rnd, RandomIsland};
    use crate::solver::sparse::factor::Layout;
    use crate::solver::sparse::pattern::PatternCache;

    /// Refactorising only the components whose held rows changed gives the same bits as a
    /// fresh factorisation, on random systems of several components (many bodies, few blocks).
    #[test]
    fn partial_refactorisation_matches_a_fresh_one() {
        let mut seed = 11u64;
        for case in 0..60 {
            let island = RandomIsland::new(&mut seed, 4 + case % 13, 8 + case % 9, case % 2 == 0);
            let n = island.rows();
            let mut cache = PatternCache::default();
            let pattern = cache.get(&island.key, &island.size, island.bodies);
            let mut layout = Layout::default();
            layout.build(pattern, &island.first, &island.size);
            let a = island.values(pattern, &layout);
            let b = vec![0.0; n];
            let sys = System {
                pattern,
                layout: &layout,
                a: &a,
                b: &b,
                links: &[],
                stamp: 7,
            };
            let random_state = |seed: &mut u64| -> Vec<Bound> {
                (0..n)
                    .map(|_| match rnd(seed) {
                        x if x < -0.5 => Bound::Lower,
                        x if x > 0.6 => Bound::Upper,
                        _ => Bound::Free,
                    })
                    .collect()
            };
            let first = random_state(&mut seed);
            let mut second = first.clone();
            // Change a few rows only.
            for _ in 0..2 {
                let i = ((rnd(&mut seed) + 1.0) * 0.5 * n as f64) as usize % n;
                second[i] = if second[i] == Bound::Free {
                    Bound::Lower
                } else {
                    Bound::Free
                };
            }
            let mut kept = HeldFactor::default();
            kept.update(&sys, &first, 1e-13, 1e-9);
            kept.update(&sys, &second, 1e-13, 1e-9);
            let mut fresh = HeldFactor::default();
            fresh.update(&sys, &second, 1e-13, 1e-9);
            assert_eq!(kept.factor, fresh.factor, "case {case}");
            assert!(!kept.singular.is_empty());
        }
    }
}
