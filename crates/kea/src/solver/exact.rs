//! The exact island solve: assemble `A + εI` and `b` in `f64`, run the boxed LCP, iterate the
//! Coulomb bounds, and hand the forces back.
//!
//! Assembly. For rows i, j and each body k they share,
//! `A_ij += J_ik · M_k⁻¹ J_jkᵀ` with `M_k⁻¹ = diag(1/m_k, I_w,k⁻¹)`; then
//! `A_ii += ε_i + s_i/h` (softness and slip) and `b_i = (c_i − γ_i·xi_i/h − J_i·v_f)/h`.
//!
//! Coulomb. A friction row linked to a normal row gets bounds `±μ·max(λₙ, 0)`. The first solve
//! uses unbounded friction (the sticking guess); each re-solve uses the bounds from the previous
//! normal forces, starting from the previous pivoting sets, until no bound moves by more than
//! 1e-9 relative, or the pass cap is hit (reported).

use super::integrate::BodyScratch;
use super::lcp::{self, Bound, LcpWorkspace};
use super::{
    block_reactions, reserve, ConstraintBlock, Reaction, SolverBody, SolverContact, SolverParams,
    SolverStats,
};
use crate::constraint::{
    Contact, PointForce, Row, RowBody, RowContext, RowWriter, Spring, MAX_CONTACT_POINTS,
};
use crate::math::{to_f64, wide, DVec3, Real};

/// One island row in `f64`: Jacobian and M⁻¹Jᵀ per body slot.
#[derive(Debug, Clone, Copy, Default)]
struct IslandRow {
    global: u32,
    bodies: [Option<u32>; 2],
    jac: [DVec3; 4],
    mj: [DVec3; 4],
    /// Island index of the linked normal row, and μ.
    link: Option<(u32, f64)>,
}

/// Workspace for island solves; grows to the largest island seen.
#[derive(Debug, Default)]
pub(crate) struct ExactWorkspace {
    /// An island's joint rows and its contacts' rows together, with their blocks, forces and
    /// reactions (contacts reach the exact path as contacts and are written as rows here).
    mixed_rows: Vec<Row>,
    mixed_blocks: Vec<ConstraintBlock>,
    mixed_order: Vec<u32>,
    mixed_lambda: Vec<Real>,
    mixed_reactions: Vec<[Reaction; 2]>,
    rows: Vec<IslandRow>,
    a: Vec<f64>,
    b: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    x: Vec<f64>,
    w: Vec<f64>,
    state: Vec<Bound>,
    lcp: LcpWorkspace,
}

impl ExactWorkspace {
    /// Reserves room for islands of `island_rows` rows, joints and contacts together.
    pub(crate) fn reserve_mixed(&mut self, island_rows: usize) {
        let n = island_rows;
        reserve(&mut self.mixed_rows, n);
        reserve(&mut self.mixed_blocks, n);
        reserve(&mut self.mixed_order, n);
        reserve(&mut self.mixed_lambda, n);
        reserve(&mut self.mixed_reactions, n);
    }

    pub(crate) fn reserve(&mut self, _rows: usize, island_rows: usize) {
        let n = island_rows;
        reserve(&mut self.rows, n);
        reserve(&mut self.a, n * n);
        for v in [
            &mut self.b,
            &mut self.lo,
            &mut self.hi,
            &mut self.x,
            &mut self.w,
        ] {
            reserve(v, n);
        }
        reserve(&mut self.state, n);
        self.lcp.reserve(n);
    }

    pub(crate) fn bytes(&self) -> usize {
        self.mixed_rows.capacity() * std::mem::size_of::<Row>()
            + self.mixed_blocks.capacity() * std::mem::size_of::<ConstraintBlock>()
            + self.mixed_order.capacity() * 4
            + self.mixed_lambda.capacity() * std::mem::size_of::<Real>()
            + self.mixed_reactions.capacity() * std::mem::size_of::<[Reaction; 2]>()
            + self.rows.capacity() * std::mem::size_of::<IslandRow>()
            + self.a.capacity() * 8
            + (self.b.capacity()
                + self.lo.capacity()
                + self.hi.capacity()
                + self.x.capacity()
                + self.w.capacity())
                * 8
            + self.state.capacity()
            + self.lcp.bytes()
    }

