//! The Gauss-Seidel sweeps over rows: per row, per equality block and per tangential pair, with
//! the soft and hard row rules of the module docs.

use super::super::bodies::{BodyStates, NONE};
use super::{JointRows, HARD, MAX_BLOCK, UNILATERAL};
use crate::math::{Real, Vec3};

impl JointRows {
    /// Solves friction pair `p` starting at row `i`.
    fn solve_pair(
        &mut self,
        states: &mut BodyStates,
        p: usize,
        i: usize,
        hs: Real,
        use_bias: bool,
        max_speed: Real,
    ) {
        let j = self.pair_second[p] as usize;
        let mut r = [0.0 as Real; 2];
        for (k, row) in [i, j].into_iter().enumerate() {
            let soft_relax = !use_bias && !self.rigid(row);
            let (jv, xi) = self.jv_and_error(states, row, soft_relax);
            let bias = self.bias(row, xi, hs, use_bias, max_speed);
            r[k] = self.target_for(row)
                - self.chord_for(row, use_bias)
                - bias
                - jv
                - self.extra[row] * self.impulse[row];
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
                self.apply(states, row, dp);
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
    pub(super) fn bounds(&self, i: usize) -> (Real, Real) {
        let l = self.link[i];
        if l == NONE {
            self.own_bounds(i)
        } else {
            let b = self.mu[i] * self.impulse[l as usize].max(0.0);
            (-b, b)
        }
    }

    /// How far each body of row i has moved from the pair's mean since the step began: the
    /// point where a two-body row pushes moves with the pair's mean, so each lever shifts by the
    /// body's departure from it (`J_ang → J_ang − δ × J_lin`). Both bodies are then pushed at
    /// one point all through the step and the pair keeps its angular momentum. A row on one
    /// body (to the world) has no shift: its point moves with that body.
    #[inline]
    fn departures(&self, states: &BodyStates, i: usize) -> (Vec3, Vec3) {
        let (a, b) = (self.row_a[i], self.row_b[i]);
        if a == NONE || b == NONE {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        let (a, b) = (a as usize, b as usize);
        // Since the rows were last linearised (the step's start, or a substep's).
        let half = 0.5
            * ((states.delta[a].dp - states.relin_dp[a])
                - (states.delta[b].dp - states.relin_dp[b]));
        let lever = self.lever[i];
        if half.length_squared() > 0.01 * lever * lever {
            // Moved more than a tenth of the lever: the linearisation is gone; do not shift.
            return (Vec3::ZERO, Vec3::ZERO);
        }
        (half, -half)
    }

    /// Applies impulse `dp` of row i (with the shifted levers of [`Self::departures`]).
    pub(super) fn apply(&self, states: &mut BodyStates, i: usize, dp: Real) {
        let (a, b) = (self.row_a[i], self.row_b[i]);
        let (da, db) = self.departures(states, i);
        if a != NONE {
            let a = a as usize;
            let shift = da.cross(self.ja_lin[i]);
            let dw = (self.ma_ang[i] - states.inv_inertia[a] * shift) * dp;
            let vel = &mut states.vel[a];
            vel.v += self.ma_lin[i] * dp;
            vel.w += dw;
        }
        if b != NONE {
            let b = b as usize;
            let shift = db.cross(self.jb_lin[i]);
            let dw = (self.mb_ang[i] - states.inv_inertia[b] * shift) * dp;
            let vel = &mut states.vel[b];
            vel.v += self.mb_lin[i] * dp;
            vel.w += dw;
        }
    }

    /// Re-applies each row's impulse of the previous substep (or step).
    pub(crate) fn warm_start(&mut self, states: &mut BodyStates) {
        for i in 0..self.row_global.len() {
            let p = self.impulse[i];
            if p != 0.0 {
                self.apply(states, i, p);
            }
        }
    }

    /// `J v` and the tracked error of row i; `substep_start` takes the error at the start of
    /// the substep instead of now.
    #[inline]
    pub(super) fn jv_and_error(
        &self,
        states: &BodyStates,
        i: usize,
        substep_start: bool,
    ) -> (Real, Real) {
        self.jv_and_error_shifted(states, i, substep_start, Some(self.departures(states, i)))
    }

    /// [`Self::jv_and_error`] with the levers shifted by the bodies' departures `(da, db)`
    /// (`None`: the row's own Jacobian, as a direct solve's matrix has it).
    #[inline]
    pub(super) fn jv_and_error_shifted(
        &self,
        states: &BodyStates,
        i: usize,
        substep_start: bool,
        shift: Option<(Vec3, Vec3)>,
    ) -> (Real, Real) {
        (
            self.jv(states, i, shift),
            self.error(states, i, substep_start),
        )
    }

    /// `J v` of row i, its levers shifted by `shift` (see [`Self::jv_and_error_shifted`]).
    #[inline]
    pub(super) fn jv(&self, states: &BodyStates, i: usize, shift: Option<(Vec3, Vec3)>) -> Real {
        let (a, b) = (self.row_a[i], self.row_b[i]);
        let mut jv = 0.0;
        if a != NONE {
            let a = a as usize;
            let ang = match shift {
                Some((da, _)) => self.ja_ang[i] - da.cross(self.ja_lin[i]),
                None => self.ja_ang[i],
            };
            jv += self.ja_lin[i].dot(states.vel[a].v) + ang.dot(states.vel[a].w);
        }
        if b != NONE {
            let b = b as usize;
            let ang = match shift {
                Some((_, db)) => self.jb_ang[i] - db.cross(self.jb_lin[i]),
                None => self.jb_ang[i],
            };
            jv += self.jb_lin[i].dot(states.vel[b].v) + ang.dot(states.vel[b].w);
        }
        jv
    }

    /// The tracked error of row i, now or (`substep_start`) at the start of the substep.
    #[inline]
    pub(super) fn error(&self, states: &BodyStates, i: usize, substep_start: bool) -> Real {
        let elapsed = if substep_start {
            self.elapsed_sub
        } else {
            self.elapsed
        };
        // Each body's displacement and turn since the step began, now or at the substep's start.
        let moved = |l: usize| {
            if substep_start {
                (states.dx_sub[l], states.dtheta_sub[l])
            } else {
                (states.delta[l].dp, states.dtheta[l])
            }
        };
        let (a, b) = (self.row_a[i], self.row_b[i]);
        // The error is measured from a reference that moves at the row's target velocity (a
        // path, a kinematic body): over one step this is what the exact path's single solve does.
        let mut xi = self.xi0[i] - self.target[i] * elapsed;
        if a != NONE {
            let (dx, dth) = moved(a as usize);
            xi += self.ja_lin[i].dot(dx) + self.ja_ang[i].dot(dth);
        }
        if b != NONE {
            let (dx, dth) = moved(b as usize);
            xi += self.jb_lin[i].dot(dx) + self.jb_ang[i].dot(dth);
        }
        xi
    }

    /// The velocity bias of row i for error `xi` (see the module docs).
    #[inline]
    pub(super) fn bias(
        &self,
        i: usize,
        xi: Real,
        hs: Real,
        use_bias: bool,
        max_speed: Real,
    ) -> Real {
        let flags = self.flags[i];
        let unilateral = flags & UNILATERAL != 0;
        if unilateral && xi > 0.0 {
            // A gap may be closed within the substep, never more.
            xi / hs
        } else if !self.rigid(i) {
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
    pub(crate) fn sweep(
        &mut self,
        states: &mut BodyStates,
        hs: Real,
        use_bias: bool,
        max_speed: Real,
    ) {
        for blk in 0..self.eq_start.len() {
            let (start, m) = (self.eq_start[blk] as usize, self.eq_len[blk] as usize);
            let first = self.eq_rows[start] as usize;
            if self.direct[first] {
                continue;
            }
            if self.synchronising {
                let rows = &self.eq_rows[start..start + m];
                if rows.iter().all(|&i| self.skipped(i as usize)) {
                    continue;
                }
                if rows.iter().any(|&i| self.skipped(i as usize)) {
                    self.solve_block_rows(states, blk, hs, max_speed);
                    continue;
                }
            }
            let mut r = [0.0 as Real; MAX_BLOCK];
            for a in 0..m {
                let i = self.eq_rows[start + a] as usize;
                let soft_relax = !use_bias && !self.rigid(i);
                let (jv, xi) = self.jv_and_error(states, i, soft_relax);
                let bias = self.bias(i, xi, hs, use_bias, max_speed);
                r[a] = self.target_for(i)
                    - self.chord_for(i, use_bias)
                    - bias
                    - jv
                    - self.extra[i] * self.impulse[i];
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
                self.apply(states, i, d);
            }
        }
        for i in 0..self.row_global.len() {
            if self.in_block[i] || self.direct[i] || self.skipped(i) {
                continue;
            }
            if self.pair_of[i] != NONE {
                self.solve_pair(states, self.pair_of[i] as usize, i, hs, use_bias, max_speed);
                continue;
            }
            self.solve_row(states, i, hs, use_bias, max_speed);
        }
    }

    /// Solves row `i` alone.
    fn solve_row(
        &mut self,
        states: &mut BodyStates,
        i: usize,
        hs: Real,
        use_bias: bool,
        max_speed: Real,
    ) {
        let soft_relax = !use_bias && !self.rigid(i);
        let (jv, xi) = self.jv_and_error(states, i, soft_relax);
        let bias = self.bias(i, xi, hs, use_bias, max_speed);
        let e = self.extra[i];
        let denom = self.diag[i] + e;
        if denom <= 0.0 {
            return;
        }
        let (ms, is) = self.scales(i, use_bias);
        let r = self.target_for(i) - self.chord_for(i, use_bias) - bias - jv - e * self.impulse[i];
        let dp = ms * r / denom - is * self.impulse[i];
        let (lo, hi) = self.bounds(i);
        let new = (self.impulse[i] + dp).clamp(lo, hi);
        let dp = new - self.impulse[i];
        self.impulse[i] = new;
        if dp != 0.0 {
            self.apply(states, i, dp);
        }
    }

    /// The synchronising pass over an equality block with a soft row (a suspension's spring
    /// among a wheel's hinges): its hard rows one by one, a few times round (the block's
    /// inverse includes the spring, which this pass leaves alone).
    fn solve_block_rows(&mut self, states: &mut BodyStates, blk: usize, hs: Real, max_speed: Real) {
        let (start, m) = (self.eq_start[blk] as usize, self.eq_len[blk] as usize);
        for _ in 0..4 {
            for a in 0..m {
                let i = self.eq_rows[start + a] as usize;
                if !self.skipped(i) {
                    self.solve_row(states, i, hs, false, max_speed);
                }
            }
        }
    }
}

impl JointRows {
    /// What a velocity pass (a sweep, or a split island's direct solve) takes off row `i`'s
    /// target for the chord of the substep ([`crate::constraint::Row::curvature`]): only the
    /// relax pass, whose velocity the substep hands on, aims along the chord. Measured at
    /// 60 Hz, 10 s, a double pendulum released horizontal: with the chord in both passes the
    /// Gauss-Seidel path gained 50% of its energy, in the relax pass only 1.4%, in neither it
    /// lost 25%; split islands lost 31% without it, gain 0.2% with it in the relax pass, and
    /// in both passes they held the energy too but let a light chain swinging a 100× heavier
    /// end open by 0.86 mm (0.21 mm relax only, 0.013 mm without).
    pub(super) fn chord_for(&self, i: usize, use_bias: bool) -> Real {
        if use_bias {
            0.0
        } else if self.synchronising {
            // Linearised at the poses reached: the velocity is made tangent there, no chord.
            0.0
        } else {
            self.chord[i]
        }
    }
}
