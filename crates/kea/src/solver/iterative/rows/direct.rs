//! Split islands: the rows of their joints solved directly inside the substeps, in place of
//! their Gauss-Seidel sweeps.
//!
//! Each pass computes, for every such row, the same residual a sweep would
//! (`r = c − bias − J v − e·P`) and solves all of them at once for the impulses that zero it,
//! within their bounds: `(J M⁻¹ Jᵀ + E)(P_new − P) = r` by the exact path's block-sparse
//! factorisation and pivoting, one system per joint-connected component
//! ([`ComponentSystems`]). A chain or a ragdoll is then as rigid after
//! each pass as its linearisation allows, however long or heavy-ended, while its contacts
//! (solved around it by the contact solver) keep their cost. Hard rows are solved rigidly in
//! both passes (their bias in the biased one only), soft rows as the springs they are.

use super::super::bodies::{BodyStates, NONE};
use super::{JointRows, HARD, UNILATERAL};
use crate::math::{to_f64, wide, Real, Vec3};
use crate::solver::exact::ComponentSystems;
use crate::solver::sparse::{LcpReport, Limits};

/// The fraction of a hard equality row's error its biased direct solve removes per substep
/// (the relax solve then takes the correcting velocity out again).
const DIRECT_RATE: Real = 0.5;

impl JointRows {
    /// Whether any gathered row is solved directly.
    pub(crate) fn has_direct(&self) -> bool {
        self.any_direct
    }

