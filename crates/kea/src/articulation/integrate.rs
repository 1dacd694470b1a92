//! How a tree's step integrates its smooth dynamics `H(q) q̈ = τ − c(q, q̇) − d q̇ + servo`:
//!
//! * **Euler** (semi-implicit): `(H + diag(h d) + servo terms) q̈ = …`, `q̇⁺ = q̇ + h q̈`,
//!   `q⁺ = q + h q̇⁺` — MuJoCo's `Euler` (damping implicit), with servo gains implicit as its
//!   `implicitfast` takes them. One evaluation a step; without damping it gains energy
//!   (a double pendulum +30% in 10 s at 60 Hz).
//! * **Implicit**: Euler with the Coriolis and centrifugal forces' derivative in the rates
//!   implicit too, `(H + h (D + ∂c/∂q̇)) q̈ = …` (MuJoCo's `implicit`), solved by LU.
//!   `c` is quadratic in `q̇`, so the central difference `(c(q̇ + e_j) − c(q̇ − e_j)) / 2` is
//!   its derivative's column `j` exactly (up to round-off).
//! * **Runge–Kutta 4**: the classic four stages on the explicit dynamics (MuJoCo's `RK4`);
//!   stops, motors and dry friction then act as impulses on the step's end (a stop on the
//!   step's mean rate `(q⁺ − q)/h`, so it is not crossed by the step's end). Energy error
//!   `O(h⁴)`: a double pendulum keeps its energy to 0.01% over 10 s at 60 Hz.

use super::dynamics::lu_solve;
use super::ArticulatedTree;
use crate::error::KeaResult;
use crate::solver::sparse::joint_space;

/// How the reduced-coordinate path integrates a tree over a step (module docs of
/// `articulation::integrate`); [`crate::WorldSettings::integrator`] picks it for a world.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Integrator {
    /// Semi-implicit Euler, damping and servos implicit (MuJoCo's `Euler`; its
    /// `implicitfast` for servo gains): one evaluation a step, the cheapest; gains energy
    /// without damping.
    Euler,
    /// Euler with the Coriolis and centrifugal forces implicit in the rates as well
    /// (MuJoCo's `implicit`).
    Implicit,
    /// Classic fourth-order Runge–Kutta (MuJoCo's `RK4`), stops and motors as impulses at
    /// the step's end: four evaluations a step, energy kept at game step sizes. The default.
    #[default]
    RungeKutta4,
}

impl Integrator {
    /// MuJoCo's name for it in an MJCF `<option integrator>` (`Euler`, `implicit`,
    /// `implicitfast` → [`Integrator::Euler`], `RK4`).
    #[must_use]
    pub fn from_mujoco(name: &str) -> Option<Self> {
        match name {
            "Euler" | "implicitfast" => Some(Self::Euler),
            "implicit" => Some(Self::Implicit),
            "RK4" => Some(Self::RungeKutta4),
            _ => None,
        }
    }
}

impl ArticulatedTree {
    /// The smooth step of `h` by the tree's integrator: `q`, `qd` advanced in place, `qdd`
    /// (scratch) left with the free accelerations; `offset` gets each coordinate's mean
    /// rate over the step less its end rate (0 but for Runge–Kutta), for the stops.
    pub(super) fn smooth_step(
        &mut self,
        q: &mut [f64],
        qd: &mut [f64],
        tau: &[f64],
        h: f64,
        qdd: &mut [f64],
    ) -> KeaResult<()> {
        let n = self.len();
        self.offset.iter_mut().for_each(|x| *x = 0.0);
        match self.integrator {
            Integrator::Euler => {
                self.solve(q, qd, tau, h, qdd)?;
                for i in 0..n {
                    qd[i] += h * qdd[i];
                }
            }
            Integrator::Implicit => {
                self.solve_implicit(q, qd, tau, h, qdd)?;
                for i in 0..n {
                    qd[i] += h * qdd[i];
                }
            }
            Integrator::RungeKutta4 => {
                self.runge_kutta(q, qd, tau, h, qdd)?;
                for i in 0..n {
                    self.offset[i] = (self.stage_q[i] - q[i]) / h - qd[i];
                }
            }
        }
        Ok(())
    }

