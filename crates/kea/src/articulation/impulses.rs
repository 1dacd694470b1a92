//! The coordinates' stops, motors and dry friction: bounded impulses on the rates after the
//! free step, found by projected Gauss–Seidel on the columns of `H'⁻¹` they act through.

use super::ArticulatedTree;
use crate::error::KeaResult;

/// A fraction of a stop's overshoot taken back per step (the maximal path's `γ` for stops).
const STOP_RECOVERY: f64 = 0.2;

/// What a coordinate's row is: a motor (its rate), dry friction or a stop.
#[derive(Debug, Clone, Copy, PartialEq)]
enum RowKind {
    Motor(f64),
    Friction,
    Stop,
}

/// One constraint on one coordinate's rate after the step: the rate aimed at, and the
/// impulse's bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct CoordinateRow {
    coordinate: usize,
    kind: RowKind,
    target: f64,
    lo: f64,
    hi: f64,
    impulse: f64,
}

impl ArticulatedTree {
    /// Stops, motors and dry friction on the rates `qd` (free, in place): impulses `P` with
    /// `q̇⁺ = q̇ + H'⁻¹ P`, each row's within its bounds, by projected Gauss–Seidel on `H'⁻¹`
    /// (the factor `solve` left). A stop's row aims the rate at what reaches the stop by the
    /// step's end, and only pushes away from it.
    /// A stop acts on the step's mean rate, `q̇ + offset` (see `integrate`). The integrator's
    /// own factor is used where it is `H'` at `q`, else `H'` is factorised here.
    pub(super) fn constrain(
        &mut self,
        q: &[f64],
        qd: &mut [f64],
        tau: &[f64],
        h: f64,
    ) -> KeaResult<()> {
        self.rows.clear();
        for i in 0..self.len() {
            self.coordinate_rows(i, q[i], qd[i], self.offset[i], h);
        }
        self.impulse.iter_mut().for_each(|p| *p = 0.0);
        if self.rows.is_empty() {
            return Ok(());
        }
        let start = std::mem::take(&mut self.rate0);
        let factored = self.factor_for_impulses(q, &start, tau, h);
        self.rate0 = start;
        factored?;
        self.inverse_columns();
        self.project(qd);
        Ok(())
    }

    /// Coordinate `i`'s rows at position `qi` and free rate `rate`: its motor, its dry friction,
    /// and each stop that the step's mean rate `rate + offset` would pass by the step's end.
    /// All act on the mean rate (their targets given here on the end rate), so the
    /// coordinate moves as they say: a stop is not crossed, friction that holds keeps it
    /// where it is, a motor moves it at its speed; `settle_rows` then brings the end rate,
    /// the one a user reads, to the same.
    fn coordinate_rows(&mut self, i: usize, qi: f64, rate: f64, offset: f64, h: f64) {
        let l = self.drives[i];
        let row = |kind: RowKind, target: f64, lo: f64, hi: f64| CoordinateRow {
            coordinate: i,
            kind,
            target,
            lo,
            hi,
            impulse: 0.0,
        };
        if let Some((v, f)) = l.motor {
            self.rows
                .push(row(RowKind::Motor(v), v - offset, -h * f, h * f));
        }
        if l.friction > 0.0 {
            self.rows.push(row(
                RowKind::Friction,
                -offset,
                -h * l.friction,
                h * l.friction,
            ));
        }
        let Some((lo, hi)) = l.limits else {
            return;
        };
        if l.soft_limit.is_some() && self.integrator != super::Integrator::Implicit {
            return; // inside the accelerations (`soft_limits`); the implicit step's are hard
        }
        // The rate that reaches a stop by the step's end; beyond one, the rate that takes
        // back a fifth of the overshoot, no faster than the stop's recovery.
        let recover = |overshoot: f64| (STOP_RECOVERY * overshoot / h).min(l.stop_recovery_speed);
        let min = if qi >= lo {
            (lo - qi) / h
        } else {
            recover(lo - qi)
        } - offset;
        let max = if qi <= hi {
            (hi - qi) / h
        } else {
            -recover(qi - hi)
        } - offset;
        if rate < min + 1e-9 || qi < lo + 1e-9 {
            self.rows.push(row(RowKind::Stop, min, 0.0, f64::INFINITY));
        }
        if rate > max - 1e-9 || qi > hi - 1e-9 {
            self.rows
                .push(row(RowKind::Stop, max, f64::NEG_INFINITY, 0.0));
        }
    }