    pub(crate) fn bytes_for(largest_island: usize, _rows: usize) -> usize {
        let n = largest_island;
        n * (std::mem::size_of::<IslandRow>()
            + std::mem::size_of::<Row>()
            + std::mem::size_of::<ConstraintBlock>()
            + 4
            + std::mem::size_of::<Real>()
            + std::mem::size_of::<[Reaction; 2]>())
            + n * n * 8
            + 5 * n * 8
            + n
            + LcpWorkspace::bytes_for(n)
    }

    /// Solves one island and accumulates its constraint forces into `scratch`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn solve_island(
        &mut self,
        island_blocks: &[u32],
        blocks: &[ConstraintBlock],
        rows: &[Row],
        bodies: &[SolverBody],
        scratch: &mut BodyScratch,
        params: &SolverParams,
        lambda: &mut [Real],
        reactions: &mut [[Reaction; 2]],
        stats: &mut SolverStats,
    ) {
        let n: usize = island_blocks
            .iter()
            .map(|&k| blocks[k as usize].row_count as usize)
            .sum();
        if n == 0 {
            return;
        }
        self.reserve(n, n);
        stats.islands += 1;
        stats.rows += n as u32;
        stats.largest_island_rows = stats.largest_island_rows.max(n as u32);

        let h = wide(params.dt);
        self.gather(island_blocks, blocks, rows, bodies, scratch, |_| true);
        self.assemble(rows, scratch, params, h);
        self.solve_with_friction(n, params, stats);

        // Forces back to rows, bodies and constraints.
        for (i, r) in self.rows.iter().enumerate() {
            let l = self.x[i];
            lambda[r.global as usize] = l as Real;
            for s in 0..2 {
                if let Some(b) = r.bodies[s] {
                    scratch.constraint_force[b as usize] += r.jac[2 * s] * l;
                    scratch.constraint_torque[b as usize] += r.jac[2 * s + 1] * l;
                }
            }
        }
        block_reactions(island_blocks, blocks, rows, lambda, reactions);
    }

    /// Solves an island of joint blocks and contacts: the contacts write their rows (three
    /// per point) next to a copy of the joints' rows, the whole is solved as one LCP, and the
    /// forces go back to the joints' λ and reactions and to each contact point.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn solve_island_with_contacts(
        &mut self,
        island_blocks: &[u32],
        island_contacts: &[u32],
        blocks: &[ConstraintBlock],
        rows: &[Row],
        contacts: &mut [SolverContact],
        bodies: &[SolverBody],
        scratch: &mut BodyScratch,
        params: &SolverParams,
        lambda: &mut [Real],
        reactions: &mut [[Reaction; 2]],
        stats: &mut SolverStats,
    ) {
        if island_contacts.is_empty() {
            return self.solve_island(
                island_blocks,
                blocks,
                rows,
                bodies,
                scratch,
                params,
                lambda,
                reactions,
                stats,
            );
        }
        let mut mrows = std::mem::take(&mut self.mixed_rows);
        let mut mblocks = std::mem::take(&mut self.mixed_blocks);
        let mut order = std::mem::take(&mut self.mixed_order);
        let mut mlambda = std::mem::take(&mut self.mixed_lambda);
        let mut mreactions = std::mem::take(&mut self.mixed_reactions);
        mrows.clear();
        mblocks.clear();
        for &k in island_blocks {
            let blk = blocks[k as usize];
            let range = blk.first_row as usize..(blk.first_row + blk.row_count) as usize;
            mblocks.push(ConstraintBlock {
                first_row: mrows.len() as u32,
                ..blk
            });
            mrows.extend_from_slice(&rows[range]);
        }
        // A pile's contacts run stiff (see EXACT_CONTACT_STIFFENING); beside joints they keep
        // the world's spring, the balance the joints' own softness was set against.
        let contact_spring = if island_blocks.is_empty() {
            exact_contact_spring(params.contact_spring)
        } else {
            params.contact_spring
        };
        for &c in island_contacts {
            let sc = &contacts[c as usize];
            let ctx = RowContext {
                bodies: sc.bodies.map(|b| row_body(b, bodies, scratch)),
                dt: params.dt,
                epsilon: params.epsilon,
                gamma: params.gamma,
                contact_spring,
            };
            let first = mrows.len();
            sc.contact.write_rows(&ctx, &mut RowWriter::new(&mut mrows));
            mblocks.push(ConstraintBlock {
                bodies: sc.bodies,
                first_row: first as u32,
                row_count: (mrows.len() - first) as u32,
            });
        }
        order.clear();
        order.extend(0..mblocks.len() as u32);
        mlambda.clear();
        mlambda.resize(mrows.len(), 0.0);
        mreactions.clear();
        mreactions.resize(mblocks.len(), [Reaction::default(); 2]);
        self.solve_island(
            &order,
            &mblocks,
            &mrows,
            bodies,
            scratch,
            params,
            &mut mlambda,
            &mut mreactions,
            stats,
        );
        for (i, &k) in island_blocks.iter().enumerate() {
            let blk = &blocks[k as usize];
            let from = mblocks[i].first_row as usize;
            let n = blk.row_count as usize;
            lambda[blk.first_row as usize..blk.first_row as usize + n]
                .copy_from_slice(&mlambda[from..from + n]);
            reactions[k as usize] = mreactions[i];
        }
        for (i, &c) in island_contacts.iter().enumerate() {
            let blk = &mblocks[island_blocks.len() + i];
            let block_rows =
                &mrows[blk.first_row as usize..(blk.first_row + blk.row_count) as usize];
            let block_lambda =
                &mlambda[blk.first_row as usize..(blk.first_row + blk.row_count) as usize];
            store_point_forces(&mut contacts[c as usize].contact, block_rows, block_lambda);
        }
        self.mixed_rows = mrows;
        self.mixed_blocks = mblocks;
        self.mixed_order = order;
        self.mixed_lambda = mlambda;
        self.mixed_reactions = mreactions;
    }

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
                    link: row
                        .friction
                        .map(|f| (base + u32::from(f.normal_row), wide(f.mu))),
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
            }
        }
    }

    /// Sizes the vectors for the gathered rows and fills `A = J M⁻¹ Jᵀ` (no diagonal terms).
    fn assemble_matrix(&mut self) {
        let n = self.rows.len();
        self.a.clear();
        self.a.resize(n * n, 0.0);
        for v in [
            &mut self.b,
            &mut self.lo,
            &mut self.hi,
            &mut self.x,
            &mut self.w,
        ] {
            v.clear();
            v.resize(n, 0.0);
        }
        self.state.clear();
        self.state.resize(n, Bound::Free);
        for i in 0..n {
            let ri = self.rows[i];
            for j in i..n {
                let rj = &self.rows[j];
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
                self.a[i * n + j] = s;
                self.a[j * n + i] = s;
            }
        }
    }

    fn assemble(&mut self, rows: &[Row], scratch: &BodyScratch, params: &SolverParams, h: f64) {
        self.assemble_matrix();
        let n = self.rows.len();
        for i in 0..n {
            let ri = self.rows[i];
            let row = &rows[ri.global as usize];
            // A spring row's ε is relative to its own effective mass: the diagonal just built.
            let diag = self.a[i * n + i];
            let (eps, gamma) = match row.spring.and_then(|sp| sp.relative_softness(h as Real)) {
                Some((relative, g)) => (wide(relative) * diag, wide(row.gamma.unwrap_or(g))),
                None => (
                    wide(row.softness.unwrap_or(params.epsilon)),
                    wide(row.gamma.unwrap_or(params.gamma)),
                ),
            };
            self.a[i * n + i] += eps + wide(row.slip) / h;
            let mut jv = 0.0;
            for s in 0..2 {
                if let Some(b) = ri.bodies[s] {
                    jv += ri.jac[2 * s].dot(to_f64(scratch.free_linear[b as usize]))
                        + ri.jac[2 * s + 1].dot(to_f64(scratch.free_angular[b as usize]));
                }
            }
            self.b[i] = (wide(row.c) - gamma * wide(row.xi) / h - jv) / h;
            if ri.link.is_some() {
                // First pass: the sticking guess.
                self.lo[i] = f64::NEG_INFINITY;
                self.hi[i] = f64::INFINITY;
            } else {
                self.lo[i] = wide(row.lo);
                self.hi[i] = wide(row.hi);
            }
        }
        lcp::initial_state(&self.lo, &self.hi, &mut self.state);
    }

    /// Position projection of one island: moves its bodies so that each equality row without
    /// its own softness (a joint) sits where the step's force puts it, by solving
    /// `(J M⁻¹ Jᵀ + δI) Δ = xi* − xi` for the rows evaluated at the new state and applying
    /// `Δq = M⁻¹ Jᵀ Δ` to positions and orientations (velocities are left alone: a
    /// post-stabilisation). With the world's ε a joint is a stiff spring, `k = γ/(ε h²)`, so its
    /// target is the spring's deflection under the force λ it carried, `xi* = −λ/k`: projecting
    /// to zero would fight the velocity solve, which keeps that deflection. The displacements are
    /// accumulated in `scratch` (linear in `constraint_force`, angular in `constraint_torque`)
    /// for the caller to apply. Returns the largest error it started from.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn project_island(
        &mut self,
        island_blocks: &[u32],
        blocks: &[ConstraintBlock],
        rows: &[Row],
        bodies: &[SolverBody],
        scratch: &mut BodyScratch,
        params: &SolverParams,
        lambda: &[Real],
        stats: &mut SolverStats,
    ) -> f64 {
        let projectable = |r: &Row| {
            r.lo == Real::NEG_INFINITY
                && r.hi == Real::INFINITY
                && r.friction.is_none()
                && r.softness.is_none()
                && r.spring.is_none()
                && r.gamma != Some(0.0)
        };
        self.gather(island_blocks, blocks, rows, bodies, scratch, projectable);
        let n = self.rows.len();
        if n == 0 {
            return 0.0;
        }
        self.reserve(n, n);
        self.assemble_matrix();
        let diag_max = (0..n).fold(0.0f64, |m, i| m.max(self.a[i * n + i]));
        // A light regularisation keeps redundant joints solvable without softening them.
        let delta = (wide(params.epsilon) * 1.0e-3).max(1.0e-12 * diag_max);
        let mut worst = 0.0f64;
        let h = wide(params.dt);
        for i in 0..n {
            self.a[i * n + i] += delta;
            let g = self.rows[i].global as usize;
            let row = &rows[g];
            let xi = wide(row.xi);
            let gamma = wide(row.gamma.unwrap_or(params.gamma));
            let deflection = if gamma > 0.0 {
                -wide(params.epsilon) * h * h / gamma * wide(lambda[g])
            } else {
                0.0
            };
            worst = worst.max(xi.abs());
            self.b[i] = deflection - xi;
            self.lo[i] = f64::NEG_INFINITY;
            self.hi[i] = f64::INFINITY;
        }
        let rep = lcp::solve(
            n,
            &self.a,
            &self.b,
            &self.lo,
            &self.hi,
            &mut self.x,
            &mut self.w,
            &mut self.state,
            &mut self.lcp,
            params.max_lcp_iterations,
        );
        stats.lcp_iterations += rep.iterations;
        for (i, r) in self.rows.iter().enumerate() {
            let d = self.x[i];
            for s in 0..2 {
                if let Some(b) = r.bodies[s] {
                    scratch.constraint_force[b as usize] += r.mj[2 * s] * d;
                    scratch.constraint_torque[b as usize] += r.mj[2 * s + 1] * d;
                }
            }
        }
        worst
    }

    fn solve_with_friction(&mut self, n: usize, params: &SolverParams, stats: &mut SolverStats) {
        let has_friction = self.rows.iter().any(|r| r.link.is_some());
        let (mut singular, mut cycled, mut capped) = (false, false, false);
        let mut friction_converged = !has_friction;
        for _pass in 0..params.max_friction_passes {
            let rep = lcp::solve(
                n,
                &self.a,
                &self.b,
                &self.lo,
                &self.hi,
                &mut self.x,
                &mut self.w,
                &mut self.state,
                &mut self.lcp,
                params.max_lcp_iterations,
            );
            stats.friction_passes += 1;
            stats.lcp_iterations += rep.iterations;
            stats.pivots += rep.pivots;
            singular |= rep.singular;
            cycled = rep.cycled;
            capped = rep.capped && !rep.converged;
            if !has_friction {
                break;
            }
            let mut moved = false;
            for i in 0..n {
                if let Some((normal, mu)) = self.rows[i].link {
                    let bound = mu * self.x[normal as usize].max(0.0);
                    if (bound - self.hi[i]).abs() > 1.0e-9 * (1.0 + bound)
                        || self.hi[i].is_infinite()
                    {
                        moved = true;
                    }
                    self.lo[i] = -bound;
                    self.hi[i] = bound;
                }
            }
            if !moved {
                friction_converged = true;
                break;
            }
        }
        if !friction_converged {
            // The last solve used the previous bounds: clamp friction to the final ones so the
            // Coulomb cone is never exceeded, and report.
            for i in 0..n {
                if self.rows[i].link.is_some() {
                    self.x[i] = self.x[i].clamp(self.lo[i], self.hi[i]);
                }
            }
            stats.friction_unconverged_islands += 1;
            log::warn!(
                "kea: Coulomb friction bounds still moving after {} re-solves",
                params.max_friction_passes
            );
        }
        if singular {
            stats.singular_islands += 1;
            log::warn!("kea: singular constraint system ({n} rows) regularised: redundant constraints with too small epsilon?");
        }
        if cycled {
            stats.cycled_islands += 1;
            log::warn!("kea: LCP pivoting cycle detected ({n} rows)");
        }
        if capped {
            stats.capped_islands += 1;
            log::warn!(
                "kea: LCP iteration cap {} reached ({n} rows)",
                params.max_lcp_iterations
            );
        }
    }
}

