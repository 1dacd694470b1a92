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
//! Same physics as the exact path. A soft row (ε > 0) is the spring of stiffness
//! `k = γ/(ε h²)` and damping `d = (1 − γ)/(ε h)` that the exact path solves in one step; here it
//! is re-discretised at the substep, `γ_s = hs·k/(hs·k + d)`, `ε_s = 1/(hs·(hs·k + d))`, so it
//! oscillates at the same frequency. A hard row (ε = 0) removes the fraction γ of its error per
//! step (`1 − (1 − γ)^(1/n)` per substep), pushing apart no faster than `max_correction_speed`,
//! and its relax sweep drops that bias, so correcting an error adds no energy. A gap (positive
//! error on a row that can only push) may always be closed within the substep.

#![allow(clippy::needless_range_loop)] // small dense blocks read best with indices

use super::integrate::{rotate_body, BodyScratch};
use super::{reserve, ConstraintBlock, Reaction, SolverBody, SolverParams, SolverStats};
use crate::constraint::Row;
use crate::error::{check_positive, KeaError, KeaResult};
use crate::math::{from_f64, rotate_by_vector, to_f64, wide, Mat3, Real, Vec3};

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
    dx: Vec<Vec3>,
    dtheta: Vec<Vec3>,
    /// Displacement at the start of the current substep (soft rows relax with the error the
    /// substep started from, so a spring stays one implicit-Euler step per substep).
    dx_sub: Vec<Vec3>,
    dtheta_sub: Vec<Vec3>,
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
            + 13 * self.diag.capacity() * r
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
        bodies * (8 + 6 * v3) + rows * (40 + 8 * v3 + (17 + MAX_BLOCK) * r + 2)
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

    fn gather_bodies(
        &mut self,
        island_blocks: &[u32],
        blocks: &[ConstraintBlock],
        bodies: &[SolverBody],
        scratch: &BodyScratch,
    ) {
        self.body_global.clear();
        self.v.clear();
        self.w.clear();
        self.dx.clear();
        self.dtheta.clear();
        self.dx_sub.clear();
        self.dtheta_sub.clear();
        if self.local_of.len() < bodies.len() {
            self.local_of.resize(bodies.len(), NONE);
        }
        for &k in island_blocks {
            for b in blocks[k as usize].bodies.iter().flatten() {
                let g = *b as usize;
                if bodies[g].is_fixed() || self.local_of[g] != NONE {
                    continue;
                }
                self.local_of[g] = self.body_global.len() as u32;
                self.body_global.push(g as u32);
                // Start from the damped velocity (the exact path's free velocity minus forces).
                self.v.push(bodies[g].linear_velocity);
                self.w.push(bodies[g].angular_velocity);
                self.dx.push(Vec3::ZERO);
                self.dtheta.push(Vec3::ZERO);
                self.dx_sub.push(Vec3::ZERO);
                self.dtheta_sub.push(Vec3::ZERO);
            }
        }
        let _ = scratch;
    }

    #[allow(clippy::too_many_arguments)]
    fn gather_rows(
        &mut self,
        island_blocks: &[u32],
        blocks: &[ConstraintBlock],
        rows: &[Row],
        bodies: &[SolverBody],
        scratch: &BodyScratch,
        params: &SolverParams,
        hs: Real,
        warm: &[Real],
    ) {
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
            xi0,
            target,
            bounce_target,
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
            pair_kinv
        );
        let h = params.dt;
        let n_sub = params.iterative.substeps as Real;
        for &k in island_blocks {
            let blk = &blocks[k as usize];
            let base = self.row_global.len() as u32;
            for g in blk.first_row..blk.first_row + blk.row_count {
                let row = &rows[g as usize];
                let mut kinematic = 0.0;
                let mut local = [NONE; 2];
                let mut jm = [(Vec3::ZERO, Vec3::ZERO); 2];
                let mut diag = 0.0;
                for s in 0..2 {
                    let Some(b) = blk.bodies[s] else { continue };
                    let body = &bodies[b as usize];
                    let j = row.jacobian[s];
                    if body.is_fixed() {
                        // A kinematic body: its motion is a constant target offset.
                        kinematic += j.linear.dot(body.linear_velocity)
                            + j.angular.dot(body.angular_velocity);
                        continue;
                    }
                    local[s] = self.local_of[b as usize];
                    let ml = j.linear * body.inv_mass;
                    let ma = scratch.inv_inertia_world[b as usize] * j.angular;
                    diag += j.linear.dot(ml) + j.angular.dot(ma);
                    jm[s] = (ml, ma);
                }
                // Two slots on the same body add their cross terms.
                if local[0] != NONE && local[0] == local[1] {
                    diag += 2.0
                        * (row.jacobian[0].linear.dot(jm[1].0)
                            + row.jacobian[0].angular.dot(jm[1].1));
                }
                // Only a row's own softness is a physical spring; the world's ε regularises the
                // exact path's matrix and is not needed here (see the module docs).
                let eps = row.softness.unwrap_or(0.0);
                let gamma = row.gamma.unwrap_or(params.gamma);
                let mut flags = 0u8;
                let (rate, extra) = if eps > 0.0 {
                    let k = gamma / (eps * h * h);
                    let d = (1.0 - gamma) / (eps * h);
                    let hkd = hs * k + d;
                    (hs * k / hkd / hs, 1.0 / (hs * hkd))
                } else {
                    flags |= HARD;
                    ((1.0 - (1.0 - gamma).powf(1.0 / n_sub)) / hs, 0.0)
                };
                let (ms, is) = if flags & HARD != 0 {
                    hard_softening(rate, hs)
                } else {
                    (1.0, 0.0)
                };
                self.mass_scale.push(ms);
                self.impulse_scale.push(is);
                if row.bounce {
                    flags |= BOUNCE;
                }
                if row.friction.is_none() && row.hi == Real::INFINITY && row.lo > Real::NEG_INFINITY
                {
                    flags |= UNILATERAL;
                }
                self.row_global.push(g);
                self.row_a.push(local[0]);
                self.row_b.push(local[1]);
                self.ja_lin.push(row.jacobian[0].linear);
                self.ja_ang.push(row.jacobian[0].angular);
                self.jb_lin.push(row.jacobian[1].linear);
                self.jb_ang.push(row.jacobian[1].angular);
                self.ma_lin.push(jm[0].0);
                self.ma_ang.push(jm[0].1);
                self.mb_lin.push(jm[1].0);
                self.mb_ang.push(jm[1].1);
                self.diag.push(diag);
                self.xi0.push(row.xi);
                // A bounce target waits for the post-pass; the substeps treat the contact as
                // resting.
                let c = if row.bounce { 0.0 } else { row.c };
                self.target.push(c - kinematic);
                self.bounce_target.push(row.c - kinematic);
                self.lo.push(row.lo * hs);
                self.hi.push(row.hi * hs);
                match row.friction {
                    Some(f) => {
                        self.link.push(base + u32::from(f.normal_row));
                        self.mu.push(f.mu);
                    }
                    None => {
                        self.link.push(NONE);
                        self.mu.push(0.0);
                    }
                }
                self.extra.push(extra + row.slip / hs);
                self.rate.push(rate);
                self.flags.push(flags);
                let w = warm[g as usize];
                self.impulse.push(if w.is_finite() { w * hs } else { 0.0 });
                self.total.push(0.0);
                self.in_block.push(false);
                self.pair_of.push(NONE);
            }
            self.make_block(base as usize, rows, blk);
            self.make_pairs(base as usize, rows);
        }
        // Warm-start impulses must respect their bounds.
        for i in 0..self.row_global.len() {
            let (lo, hi) = self.bounds(i);
            self.impulse[i] = self.impulse[i].clamp(lo, hi);
        }
    }

    /// Groups a constraint's unbounded rows (2 to 6 of them) into one block and stores the
    /// inverse of its `J M⁻¹ Jᵀ + E`, so that a joint's rows are solved together: per-row
    /// Gauss-Seidel converges slowly when rows share a badly conditioned body (a small sphere at
    /// the end of a long pendulum).
    fn make_block(&mut self, base: usize, rows: &[Row], blk: &ConstraintBlock) {
        let mut idx = [0usize; MAX_BLOCK];
        let mut m = 0;
        for i in base..self.row_global.len() {
            let row = &rows[self.row_global[i] as usize];
            let equality =
                row.lo == Real::NEG_INFINITY && row.hi == Real::INFINITY && row.friction.is_none();
            if equality {
                if m == MAX_BLOCK {
                    return;
                }
                idx[m] = i;
                m += 1;
            }
        }
        if m < 2 || (blk.bodies[0].is_some() && blk.bodies[0] == blk.bodies[1]) {
            return;
        }
        let mut k = [[0.0f64; MAX_BLOCK]; MAX_BLOCK];
        for a in 0..m {
            for b in 0..m {
                let (i, j) = (idx[a], idx[b]);
                let mut s = self.ja_lin[i].dot(self.ma_lin[j])
                    + self.ja_ang[i].dot(self.ma_ang[j])
                    + self.jb_lin[i].dot(self.mb_lin[j])
                    + self.jb_ang[i].dot(self.mb_ang[j]);
                if a == b {
                    s += self.extra[i];
                }
                k[a][b] = wide(s);
            }
        }
        let Some(inv) = invert(&mut k, m) else { return };
        self.eq_start.push(self.eq_rows.len() as u32);
        self.eq_len.push(m as u32);
        self.eq_kstart.push(self.eq_kinv.len() as u32);
        for a in 0..m {
            self.eq_rows.push(idx[a] as u32);
            self.in_block[idx[a]] = true;
            for b in 0..m {
                self.eq_kinv.push(inv[a][b] as Real);
            }
        }
    }

    /// Pairs consecutive bounded tangential rows of one constraint (Coulomb rows on the same
    /// normal row, or symmetric box bounds) and stores the inverse of their 2×2 `K + E`.
    fn make_pairs(&mut self, base: usize, rows: &[Row]) {
        let end = self.row_global.len();
        let mut i = base;
        while i + 1 < end {
            let j = i + 1;
            let (ri, rj) = (
                &rows[self.row_global[i] as usize],
                &rows[self.row_global[j] as usize],
            );
            let free = !self.in_block[i] && !self.in_block[j];
            let coulomb = matches!((ri.friction, rj.friction), (Some(a), Some(b)) if a.normal_row == b.normal_row);
            let boxed = ri.friction.is_none()
                && rj.friction.is_none()
                && ri.hi.is_finite()
                && rj.hi.is_finite()
                && ri.lo == -ri.hi
                && rj.lo == -rj.hi;
            if !(free && (coulomb || boxed)) {
                i += 1;
                continue;
            }
            let dot = |a: usize, b: usize| {
                self.ja_lin[a].dot(self.ma_lin[b])
                    + self.ja_ang[a].dot(self.ma_ang[b])
                    + self.jb_lin[a].dot(self.mb_lin[b])
                    + self.jb_ang[a].dot(self.mb_ang[b])
            };
            let (k11, k12, k22) = (
                dot(i, i) + self.extra[i],
                dot(i, j),
                dot(j, j) + self.extra[j],
            );
            let det = k11 * k22 - k12 * k12;
            if det.is_nan() || det <= 1.0e-9 * k11 * k22 {
                i += 1;
                continue;
            }
            self.pair_of[i] = self.pair_kinv.len() as u32;
            self.pair_second.push(j as u32);
            self.pair_kinv
                .push([k22 / det, -k12 / det, -k12 / det, k11 / det]);
            self.in_block[j] = true;
            i += 2;
        }
    }

    /// Solves friction pair `p` starting at row `i`.
    fn solve_pair(&mut self, p: usize, i: usize, hs: Real, use_bias: bool, max_speed: Real) {
        let j = self.pair_second[p] as usize;
        let mut r = [0.0 as Real; 2];
        for (k, row) in [i, j].into_iter().enumerate() {
            let soft_relax = !use_bias && self.flags[row] & HARD == 0;
            let (jv, xi) = self.jv_and_error(row, soft_relax);
            let bias = self.bias(row, xi, hs, use_bias, max_speed);
            r[k] = self.target[row] - bias - jv - self.extra[row] * self.impulse[row];
        }
        let kinv = self.pair_kinv[p];
        let (msi, isi) = self.scales(i, use_bias);
        let (msj, isj) = self.scales(j, use_bias);
        let mut new = [
            self.impulse[i] + msi * (kinv[0] * r[0] + kinv[1] * r[1]) - isi * self.impulse[i],
            self.impulse[j] + msj * (kinv[2] * r[0] + kinv[3] * r[1]) - isj * self.impulse[j],
        ];
        // Each direction within its own bounds: the exact path's friction model (a pyramid,
        // with the primary direction along the sliding velocity), so the two paths agree.
        for (k, row) in [i, j].into_iter().enumerate() {
            let (lo, hi) = self.bounds(row);
            new[k] = new[k].clamp(lo, hi);
        }
        for (k, row) in [i, j].into_iter().enumerate() {
            let dp = new[k] - self.impulse[row];
            self.impulse[row] = new[k];
            if dp != 0.0 {
                self.apply(row, dp);
            }
        }
    }

    /// Mass and impulse scales of row i in this pass: a hard row is softened in the biased
    /// solve only, rigid in the relax.
    #[inline]
    fn scales(&self, i: usize, use_bias: bool) -> (Real, Real) {
        if use_bias && self.flags[i] & HARD != 0 {
            (self.mass_scale[i], self.impulse_scale[i])
        } else {
            (1.0, 0.0)
        }
    }

    #[inline]
    fn bounds(&self, i: usize) -> (Real, Real) {
        let l = self.link[i];
        if l == NONE {
            (self.lo[i], self.hi[i])
        } else {
            let b = self.mu[i] * self.impulse[l as usize].max(0.0);
            (-b, b)
        }
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

    fn apply(&mut self, i: usize, dp: Real) {
        let (a, b) = (self.row_a[i], self.row_b[i]);
        if a != NONE {
            self.v[a as usize] += self.ma_lin[i] * dp;
            self.w[a as usize] += self.ma_ang[i] * dp;
        }
        if b != NONE {
            self.v[b as usize] += self.mb_lin[i] * dp;
            self.w[b as usize] += self.mb_ang[i] * dp;
        }
    }

    fn warm_start(&mut self) {
        for i in 0..self.row_global.len() {
            let p = self.impulse[i];
            if p != 0.0 {
                self.apply(i, p);
            }
        }
    }

    /// `J v` and the tracked error of row i; `substep_start` takes the error at the start of
    /// the substep instead of now.
    #[inline]
    fn jv_and_error(&self, i: usize, substep_start: bool) -> (Real, Real) {
        let (dx, dth) = if substep_start {
            (&self.dx_sub, &self.dtheta_sub)
        } else {
            (&self.dx, &self.dtheta)
        };
        let (a, b) = (self.row_a[i], self.row_b[i]);
        let mut jv = 0.0;
        let mut xi = self.xi0[i];
        if a != NONE {
            let a = a as usize;
            jv += self.ja_lin[i].dot(self.v[a]) + self.ja_ang[i].dot(self.w[a]);
            xi += self.ja_lin[i].dot(dx[a]) + self.ja_ang[i].dot(dth[a]);
        }
        if b != NONE {
            let b = b as usize;
            jv += self.jb_lin[i].dot(self.v[b]) + self.jb_ang[i].dot(self.w[b]);
            xi += self.jb_lin[i].dot(dx[b]) + self.jb_ang[i].dot(dth[b]);
        }
        (jv, xi)
    }

    /// The velocity bias of row i for error `xi` (see the module docs).
    #[inline]
    fn bias(&self, i: usize, xi: Real, hs: Real, use_bias: bool, max_speed: Real) -> Real {
        let flags = self.flags[i];
        let unilateral = flags & UNILATERAL != 0;
        if unilateral && xi > 0.0 {
            // A gap may be closed within the substep, never more.
            xi / hs
        } else if flags & HARD == 0 {
            // A soft row is a physical spring: its full force, always.
            self.rate[i] * xi
        } else if !use_bias {
            0.0
        } else if unilateral {
            (self.rate[i] * xi).max(-max_speed)
        } else {
            self.rate[i] * xi
        }
    }

    /// One sweep: the equality blocks, then every other row, each in constraint order.
    fn sweep(&mut self, hs: Real, use_bias: bool, max_speed: Real) {
        for blk in 0..self.eq_start.len() {
            let (start, m) = (self.eq_start[blk] as usize, self.eq_len[blk] as usize);
            let mut r = [0.0 as Real; MAX_BLOCK];
            for a in 0..m {
                let i = self.eq_rows[start + a] as usize;
                let soft_relax = !use_bias && self.flags[i] & HARD == 0;
                let (jv, xi) = self.jv_and_error(i, soft_relax);
                let bias = self.bias(i, xi, hs, use_bias, max_speed);
                r[a] = self.target[i] - bias - jv - self.extra[i] * self.impulse[i];
            }
            let mut dp = [0.0 as Real; MAX_BLOCK];
            for a in 0..m {
                let kinv = &self.eq_kinv[self.eq_kstart[blk] as usize + a * m..];
                dp[a] = (0..m).map(|b| kinv[b] * r[b]).sum();
            }
            for a in 0..m {
                let i = self.eq_rows[start + a] as usize;
                let (ms, is) = self.scales(i, use_bias);
                let d = ms * dp[a] - is * self.impulse[i];
                self.impulse[i] += d;
                self.apply(i, d);
            }
        }
        for i in 0..self.row_global.len() {
            if self.in_block[i] {
                continue;
            }
            if self.pair_of[i] != NONE {
                self.solve_pair(self.pair_of[i] as usize, i, hs, use_bias, max_speed);
                continue;
            }
            let soft_relax = !use_bias && self.flags[i] & HARD == 0;
            let (jv, xi) = self.jv_and_error(i, soft_relax);
            let bias = self.bias(i, xi, hs, use_bias, max_speed);
            let e = self.extra[i];
            let denom = self.diag[i] + e;
            if denom <= 0.0 {
                continue;
            }
            let (ms, is) = self.scales(i, use_bias);
            let dp = ms * (self.target[i] - bias - jv - e * self.impulse[i]) / denom
                - is * self.impulse[i];
            let (lo, hi) = self.bounds(i);
            let new = (self.impulse[i] + dp).clamp(lo, hi);
            let dp = new - self.impulse[i];
            self.impulse[i] = new;
            if dp != 0.0 {
                self.apply(i, dp);
            }
        }
    }

    fn integrate_positions(&mut self, bodies: &mut [SolverBody], hs: Real) {
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
        for &k in island_blocks {
            let blk = &blocks[k as usize];
            let mut out = [Reaction::default(); 2];
            for g in blk.first_row..blk.first_row + blk.row_count {
                let row = &rows[g as usize];
                let l = lambda[g as usize];
                for (s, o) in out.iter_mut().enumerate() {
                    if blk.bodies[s].is_some() {
                        o.force += row.jacobian[s].linear * l;
                        o.torque += row.jacobian[s].angular * l;
                    }
                }
            }
            reactions[k as usize] = out;
        }
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

/// Damping ratio of the implicit softening of hard rows in the biased solve.
const HARD_DAMPING_RATIO: Real = 10.0;

/// Softening of a hard row in the biased solve (the soft step of Box2D v3, after Catto): the
/// row behaves there as a heavily damped spring, mass-normalised, whose bias rate equals the
/// γ-derived `rate`; this damps the Gauss-Seidel iteration of stiff stacks. The relax solve is
/// rigid. Returns (mass scale, impulse scale).
fn hard_softening(rate: Real, hs: Real) -> (Real, Real) {
    if rate <= 0.0 {
        return (1.0, 0.0);
    }
    // Bias rate of a spring (ω, ζ) at step hs is ω/(2ζ + hs·ω); solve it for ω.
    let hr = (hs * rate).min(0.9);
    let omega = 2.0 * HARD_DAMPING_RATIO * rate / (1.0 - hr);
    let a1 = 2.0 * HARD_DAMPING_RATIO + hs * omega;
    let a2 = hs * omega * a1;
    (a2 / (1.0 + a2), 1.0 / (1.0 + a2))
}

/// Inverse of the leading `m×m` block of `k` by Gauss-Jordan elimination with partial pivoting;
/// `None` if it is singular.
#[allow(clippy::needless_range_loop)]
fn invert(
    k: &mut [[f64; MAX_BLOCK]; MAX_BLOCK],
    m: usize,
) -> Option<[[f64; MAX_BLOCK]; MAX_BLOCK]> {
    let mut inv = [[0.0f64; MAX_BLOCK]; MAX_BLOCK];
    for (i, row) in inv.iter_mut().enumerate().take(m) {
        row[i] = 1.0;
    }
    let scale = (0..m).fold(0.0f64, |s, i| s.max(k[i][i].abs()));
    for col in 0..m {
        let pivot = (col..m).max_by(|&a, &b| k[a][col].abs().total_cmp(&k[b][col].abs()))?;
        if k[pivot][col].abs().is_nan() || k[pivot][col].abs() <= 1.0e-12 * scale {
            return None;
        }
        k.swap(col, pivot);
        inv.swap(col, pivot);
        let p = k[col][col];
        for j in 0..m {
            k[col][j] /= p;
            inv[col][j] /= p;
        }
        for r in 0..m {
            if r != col {
                let f = k[r][col];
                if f != 0.0 {
                    for j in 0..m {
                        k[r][j] -= f * k[col][j];
                        inv[r][j] -= f * inv[col][j];
                    }
                }
            }
        }
    }
    Some(inv)
}