    /// After the coordinates moved (Runge–Kutta, whose rows act on the step's mean rate):
    /// the end rates, the ones a user reads and the next step starts from, brought to what
    /// the rows hold, instead of carrying the free step's difference between mean and end
    /// rates (`offset`, half a step of the free acceleration) from step to step: a motor's
    /// coordinate ends at the motor's speed, one held by friction or by a stop at rest (a
    /// door pressed on its stop read 0.09 rad/s). Uses the columns of `H'⁻¹` the step's rows
    /// left.
    pub(super) fn settle_rows(&mut self, qd: &mut [f64]) {
        let mut kept = 0;
        for r in 0..self.rows.len() {
            let row = self.rows[r];
            if !row.impulse.is_finite() {
                // A step gone wrong (it is refused as not finite): nothing to settle.
                self.rows.clear();
                return;
            }
            // A motor and friction have what their force left after the step's own pass.
            let (lo, hi) = (row.lo - row.impulse, row.hi - row.impulse);
            let settled = match row.kind {
                RowKind::Motor(v) => Some((v, lo, hi)),
                RowKind::Friction => Some((0.0, lo, hi)),
                RowKind::Stop if row.impulse != 0.0 => {
                    Some((0.0, f64::NEG_INFINITY, f64::INFINITY))
                }
                RowKind::Stop => None,
            };
            if let Some((target, lo, hi)) = settled {
                self.rows[kept] = CoordinateRow {
                    target,
                    lo,
                    hi,
                    impulse: 0.0,
                    ..row
                };
                kept += 1;
            }
        }
        self.rows.truncate(kept);
        if kept > 0 {
            self.project(qd);
        }
    }

    /// The columns of `H'⁻¹` the rows act through (one per constrained coordinate, each a
    /// solve with the factor `solve` left): a coordinate's impulse moves every rate along its
    /// column.
    fn inverse_columns(&mut self) {
        for r in 0..self.rows.len() {
            let j = self.rows[r].coordinate;
            if self.rows[..r].iter().any(|x| x.coordinate == j) {
                continue; // solved for an earlier row of the same coordinate
            }
            self.inverse_column(j);
        }
    }

    /// Column `j` of `H'⁻¹` into `inverse` (a solve with the factor in `h`).
    pub(super) fn inverse_column(&mut self, j: usize) {
        let n = self.len();
        self.column.iter_mut().for_each(|c| *c = 0.0);
        self.column[j] = 1.0;
        let mut col = std::mem::take(&mut self.column);
        self.solve_h(&mut col);
        for (i, &c) in col.iter().enumerate() {
            self.inverse[i * n + j] = c;
        }
        self.column = col;
    }

    /// Projected Gauss–Seidel over the rows until no impulse moves a rate by more than
    /// round-off, the rates `qd` updated as it goes.
    fn project(&mut self, qd: &mut [f64]) {
        let n = self.len();
        for _sweep in 0..200 {
            let mut largest: f64 = 0.0;
            for r in 0..self.rows.len() {
                let row = self.rows[r];
                let i = row.coordinate;
                let w = self.inverse[i * n + i];
                // The impulse that brings the rate to the row's target, kept in its bounds (a
                // stop's bounds let it push one way only).
                let p = (row.impulse + (row.target - qd[i]) / w).clamp(row.lo, row.hi);
                let delta = p - row.impulse;
                if delta != 0.0 {
                    self.rows[r].impulse = p;
                    self.impulse[i] += delta;
                    for (k, rate) in qd.iter_mut().enumerate() {
                        *rate += self.inverse[k * n + i] * delta;
                    }
                    largest = largest.max((delta * w).abs());
                }
            }
            if largest < 1e-12 {
                break;
            }
        }
    }
}
