//! Joint and user rows in the iterative path: projected Gauss-Seidel over Kea's generic rows,
//! on the shared hot body states, inside the same substeps as the contacts.
//!
//! Rows. For row i with Jacobian J, the sweep solves, in impulse units `P = λ·hs`,
//! `J v⁺ = c − bias − e·P` with `e = ε_s + s/hs` (softness and slip) and projects P on its bounds
//! (`lo·hs, hi·hs`, or `±μ·P_normal` for a Coulomb row): `ΔP = (c − bias − J v − e P)/(A_ii + e)`.
//! The error `xi` is tracked through the substeps by linearisation,
//! `xi = xi₀ + J·(Δx, Δθ)`, with Δx, Δθ each body's displacement since the step began.
//!
//! Same physics as the exact path. A row with its own softness ε > 0 (or a [`Spring`], turned
//! into ε and γ with the row's effective mass) is the spring of stiffness `k = γ/(ε h²)` and
//! damping `d = (1 − γ)/(ε h)` that the exact path solves in one step; here it is
//! re-discretised at the substep, `γ_s = hs·k/(hs·k + d)`, `ε_s = 1/(hs·(hs·k + d))`, so it
//! oscillates at the same frequency (and a single soft row follows implicit Euler at hs
//! exactly). Every other row is hard: the world's ε regularises the exact path's matrix and is
//! not needed by Gauss-Seidel. A hard row removes the fraction γ of its error per step
//! (`1 − (1 − γ)^(1/n)` per substep), pushing apart no faster than `max_correction_speed`; in
//! the biased sweeps a unilateral hard row is softened, mass-normalised, as a heavily damped
//! spring with that same rate (Catto's soft step, damping ratio 10); its relax sweeps are rigid
//! and drop the bias, so correcting an error adds no energy. A gap (positive error on a row
//! that can only push) may always be closed within the substep. A row with γ = 0 acts on
//! velocity only (friction, motors).
//!
//! Rows of one constraint that are unbounded (a joint's) are solved as one block with the
//! inverse of their `J M⁻¹ Jᵀ`; a pair of tangential rows as a 2×2 pair, each clamped to its
//! own bound (the exact path's pyramid). Rows are swept in constraint order (deterministic);
//! each row's λ of the last step warm-starts it.
//!
//! Re-linearisation: given a [`RowSource`](crate::solver::RowSource) (the world gives one),
//! every joint's rows are written again at the present poses from the second substep on
//! (`relinearise`), so fast rotation inside a step does not tear joints; without one (the
//! immediate-mode solver), Jacobians stay those of the step's start.
//!
//! [`Spring`]: crate::constraint::Spring

#![allow(clippy::needless_range_loop)] // small dense blocks read best with indices

mod direct;
mod gather;
mod relinearise;
mod sweep;
mod synchronise;

use super::super::integrate::BodyScratch;
use super::super::{reserve, ConstraintBlock, Reaction};
use super::bodies::{BodyStates, NONE};
use crate::constraint::Row;
use crate::math::{rotate_by_vector, to_f64, Real, Vec3};

/// Most rows solved as one block (a fixed joint has 6).
pub(super) const MAX_BLOCK: usize = 6;

const HARD: u8 = 1;
const BOUNCE: u8 = 2;
const UNILATERAL: u8 = 4;
/// A row of an island whose step is synchronised (no contacts; `substep` module docs).
const SYNCHRONISED: u8 = 8;

