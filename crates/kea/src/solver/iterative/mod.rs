//! The fast path: warm-started projected Gauss-Seidel with substeps (the soft step of Box2D v3,
//! over Kea's generic rows), for islands too big for the exact solver.
//!
//! Per step of size h with n substeps of size `hs = h/n`, for each substep:
//! 1. integrate velocities with gravity, applied forces and damping;
//! 2. warm start: re-apply each row's impulse from the previous substep (or step);
//! 3. solve (`iterations` sweeps, with the rows' error terms);
//! 4. integrate positions (and orientations, keeping angular momentum, as the exact path);
//! 5. relax (`relax_iterations` sweeps without the error-correction of hard rows).
//!
//! After the substeps, restitution is applied once (a post-pass over bounce rows whose contact
//! carried impulse), and the force of each row is reported as its total impulse over h.
//!
//! Rows. For row i with Jacobian J, the sweep solves, in impulse units `P = λ·hs`,
//! `J v⁺ = c − bias − e·P` with `e = ε_s + s/hs` (softness and slip) and projects P on its bounds
//! (`lo·hs, hi·hs`, or `±μ·P_normal` for a Coulomb row): `ΔP = (c − bias − J v − e P)/(A_ii + e)`.
//! The error `xi` is tracked through the substeps by linearisation,
//! `xi = xi₀ + J·(Δx, Δθ)`, with Δx, Δθ each body's displacement since the step began.
//!
//! Same physics as the exact path. A row with its own softness ε > 0 is the spring of stiffness
//! `k = γ/(ε h²)` and damping `d = (1 − γ)/(ε h)` that the exact path solves in one step; here it
//! is re-discretised at the substep, `γ_s = hs·k/(hs·k + d)`, `ε_s = 1/(hs·(hs·k + d))`, so it
//! oscillates at the same frequency (and a single soft row follows implicit Euler at hs exactly).
//! Every other row is hard: the world's ε regularises the exact path's matrix and is not needed
//! by Gauss-Seidel. A hard row removes the fraction γ of its error per step
//! (`1 − (1 − γ)^(1/n)` per substep), pushing apart no faster than `max_correction_speed`; in the
//! biased sweeps it is softened, mass-normalised, as a heavily damped spring with that same rate
//! (Catto's soft step, damping ratio 10), which keeps Gauss-Seidel convergent on stiff stacks;
//! its relax sweeps are rigid and drop the bias, so correcting an error adds no energy. A gap
//! (positive error on a row that can only push) may always be closed within the substep. A row
//! with γ = 0 acts on velocity only (friction, motors).
//!
//! Rows of one constraint that are unbounded (a joint's) are solved as one block with the
//! inverse of their `J M⁻¹ Jᵀ`; a contact's two friction rows as a 2×2 pair, each clamped to its
//! own bound (the exact path's pyramid). Rows are kept in structure-of-arrays form and swept in
//! constraint order (deterministic); each row's λ of the last step warm-starts it.
//!
//! Known limits: Jacobians stay those of the step's start through the substeps, so a jointed pair
//! tumbling fast feels a small spurious moment (angular momentum drifts ~1e-2/s in
//! `tests/momentum.rs`), and a long chain whipped at 60 Hz comes apart (`tests/chain.rs`); use
//! the exact path, with position projection, for those.

#![allow(clippy::needless_range_loop)] // small dense blocks read best with indices

mod gather;
mod sweep;

use super::integrate::{rotate_body, BodyScratch};
use super::{
    block_reactions, reserve, ConstraintBlock, Reaction, SolverBody, SolverParams, SolverStats,
};
use crate::constraint::Row;
use crate::error::{check_positive, KeaError, KeaResult};
use crate::math::{from_f64, rotate_by_vector, to_f64, Mat3, Real, Vec3};

