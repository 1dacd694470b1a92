//! The iterative path's substep loop, as named stages (Box2D v3's soft step with relax).
//!
//! A step of `h` runs `n` substeps of `hs = h/n`. With `v` the bodies' velocities, `x` their
//! poses, `J` a row's Jacobian, `λ` its accumulated impulse and `C` its error, each substep:
//!
//! 1. **relinearise** (after the first, given a row source): the joints' `J`, `C` written
//!    again at the present poses, so a fast rotation inside a step does not tear them;
//! 2. **integrate velocities**: `v ← v + hs M⁻¹ (f + m g) − damping`;
//! 3. **warm start**: `v ← v + M⁻¹ Jᵀ λ` for every joint row and contact point;
//! 4. **solve** (`iterations` sweeps): per row `Δλ = −m_eff (J v + b)` clamped to its bounds,
//!    with the bias `b` of a soft constraint, `b = (ω/(2ζ + hs ω)) C`-like for contacts (the
//!    world's contact spring, mass-independent) and the rows' own ε, γ for joints; joints then
//!    contacts colour by colour in SIMD lanes;
//! 5. **direct**: the split islands' joint rows solved as one LCP after the contacts, so that
//!    they hold whatever the contacts did;
//! 6. **integrate positions**: `x ← x + hs v`, orientations keeping angular momentum;
//! 7. **relax** (`relax_iterations` sweeps): stage 4 (and 5) with `b = 0`, so that correcting
//!    an error adds no kinetic energy;
//! 8. **accumulate** the rows' impulses for the read-outs.
//!
//! After the last substep, restitution once (`v_n ← −e v_n⁻` for closing contacts and
//! bouncing stops).
//!
//! **Synchronised islands** (no contacts, joints written again by a row source): the loop above
//! is symplectic Euler, whose velocity at a step's end belongs half a substep back; the energy
//! read from it swings by `(hs/2)·v·∇V` (a 30° pendulum 0.64% of its swing at 4 × 60 Hz, a
//! conical one the same). Their forcing is split into half kicks: the first substep's kick is
//! half, and once the step's poses are final (after restitution and post-stabilisation) the
//! other half is given and the velocities are projected on the joints written at those poses
//! (`synchronise`: a Gauss–Seidel sweep of the motors then one of the rigid rows, or a direct
//! relax solve): Störmer–Verlet with RATTLE's velocity projection, whose energy error is
//! second order. Within the step the trajectory is the one before (a projection followed by a
//! kick and the next projection at the same linearisation is the projection of the sum); the
//! state handed on is synchronised. Only what acts at an instant takes part: rigid rows, and
//! motors with half their force budget (the first substep has the other half); springs act
//! through the substeps, and a stop pushes at most half of what it pushed in the last substep
//! (it holds a resting load's half kick, never takes an impact, which belongs to the next
//! step's bounce). Measured: the projection must use the joints at the new poses; on the last
//! substep's rows (a substep back, with or without its chord) it fed energy in (+3.5% to +6%
//! of a pendulum's swing in 10 s).

use super::contacts::{KernelParams, PrepareParams, Stage};
use super::{DirectReport, IterativeWorkspace, RowsLeft};
use crate::math::Real;
use crate::solver::sparse::Limits;
use crate::solver::{ConstraintBlock, RowSource, SolverBody, SolverParams};

/// What every substep of a step shares.
pub(super) struct SubstepPlan<'a> {
    pub(super) source: Option<&'a dyn RowSource>,
    pub(super) blocks: &'a [ConstraintBlock],
    pub(super) params: &'a SolverParams,
    pub(super) prepare: PrepareParams,
    pub(super) kernel: KernelParams,
    pub(super) limits: Limits,
    /// Some islands' joints are solved directly (split islands).
    pub(super) direct: bool,
    /// The relax stage needs the rows at the poses the substep reached (a body spins fast
    /// about an axle: on the rows of the substep's start its pushes, square to the old axle,
    /// feed the spin — a gyroscope gained 4% in 4 s). Elsewhere the rows of the substep's
    /// start serve both stages.
    pub(super) fresh_relax: bool,
}

impl SubstepPlan<'_> {
    /// Whether the step synchronises its islands without contacts (module docs): only with a
    /// row source, which can write the joints at the poses reached.
    pub(super) fn synchronised(&self, states: &super::bodies::BodyStates) -> bool {
        self.source.is_some() && states.any_synchronised()
    }
}

impl<'a> SubstepPlan<'a> {
    /// The plan of a step of `params.dt` in substeps of `hs`.
    pub(super) fn new(
        params: &'a SolverParams,
        blocks: &'a [ConstraintBlock],
        source: Option<&'a dyn RowSource>,
        hs: Real,
        (direct, fast_spin): (bool, bool),
    ) -> Self {
        let (h, it) = (params.dt, &params.iterative);
        Self {
            source,
            blocks,
            params,
            prepare: PrepareParams {
                h,
                hs,
                spring: params.contact_spring,
                gamma: params.gamma,
            },
            kernel: KernelParams {
                inv_hs: 1.0 / hs,
                max_push: it.max_correction_speed,
                substep: 0.0,
                closing: false,
                friction_in_solve: it.relax_iterations == 0,
                h,
                hs,
            },
            limits: Limits {
                iterations: params.max_lcp_iterations,
                bound_updates: params.max_friction_passes,
            },
            direct,
            fresh_relax: source.is_some() && fast_spin,
        }
    }
}