/// The rows of every iterative island, in compact arrays (structure of arrays: each sweep
/// streams through them in order).
#[derive(Debug, Default, Clone)]
pub(crate) struct JointRows {
    /// Time since the step began, now and at the start of the current substep.
    elapsed: Real,
    elapsed_sub: Real,
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
    /// The most a stop may push in the synchronising pass: half of what it pushed in the last
    /// substep (`sweep.rs`, `begin_synchronising`).
    sync_cap: Vec<Real>,
    /// `(hs/2)·J̇v`: what a substep's velocity solve takes off the target so that it aims
    /// along the chord of the substep ([`crate::constraint::Row::curvature`]); the error's
    /// tracking keeps the plain target.
    chord: Vec<Real>,
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
    // Friction pairs: two tangential rows of a constraint, solved together and projected on
    // their bounds as a pair (per-row Gauss-Seidel leaves the corners of a resting box rocking).
    pair_of: Vec<u32>,
    pair_second: Vec<u32>,
    pair_kinv: Vec<[Real; 4]>,
    /// Velocities before the restitution pass, per local body.
    before_bounce: Vec<(Vec3, Vec3)>,
    // Per gathered constraint block: its index, first row here, row count and equality block
    // (for re-linearising it), and the rows a re-linearisation writes.
    blk_global: Vec<u32>,
    blk_base: Vec<u32>,
    blk_count: Vec<u32>,
    blk_eq: Vec<u32>,
    fresh: Vec<Row>,
    // Rows of split islands, solved directly (`direct`): whether each row is one, its index
    // in the direct system (or NONE), and the system's rows.
    any_direct: bool,
    direct: Vec<bool>,
    direct_index: Vec<u32>,
    direct_rows: Vec<u32>,
    /// Per local body, the move post-stabilisation gives it.
    moves: Vec<(Vec3, Vec3)>,
    /// The synchronising pass is running: only synchronised rows are solved, aiming at the
    /// tangent of the poses reached (`synchronise`).
    synchronising: bool,
    /// Synchronised rows have half their impulse budget (`sweep.rs`, `own_bounds`).
    half_budget: bool,
    /// Which rows a synchronising sweep solves.
    sync_rows: SyncRows,
}

/// The rows of a synchronising sweep (`sweep.rs`, `synchronise`).
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
enum SyncRows {
    /// Every row that acts at an instant (the direct solve's single pass).
    #[default]
    All,
    /// Only the motors (soft rows without a spring).
    Motors,
    /// Only the hard rows.
    Hard,
}

impl JointRows {
    pub(crate) fn reserve(&mut self, bodies: usize, rows: usize) {
        for v in [
            &mut self.row_global,
            &mut self.row_a,
            &mut self.row_b,
            &mut self.link,
            &mut self.eq_start,
            &mut self.eq_len,
            &mut self.eq_rows,
            &mut self.eq_kstart,
            &mut self.pair_of,
            &mut self.pair_second,
            &mut self.blk_global,
            &mut self.blk_base,
            &mut self.blk_count,
            &mut self.blk_eq,
            &mut self.direct_index,
            &mut self.direct_rows,
        ] {
            reserve(v, rows);
        }
        reserve(&mut self.direct, rows);
        reserve(&mut self.fresh, 4 * MAX_BLOCK);
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
            &mut self.sync_cap,
            &mut self.chord,
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
        reserve(&mut self.eq_kinv, rows * MAX_BLOCK);
        reserve(&mut self.pair_kinv, rows);
        reserve(&mut self.before_bounce, bodies + 1);
        reserve(&mut self.moves, bodies + 1);
    }

    pub(crate) fn bytes(&self) -> usize {
        let v3 = std::mem::size_of::<Vec3>();
        let r = std::mem::size_of::<Real>();
        (self.row_global.capacity()
            + self.row_a.capacity()
            + self.row_b.capacity()
            + self.link.capacity()
            + self.eq_start.capacity()
            + self.eq_len.capacity()
            + self.eq_rows.capacity()
            + self.eq_kstart.capacity()
            + self.pair_of.capacity()
            + self.pair_second.capacity()
            + 4 * self.blk_global.capacity()
            + self.direct_index.capacity()
            + self.direct_rows.capacity())
            * 4
            + self.direct.capacity()
            + self.fresh.capacity() * std::mem::size_of::<Row>()
            + 8 * self.ja_lin.capacity() * v3
            + 15 * self.diag.capacity() * r
            + self.flags.capacity()
            + self.in_block.capacity()
            + self.eq_kinv.capacity() * r
            + self.pair_kinv.capacity() * 4 * r
            + (self.before_bounce.capacity() + self.moves.capacity()) * 2 * v3
    }

    pub(crate) fn bytes_for(bodies: usize, rows: usize) -> usize {
        let v3 = std::mem::size_of::<Vec3>();
        let r = std::mem::size_of::<Real>();
        rows * (56 + 8 + 32 + 1 + 8 * v3 + (19 + MAX_BLOCK) * r + 2)
            + (bodies + 1) * 4 * v3
            + 4 * MAX_BLOCK * std::mem::size_of::<Row>()
    }

    /// Number of rows gathered.
    pub(crate) fn len(&self) -> usize {
        self.row_global.len()
    }

    /// Whether any row bounces (a stop with restitution).
    pub(crate) fn has_bounce(&self) -> bool {
        self.flags.iter().any(|f| f & BOUNCE != 0)
    }

