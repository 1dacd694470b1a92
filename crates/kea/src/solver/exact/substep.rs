//! The direct solve of joint rows inside the iterative path's substeps (split islands): the
//! rows of the island's joints, written at the present poses, as one block-sparse system
//! `(J M⁻¹ Jᵀ + E) y = b` over the same analysis, factorisation and pivoting as the exact
//! path, while the island's contacts run in the contact solver around it.
//!
//! The caller (the iterative path's joint rows) adds its rows block by block (their count,
//! softness and friction links, and its bodies' slots), calls [`SubstepSystem::assemble`] once
//! per linearisation with a reader of each row's Jacobian and `M⁻¹Jᵀ`, which a tree's solve
//! takes straight into its storage in elimination order (no copy of the rows in between), and
//! then solves for the rows' impulses as often as it likes with different right-hand sides
//! (the biased solve and the relax of a substep share one matrix).

use super::{ExactWorkspace, RowValues};
use crate::solver::sparse::pattern::BlockBodies;
use crate::solver::sparse::pivoting::{self, FrictionLink, LcpReport, Limits};

/// A relative compliance added to every row's diagonal: redundant joints (two hinges on one
/// axis) keep a solvable system, at a stiffness no step can tell from rigid.
const REGULARISATION: f64 = 1.0e-9;

/// The relative compliance of every row of a system whose joints close loops (its blocks do
/// not form a forest). A flat net of ball joints is over-constrained in its plane (a 10×10
/// net: 364 in-plane rows on 300 in-plane freedoms), and once bent its rows are nearly
/// redundant and their errors inconsistent: at 1e-9 every solve amplified the inconsistency
/// until the factor overflowed and the net fell apart; at 1e-6 it held to 3 mm but never
/// settled. At 1e-4 the redundant rows share the load as stiff springs would (a joint yields
/// by 1e-4 of what its effective mass takes, far below a step's motion): the net settles,
/// 0.04 mm worst; 1e-3 gave 0.07 mm, 1e-2 0.12 mm. Trees keep [`REGULARISATION`].
const LOOP_COMPLIANCE: f64 = 1.0e-4;

/// The system of the split islands' joint rows (see the module docs).
#[derive(Debug, Default, Clone)]
pub(crate) struct SubstepSystem {
    ws: ExactWorkspace,
    /// Rows added.
    count: usize,
    extra: Vec<f64>,
    /// `A·y₀` for the current impulses `y₀`.
    product: Vec<f64>,
    /// One pass's residuals, bounds and impulses (present on entry, solved on return), row by
    /// row as [`SubstepSystem::push`] gave them.
    r: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    y: Vec<f64>,
}