/// Settings of the iterative path. Every field has its unit, normal value and range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterativeParams {
    /// Substeps per step (≥ 1). Default 4. More substeps stiffen contacts and joints at a
    /// linear cost; 1 is plain sequential impulses.
    pub substeps: u32,
    /// Gauss-Seidel sweeps per substep with error correction (≥ 1). Default 2: one leaves a
    /// column of 4-point contacts leaning by a few millimetres.
    pub iterations: u32,
    /// Sweeps per substep without the correction of hard rows (≥ 0). Default 1.
    pub relax_iterations: u32,
    /// Fastest speed at which penetration of a unilateral hard row is corrected, m/s (or rad/s
    /// for angular rows), > 0. Default 3. Larger values pop deep overlaps apart violently.
    pub max_correction_speed: Real,
}

impl Default for IterativeParams {
    fn default() -> Self {
        Self {
            substeps: 4,
            iterations: 2,
            relax_iterations: 1,
            max_correction_speed: 3.0,
        }
    }
}

impl IterativeParams {
    /// Checks every field, naming the first bad one.
    pub fn validate(&self) -> KeaResult<()> {
        let at_least_one = |arg: &'static str, v: u32| {
            if v == 0 {
                Err(KeaError::OutOfRange {
                    arg,
                    value: "0".into(),
                    expected: "must be >= 1",
                })
            } else {
                Ok(())
            }
        };
        at_least_one("substeps", self.substeps)?;
        at_least_one("iterations", self.iterations)?;
        if self.substeps > 64 {
            return Err(KeaError::OutOfRange {
                arg: "substeps",
                value: self.substeps.to_string(),
                expected: "must be <= 64",
            });
        }
        if self.iterations > 1000 || self.relax_iterations > 1000 {
            return Err(KeaError::OutOfRange {
                arg: "iterations",
                value: self.iterations.max(self.relax_iterations).to_string(),
                expected: "iterations and relax_iterations must be <= 1000",
            });
        }
        check_positive("max_correction_speed", self.max_correction_speed)?;
        Ok(())
    }
}

const NONE: u32 = u32::MAX;

/// Workspace of the iterative path: the island's bodies and rows in compact arrays (structure
/// of arrays: each sweep streams through them in order).
#[derive(Debug, Default)]
pub(crate) struct IterativeWorkspace {
    // Bodies of the island, by local index.
    body_global: Vec<u32>,
    local_of: Vec<u32>,
    v: Vec<Vec3>,
    w: Vec<Vec3>,
    /// World inverse inertia of each body at the step's start.
    inv_iw: Vec<Mat3>,
    dx: Vec<Vec3>,
    dtheta: Vec<Vec3>,
    /// Displacement at the start of the current substep (soft rows relax with the error the
    /// substep started from, so a spring stays one implicit-Euler step per substep).
    dx_sub: Vec<Vec3>,
    dtheta_sub: Vec<Vec3>,
    /// Time since the step began, now and at the start of the current substep.
    elapsed: Real,
    elapsed_sub: Real,
    // Rows of the island.
    row_global: Vec<u32>,
    row_a: Vec<u32>,
    row_b: Vec<u32>,
    ja_lin: Vec<Vec3>,
    ja_ang: Vec<Vec3>,
    jb_lin: Vec<Vec3>,
    jb_ang: Vec<Vec3>,
    ma_lin: Vec<Vec3>,
    ma_ang: Vec<Vec3>,
    mb_lin: Vec<Vec3>,
    mb_ang: Vec<Vec3>,
    diag: Vec<Real>,
    /// Longest lever `|J_ang|/|J_lin|` among the rows of the row's constraint.
    lever: Vec<Real>,
    xi0: Vec<Real>,
    target: Vec<Real>,
    bounce_target: Vec<Real>,
    lo: Vec<Real>,
    hi: Vec<Real>,
    link: Vec<u32>,
    mu: Vec<Real>,
    extra: Vec<Real>,
    rate: Vec<Real>,
    /// Softening of a hard row in the biased solve, `ΔP = s_m·ΔP_rigid − s_i·P` (see docs).
    mass_scale: Vec<Real>,
    impulse_scale: Vec<Real>,
    flags: Vec<u8>,
    impulse: Vec<Real>,
    total: Vec<Real>,
    // Equality blocks: the unbounded rows of one constraint, solved together.
    in_block: Vec<bool>,
    eq_start: Vec<u32>,
    eq_len: Vec<u32>,
    eq_rows: Vec<u32>,
    /// Start of each block's m×m inverse in `eq_kinv`.
    eq_kstart: Vec<u32>,
    eq_kinv: Vec<Real>,
    // Friction pairs: the two tangential rows of a contact, solved together and projected on
    // their bounds as a pair (per-row Gauss-Seidel leaves the corners of a resting box rocking).
    pair_of: Vec<u32>,
    pair_second: Vec<u32>,
    pair_kinv: Vec<[Real; 4]>,
}