    /// Marks the rows from `first` on as synchronised (their island has no contacts).
    pub(crate) fn synchronise_from(&mut self, first: usize) {
        for f in &mut self.flags[first..] {
            *f |= SYNCHRONISED;
        }
    }

    /// Starts a step: no rows, no time elapsed.
    pub(crate) fn begin(&mut self) {
        self.elapsed = 0.0;
        self.elapsed_sub = 0.0;
        self.any_direct = false;
        macro_rules! clear_all {
            ($($v:ident),*) => { $(self.$v.clear();)* };
        }
        clear_all!(
            row_global,
            row_a,
            row_b,
            ja_lin,
            ja_ang,
            jb_lin,
            jb_ang,
            ma_lin,
            ma_ang,
            mb_lin,
            mb_ang,
            diag,
            lever,
            xi0,
            target,
            bounce_target,
            sync_cap,
            chord,
            lo,
            hi,
            link,
            mu,
            extra,
            rate,
            mass_scale,
            impulse_scale,
            flags,
            impulse,
            total,
            in_block,
            eq_start,
            eq_len,
            eq_rows,
            eq_kstart,
            eq_kinv,
            pair_of,
            pair_second,
            pair_kinv,
            blk_global,
            blk_base,
            blk_count,
            blk_eq,
            direct,
            direct_index,
            direct_rows
        );
    }

    /// Advances the rows' clock by a substep (after the bodies moved).
    pub(crate) fn advance_clock(&mut self, hs: Real) {
        self.elapsed_sub = self.elapsed;
        self.elapsed += hs;
    }

    /// Adds each row's impulse of the substep to its total.
    pub(crate) fn accumulate(&mut self) {
        for (t, &p) in self.total.iter_mut().zip(&self.impulse) {
            *t += p;
        }
    }

    /// Restitution, once, after the substeps: bounce rows (limits with restitution) whose row
    /// carried impulse are driven to their rebound velocity (a hard solve of the row's target).
    /// The bounce belongs to the impact at the start of the step, so the bodies also travel
    /// with their change of velocity for the whole step, as they do in the exact path.
    pub(crate) fn restitution(&mut self, states: &mut BodyStates, h: Real) {
        if !self.has_bounce() {
            return;
        }
        self.before_bounce.clear();
        self.before_bounce
            .extend(states.vel.iter().map(|s| (s.v, s.w)));
        for i in 0..self.len() {
            if self.flags[i] & BOUNCE == 0 || self.total[i] <= 0.0 || self.diag[i] <= 0.0 {
                continue;
            }
            let (jv, _) = self.jv_and_error(states, i, false);
            let dp = (self.bounce_target[i] - jv) / self.diag[i];
            let new = (self.impulse[i] + dp).max(self.lo[i]);
            let dp = new - self.impulse[i];
            self.impulse[i] = new;
            self.total[i] += dp;
            self.apply(states, i, dp);
        }
        for (l, &(v0, w0)) in self.before_bounce.iter().enumerate() {
            let dv = states.vel[l].v - v0;
            let dw = states.vel[l].w - w0;
            if states.writable[l] && (dv != Vec3::ZERO || dw != Vec3::ZERO) {
                states.delta[l].dp += h * dv;
                states.delta[l].dq = rotate_by_vector(states.delta[l].dq, h * dw);
            }
        }
    }

    /// Reports each row's force (total impulse / h), the constraint forces on the bodies and
    /// each block's reaction.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn write_out(
        &self,
        states: &BodyStates,
        blocks: &[ConstraintBlock],
        iterative_blocks: &[u32],
        rows: &[Row],
        scratch: &mut BodyScratch,
        h: Real,
        lambda: &mut [Real],
        reactions: &mut [[Reaction; 2]],
    ) {
        for i in 0..self.len() {
            let l = self.total[i] / h;
            lambda[self.row_global[i] as usize] = l;
            let (a, b) = (self.row_a[i], self.row_b[i]);
            for (slot, lin, ang) in [
                (a, self.ja_lin[i], self.ja_ang[i]),
                (b, self.jb_lin[i], self.jb_ang[i]),
            ] {
                if slot != NONE {
                    let g = states.global[slot as usize] as usize;
                    scratch.constraint_force[g] += to_f64(lin * l);
                    scratch.constraint_torque[g] += to_f64(ang * l);
                }
            }
        }
        super::super::block_reactions(iterative_blocks, blocks, rows, lambda, reactions);
    }
}
