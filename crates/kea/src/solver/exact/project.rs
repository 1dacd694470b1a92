//! Position projection of an exact island after its step (the world's
//! `projection_iterations`): a Newton step on the joints written at the new poses, moving
//! bodies, not velocities.

use super::super::integrate::BodyScratch;
use super::super::SolverStats;
use super::ExactWorkspace;
use crate::constraint::Row;
use crate::math::{wide, Real};

impl ExactWorkspace {
    /// Position projection of one island: moves its bodies so that each equality row without
    /// its own softness (a joint) sits where the step's force puts it, by solving
    /// `(J M⁻¹ Jᵀ + δI) Δ = xi* − xi` for the rows evaluated at the new state and applying
    /// `Δq = M⁻¹ Jᵀ Δ` to positions and orientations (velocities are left alone: a
    /// post-stabilisation). With the world's ε a joint is a stiff spring, `k = γ/(ε h²)`, so its
    /// target is the spring's deflection under the force λ it carried, `xi* = −λ/k`: projecting
    /// to zero would fight the velocity solve, which keeps that deflection. The displacements are
    /// accumulated in `scratch` (linear in `constraint_force`, angular in `constraint_torque`)
    /// for the caller to apply. Returns the largest error it started from.
    pub(crate) fn project_island(
        &mut self,
        island_blocks: &[u32],
        input: super::IslandInputs<'_>,
        scratch: &mut BodyScratch,
        lambda: &[Real],
        stats: &mut SolverStats,
    ) -> f64 {
        let super::IslandInputs {
            blocks,
            rows,
            bodies,
            params,
        } = input;
        let projectable = |r: &Row| {
            r.lo == Real::NEG_INFINITY
                && r.hi == Real::INFINITY
                && r.friction.is_none()
                && r.softness.is_none()
                && r.spring.is_none()
                && r.gamma != Some(0.0)
        };
        self.gather(island_blocks, blocks, rows, bodies, scratch, projectable);
        let n = self.rows.len();
        if n == 0 {
            return 0.0;
        }
        self.fill_system();
        let diag_max = (0..n).fold(0.0f64, |m, i| m.max(self.diagonal(i)));
        // A light regularisation keeps redundant joints solvable without softening them.
        let delta = (wide(params.epsilon) * 1.0e-3).max(1.0e-12 * diag_max);
        let mut worst = 0.0f64;
        let h = wide(params.dt);
        for i in 0..n {
            self.add_diagonal(i, delta);
            let g = self.rows[i].global as usize;
            let row = &rows[g];
            let xi = wide(row.xi);
            let gamma = wide(row.gamma.unwrap_or(params.gamma));
            let deflection = if gamma > 0.0 {
                -wide(params.epsilon) * h * h / gamma * wide(lambda[g])
            } else {
                0.0
            };
            worst = worst.max(xi.abs());
            self.sys.b[i] = deflection - xi;
            self.sys.lo[i] = f64::NEG_INFINITY;
            self.sys.hi[i] = f64::INFINITY;
        }
        self.solve_lcp(params, stats);
        for (i, r) in self.rows.iter().enumerate() {
            let d = self.sys.x[i];
            for s in 0..2 {
                if let Some(b) = r.bodies[s] {
                    scratch.constraint_force[b as usize] += r.mj[2 * s] * d;
                    scratch.constraint_torque[b as usize] += r.mj[2 * s + 1] * d;
                }
            }
        }
        worst
    }
}