    /// Writes the direct rows' system at their present linearisation (after gathering or
    /// re-linearising).
    pub(crate) fn assemble_direct(&mut self, states: &BodyStates, sys: &mut ComponentSystems) {
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
                    let link = (self.link[i] != NONE)
                        .then(|| (self.direct_index[self.link[i] as usize], wide(self.mu[i])));
                    (wide(self.extra[i]), link)
                }),
            );
        }
        let direct_rows = &self.direct_rows;
        sys.assemble(|s| {
            let i = direct_rows[s] as usize;
            (
                [
                    to_f64(self.ja_lin[i]),
                    to_f64(self.ja_ang[i]),
                    to_f64(self.jb_lin[i]),
                    to_f64(self.jb_ang[i]),
                ],
                [
                    to_f64(self.ma_lin[i]),
                    to_f64(self.ma_ang[i]),
                    to_f64(self.mb_lin[i]),
                    to_f64(self.mb_ang[i]),
                ],
            )
        });
    }

    /// Applies impulse `dp` of row `i` with its own Jacobian (no lever shift).
    fn apply_unshifted(&self, states: &mut BodyStates, i: usize, dp: Real) {
        let (a, b) = (self.row_a[i], self.row_b[i]);
        if a != NONE {
            let vel = &mut states.vel[a as usize];
            vel.v += self.ma_lin[i] * dp;
            vel.w += self.ma_ang[i] * dp;
        }
        if b != NONE {
            let vel = &mut states.vel[b as usize];
            vel.v += self.mb_lin[i] * dp;
            vel.w += self.mb_ang[i] * dp;
        }
    }

    /// Row `i` is in the direct system being built (rows come in order, so a normal row
    /// precedes its friction rows).
    fn in_direct(&self, i: usize) -> bool {
        self.direct_index.get(i).is_some_and(|&d| d != NONE)
    }

    /// Starts a pass of the direct system and gives it each direct row's right-hand side,
    /// bounds and guess, `(r, lo, hi, guess)` from `row(self, i)`.
    fn fill_direct(
        &self,
        sys: &mut ComponentSystems,
        row: impl Fn(&Self, usize) -> (f64, f64, f64, f64),
    ) {
        sys.begin_pass();
        for &i in &self.direct_rows {
            let (r, lo, hi, guess) = row(self, i as usize);
            sys.push(r, lo, hi, guess);
        }
    }

    /// One direct pass over the split islands' rows (module docs): the biased solve with
    /// `use_bias`, else the relax.
    pub(crate) fn solve_direct(
        &mut self,
        states: &mut BodyStates,
        sys: &mut ComponentSystems,
        hs: Real,
        use_bias: bool,
        max_speed: Real,
        limits: Limits,
    ) -> LcpReport {
        let n = self.direct_rows.len();
        self.fill_direct(sys, |rows, i| {
            if rows.skipped(i) {
                // Held where it is: a split island with contacts is not synchronised.
                let y = wide(rows.impulse[i]);
                return (0.0, y, y, y);
            }
            let soft_relax = !use_bias && !rows.rigid(i);
            let (jv, xi) = rows.jv_and_error_shifted(states, i, soft_relax, None);
            let bias = if use_bias && rows.correction(i) == Correction::Equality {
                DIRECT_RATE * xi / hs
            } else {
                rows.bias(i, xi, hs, use_bias, max_speed)
            };
            let r = rows.target_for(i)
                - rows.chord_for(i, use_bias)
                - bias
                - jv
                - rows.extra[i] * rows.impulse[i];
            let (lo, hi) = rows.own_bounds(i);
            let (lo, hi) = (wide(lo), wide(hi));
            (wide(r), lo, hi, wide(rows.impulse[i]))
        });
        let report = sys.solve(limits);
        for s in 0..n {
            let i = self.direct_rows[s] as usize;
            let new = sys.impulse(s) as Real;
            let dp = new - self.impulse[i];
            if dp != 0.0 && dp.is_finite() {
                self.impulse[i] = new;
                self.apply_unshifted(states, i, dp);
            }
        }
        report
    }

    /// Whether any row of the direct system is synchronised.
    pub(crate) fn any_direct_synchronised(&self) -> bool {
        self.direct_rows
            .iter()
            .any(|&i| self.flags[i as usize] & super::SYNCHRONISED != 0)
    }

    /// One post-stabilisation pass (a Newton step on positions): solves
    /// `(J M⁻¹ Jᵀ) Δ = −xi` for the rigid rows that correct errors (equalities free,
    /// one-sided stops with `Δ ≥ 0`; others held at zero) and moves the bodies by `M⁻¹ Jᵀ Δ`,
    /// velocities untouched. The rows must be linearised at the present poses.
    pub(crate) fn stabilise(
        &mut self,
        states: &mut BodyStates,
        sys: &mut ComponentSystems,
        limits: Limits,
    ) -> LcpReport {
        let n = self.direct_rows.len();
        self.fill_direct(sys, |rows, i| {
            let xi = rows.error(states, i, false);
            let (lo, hi, r) = match rows.correction(i) {
                Correction::Equality => (f64::NEG_INFINITY, f64::INFINITY, -wide(xi)),
                Correction::Push if xi < 0.0 => (0.0, f64::INFINITY, -wide(xi)),
                _ => (0.0, 0.0, 0.0),
            };
            (r, lo, hi, 0.0)
        });
        let report = sys.solve(limits);
        // Each body's move summed over its rows, then made once.
        self.moves.clear();
        self.moves.resize(states.len(), (Vec3::ZERO, Vec3::ZERO));
        for s in 0..n {
            let d = sys.impulse(s) as Real;
            if d == 0.0 || !d.is_finite() {
                continue;
            }
            let i = self.direct_rows[s] as usize;
            for (slot, lin, ang) in [
                (self.row_a[i], self.ma_lin[i], self.ma_ang[i]),
                (self.row_b[i], self.mb_lin[i], self.mb_ang[i]),
            ] {
                if slot != NONE {
                    let m = &mut self.moves[slot as usize];
                    m.0 += lin * d;
                    m.1 += ang * d;
                }
            }
        }
        for (l, &(dx, dtheta)) in self.moves.iter().enumerate() {
            if dx != Vec3::ZERO || dtheta != Vec3::ZERO {
                states.displace(l, dx, dtheta);
            }
        }
        report
    }

    /// The largest error post-stabilisation would correct now (module docs of
    /// [`Self::stabilise`]).
    pub(crate) fn direct_error(&self, states: &BodyStates) -> Real {
        let mut worst: Real = 0.0;
        for &i in &self.direct_rows {
            let i = i as usize;
            let correction = self.correction(i);
            if correction == Correction::None {
                continue;
            }
            let xi = self.error(states, i, false);
            worst = match correction {
                Correction::Equality => worst.max(xi.abs()),
                _ => worst.max(-xi),
            };
        }
        worst
    }

    /// How post-stabilisation treats row `i`: only rigid rows that correct an error do
    /// (equalities both ways, one-sided stops only out of penetration).
    fn correction(&self, i: usize) -> Correction {
        if self.flags[i] & HARD == 0 || self.rate[i] <= 0.0 || self.link[i] != NONE {
            Correction::None
        } else if self.lo[i] == Real::NEG_INFINITY && self.hi[i] == Real::INFINITY {
            Correction::Equality
        } else if self.flags[i] & UNILATERAL != 0 {
            Correction::Push
        } else {
            Correction::None
        }
    }
}

/// What post-stabilisation does with a row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Correction {
    /// Left alone (soft, velocity-only, friction or two-sided bounded rows).
    None,
    /// Closed both ways.
    Equality,
    /// Pushed out of penetration only.
    Push,
}
