//! The exact path for islands with contacts or Coulomb friction: the dense `A`, solved by the
//! dense boxed LCP (`lcp_dense`) with the friction bounds iterated around it. Contact piles
//! with redundant points are hard for principal pivoting, and this loop, one full LCP per set
//! of bounds, is the one their tests and scenes were tuned on (the block-sparse pivoting with
//! friction inside is tested but not yet as robust there); contact graphs also change every
//! few steps, where the sparse analysis pays off on graphs that last. Islands of joints alone
//! take the block-sparse path, whose cost is linear in a tree's rows.

// Dense kernels over row and block indices read clearest as index loops.
#![allow(clippy::needless_range_loop)]

use super::IslandRow;
use crate::solver::reserve;
use crate::solver::sparse::lcp_dense::{self as lcp, Bound, LcpWorkspace, Unknowns};
use crate::solver::sparse::pivoting::FrictionLink;
use crate::solver::{SolverParams, SolverStats};

/// An island's boxed LCP `A x = b + w`, `lo ≤ x ≤ hi`: the matrix (dense here, block-packed
/// on the sparse path), the right-hand side and bounds, the solution and slack, each row's
/// friction link and bound state. Both exact paths keep one, beside their pivoting's
/// workspace.
#[derive(Debug, Default, Clone)]
pub(crate) struct LcpArrays {
    pub(super) a: Vec<f64>,
    pub(super) b: Vec<f64>,
    pub(super) lo: Vec<f64>,
    pub(super) hi: Vec<f64>,
    pub(super) x: Vec<f64>,
    pub(super) w: Vec<f64>,
    pub(super) links: Vec<FrictionLink>,
    pub(super) state: Vec<Bound>,
}

impl LcpArrays {
    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        (self.a.capacity()
            + self.b.capacity()
            + self.lo.capacity()
            + self.hi.capacity()
            + self.x.capacity()
            + self.w.capacity())
            * 8
            + self.links.capacity() * std::mem::size_of::<FrictionLink>()
            + self.state.capacity()
    }
}

/// A dense island system and its LCP workspace.
#[derive(Debug, Default, Clone)]
pub(crate) struct DenseIsland {
    sys: LcpArrays,
    lcp: LcpWorkspace,
}

