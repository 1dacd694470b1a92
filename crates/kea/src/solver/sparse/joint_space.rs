//! The joint-space factorisation of a kinematic tree (the reduced-coordinate path's `H q̈ = τ`):
//! `H = Lᵀ L` with no fill, the scalar counterpart of the tree solve's block factorisation.
//!
//! Coordinates are numbered so that every coordinate's parent comes before it. `H_ij` is then
//! non-zero only where `i` and `j` lie on one path to the root (a link's inertia couples only
//! the coordinates that move it), and eliminating from the highest number down — leaf to root
//! — touches only those entries: each coordinate `k` divides the entries of its ancestors in
//! row `k` by its pivot, then subtracts their products from the ancestors' rows, so the factor
//! has the sparsity of `H` (Featherstone's `LᵀL` factorisation, RBDA §6.5). Cost: the sum over
//! coordinates of their depth squared, against `n³/3` for a dense Cholesky — a legged robot's
//! 30 coordinates on branches 6 deep cost ~1,000 multiplications rather than 9,000.
//!
//! Storage is packed ([`Ancestry::packed_len`] numbers): each coordinate's diagonal, then
//! each coordinate's entries against its ancestors in [`Ancestry::of`]'s order. Coordinate
//! `k`'s ancestors from `a` on are `a`'s own ancestors, so row `a` lines up with the tail of
//! row `k`: the factor's updates run over contiguous slices (as MuJoCo's sparse `qLD`).

use std::ops::Range;

/// Factorises `h` (packed, symmetric positive definite) in place into the `L` of
/// `H = Lᵀ L`, each diagonal entry held as its reciprocal. On a pivot not clearly positive,
/// returns the coordinate it belongs to.
pub(crate) fn factor(h: &mut [f64], tree: &Ancestry) -> Result<(), usize> {
    let n = tree.len();
    let (diag, off) = h.split_at_mut(n);
    for k in (0..n).rev() {
        let d = diag[k];
        if d.is_nan() || d <= 0.0 {
            return Err(k);
        }
        // The pivot is kept as its reciprocal: the solves' serial chains multiply instead of
        // divide.
        let inv = 1.0 / d.sqrt();
        diag[k] = inv;
        let at = tree.start[k] as usize;
        let (before, from_k) = off.split_at_mut(at);
        let row_k = &mut from_k[..tree.start[k + 1] as usize - at];
        row_k.iter_mut().for_each(|x| *x *= inv);
        for (x, &a) in tree.of(k).iter().enumerate() {
            let a = a as usize;
            let lka = row_k[x];
            diag[a] -= lka * lka;
            // `a`'s own ancestors: the rest of `k`'s row after `a`.
            let row_a = &mut before[tree.start[a] as usize..tree.start[a + 1] as usize];
            for (y, lkb) in row_a.iter_mut().zip(&row_k[x + 1..]) {
                *y -= lka * lkb;
            }
        }
    }
    Ok(())
}

/// Solves `Lᵀ L x = b` with the factor [`factor`] left in `l`; `b` is overwritten by `x`.
pub(crate) fn solve(l: &[f64], tree: &Ancestry, b: &mut [f64]) {
    solve_transposed(l, tree, b);
    solve_factor(l, tree, b);
}

/// The first half of [`solve`]: `Lᵀ y = b`, leaf to root, `b` becoming `y` (so that
/// `bᵀ (LᵀL)⁻¹ c` is the dot of the two halves).
pub(crate) fn solve_transposed(l: &[f64], tree: &Ancestry, b: &mut [f64]) {
    for k in (0..tree.len()).rev() {
        b[k] *= l[k];
        let bk = b[k];
        for (&a, lka) in tree.of(k).iter().zip(&l[tree.packed_row(k)]) {
            b[a as usize] -= lka * bk;
        }
    }
}

/// [`solve_transposed`] for a `b` that is zero but on the path from `leaf` to the root (a
/// point's Jacobian on one link): only that path is visited, leaf to root.
pub(crate) fn solve_transposed_path(l: &[f64], tree: &Ancestry, leaf: usize, b: &mut [f64]) {
    let path = tree.of(leaf);
    for x in 0..=path.len() {
        let k = if x == 0 { leaf } else { path[x - 1] as usize };
        b[k] *= l[k];
        let bk = b[k];
        for (&a, lka) in path[x..].iter().zip(&l[tree.packed_row(k)]) {
            b[a as usize] -= lka * bk;
        }
    }
}

/// The second half of [`solve`]: `L x = y`, root to leaf, `b` becoming `x`.
fn solve_factor(l: &[f64], tree: &Ancestry, b: &mut [f64]) {
    for k in 0..tree.len() {
        let mut s = b[k];
        for (&a, lka) in tree.of(k).iter().zip(&l[tree.packed_row(k)]) {
            s -= lka * b[a as usize];
        }
        b[k] = s * l[k];
    }
}

/// Adds the packed symmetric `h` into the dense row-major `dense` (`n × n`).
pub(crate) fn add_to_dense(h: &[f64], tree: &Ancestry, dense: &mut [f64]) {
    let n = tree.len();
    for k in 0..n {
        dense[k * n + k] += h[k];
        for (&a, v) in tree.of(k).iter().zip(&h[tree.packed_row(k)]) {
            let a = a as usize;
            dense[k * n + a] += v;
            dense[a * n + k] += v;
        }
    }
}

