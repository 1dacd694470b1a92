//! The exact island solve: assemble the island's system `A + εI` and `b` in `f64` as a
//! block-sparse matrix, solve the boxed LCP with Coulomb friction inside, and hand the forces
//! back.
//!
//! Assembly. Rows come in blocks (a joint's, a contact's); for rows i, j and each dynamic body
//! k their blocks share, `A_ij += J_ik · M_k⁻¹ J_jkᵀ` with `M_k⁻¹ = diag(1/m_k, I_w,k⁻¹)`; then
//! `A_ii += ε_i + s_i/h` (softness and slip) and `b_i = (c_i − γ_i·xi_i/h − J_i·v_f)/h`. Only
//! blocks that share a body couple, so `A` is sparse: the sparse library's [`pattern`](crate::solver::sparse::pattern) orders the blocks so that
//! factorising creates little or no fill (none for a tree), [`factor`](crate::solver::sparse::factor) factorises, and
//! [`pivoting`] solves the LCP over that fixed structure, warm started from last step's forces.
//! A chain or an articulated tree costs time linear in its rows.
//!
//! Islands of contacts only whose blocks form a forest (a stack of boxes: no body reached
//! twice through the blocks) take the block-sparse path too, friction inside the pivoting:
//! their factor has no fill, so a column of 40 boxes (480 rows) costs a fraction of a
//! millisecond where the dense LCP took 30. Their normal rows with no force of their own yet
//! start free, as if carrying load: a column that appears at rest then settles in one solve,
//! where starting them at rest wakes the contacts one block pivot at a time from the ground
//! up. A stack whose pivoting does not settle (sliding, the Coulomb bounds move under it) is
//! handed back unsolved, and the contact solver takes it for the step. Other islands with
//! contacts take the dense path ([`dense`]): the dense LCP with
//! the Coulomb bounds `±μ·max(λₙ, 0)` iterated around it; on a pile with loops (a pyramid)
//! the block-sparse pivoting fills in and does not converge as reliably as that loop.

// Dense kernels over row and block indices read clearest as index loops.
#![allow(clippy::needless_range_loop)]

mod assembly;
mod components;
mod contacts;
mod dense;
mod project;
mod sparsity;
mod substep;

use super::integrate::BodyScratch;
use super::{
    block_reactions, reserve, ConstraintBlock, Reaction, SolverBody, SolverParams, SolverStats,
};
use crate::constraint::Row;
use crate::math::{to_f64, wide, DVec3, Real};
use crate::solver::sparse::factor::Layout;
use crate::solver::sparse::pattern::{BlockBodies, PatternCache};
use crate::solver::sparse::pivoting::{self, FrictionLink, LcpWorkspace, System, Unknowns};
use crate::solver::sparse::tree::TreeSystem;
pub(crate) use crate::solver::sparse::{LcpReport, Limits};
pub(crate) use components::ComponentSystems;
use substep::SubstepSystem;

/// A row's Jacobian and `M⁻¹Jᵀ` in `f64`, linear then angular, per body slot.
pub(crate) type RowValues = ([DVec3; 4], [DVec3; 4]);

/// One island row in `f64`: Jacobian and M⁻¹Jᵀ per body slot.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct IslandRow {
    pub(crate) global: u32,
    pub(crate) bodies: [Option<u32>; 2],
    pub(crate) jac: [DVec3; 4],
    pub(crate) mj: [DVec3; 4],
}

/// What an island solve reads: the step's constraint blocks and rows, its bodies and its
/// parameters.
#[derive(Clone, Copy)]
pub(crate) struct IslandInputs<'a> {
    pub(crate) blocks: &'a [ConstraintBlock],
    pub(crate) rows: &'a [Row],
    pub(crate) bodies: &'a [SolverBody],
    pub(crate) params: &'a SolverParams,
}

