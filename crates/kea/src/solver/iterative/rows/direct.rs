//! Split islands: the rows of their joints solved directly inside the substeps, in place of
//! their Gauss-Seidel sweeps.
//!
//! Each pass computes, for every such row, the same residual a sweep would
//! (`r = c − bias − J v − e·P`) and solves all of them at once for the impulses that zero it,
//! within their bounds: `(J M⁻¹ Jᵀ + E)(P_new − P) = r` by the exact path's block-sparse
//! factorisation and pivoting ([`SubstepSystem`]). A chain or a ragdoll is then as rigid after
//! each pass as its linearisation allows, however long or heavy-ended, while its contacts
//! (solved around it by the contact solver) keep their cost. Hard rows are solved rigidly in
//! both passes (their bias in the biased one only), soft rows as the springs they are.

use super::super::bodies::{BodyStates, NONE};
use super::{JointRows, HARD};
use crate::math::{to_f64, Real};
use crate::solver::exact::{LcpReport, Limits, SubstepRow, SubstepSystem};

impl JointRows {
    /// Whether any gathered row is solved directly.
    pub(crate) fn has_direct(&self) -> bool {
        self.any_direct
    }

    /// Writes the direct rows' system at their present linearisation (after gathering or
    /// re-linearising).
    pub(crate) fn assemble_direct(&mut self, states: &BodyStates, sys: &mut SubstepSystem) {
        sys.clear(states.vel.len());
        self.direct_rows.clear();
        self.direct_index.clear();
        self.direct_index.resize(self.len(), NONE);
        for b in 0..self.blk_base.len() {
            let (base, count) = (self.blk_base[b] as usize, self.blk_count[b] as usize);
            let first = self.direct_rows.len();
            for i in base..base + count {
                let linked_out = self.link[i] != NONE && !self.in_direct(self.link[i] as usize);
                if self.direct[i] && self.diag[i] + self.extra[i] > 0.0 && !linked_out {
                    self.direct_index[i] = self.direct_rows.len() as u32;
                    self.direct_rows.push(i as u32);
                }
            }
            if self.direct_rows.len() == first {
                continue;
            }
            let slot = |l: u32| {
                if l == NONE || !states.writable[l as usize] {
                    u32::MAX
                } else {
                    l
                }
            };
            let slots = [slot(self.row_a[base]), slot(self.row_b[base])];
            let rows = &self.direct_rows[first..];
            sys.add_block(
                slots,
                rows.iter().map(|&i| {
                    let i = i as usize;
                    SubstepRow {
                        jac: [
                            to_f64(self.ja_lin[i]),
                            to_f64(self.ja_ang[i]),
                            to_f64(self.jb_lin[i]),
                            to_f64(self.jb_ang[i]),
                        ],
                        mj: [
                            to_f64(self.ma_lin[i]),
                            to_f64(self.ma_ang[i]),
                            to_f64(self.mb_lin[i]),
                            to_f64(self.mb_ang[i]),
                        ],
                        extra: f64::from(self.extra[i]),
                        link: (self.link[i] != NONE).then(|| {
                            (
                                self.direct_index[self.link[i] as usize],
                                f64::from(self.mu[i]),
                            )
                        }),
                    }
                }),
            );
        }
        sys.assemble();
    }

    /// Row `i` is in the direct system being built (rows come in order, so a normal row
    /// precedes its friction rows).
    fn in_direct(&self, i: usize) -> bool {
        self.direct_index.get(i).is_some_and(|&d| d != NONE)
    }

    /// One direct pass over the split islands' rows (module docs): the biased solve with
    /// `use_bias`, else the relax.
    pub(crate) fn solve_direct(
        &mut self,
        states: &mut BodyStates,
        sys: &mut SubstepSystem,
        hs: Real,
        use_bias: bool,
        max_speed: Real,
        limits: Limits,
    ) -> LcpReport {
        let n = self.direct_rows.len();
        self.direct_r.clear();
        self.direct_lo.clear();
        self.direct_hi.clear();
        self.direct_y.clear();
        for s in 0..n {
            let i = self.direct_rows[s] as usize;
            let soft_relax = !use_bias && self.flags[i] & HARD == 0;
            let (jv, xi) = self.jv_and_error(states, i, soft_relax);
            let bias = self.bias(i, xi, hs, use_bias, max_speed);
            let r = self.target[i] - bias - jv - self.extra[i] * self.impulse[i];
            self.direct_r.push(f64::from(r));
            self.direct_lo.push(f64::from(self.lo[i]));
            self.direct_hi.push(f64::from(self.hi[i]));
            self.direct_y.push(f64::from(self.impulse[i]));
        }
        let report = sys.solve(
            &self.direct_r,
            &self.direct_lo,
            &self.direct_hi,
            &mut self.direct_y,
            limits,
        );
        for s in 0..n {
            let i = self.direct_rows[s] as usize;
            let new = self.direct_y[s] as Real;
            let dp = new - self.impulse[i];
            if dp != 0.0 && dp.is_finite() {
                self.impulse[i] = new;
                self.apply(states, i, dp);
            }
        }
        report
    }
}
