//! The sparse-solve library both solver paths call: the boxed LCP of a symmetric positive
//! definite system, in `f64`.
//!
//! Problem (BLCP): given `A = J M⁻¹ Jᵀ + E` (`E` the rows' softness), `b` and bounds
//! `lo ≤ hi`, find `x` and `w = A x − b` with, for each row, `lo ≤ x ≤ hi` and `w ≥ 0` where
//! `x = lo`, `w ≤ 0` where `x = hi`, `w = 0` between. A Coulomb row's bounds are `±μ λ_n`, its
//! normal row's force, moved inside the solve.
//!
//! * [`pattern`]: which constraint blocks couple (they share a dynamic body) and the
//!   elimination order (minimum degree) that keeps the factor's fill small (none for a tree);
//! * [`factor`]: the block layout over that pattern, `A x`, and the block Cholesky
//!   `A = L Lᵀ` with its forward and back solves, in time linear in a tree's rows;
//! * [`held_factor`]: that factorisation kept across pivots, with the rows held at a bound
//!   replaced by identity rows, refactorising only the islands a pivot touched;
//! * [`pivoting`]: block principal pivoting with a single-pivot fallback over the held
//!   factor, and the equality-only solve that needs no pivoting;
//! * [`lcp_dense`]: the same BLCP on a dense `A` (islands of redundant contacts);
//! * [`sets`]: the complementarity sets both pivotings keep, what violates them and the
//!   pivot rule (block pivoting while it gains, single pivoting once it cycles);
//! * [`tree`] (with `tree_order`, its analysis): the tree solve, for systems whose blocks
//!   join their bodies without a loop (chains, ragdolls, vehicles, stacks): the blocks in an
//!   elimination order with no fill, filled in place, factorised leaf to root, a change of
//!   held rows refactorising only the branch it is on; a [`pivoting::HeldSystem`] like the
//!   general system, so the same pivoting runs on both;
//! * [`joint_space`]: the reduced-coordinate path's joint-space inertia of a kinematic tree,
//!   `H = Lᵀ L` with no fill, leaf to root (the scalar counterpart of the tree solve);
//! * [`system`]: the borrowed view (`A` over its pattern and layout, `b`, friction links)
//!   that pivoting solves and the held factor factorises.
//!
//! The exact path (`solver/exact`) assembles an island's system and calls this; the iterative
//! path calls it for the split islands' joint rows inside its substeps
//! (`exact::SubstepSystem`, over the same assembly).

pub(crate) mod factor;
pub(crate) mod held_factor;
pub(crate) mod joint_space;
pub(crate) mod lcp_dense;
pub(crate) mod pattern;
pub(crate) mod pivoting;
mod sets;
pub(crate) mod system;
pub(crate) mod tree;
mod tree_order;

pub(crate) use pivoting::{LcpReport, Limits};

/// `a · b` over the shorter of the two in four running sums: a dense row's products are
/// independent, so four chains of additions run side by side instead of one waiting on the
/// last (the Delassus matrices and dense factors of small LCPs are latency bound otherwise).
/// The rounding differs from an in-order sum's; it is the same on every run.
#[inline]
pub(crate) fn dot_lanes(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ca
        .remainder()
        .iter()
        .zip(cb.remainder())
        .map(|(x, y)| x * y)
        .sum();
    let mut s = [0.0_f64; 4];
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            s[k] += x[k] * y[k];
        }
    }
    (s[0] + s[1]) + (s[2] + s[3]) + tail
}
