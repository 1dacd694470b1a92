//! MuJoCo's soft stops on a tree's coordinates (`crate::SoftLimit`): inside every evaluation
//! of the accelerations, each stop within its margin is a row `J = ±e_i` whose force `f ≥ 0`
//! solves `min ½ fᵀ (A + R) f + fᵀ (J q̈₀ − a_ref)` — `A = J H'⁻¹ Jᵀ`, `q̈₀` the free
//! accelerations — exactly, then `q̈ = q̈₀ + H'⁻¹ Jᵀ f`. The regulariser uses the current
//! `[H'⁻¹]ᵢᵢ` where MuJoCo uses its value at the model's reference pose (equal for a slider on
//! a free body, close for an arm). The links' contacts with the base (`contacts.rs`) are rows
//! of the same problem: stops and contacts are one small LCP, solved by the dense pivoting
//! solver warm-started from the last evaluation's sets (`solve_rows_exactly`; it replaced
//! projected Gauss–Seidel sweeps, which converge slowly where a limb's stops couple).

use super::ArticulatedTree;
use crate::math::wide;
use crate::SoftLimit;

/// One engaged soft stop: its coordinate, direction (+1 lower, −1 upper), the acceleration it
/// pulls towards, and its regulariser.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct SoftRow {
    coordinate: usize,
    sign: f64,
    reference: f64,
    regulariser: f64,
}

/// `base^e` for a power other than 1 or 2, out of line: LLVM may compute a `powf` it can see
/// on both sides of the branch (it is marked speculatable), which cost the common power 2 a
/// `pow` call per row.
#[cold]
#[inline(never)]
fn general_power(base: f64, e: f64) -> f64 {
    base.powf(e)
}

/// MuJoCo's reference gains of soft model `s` at step `step`: `b = 2 / (d_max τ)` and
/// `k = 1 / (d_max² τ² ζ²)`, the time constant τ at least two steps.
pub(crate) fn reference_gains(s: &SoftLimit, step: f64) -> (f64, f64) {
    let tau = wide(s.solref[0]).max(2.0 * step);
    let (zeta, dmax) = (wide(s.solref[1]), wide(s.solimp[1]));
    (
        2.0 / (dmax * tau),
        1.0 / (dmax * dmax * tau * tau * zeta * zeta),
    )
}

/// MuJoCo's impedance at distance `x` past the margin.
pub(crate) fn impedance(s: &SoftLimit, x: f64) -> f64 {
    let [dmin, dmax, width, mid, power] = s.solimp.map(wide);
    let x = (x.abs() / width).min(1.0);
    // MuJoCo's default power is 2: a product instead of two `pow` calls.
    let pow = |base: f64, e: f64| {
        if e == 2.0 {
            base * base
        } else if e == 1.0 {
            base
        } else {
            general_power(base, e)
        }
    };
    let y = if x <= mid {
        pow(x, power) / pow(mid, power - 1.0)
    } else {
        1.0 - pow(1.0 - x, power) / pow(1.0 - mid, power - 1.0)
    };
    dmin + y * (dmax - dmin)
}

impl ArticulatedTree {
    /// Adds the soft stops' and the contacts' forces to the accelerations `qdd` at `q`, `qd`;
    /// the factor of `H'` must be in `h`. `step` is the step's length (a time constant is at
    /// least two).
    pub(super) fn soft_stops(&mut self, q: &[f64], qd: &[f64], qdd: &mut [f64], step: f64) {
        let n = self.len();
        self.soft_rows.clear();
        for i in 0..n {
            let l = &self.drives[i];
            let (Some(s), Some((lo, hi))) = (l.soft_limit, l.limits) else {
                continue;
            };
            let margin = wide(s.margin);
            let (b, k) = reference_gains(&s, step);
            for (sign, distance) in [(1.0, q[i] - lo), (-1.0, hi - q[i])] {
                if distance >= margin {
                    continue;
                }
                let x = distance - margin;
                let d = impedance(&s, x);
                self.soft_rows.push(SoftRow {
                    coordinate: i,
                    sign,
                    reference: -b * sign * qd[i] - k * d * x,
                    regulariser: (1.0 - d) / d,
                });
            }
        }
        self.tendon_rows(q, qd, step);
        self.contact_rows(qd, step);
        if self.soft_rows.is_empty() && self.tendon.rows.is_empty() && self.contact.rows.is_empty()
        {
            return;
        }
        // One exact solve of the small LCP (stops and contacts together), warm-started from
        // the last evaluation's sets: a pyramid's edges share a point and a limb's stops
        // couple through the inertia, where sweeps converge slowly.
        self.solve_rows_exactly(qdd);
        self.record_contact_forces();
    }

    /// The soft stops' row `r`: its coordinate, direction, reference, and regulariser relative
    /// to its `[H'⁻¹]ᵢᵢ`.
    pub(super) fn stop_row(&self, r: usize) -> (usize, f64, f64, f64) {
        let row = &self.soft_rows[r];
        (row.coordinate, row.sign, row.reference, row.regulariser)
    }

    /// The soft stops' rows this evaluation.
    pub(super) fn stop_rows(&self) -> usize {
        self.soft_rows.len()
    }
}