/// Each coordinate's ancestors, nearest first, in one flat list: the factor's loops run over
/// slices instead of chasing parents one load at a time.
#[derive(Debug, Default, PartialEq)]
pub(crate) struct Ancestry {
    start: Vec<u32>,
    list: Vec<u32>,
}

impl Clone for Ancestry {
    fn clone(&self) -> Self {
        Self {
            start: self.start.clone(),
            list: self.list.clone(),
        }
    }

    /// Reuses this one's buffers (a world's state copied into another allocates nothing).
    fn clone_from(&mut self, source: &Self) {
        self.start.clone_from(&source.start);
        self.list.clone_from(&source.list);
    }
}

impl Ancestry {
    /// The ancestry of a tree whose coordinate `k` has parent `parents[k]` (below `k`),
    /// reusing this one's buffers.
    pub(crate) fn refill(&mut self, parents: &[Option<usize>]) {
        self.start.clear();
        self.list.clear();
        if parents.is_empty() {
            return; // nothing to hold (an empty tree, made in passing, allocates nothing)
        }
        for k in 0..parents.len() {
            self.start.push(self.list.len() as u32);
            let mut i = parents[k];
            while let Some(a) = i {
                self.list.push(a as u32);
                i = parents[a];
            }
        }
        self.start.push(self.list.len() as u32);
    }

    /// Number of coordinates.
    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// Numbers in a packed matrix of the tree (module docs).
    pub(crate) fn packed_len(&self) -> usize {
        self.len() + self.list.len()
    }

    /// Where coordinate `k`'s entries against its ancestors lie in a packed matrix, in
    /// [`Ancestry::of`]'s order (its diagonal is entry `k`).
    #[inline]
    pub(crate) fn packed_row(&self, k: usize) -> Range<usize> {
        let n = self.len();
        n + self.start[k] as usize..n + self.start[k + 1] as usize
    }

    /// Coordinate `k`'s ancestors, nearest first.
    #[inline]
    pub(crate) fn of(&self, k: usize) -> &[u32] {
        &self.list[self.start[k] as usize..self.start[k + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::sparse::factor::tests::rnd;

    /// A random tree of `n` coordinates (each parent below its child) and an `H` with its
    /// sparsity: `Σ` over links of `J_lᵀ J_l` plus a positive diagonal, where link `l` moves
    /// the coordinates on its path to the root.
    fn random_tree(seed: &mut u64, n: usize) -> (Vec<Option<usize>>, Vec<f64>) {
        let parent: Vec<Option<usize>> = (0..n)
            .map(|k| {
                if k == 0 || rnd(seed) < -0.6 {
                    None
                } else {
                    Some(((rnd(seed) * 0.5 + 0.5) * k as f64) as usize % k)
                }
            })
            .collect();
        let mut h = vec![0.0; n * n];
        for link in 0..n {
            for _ in 0..3 {
                let mut path = Vec::new();
                let mut c = Some(link);
                while let Some(k) = c {
                    path.push((k, rnd(seed)));
                    c = parent[k];
                }
                for &(i, ji) in &path {
                    for &(j, jj) in &path {
                        h[i * n + j] += ji * jj;
                    }
                }
            }
            h[link * n + link] += 0.1 + rnd(seed).abs();
        }
        (parent, h)
    }

    #[test]
    fn the_tree_factorisation_solves_as_the_dense_matrix_multiplies() {
        let mut seed = 11u64;
        for case in 0..200 {
            let n = 1 + case % 17;
            let (parent, h) = random_tree(&mut seed, n);
            let x_true: Vec<f64> = (0..n).map(|_| rnd(&mut seed)).collect();
            let mut b: Vec<f64> = (0..n)
                .map(|i| (0..n).map(|j| h[i * n + j] * x_true[j]).sum())
                .collect();
            let mut tree = Ancestry::default();
            tree.refill(&parent);
            // Packed, then unpacked: `H` has the tree's sparsity (nothing off its paths).
            let mut l = vec![0.0; tree.packed_len()];
            for k in 0..n {
                l[k] = h[k * n + k];
                for (&a, v) in tree.of(k).iter().zip(&mut l[tree.packed_row(k)]) {
                    *v = h[k * n + a as usize];
                }
            }
            let mut dense = vec![0.0; n * n];
            add_to_dense(&l, &tree, &mut dense);
            assert_eq!(dense, h, "case {case}: packed and back");
            factor(&mut l, &tree).unwrap();
            solve(&l, &tree, &mut b);
            for i in 0..n {
                assert!(
                    (b[i] - x_true[i]).abs() < 1e-9 * (1.0 + x_true[i].abs()),
                    "case {case}: x[{i}] = {} for {}",
                    b[i],
                    x_true[i]
                );
            }
        }
    }

    #[test]
    fn a_matrix_not_positive_definite_is_refused_with_its_coordinate() {
        // A chain of two with a zero pivot at the leaf (packed: diagonals 1 and 0, H₁₀ = 0).
        let mut h = vec![1.0, 0.0, 0.0];
        let mut tree = Ancestry::default();
        tree.refill(&[None, Some(0)]);
        assert_eq!(factor(&mut h, &tree), Err(1));
    }
}
