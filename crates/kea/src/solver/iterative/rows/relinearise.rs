//! Joints re-linearised inside the substeps: each joint's rows written again at the bodies'
//! present poses, so that a link turning fast within a step keeps its anchors and axes where
//! they are rather than where they were when the step began (a whipped chain).
//!
//! The fresh rows replace the Jacobians, effective masses, blocks and errors of the rows packed
//! at the step's start, and the error tracking restarts from here: `xi0` is set so that the
//! usual `xi0 − c·t + J·(Δx, Δθ)` gives the fresh error now. Impulses, bounds and softness stay
//! (a block whose rows change in number or kind keeps its step-start rows).

use super::super::bodies::{BodyStates, NONE};
use super::gather::{block_matrix, invert, row_lever, row_masses};
use super::{JointRows, MAX_BLOCK};
use crate::constraint::{Row, RowBody, RowContext, RowWriter};
use crate::math::{rotate_by_vector, Real};
use crate::solver::{ConstraintBlock, RowSource, SolverBody, SolverParams};

impl JointRows {
    /// Writes every gathered joint block's rows again at the present poses (module docs).
    pub(crate) fn relinearise(
        &mut self,
        source: &dyn RowSource,
        blocks: &[ConstraintBlock],
        bodies: &[SolverBody],
        states: &mut BodyStates,
        params: &SolverParams,
    ) {
        if self.blk_global.is_empty() {
            return; // contacts only: nothing to write again, no base to move
        }
        states.mark_linearisation();
        let hs = params.dt / params.iterative.substeps as Real;
        let mut fresh = std::mem::take(&mut self.fresh);
        for b in 0..self.blk_global.len() {
            let k = self.blk_global[b] as usize;
            let blk = &blocks[k];
            let ctx = RowContext {
                bodies: blk.bodies.map(|g| self.present_body(g, bodies, states)),
                dt: params.dt,
                epsilon: params.epsilon,
                gamma: params.gamma,
                contact_spring: params.contact_spring,
            };
            fresh.clear();
            source.rewrite(k, &ctx, &mut RowWriter::new(&mut fresh));
            let (base, count) = (self.blk_base[b] as usize, self.blk_count[b] as usize);
            let same_kind = fresh.len() == count
                && fresh.iter().enumerate().all(|(j, r)| {
                    let i = base + j;
                    r.bounce == (self.flags[i] & super::BOUNCE != 0)
                        && r.friction.is_some() == (self.link[i] != NONE)
                        && r.lo.is_finite() == self.lo[i].is_finite()
                        && r.hi.is_finite() == self.hi[i].is_finite()
                });
            // A block whose rows changed (a limit coming or going) still refreshes its leading
            // equality rows (a joint writes those first, always the same): its anchors and axes
            // keep up with the poses, its stops stay as the step began.
            let refreshed = if same_kind {
                count
            } else {
                fresh
                    .iter()
                    .take(count)
                    .enumerate()
                    .take_while(|(j, r)| {
                        let i = base + j;
                        is_equality(r)
                            && self.lo[i] == Real::NEG_INFINITY
                            && self.hi[i] == Real::INFINITY
                            && self.link[i] == NONE
                    })
                    .count()
            };
            for (j, row) in fresh.iter().enumerate().take(refreshed) {
                // A stop stays as the step began: refreshed, a twist stop pressed by a steady
                // torque settled 0.026 rad past it on Gauss–Seidel islands.
                if self.flags[base + j] & super::UNILATERAL != 0 && !self.direct[base + j] {
                    continue;
                }
                self.refresh_row(base + j, row, blk, bodies, states, hs);
            }
            if refreshed == 0 {
                continue;
            }
            self.share_lever(base..base + refreshed);
            if self.direct[base] {
                continue; // solved directly: no block or pair inverses needed
            }
            if self.blk_eq[b] != NONE {
                self.refresh_block(self.blk_eq[b] as usize);
            }
            for i in base..base + refreshed {
                if self.pair_of[i] != NONE {
                    self.refresh_pair(self.pair_of[i] as usize, i);
                }
            }
        }
        self.fresh = fresh;
    }