/// Most rows solved as one block (a fixed joint has 6).
const MAX_BLOCK: usize = 6;

const HARD: u8 = 1;
const BOUNCE: u8 = 2;
const UNILATERAL: u8 = 4;

impl IterativeWorkspace {
    pub(crate) fn reserve(&mut self, bodies: usize, rows: usize) {
        for v in [&mut self.body_global, &mut self.local_of] {
            reserve(v, bodies);
        }
        reserve(&mut self.inv_iw, bodies);
        for v in [
            &mut self.v,
            &mut self.w,
            &mut self.dx,
            &mut self.dtheta,
            &mut self.dx_sub,
            &mut self.dtheta_sub,
        ] {
            reserve(v, bodies);
        }
        for v in [
            &mut self.row_global,
            &mut self.row_a,
            &mut self.row_b,
            &mut self.link,
        ] {
            reserve(v, rows);
        }
        for v in [
            &mut self.ja_lin,
            &mut self.ja_ang,
            &mut self.jb_lin,
            &mut self.jb_ang,
            &mut self.ma_lin,
            &mut self.ma_ang,
            &mut self.mb_lin,
            &mut self.mb_ang,
        ] {
            reserve(v, rows);
        }
        for v in [
            &mut self.diag,
            &mut self.lever,
            &mut self.xi0,
            &mut self.target,
            &mut self.bounce_target,
            &mut self.lo,
            &mut self.hi,
            &mut self.mu,
            &mut self.extra,
            &mut self.rate,
            &mut self.mass_scale,
            &mut self.impulse_scale,
            &mut self.impulse,
            &mut self.total,
        ] {
            reserve(v, rows);
        }
        reserve(&mut self.flags, rows);
        reserve(&mut self.in_block, rows);
        for v in [
            &mut self.eq_start,
            &mut self.eq_len,
            &mut self.eq_rows,
            &mut self.eq_kstart,
        ] {
            reserve(v, rows);
        }
        reserve(&mut self.eq_kinv, rows * MAX_BLOCK);
        reserve(&mut self.pair_of, rows);
        reserve(&mut self.pair_second, rows);
        reserve(&mut self.pair_kinv, rows);
    }

    pub(crate) fn bytes(&self) -> usize {
        let v3 = std::mem::size_of::<Vec3>();
        let r = std::mem::size_of::<Real>();
        (self.body_global.capacity() + self.local_of.capacity()) * 4
            + (self.v.capacity()
                + self.w.capacity()
                + self.dx.capacity()
                + self.dtheta.capacity()
                + self.dx_sub.capacity()
                + self.dtheta_sub.capacity())
                * v3
            + (self.row_global.capacity()
                + self.row_a.capacity()
                + self.row_b.capacity()
                + self.link.capacity())
                * 4
            + 8 * self.ja_lin.capacity() * v3
            + 14 * self.diag.capacity() * r
            + self.flags.capacity()
            + self.in_block.capacity()
            + (self.eq_start.capacity()
                + self.eq_len.capacity()
                + self.eq_rows.capacity()
                + self.eq_kstart.capacity())
                * 4
            + self.eq_kinv.capacity() * r
            + (self.pair_of.capacity() + self.pair_second.capacity()) * 4
            + self.pair_kinv.capacity() * 4 * r
    }