/// Workspace for island solves; grows to the largest island seen.
#[derive(Debug, Default, Clone)]
pub(crate) struct ExactWorkspace {
    /// An island's joint rows and its contacts' rows together (contacts reach the exact path
    /// as contacts and are written as rows here).
    mixed: contacts::MixedIsland,
    rows: Vec<IslandRow>,
    /// The island's blocks: first row, row count, the dynamic bodies they touch (island-local
    /// numbers) and, per local body, the blocks that touch it and in which slot.
    block_first: Vec<u32>,
    block_size: Vec<u32>,
    block_key: Vec<BlockBodies>,
    block_position: Vec<u32>,
    local_body: Vec<u32>,
    island_bodies: Vec<u32>,
    body_start: Vec<u32>,
    body_entries: Vec<(u32, u8)>,
    patterns: PatternCache,
    layout: Layout,
    /// The block-sparse system (`a` block-packed by `layout`).
    sys: dense::LcpArrays,
    lcp: LcpWorkspace,
    dense: dense::DenseIsland,
    /// The island being solved has contacts (and so takes the dense path).
    with_contacts: bool,
    /// The system last filled is the dense one ([`ExactWorkspace::fill_system`]).
    dense_now: bool,
    /// The tree solve, and whether the block-sparse system last filled is on it (its blocks
    /// join the bodies without a loop) rather than on the general pattern. Boxed: a world
    /// must still fit on a 64 KiB thread stack while it is made.
    tree: Box<TreeSystem>,
    tree_now: bool,
    /// Union-find scratch of [`ExactWorkspace::blocks_form_forest`].
    forest: Vec<u32>,
    /// The first row of the island's contacts (in the rows the island was gathered from):
    /// their normal rows without a warm force start free, as if carrying load.
    contact_rows_from: Option<u32>,
    /// Counts assemblies of `a`, so that a factorisation of the same values can be reused.
    stamp: u64,
}

/// Values of the block-sparse system a row is budgeted for in [`ExactWorkspace::bytes_for`]:
/// its own block's row (up to 12) and the rows of the blocks it couples to (a few).
const VALUES_PER_ROW: usize = 48;

impl ExactWorkspace {
    /// Reserves room for islands of `island_rows` rows, joints and contacts together.
    pub(crate) fn reserve_mixed(&mut self, island_rows: usize) {
        self.mixed.reserve(island_rows);
    }

    /// The per-row vectors of the system: `b`, the bounds, `x` and `w`.
    fn row_vectors(&mut self) -> [&mut Vec<f64>; 5] {
        [
            &mut self.sys.b,
            &mut self.sys.lo,
            &mut self.sys.hi,
            &mut self.sys.x,
            &mut self.sys.w,
        ]
    }

    pub(crate) fn reserve(&mut self, _rows: usize, island_rows: usize) {
        let n = island_rows;
        reserve(&mut self.rows, n);
        for v in self.row_vectors() {
            reserve(v, n);
        }
        reserve(&mut self.sys.links, n);
        reserve(&mut self.sys.state, n);
        reserve(&mut self.forest, n);
        self.dense
            .reserve(n.min(crate::solver::DENSE_EXACT_MAX_ROWS as usize));
        self.tree.reserve(n);
    }

    pub(crate) fn bytes(&self) -> usize {
        self.mixed.bytes()
            + self.rows.capacity() * std::mem::size_of::<IslandRow>()
            + (self.block_first.capacity()
                + self.block_size.capacity()
                + self.block_position.capacity()
                + self.local_body.capacity()
                + self.island_bodies.capacity()
                + self.body_start.capacity()
                + self.forest.capacity())
                * 4
            + self.block_key.capacity() * std::mem::size_of::<BlockBodies>()
            + self.body_entries.capacity() * 8
            + self.sys.bytes()
            + self.lcp.bytes()
            + self.dense.bytes()
            + self.tree.bytes()
    }

    /// An estimate of the bytes islands of up to `largest_island` rows need (a tree's system
    /// is about [`VALUES_PER_ROW`] values a row; a pile with loops may need more).
    pub(crate) fn bytes_for(largest_island: usize, _rows: usize) -> usize {
        let n = largest_island;
        n * (std::mem::size_of::<IslandRow>()
            + std::mem::size_of::<Row>()
            + std::mem::size_of::<ConstraintBlock>()
            + 4
            + 2 * std::mem::size_of::<Real>()
            + std::mem::size_of::<[Reaction; 2]>())
            + n * 6 * 4
            + n * std::mem::size_of::<BlockBodies>()
            + n * 8
            + 2 * n * VALUES_PER_ROW * 8
            + 6 * n * 8
            + n * std::mem::size_of::<FrictionLink>()
            + n
            // The dense path of islands with friction.
            + n * n * 8
            + 6 * n * 8
            + n * std::mem::size_of::<FrictionLink>()
            + n
            + crate::solver::sparse::lcp_dense::LcpWorkspace::bytes_for(n)
    }