    /// Solver body `g` as a row writer sees it now.
    fn present_body(&self, g: Option<u32>, bodies: &[SolverBody], states: &BodyStates) -> RowBody {
        let Some(g) = g else {
            return RowBody::STATIC;
        };
        let body = &bodies[g as usize];
        let l = states.local_of[g as usize];
        if l == NONE {
            // A kinematic body: it moves at its set velocity.
            let t = self.elapsed;
            let mut rb = RowBody::fixed(
                body.position + body.linear_velocity * t,
                rotate_by_vector(body.orientation, body.angular_velocity * t),
            );
            rb.linear_velocity = body.linear_velocity;
            rb.angular_velocity = body.angular_velocity;
            return rb;
        }
        let l = l as usize;
        let (vel, q) = (states.vel[l], states.orientation_now(l));
        RowBody {
            position: body.position + states.delta[l].dp,
            orientation: q,
            linear_velocity: vel.v,
            angular_velocity: vel.w,
            free_linear_velocity: vel.v,
            free_angular_velocity: vel.w,
            dynamic: !body.is_fixed(),
            fast_spin_axis: body.fast_spin_axis.map(|a| q * a),
        }
    }

    /// Row `i` from its fresh version `row` (block `blk`).
    fn refresh_row(
        &mut self,
        i: usize,
        row: &Row,
        blk: &ConstraintBlock,
        bodies: &[SolverBody],
        states: &BodyStates,
        hs: Real,
    ) {
        let (kinematic, jm, mut diag) = row_masses(row, blk, bodies, |g| {
            states.inv_inertia[states.local_of[g as usize] as usize]
        });
        // How far the row's bodies moved along it since the step began.
        let mut moved = 0.0;
        for (s, l) in [(0, self.row_a[i]), (1, self.row_b[i])] {
            if l != NONE {
                let (j, l) = (row.jacobian[s], l as usize);
                moved += j.linear.dot(states.delta[l].dp) + j.angular.dot(states.dtheta[l]);
            }
        }
        if self.row_a[i] != NONE && self.row_a[i] == self.row_b[i] {
            diag +=
                2.0 * (row.jacobian[0].linear.dot(jm[1].0) + row.jacobian[0].angular.dot(jm[1].1));
        }
        self.ja_lin[i] = row.jacobian[0].linear;
        self.ja_ang[i] = row.jacobian[0].angular;
        self.jb_lin[i] = row.jacobian[1].linear;
        self.jb_ang[i] = row.jacobian[1].angular;
        (self.ma_lin[i], self.ma_ang[i]) = jm[0];
        (self.mb_lin[i], self.mb_ang[i]) = jm[1];
        self.diag[i] = diag;
        let c = if row.bounce { 0.0 } else { row.c };
        self.target[i] = c - kinematic;
        self.bounce_target[i] = row.c - kinematic;
        self.chord[i] = 0.5 * hs * row.curvature;
        // The fresh error now is `row.xi − c·t`: a row's moving reference (a path) is written
        // as of the step's start, while the kinematic bodies were written where they are now.
        // Through the usual tracking (module docs) that takes:
        self.xi0[i] = row.xi - kinematic * self.elapsed - moved;
        self.lever[i] = row_lever(row);
    }

    /// The inverse of equality block `e` from its rows' present Jacobians (kept if singular).
    fn refresh_block(&mut self, e: usize) {
        let (start, m) = (self.eq_start[e] as usize, self.eq_len[e] as usize);
        let mut idx = [0usize; MAX_BLOCK];
        for a in 0..m {
            idx[a] = self.eq_rows[start + a] as usize;
        }
        let mut k = block_matrix(self, &idx[..m]);
        if let Some(inv) = invert(&mut k, m) {
            let ks = self.eq_kstart[e] as usize;
            for a in 0..m {
                for b in 0..m {
                    self.eq_kinv[ks + a * m + b] = inv[a][b] as Real;
                }
            }
        }
    }

    /// The 2×2 inverse of friction pair `p` (rows `i` and its second), kept if singular.
    fn refresh_pair(&mut self, p: usize, i: usize) {
        let j = self.pair_second[p] as usize;
        let k = block_matrix(self, &[i, j]);
        let (k11, k12, k22) = (k[0][0] as Real, k[0][1] as Real, k[1][1] as Real);
        let det = k11 * k22 - k12 * k12;
        if det.is_finite() && det > 1.0e-9 * k11 * k22 {
            self.pair_kinv[p] = [k22 / det, -k12 / det, -k12 / det, k11 / det];
        }
    }
}

/// A row with no bounds and no friction link: a joint's equality.
fn is_equality(r: &Row) -> bool {
    r.lo == Real::NEG_INFINITY && r.hi == Real::INFINITY && r.friction.is_none()
}