    /// The four stages: leaves the end rates in `qd` and the end coordinates in `stage_q`
    /// (`q` untouched; the caller moves them after the stops).
    fn runge_kutta(
        &mut self,
        q: &[f64],
        qd: &mut [f64],
        tau: &[f64],
        h: f64,
        qdd: &mut [f64],
    ) -> KeaResult<()> {
        let n = self.len();
        let mut sq = std::mem::take(&mut self.stage_q);
        let mut sv = std::mem::take(&mut self.stage_v);
        let mut sum_a = std::mem::take(&mut self.sum_a);
        let mut sum_v = std::mem::take(&mut self.sum_v);
        sq.copy_from_slice(q);
        sv.copy_from_slice(qd);
        sum_a.iter_mut().for_each(|x| *x = 0.0);
        sum_v.iter_mut().for_each(|x| *x = 0.0);
        // Stage k is at q + c_k h v_{k−1}, q̇ + c_k h a_{k−1}, weighted b_k.
        const C: [f64; 4] = [0.0, 0.5, 0.5, 1.0];
        const B: [f64; 4] = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];
        let mut result = Ok(());
        for k in 0..4 {
            if k > 0 {
                for i in 0..n {
                    // sv holds the last stage's rate, qdd its acceleration.
                    sq[i] = q[i] + C[k] * h * sv[i];
                    sv[i] = qd[i] + C[k] * h * qdd[i];
                }
            }
            self.contact.weight = B[k];
            result = self.solve(&sq, &sv, tau, 0.0, qdd);
            if result.is_err() {
                break;
            }
            for i in 0..n {
                sum_a[i] += B[k] * qdd[i];
                sum_v[i] += B[k] * sv[i];
            }
        }
        if result.is_ok() {
            for i in 0..n {
                sq[i] = q[i] + h * sum_v[i];
                qd[i] += h * sum_a[i];
            }
        }
        self.stage_q = sq;
        self.stage_v = sv;
        self.sum_a = sum_a;
        self.sum_v = sum_v;
        result
    }

    /// `(H + h (D + ∂c/∂q̇) + servo terms) q̈ = τ − c − d q̇ + servo` into `qdd`, by LU.
    fn solve_implicit(
        &mut self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        h: f64,
        qdd: &mut [f64],
    ) -> KeaResult<()> {
        let n = self.len();
        let mut plus = std::mem::take(&mut self.stage_q);
        let mut minus = std::mem::take(&mut self.sum_a);
        let mut rate = std::mem::take(&mut self.stage_v);
        let mut m = std::mem::take(&mut self.lu);
        // The bias's derivative first: `solve` below leaves `H'` factorised, not as is.
        self.place(q);
        for j in 0..n {
            rate.copy_from_slice(qd);
            rate[j] += 1.0;
            self.bias_into(&rate, &mut plus);
            rate[j] -= 2.0;
            self.bias_into(&rate, &mut minus);
            for i in 0..n {
                m[i * n + j] = 0.5 * h * (plus[i] - minus[i]);
            }
        }
        self.assemble(q, qd, tau, h, qdd);
        joint_space::add_to_dense(&self.h, &self.model.ancestry, &mut m);
        let solved = lu_solve(&mut m, n, qdd);
        self.stage_q = plus;
        self.sum_a = minus;
        self.stage_v = rate;
        self.lu = m;
        solved
    }

    /// Factorises `H' = H + diag(h d) + servo terms` at `q` for the stops' impulses, when the
    /// step's own solve left no such factor (Runge–Kutta's last stage is elsewhere; the
    /// implicit step's matrix is not symmetric).
    pub(super) fn factor_for_impulses(
        &mut self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        h: f64,
    ) -> KeaResult<()> {
        let damped = match self.integrator {
            Integrator::Euler => return Ok(()),
            Integrator::Implicit => h,
            Integrator::RungeKutta4 => 0.0,
        };
        let mut scratch = std::mem::take(&mut self.column);
        self.assemble(q, qd, tau, damped, &mut scratch);
        self.column = scratch;
        self.factor_h()
    }
}
