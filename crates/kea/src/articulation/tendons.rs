//! Fixed tendons on a tree's coordinates (MuJoCo's `<tendon><fixed>`): a length
//! `L = L₀ + Σ cᵢ qᵢ`, its rate `L̇ = Σ cᵢ q̇ᵢ`, and
//!
//! * a **spring and damper** along it, MuJoCo's passive tendon force
//!   `f = −k (L − l_hi)` above the spring's length range `[l_lo, l_hi]`, `−k (L − l_lo)` below,
//!   0 inside, less `b L̇`, passed to the coordinates as `τᵢ += cᵢ f` in every evaluation of the
//!   accelerations — explicit, as MuJoCo's `Euler` and `RK4` take it (its `implicitfast` takes
//!   the damper implicitly; Kea's Euler does not, so a stiff tendon damper needs a step that
//!   resolves it);
//! * a **range** `[lo, hi]`: within the soft model's margin of an end, a row `J = ±cᵀ` of the
//!   soft stops' problem (`soft_limits.rs`), with MuJoCo's reference acceleration
//!   `−b J q̇ − k·imp(x)·x` and regulariser `(1 − imp)/imp · J H'⁻¹ Jᵀ` — solved exactly with
//!   the stops and the contacts (`solve_rows_exactly`).

use super::soft_limits::{impedance, reference_gains};
use super::ArticulatedTree;
use crate::math::wide;
use crate::SoftLimit;

/// A fixed tendon over some of a tree's coordinates (module docs). Its terms are
/// `terms[first..first + count]` of the slice given with it to
/// [`ArticulatedTree::set_tendons`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TreeTendon {
    pub first: usize,
    pub count: usize,
    /// The length at `q = 0`.
    pub offset: f64,
    pub stiffness: f64,
    pub damping: f64,
    /// The spring's rest lengths: no spring force between them.
    pub spring: (f64, f64),
    pub range: Option<(f64, f64)>,
    /// The range's soft model.
    pub soft: SoftLimit,
}

/// One engaged end of a tendon's range this evaluation: its tendon, direction (+1 lower,
/// −1 upper), reference acceleration and regulariser relative to `J H'⁻¹ Jᵀ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct TendonRow {
    pub tendon: usize,
    pub sign: f64,
    pub reference: f64,
    pub regulariser: f64,
}

/// A tree's tendons and their terms `(coordinate, coefficient)`.
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct TendonState {
    pub tendons: Vec<TreeTendon>,
    pub terms: Vec<(usize, f64)>,
    pub rows: Vec<TendonRow>,
}

impl TendonState {
    /// Tendon `t`'s terms.
    pub fn terms(&self, t: usize) -> &[(usize, f64)] {
        let x = &self.tendons[t];
        &self.terms[x.first..x.first + x.count]
    }

    /// Tendon `t`'s length and rate at `q`, `qd`.
    fn length(&self, t: usize, q: &[f64], qd: &[f64]) -> (f64, f64) {
        let mut length = self.tendons[t].offset;
        let mut rate = 0.0;
        for &(i, c) in self.terms(t) {
            length += c * q[i];
            rate += c * qd[i];
        }
        (length, rate)
    }
}

impl ArticulatedTree {
    /// Sets the tendons of the steps that follow (replacing any before); each one's terms
    /// index `terms` and name coordinates of the tree (trusted: the world builds them).
    pub(crate) fn set_tendons(&mut self, tendons: &[TreeTendon], terms: &[(usize, f64)]) {
        let s = &mut self.tendon;
        s.tendons.clear();
        s.tendons.extend_from_slice(tendons);
        s.terms.clear();
        s.terms.extend_from_slice(terms);
        debug_assert!(terms.iter().all(|&(i, _)| i < self.len()));
    }

    /// Adds the tendons' springs and dampers at `q`, `qd` to the right side `rhs`.
    pub(super) fn tendon_forces(&self, q: &[f64], qd: &[f64], rhs: &mut [f64]) {
        let s = &self.tendon;
        for (t, x) in s.tendons.iter().enumerate() {
            if x.stiffness == 0.0 && x.damping == 0.0 {
                continue;
            }
            let (length, rate) = s.length(t, q, qd);
            let f = -x.stiffness * stretch(length, x.spring) - x.damping * rate;
            for &(i, c) in s.terms(t) {
                rhs[i] += c * f;
            }
        }
    }

    /// The rows of the tendons' ranges within their margins at `q`, `qd` (module docs).
    pub(super) fn tendon_rows(&mut self, q: &[f64], qd: &[f64], step: f64) {
        let mut rows = std::mem::take(&mut self.tendon.rows);
        rows.clear();
        let s = &self.tendon;
        for (t, x) in s.tendons.iter().enumerate() {
            let Some((lo, hi)) = x.range else {
                continue;
            };
            let soft = &x.soft;
            let margin = wide(soft.margin);
            let (b, k) = reference_gains(soft, step);
            let (length, rate) = s.length(t, q, qd);
            for (sign, distance) in [(1.0, length - lo), (-1.0, hi - length)] {
                if distance >= margin {
                    continue;
                }
                let x = distance - margin;
                let d = impedance(soft, x);
                rows.push(TendonRow {
                    tendon: t,
                    sign,
                    reference: -b * sign * rate - k * d * x,
                    regulariser: (1.0 - d) / d,
                });
            }
        }
        self.tendon.rows = rows;
    }

    /// Whether the tree has tendons.
    pub(super) fn has_tendons(&self) -> bool {
        !self.tendon.tendons.is_empty()
    }
}

/// How far `length` is past the spring's rest band `[lo, hi]` (negative below it, 0 inside).
pub(crate) fn stretch(length: f64, (lo, hi): (f64, f64)) -> f64 {
    if length > hi {
        length - hi
    } else if length < lo {
        length - lo
    } else {
        0.0
    }
}