impl SubstepSystem {
    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        self.ws.bytes()
            + (self.extra.capacity()
                + self.product.capacity()
                + self.r.capacity()
                + self.lo.capacity()
                + self.hi.capacity()
                + self.y.capacity())
                * 8
    }

    /// Starts over with no rows, for bodies numbered below `bodies`.
    pub(crate) fn clear(&mut self, bodies: usize) {
        let ws = &mut self.ws;
        for &b in &ws.island_bodies {
            ws.local_body[b as usize] = u32::MAX;
        }
        ws.rows.clear();
        ws.sys.links.clear();
        ws.block_first.clear();
        ws.block_size.clear();
        ws.block_key.clear();
        ws.island_bodies.clear();
        if ws.local_body.len() < bodies {
            ws.local_body.resize(bodies, u32::MAX);
        }
        self.extra.clear();
        self.count = 0;
    }

    /// Rows in the system.
    pub(crate) fn len(&self) -> usize {
        self.count
    }

    /// Adds one block of rows acting on the bodies in `slots` (`u32::MAX`: none, or a body
    /// that cannot move), each row given by its softness and slip on the diagonal (in the
    /// system's units) and its friction link (a Coulomb row: its normal row, an index into this
    /// system, and μ). A block must have at least one row.
    pub(crate) fn add_block(
        &mut self,
        slots: [u32; 2],
        rows: impl Iterator<Item = (f64, FrictionLink)>,
    ) {
        let ws = &mut self.ws;
        let base = self.count as u32;
        for (extra, link) in rows {
            ws.sys.links.push(link);
            self.extra.push(extra);
            self.count += 1;
        }
        let size = self.count as u32 - base;
        debug_assert!(size > 0, "a block has rows");
        let key: BlockBodies = slots.map(|s| {
            if s == u32::MAX {
                return u32::MAX;
            }
            let local = &mut ws.local_body[s as usize];
            if *local == u32::MAX {
                *local = ws.island_bodies.len() as u32;
                ws.island_bodies.push(s);
            }
            *local
        });
        ws.block_first.push(base);
        ws.block_size.push(size);
        ws.block_key.push(key);
    }

    /// Builds `A = J M⁻¹ Jᵀ + E` for the rows added, row `i`'s Jacobian and `M⁻¹Jᵀ` read from
    /// `row(i)` (their analysis from the cache while the blocks' graph is unchanged).
    pub(crate) fn assemble(&mut self, row: impl Fn(usize) -> RowValues) {
        let ws = &mut self.ws;
        if self.count == 0 {
            return;
        }
        ws.assemble_matrix_by(Some(row));
        let reg = if ws.tree_now {
            REGULARISATION
        } else {
            LOOP_COMPLIANCE
        };
        for (i, &extra) in self.extra.iter().enumerate() {
            let d = ws.diagonal(i);
            ws.add_diagonal(i, extra + reg * d);
        }
    }

    /// Starts a pass: no row's right-hand side given yet.
    pub(crate) fn begin_pass(&mut self) {
        self.r.clear();
        self.lo.clear();
        self.hi.clear();
        self.y.clear();
    }

    /// Gives the next row its residual `r`, bounds `[lo, hi]` and present impulse `y0`.
    pub(crate) fn push(&mut self, r: f64, lo: f64, hi: f64, y0: f64) {
        self.r.push(r);
        self.lo.push(lo);
        self.hi.push(hi);
        self.y.push(y0);
    }

    /// Row `s`'s impulse: as pushed, or as solved after [`SubstepSystem::solve`].
    pub(crate) fn impulse(&self, s: usize) -> f64 {
        self.y[s]
    }

    /// Solves for the impulses `y` within `[lo, hi]` (Coulomb rows: `±μ·y_normal`) such that
    /// `A (y − y₀) = r`, where `y₀` are the present impulses and `r` the rows' residuals
    /// given by [`SubstepSystem::push`]; warm started from the sets `y₀` lies in.
    pub(crate) fn solve(&mut self, limits: Limits) -> LcpReport {
        let ws = &mut self.ws;
        let (r, lo, hi, y) = (&self.r, &self.lo, &self.hi, &mut self.y);
        let n = self.count;
        if n == 0 {
            return LcpReport {
                converged: true,
                ..LcpReport::default()
            };
        }
        ws.fit_vectors(n);
        let equalities = ws.sys.links.iter().all(Option::is_none)
            && lo.iter().all(|&l| l == f64::NEG_INFINITY)
            && hi.iter().all(|&h| h == f64::INFINITY);
        if equalities {
            // Equalities first: `A (y − y₀) = r` straight through the factor, no pivoting.
            ws.sys.x[..n].copy_from_slice(&r[..n]);
            let report = if ws.tree_now {
                pivoting::solve_equalities_on(&mut *ws.tree, &mut ws.sys.state, &mut ws.sys.x)
            } else {
                let (system, unknowns, lcp) = ws.split();
                pivoting::solve_equalities(&system, unknowns.state, unknowns.x, lcp)
            };
            for (yi, dx) in y[..n].iter_mut().zip(&ws.sys.x[..n]) {
                *yi += dx;
            }
            return report;
        }
        if ws.sys.links.iter().all(Option::is_none) {
            // No Coulomb row: solved for the change `Δ = y − y₀`, `A Δ = r` within
            // `[lo − y₀, hi − y₀]`, which needs no product with `A`.
            for i in 0..n {
                ws.sys.b[i] = r[i];
                (ws.sys.lo[i], ws.sys.hi[i]) = (lo[i] - y[i], hi[i] - y[i]);
                ws.sys.x[i] = 0.0;
                ws.sys.state[i] = pivoting::state_from_guess(ws.sys.lo[i], ws.sys.hi[i], 0.0);
            }
            let report = ws.pivot(limits);
            for (yi, dx) in y[..n].iter_mut().zip(&ws.sys.x[..n]) {
                *yi += dx;
            }
            return report;
        }
        self.product.clear();
        self.product.resize(n, 0.0);
        ws.multiply(y, &mut self.product);
        for i in 0..n {
            ws.sys.b[i] = r[i] + self.product[i];
            (ws.sys.lo[i], ws.sys.hi[i]) = match ws.sys.links[i] {
                Some((normal, mu)) => {
                    let bound = mu * y[normal as usize].max(0.0);
                    if bound > 0.0 {
                        (-bound, bound)
                    } else {
                        (f64::NEG_INFINITY, f64::INFINITY)
                    }
                }
                None => (lo[i], hi[i]),
            };
            ws.sys.x[i] = y[i];
            ws.sys.state[i] = pivoting::state_from_guess(ws.sys.lo[i], ws.sys.hi[i], y[i]);
        }
        let report = ws.pivot(limits);
        y[..n].copy_from_slice(&ws.sys.x[..n]);
        report
    }
}