    pub(crate) fn bytes_for(bodies: usize, rows: usize) -> usize {
        let v3 = std::mem::size_of::<Vec3>();
        let r = std::mem::size_of::<Real>();
        bodies * (8 + 6 * v3) + rows * (40 + 8 * v3 + (18 + MAX_BLOCK) * r + 2)
    }

    /// Solves one island and integrates its bodies. `lambda` holds warm-start forces on input.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn solve_island(
        &mut self,
        island_blocks: &[u32],
        blocks: &[ConstraintBlock],
        rows: &[Row],
        bodies: &mut [SolverBody],
        scratch: &mut BodyScratch,
        params: &SolverParams,
        lambda: &mut [Real],
        reactions: &mut [[Reaction; 2]],
        stats: &mut SolverStats,
    ) -> u32 {
        let it = &params.iterative;
        let h = params.dt;
        let n_sub = it.substeps;
        let hs = h / n_sub as Real;
        self.gather_bodies(island_blocks, blocks, bodies, scratch);
        self.gather_rows(
            island_blocks,
            blocks,
            rows,
            bodies,
            scratch,
            params,
            hs,
            lambda,
        );
        let n = self.row_global.len();
        stats.islands += 1;
        stats.rows += n as u32;
        stats.largest_island_rows = stats.largest_island_rows.max(n as u32);

        self.elapsed = 0.0;
        self.elapsed_sub = 0.0;
        for _ in 0..n_sub {
            self.integrate_velocities(bodies, scratch, params, hs);
            self.warm_start();
            for _ in 0..it.iterations {
                self.sweep(hs, true, it.max_correction_speed);
            }
            self.integrate_positions(bodies, hs);
            for _ in 0..it.relax_iterations {
                self.sweep(hs, false, it.max_correction_speed);
            }
            for i in 0..n {
                self.total[i] += self.impulse[i];
            }
        }
        self.restitution(bodies, h);
        let sweeps = n_sub * (it.iterations + it.relax_iterations);
        stats.iterative_sweeps += sweeps;
        self.write_out(
            blocks,
            island_blocks,
            rows,
            bodies,
            scratch,
            h,
            lambda,
            reactions,
        );
        sweeps
    }

    fn integrate_velocities(
        &mut self,
        bodies: &[SolverBody],
        scratch: &BodyScratch,
        params: &SolverParams,
        hs: Real,
    ) {
        for (l, &g) in self.body_global.iter().enumerate() {
            let b = &bodies[g as usize];
            let inv_iw = scratch.inv_inertia_world[g as usize];
            let mut v = self.v[l];
            let mut w = self.w[l];
            if b.linear_damping > 0.0 {
                v /= 1.0 + hs * b.linear_damping * b.inv_mass;
            }
            if b.angular_damping > 0.0 {
                // Implicit, with the world inertia of the step's start.
                let iw = inv_iw.inverse();
                let damped = iw + Mat3::from_diagonal(Vec3::splat(hs * b.angular_damping));
                w = damped.inverse() * (iw * w);
            }
            self.v[l] = v + hs * (params.gravity + b.inv_mass * b.force);
            self.w[l] = w + hs * (inv_iw * b.torque);
        }
    }

    fn integrate_positions(&mut self, bodies: &mut [SolverBody], hs: Real) {
        self.elapsed_sub = self.elapsed;
        self.elapsed += hs;
        for (l, &g) in self.body_global.iter().enumerate() {
            let b = &mut bodies[g as usize];
            let v = self.v[l];
            let w = self.w[l];
            b.position += hs * v;
            self.dx_sub[l] = self.dx[l];
            self.dtheta_sub[l] = self.dtheta[l];
            self.dx[l] += hs * v;
            self.dtheta[l] += hs * w;
            let (q, w_new) = rotate_body(b, w, hs);
            b.orientation = q;
            self.w[l] = w_new;
        }
    }

    /// Restitution, once, after the substeps: bounce rows whose contact carried impulse are
    /// driven to their rebound velocity (a hard solve of the row's target). The bounce belongs
    /// to the impact at the start of the step, so the bodies also travel with their change of
    /// velocity for the whole step, as they do in the exact path (otherwise every bounce would
    /// start a step late and apexes would come out low by `e·v_in·h`).
    fn restitution(&mut self, bodies: &mut [SolverBody], h: Real) {
        if !self.flags.iter().any(|f| f & BOUNCE != 0) {
            return;
        }
        // dx/dθ are free after the substeps: keep the velocities before the pass there.
        self.dx.copy_from_slice(&self.v);
        self.dtheta.copy_from_slice(&self.w);
        let n = self.row_global.len();
        for i in 0..n {
            if self.flags[i] & BOUNCE == 0 || self.total[i] <= 0.0 || self.diag[i] <= 0.0 {
                continue;
            }
            let (jv, _) = self.jv_and_error(i, false);
            let dp = (self.bounce_target[i] - jv) / self.diag[i];
            let new = (self.impulse[i] + dp).max(self.lo[i]);
            let dp = new - self.impulse[i];
            self.impulse[i] = new;
            self.total[i] += dp;
            self.apply(i, dp);
        }
        for (l, &g) in self.body_global.iter().enumerate() {
            let dv = self.v[l] - self.dx[l];
            let dw = self.w[l] - self.dtheta[l];
            if dv != Vec3::ZERO || dw != Vec3::ZERO {
                let b = &mut bodies[g as usize];
                b.position += h * dv;
                b.orientation = rotate_by_vector(b.orientation, h * dw);
            }
        }
    }

    /// Reports forces (total impulse / h), reactions and body outputs, and clears the local
    /// index map for the next island.
    #[allow(clippy::too_many_arguments)]
    fn write_out(
        &mut self,
        blocks: &[ConstraintBlock],
        island_blocks: &[u32],
        rows: &[Row],
        bodies: &mut [SolverBody],
        scratch: &mut BodyScratch,
        h: Real,
        lambda: &mut [Real],
        reactions: &mut [[Reaction; 2]],
    ) {
        for i in 0..self.row_global.len() {
            let l = self.total[i] / h;
            lambda[self.row_global[i] as usize] = l;
            let (a, b) = (self.row_a[i], self.row_b[i]);
            for (slot, lin, ang) in [
                (a, self.ja_lin[i], self.ja_ang[i]),
                (b, self.jb_lin[i], self.jb_ang[i]),
            ] {
                if slot != NONE {
                    let g = self.body_global[slot as usize] as usize;
                    scratch.constraint_force[g] += to_f64(lin * l);
                    scratch.constraint_torque[g] += to_f64(ang * l);
                }
            }
        }
        block_reactions(island_blocks, blocks, rows, lambda, reactions);
        for (l, &g) in self.body_global.iter().enumerate() {
            let g = g as usize;
            let b = &mut bodies[g];
            b.linear_acceleration = (self.v[l] - b.linear_velocity) / h;
            b.angular_acceleration = (self.w[l] - b.angular_velocity) / h;
            b.linear_velocity = self.v[l];
            b.angular_velocity = self.w[l];
            b.constraint_force = from_f64(scratch.constraint_force[g]);
            b.constraint_torque = from_f64(scratch.constraint_torque[g]);
            scratch.integrated[g] = true;
            self.local_of[g] = NONE;
        }
    }
}