impl DenseIsland {
    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        self.sys.bytes() + self.lcp.bytes()
    }

    /// Makes room for islands of `n` rows, so that a step allocates nothing when one first
    /// reaches that size.
    pub(crate) fn reserve(&mut self, n: usize) {
        let s = &mut self.sys;
        reserve(&mut s.a, n * n);
        for v in [&mut s.b, &mut s.lo, &mut s.hi, &mut s.x, &mut s.w] {
            reserve(v, n);
        }
        reserve(&mut s.links, n);
        reserve(&mut s.state, n);
        self.lcp.reserve(n);
    }

    /// Fills `A = J M⁻¹ Jᵀ` for the rows (no softness on the diagonal yet).
    pub(crate) fn fill(&mut self, rows: &[IslandRow], links: &[FrictionLink]) {
        let n = rows.len();
        self.sys.links.clear();
        self.sys.links.extend_from_slice(&links[..n]);
        self.sys.a.clear();
        self.sys.a.resize(n * n, 0.0);
        for i in 0..n {
            let ri = rows[i];
            for j in i..n {
                let rj = &rows[j];
                let mut s = 0.0;
                for si in 0..2 {
                    let Some(bi) = ri.bodies[si] else { continue };
                    for sj in 0..2 {
                        if rj.bodies[sj] == Some(bi) {
                            s += ri.jac[2 * si].dot(rj.mj[2 * sj])
                                + ri.jac[2 * si + 1].dot(rj.mj[2 * sj + 1]);
                        }
                    }
                }
                self.sys.a[i * n + j] = s;
                self.sys.a[j * n + i] = s;
            }
        }
    }

    /// Row `i`'s diagonal entry.
    pub(crate) fn diagonal(&self, i: usize) -> f64 {
        self.sys.a[i * self.sys.links.len() + i]
    }

    /// Adds `v` to row `i`'s diagonal entry.
    pub(crate) fn add_diagonal(&mut self, i: usize, v: f64) {
        let n = self.sys.links.len();
        self.sys.a[i * n + i] += v;
    }

    /// Solves the BLCP with Coulomb bounds iterated outside the pivoting: solve, re-set the
    /// bounds from the normal forces, solve again while they move (at most
    /// `max_friction_passes` times); the answer goes to `x`.
    pub(crate) fn solve_with_friction(
        &mut self,
        b: &[f64],
        lo: &[f64],
        hi: &[f64],
        x: &mut [f64],
        params: &SolverParams,
        stats: &mut SolverStats,
    ) {
        let n = self.sys.links.len();
        self.start(b, lo, hi);
        let has_friction = self.sys.links.iter().any(Option::is_some);
        let mut trouble = Trouble::default();
        let mut friction_converged = !has_friction;
        let mut iterations_left = lcp::affordable_iterations(n);
        for _pass in 0..params.max_friction_passes {
            if iterations_left == 0 {
                trouble.capped = true;
                break;
            }
            let mut unknowns = Unknowns {
                lo: &mut self.sys.lo,
                hi: &mut self.sys.hi,
                x: &mut self.sys.x,
                w: &mut self.sys.w,
                state: &mut self.sys.state,
            };
            let cap = params.max_lcp_iterations.min(iterations_left);
            let system = (&self.sys.a[..], &self.sys.b[..]);
            let rep = lcp::solve(n, system, &mut unknowns, &mut self.lcp, cap);
            iterations_left -= rep.iterations.min(iterations_left);
            stats.friction_passes += 1;
            stats.lcp_iterations += rep.iterations;
            stats.pivots += rep.pivots;
            trouble.singular |= rep.singular;
            trouble.cycled = rep.cycled;
            trouble.capped = rep.capped && !rep.converged;
            if !has_friction || !self.move_friction_bounds() {
                friction_converged = true;
                break;
            }
        }
        if !friction_converged {
            // The last solve used the previous bounds: clamp friction to the final ones so the
            // Coulomb cone is never exceeded, and report.
            for i in 0..n {
                if self.sys.links[i].is_some() {
                    self.sys.x[i] = self.sys.x[i].clamp(self.sys.lo[i], self.sys.hi[i]);
                }
            }
            stats.friction_unconverged_islands += 1;
            log::warn!(
                "kea: Coulomb friction bounds still moving after {} re-solves",
                params.max_friction_passes
            );
        }
        trouble.report(n, params, stats);
        x.copy_from_slice(&self.sys.x);
    }

    /// The first pass's system: `b`, the bounds with friction unbounded (the sticking guess),
    /// `x = w = 0` and the bound states they give.
    fn start(&mut self, b: &[f64], lo: &[f64], hi: &[f64]) {
        let n = self.sys.links.len();
        self.sys.b.clear();
        self.sys.b.extend_from_slice(b);
        self.sys.lo.clear();
        self.sys.hi.clear();
        for i in 0..n {
            let (l, h) = match self.sys.links[i] {
                Some(_) => (f64::NEG_INFINITY, f64::INFINITY),
                None => (lo[i], hi[i]),
            };
            self.sys.lo.push(l);
            self.sys.hi.push(h);
        }
        for v in [&mut self.sys.x, &mut self.sys.w] {
            v.clear();
            v.resize(n, 0.0);
        }
        self.sys.state.clear();
        self.sys.state.resize(n, Bound::Free);
        lcp::initial_state(&self.sys.lo, &self.sys.hi, &mut self.sys.state);
    }

    /// Sets each friction row's bounds to `±μ λ_n` from its normal row's force; whether any
    /// moved (a first pass's infinite bounds always do).
    fn move_friction_bounds(&mut self) -> bool {
        let mut moved = false;
        for i in 0..self.sys.links.len() {
            if let Some((normal, mu)) = self.sys.links[i] {
                let bound = mu * self.sys.x[normal as usize].max(0.0);
                if (bound - self.sys.hi[i]).abs() > 1.0e-9 * (1.0 + bound)
                    || self.sys.hi[i].is_infinite()
                {
                    moved = true;
                }
                self.sys.lo[i] = -bound;
                self.sys.hi[i] = bound;
            }
        }
        moved
    }
}

/// What went wrong in an island's dense solves, counted and logged once.
#[derive(Default)]
struct Trouble {
    singular: bool,
    cycled: bool,
    capped: bool,
}

impl Trouble {
    fn report(&self, n: usize, params: &SolverParams, stats: &mut SolverStats) {
        if self.singular {
            stats.singular_islands += 1;
            log::warn!("kea: singular constraint system ({n} rows) regularised: redundant constraints with too small epsilon?");
        }
        if self.cycled {
            stats.cycled_islands += 1;
            log::warn!("kea: LCP pivoting cycle detected ({n} rows)");
        }
        if self.capped {
            stats.capped_islands += 1;
            log::warn!(
                "kea: LCP iteration cap {} reached ({n} rows)",
                params.max_lcp_iterations
            );
        }
    }
}