    /// Solves one island and accumulates its constraint forces into `scratch`. `lambda` holds
    /// each row's force of the last step on entry (the warm start) and of this step on return.
    /// Returns false, having written nothing, for a stack its pivoting did not settle.
    pub(crate) fn solve_island(
        &mut self,
        island_blocks: &[u32],
        input: IslandInputs<'_>,
        scratch: &mut BodyScratch,
        (lambda, reactions): (&mut [Real], &mut [[Reaction; 2]]),
        stats: &mut SolverStats,
    ) -> bool {
        let IslandInputs {
            blocks,
            rows,
            bodies,
            params,
        } = input;
        let h = wide(params.dt);
        self.gather(island_blocks, blocks, rows, bodies, scratch, |_| true);
        let n = self.rows.len();
        if n == 0 {
            return true;
        }
        self.assemble(rows, scratch, params, h, lambda);
        if !self.solve_lcp(params, stats) {
            // A stack whose block-sparse pivoting did not settle (a row of boxes sliding:
            // the Coulomb bounds move under it): nothing written, the caller hands the
            // island to the iterative path.
            return false;
        }
        stats.islands += 1;
        stats.rows += n as u32;
        stats.largest_island_rows = stats.largest_island_rows.max(n as u32);

        // Forces back to rows, bodies and constraints.
        for (i, r) in self.rows.iter().enumerate() {
            let l = self.sys.x[i];
            lambda[r.global as usize] = l as Real;
            for s in 0..2 {
                if let Some(b) = r.bodies[s] {
                    scratch.constraint_force[b as usize] += r.jac[2 * s] * l;
                    scratch.constraint_torque[b as usize] += r.jac[2 * s + 1] * l;
                }
            }
        }
        block_reactions(island_blocks, blocks, rows, lambda, reactions);
        true
    }

    /// Gathers the island's rows that `keep` accepts, block by block, with each block's
    /// dynamic bodies as island-local numbers (a block left with no row is dropped).
    fn gather(
        &mut self,
        island_blocks: &[u32],
        blocks: &[ConstraintBlock],
        rows: &[Row],
        bodies: &[SolverBody],
        scratch: &BodyScratch,
        keep: impl Fn(&Row) -> bool,
    ) {
        self.rows.clear();
        self.sys.links.clear();
        self.island_bodies.clear();
        self.block_first.clear();
        self.block_size.clear();
        self.block_key.clear();
        if self.local_body.len() < bodies.len() {
            self.local_body.resize(bodies.len(), u32::MAX);
        }
        for &k in island_blocks {
            let blk = &blocks[k as usize];
            let base = self.rows.len() as u32;
            for g in blk.first_row..blk.first_row + blk.row_count {
                let row = &rows[g as usize];
                if !keep(row) {
                    continue;
                }
                let mut ir = IslandRow {
                    global: g,
                    bodies: blk.bodies,
                    ..IslandRow::default()
                };
                for s in 0..2 {
                    if let Some(b) = blk.bodies[s] {
                        let body = &bodies[b as usize];
                        let jl = to_f64(row.jacobian[s].linear);
                        let ja = to_f64(row.jacobian[s].angular);
                        ir.jac[2 * s] = jl;
                        ir.jac[2 * s + 1] = ja;
                        ir.mj[2 * s] = jl * wide(body.inv_mass);
                        ir.mj[2 * s + 1] =
                            to_f64(scratch.inv_inertia_world[b as usize] * row.jacobian[s].angular);
                    }
                }
                self.rows.push(ir);
                self.sys.links.push(
                    row.friction
                        .map(|f| (base + u32::from(f.normal_row), wide(f.mu))),
                );
            }
            let size = self.rows.len() as u32 - base;
            if size == 0 {
                continue;
            }
            let key = blk.bodies.map(|b| match b {
                Some(b) if !bodies[b as usize].is_fixed() => {
                    let local = &mut self.local_body[b as usize];
                    if *local == u32::MAX {
                        *local = self.island_bodies.len() as u32;
                        self.island_bodies.push(b);
                    }
                    *local
                }
                _ => u32::MAX,
            });
            self.block_first.push(base);
            self.block_size.push(size);
            self.block_key.push(key);
        }
        for &b in &self.island_bodies {
            self.local_body[b as usize] = u32::MAX;
        }
    }