/// The row-writing view of solver body `b` (`None`: the static world).
pub(crate) fn row_body(b: Option<u32>, bodies: &[SolverBody], scratch: &BodyScratch) -> RowBody {
    let Some(b) = b else {
        return RowBody::STATIC;
    };
    let body = &bodies[b as usize];
    RowBody {
        position: body.position,
        orientation: body.orientation,
        linear_velocity: body.linear_velocity,
        angular_velocity: body.angular_velocity,
        free_linear_velocity: scratch.free_linear[b as usize],
        free_angular_velocity: scratch.free_angular[b as usize],
        dynamic: !body.is_fixed(),
        fast_spin_axis: body.fast_spin_axis.map(|a| body.orientation * a),
    }
}

/// Each point's force from the λ of the rows a contact wrote (normal, then its friction rows),
/// and the primary direction they used.
fn store_point_forces(contact: &mut Contact, rows: &[Row], lambda: &[Real]) {
    let per_point = rows.len() / contact.points().len().max(1);
    let mut forces = [PointForce::default(); MAX_CONTACT_POINTS];
    for (j, f) in forces.iter_mut().enumerate().take(contact.points().len()) {
        let base = j * per_point;
        f.normal = lambda[base];
        for k in 1..per_point {
            f.friction += rows[base + k].jacobian[0].linear * lambda[base + k];
        }
    }
    contact.set_forces(&forces[..contact.points().len()]);
    if per_point >= 2 {
        contact.remember_direction(rows[1].jacobian[0].linear);
    }
}

/// How much stiffer the exact path's contacts are than the iterative path's in an island of
/// contacts only (beside joints, contacts keep the world's spring: a ragdoll's limits, soft
/// by the guide's ε, would yield to stiffer ground contacts): a direct solve stays stable
/// however stiff its springs, so it runs them at eight times the frequency (240
/// Hz by default), and eight times the damping ratio so that a step still removes the same
/// fraction of a penetration (`hω/(hω + 2ζ)`, the step's γ, stays as it was) rather than
/// kicking bodies out. Resting, such a contact yields 64 times less: a column of 40 unit boxes
/// sags under 1 cm, and a 1 kg box under a 100 kg one sinks a millimetre or two, where the
/// soft step's 30 Hz gives 44 cm and 13 cm.
pub(crate) const EXACT_CONTACT_STIFFENING: Real = 8.0;

/// The spring of the exact path's contacts for the world's contact spring.
pub(crate) fn exact_contact_spring(spring: Spring) -> Spring {
    Spring::new(
        spring.hertz * EXACT_CONTACT_STIFFENING,
        spring.damping_ratio,
    )
}