impl IterativeWorkspace {
    /// Every substep of the step, in order; the direct solves are counted in `report`.
    pub(super) fn run_substeps(
        &mut self,
        bodies: &[SolverBody],
        plan: &mut SubstepPlan<'_>,
        report: &mut DirectReport,
    ) {
        let n = plan.params.iterative.substeps;
        let synchronised = plan.synchronised(&self.states);
        for sub in 0..n {
            plan.kernel.substep = sub as Real;
            if plan.fresh_relax {
                if sub == 0 {
                    self.assemble(plan);
                }
            } else if sub > 0 {
                self.relinearise(bodies, plan);
            } else {
                self.assemble(plan);
            }
            self.states.integrate_velocities(plan.kernel.hs);
            if sub == 0 && synchronised {
                self.states.kick_synchronised(-0.5);
                self.rows.halve_budget(true);
            }
            self.rows.warm_start(&mut self.states);
            self.contacts
                .run(Stage::WarmStart, &mut self.states, &plan.kernel);
            self.solve_stage(plan, true, report);
            self.states.integrate_positions(bodies, plan.kernel.hs);
            self.rows.advance_clock(plan.kernel.hs);
            if plan.fresh_relax {
                self.relinearise(bodies, plan);
            }
            self.relax_stage(plan, sub + 1 == n, report);
            self.rows.accumulate();
            self.rows.halve_budget(false);
        }
    }

    /// The step's last half kick and the velocity projection that synchronises the islands
    /// without contacts (module docs), after restitution and post-stabilisation: at the poses
    /// handed on.
    pub(super) fn synchronise(
        &mut self,
        bodies: &[SolverBody],
        plan: &SubstepPlan<'_>,
        rows_left: RowsLeft,
        report: &mut DirectReport,
    ) {
        let (hs, max_speed) = (plan.kernel.hs, plan.kernel.max_push);
        self.states.kick_synchronised(0.5);
        // Rows post-stabilisation wrote at these poses are used as they are, with the direct
        // system it last assembled (a pass's correction earlier, under 10 µm away): the
        // residual is the fresh rows', only the matrix is a correction old. Otherwise the rows
        // are written again.
        if rows_left == RowsLeft::Stale {
            self.relinearise(bodies, plan);
        }
        self.rows.begin_synchronising();
        self.rows.synchronise(&mut self.states, hs, max_speed);
        if self.rows.any_direct_synchronised() {
            // The relax solve, over the synchronised rows only (the others are held).
            self.solve_direct(plan, false, report);
        }
        self.rows.end_synchronising();
    }

    /// Stage 1: the joints' rows at the present poses (when a row source gives them), and the
    /// direct system assembled from them.
    fn relinearise(&mut self, bodies: &[SolverBody], plan: &SubstepPlan<'_>) {
        if let Some(source) = plan.source {
            self.rows
                .relinearise(source, plan.blocks, bodies, &mut self.states, plan.params);
            self.assemble(plan);
        }
    }

    /// The split islands' joint rows assembled as one direct system.
    fn assemble(&mut self, plan: &SubstepPlan<'_>) {
        if plan.direct {
            self.rows.assemble_direct(&self.states, &mut self.direct);
        }
    }

    /// Stages 4 and 5: the biased sweeps, then the direct joints.
    fn solve_stage(&mut self, plan: &SubstepPlan<'_>, biased: bool, report: &mut DirectReport) {
        let (hs, max_speed) = (plan.kernel.hs, plan.kernel.max_push);
        for _ in 0..plan.params.iterative.iterations {
            self.rows.sweep(&mut self.states, hs, biased, max_speed);
            self.contacts
                .run(Stage::Solve, &mut self.states, &plan.kernel);
        }
        self.solve_direct(plan, biased, report);
    }

    /// Stage 7: the unbiased sweeps, then the direct joints; the last substep's last sweep
    /// closes the contacts' friction.
    fn relax_stage(&mut self, plan: &mut SubstepPlan<'_>, last: bool, report: &mut DirectReport) {
        let (hs, max_speed) = (plan.kernel.hs, plan.kernel.max_push);
        let relax = plan.params.iterative.relax_iterations;
        for r in 0..relax {
            plan.kernel.closing = last && r + 1 == relax;
            self.rows.sweep(&mut self.states, hs, false, max_speed);
            self.contacts
                .run(Stage::Relax, &mut self.states, &plan.kernel);
        }
        if relax > 0 {
            self.solve_direct(plan, false, report);
        }
    }

    /// Stage 5: the split islands' joints solved directly, with or without their bias.
    fn solve_direct(&mut self, plan: &SubstepPlan<'_>, biased: bool, report: &mut DirectReport) {
        if plan.direct {
            let (hs, max_speed) = (plan.kernel.hs, plan.kernel.max_push);
            let r = self.rows.solve_direct(
                &mut self.states,
                &mut self.direct,
                hs,
                biased,
                max_speed,
                plan.limits,
            );
            report.add(r);
        }
    }
}