    /// Solves the assembled LCP and reports its outcome. An island with Coulomb friction
    /// takes the dense path (see [`dense`]); the others the block-sparse one. Returns false
    /// only for a stack (contacts on the block-sparse system) whose pivoting did not
    /// converge: nothing is reported then, and the caller solves it dense.
    fn solve_lcp(&mut self, params: &SolverParams, stats: &mut SolverStats) -> bool {
        let n = self.rows.len();
        if self.dense_now {
            self.dense.solve_with_friction(
                &self.sys.b,
                &self.sys.lo,
                &self.sys.hi,
                &mut self.sys.x,
                params,
                stats,
            );
            return true;
        }
        let limits = self.limits(params);
        let rep = self.pivot(limits);
        if self.with_contacts && !rep.converged {
            return false;
        }
        stats.friction_passes += rep.bound_updates.max(1);
        stats.lcp_iterations += rep.iterations;
        stats.pivots += rep.pivots;
        if rep.bounds_moving {
            stats.friction_unconverged_islands += 1;
            log::warn!(
                "kea: Coulomb friction bounds still moving after {} updates",
                params.max_friction_passes
            );
        }
        if rep.singular {
            stats.singular_islands += 1;
            log::warn!("kea: singular constraint system ({n} rows) regularised: redundant constraints with too small epsilon?");
        }
        if rep.cycled {
            stats.cycled_islands += 1;
            log::warn!("kea: LCP pivoting cycle detected ({n} rows)");
        }
        if rep.capped && !rep.converged {
            stats.capped_islands += 1;
            log::warn!(
                "kea: LCP iteration cap {} reached ({n} rows)",
                params.max_lcp_iterations
            );
        }
        true
    }
}

/// Most row-iterations (rows × pivoting solves, per set of Coulomb bounds) a stack's
/// block-sparse pivoting may spend before it hands the stack back unsolved: one solve of a
/// 2,400-row column of 200 boxes takes about 0.5 ms here, a stack at rest needs one or two,
/// and a sliding one that has not settled by then goes to the contact solver rather than
/// stall the step (with five sets of bounds, about 20 ms at most).
const STACK_WORK: usize = 20_000;

/// The rows on one body [`STACK_WORK`] is measured for: a box in a column, its contacts above
/// and below (a body with more rows on it costs the square of their number per solve, and
/// affords that much fewer solves).
const STACK_WIDTH: u32 = 24;

/// Sets of Coulomb bounds a stack's pivoting may try (see [`STACK_WORK`]).
const STACK_BOUND_UPDATES: u32 = 4;

impl ExactWorkspace {
    /// The block-sparse system as filled, its unknowns and the pivoting's workspace, borrowed
    /// apart for a solve.
    pub(super) fn split(&mut self) -> (System<'_>, Unknowns<'_>, &mut LcpWorkspace) {
        let system = System {
            pattern: self.patterns.current(),
            layout: &self.layout,
            a: &self.sys.a,
            b: &self.sys.b,
            links: &self.sys.links,
            stamp: self.stamp,
        };
        let unknowns = Unknowns {
            lo: &mut self.sys.lo,
            hi: &mut self.sys.hi,
            x: &mut self.sys.x,
            w: &mut self.sys.w,
            state: &mut self.sys.state,
        };
        (system, unknowns, &mut self.lcp)
    }

    /// Principal pivoting on the block-sparse system as filled, from the bounds, guesses and
    /// bound states in `sys`; the solution is left in `sys.x`.
    pub(super) fn pivot(&mut self, limits: Limits) -> LcpReport {
        if self.tree_now {
            let mut unknowns = Unknowns {
                lo: &mut self.sys.lo,
                hi: &mut self.sys.hi,
                x: &mut self.sys.x,
                w: &mut self.sys.w,
                state: &mut self.sys.state,
            };
            return self
                .tree
                .pivot((&self.sys.b, &self.sys.links), &mut unknowns, limits);
        }
        let (system, mut unknowns, lcp) = self.split();
        pivoting::solve(&system, &mut unknowns, lcp, limits)
    }

    /// The pivoting's caps: the solver's, or for a stack the smaller ones its fallback allows.
    fn limits(&mut self, params: &SolverParams) -> Limits {
        let general = Limits {
            iterations: params.max_lcp_iterations,
            bound_updates: params.max_friction_passes,
        };
        if !self.with_contacts {
            return general;
        }
        // A solve costs its rows times the square of the widest body's rows: a body with
        // many contacts is one dense block.
        let widest = &mut self.forest;
        widest.clear();
        widest.resize(self.island_bodies.len(), 0);
        for (key, &size) in self.block_key.iter().zip(&self.block_size) {
            for &b in key.iter().filter(|&&b| b != u32::MAX) {
                widest[b as usize] += size;
            }
        }
        let widest = widest.iter().copied().max().unwrap_or(0).max(STACK_WIDTH) as usize;
        let scale = (STACK_WIDTH as usize * STACK_WIDTH as usize) as f64 / (widest * widest) as f64;
        let affordable = ((STACK_WORK / self.rows.len().max(1)) as f64 * scale).max(2.0) as u32;
        Limits {
            iterations: general.iterations.min(affordable),
            bound_updates: general.bound_updates.min(STACK_BOUND_UPDATES),
        }
    }
}
