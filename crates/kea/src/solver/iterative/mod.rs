//! The iterative path: the soft step of Box2D v3 over contacts and rows, for big islands.
//!
//! Every island routed here is solved in one pass over the step, with n substeps of size
//! `hs = h/n` (islands never share a body, so solving them together gives each the answer it
//! would get alone). Per substep:
//!
//! 1. integrate velocities: gravity, applied forces and damping (`bodies`);
//! 2. warm start: re-apply each joint row's and contact point's impulse of the previous
//!    substep (or step);
//! 3. solve (`iterations` sweeps): joint rows (`rows`), then contacts colour by colour in SIMD
//!    lanes (`contacts`), with the error terms: contacts push apart as a mass-independent spring
//!    (the world's contact [`Spring`](crate::constraint::Spring)), separations recomputed from
//!    the bodies' current poses;
//! 4. integrate positions (orientations keeping angular momentum);
//! 5. relax (`relax_iterations` sweeps): the same without the error terms, so that correcting
//!    an error adds no kinetic energy.
//!
//! After the substeps, restitution once (contacts and bouncing stops), then the forces are
//! stored (contact points keep theirs for the next step's warm start) and the bodies written
//! back. Split islands' joint rows skip the sweeps: they are solved directly after the
//! contacts in both the biased and the relax stage (`rows/direct.rs`), and post-stabilised on
//! positions after restitution.

mod bodies;
mod contacts;
mod disjoint;
mod graph;
mod pass;
mod rows;
mod substep;

use super::exact::ComponentSystems;
use super::integrate::BodyScratch;
use super::island::Islands;
use super::sparse::LcpReport;
use super::wide::SimdLevel;
use super::{SolverBody, StepArrays, StepInputs};
use crate::error::{check_positive, KeaError, KeaResult};
use crate::math::{from_f64, Real};
use bodies::BodyStates;
use contacts::{ContactSolver, Stage};
use rows::JointRows;
use substep::SubstepPlan;

pub(crate) use pass::IterativePass;

/// Settings of the iterative path. Every field has its unit, normal value and range.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct IterativeParams {
    /// Substeps per step (≥ 1). Default 4. More substeps stiffen contacts and joints at a
    /// linear cost; 1 is plain sequential impulses.
    pub substeps: u32,
    /// Gauss-Seidel sweeps per substep with error correction (≥ 1). Default 1 (Box2D v3's).
    pub iterations: u32,
    /// Sweeps per substep without the correction of hard rows (≥ 0). Default 1.
    pub relax_iterations: u32,
    /// Fastest speed at which penetration of a unilateral hard row is corrected, m/s (or rad/s
    /// for angular rows), > 0. Default 3. Larger values pop deep overlaps apart violently.
    pub max_correction_speed: Real,
    /// Post-stabilisation passes of split islands after the substeps (0 to 64): Newton steps
    /// on positions that close their rigid joints (rows written again at the bodies' new
    /// poses, bodies moved by `M⁻¹Jᵀ Δ`, velocities untouched, so no energy is injected or
    /// drained), stopping once every error is below 10 µm (or, far from the origin, four units
    /// in the last place of the farthest position). Default 16: most steps stop after one or
    /// two; a light chain whipping a 100 to 400 times heavier end, pulled straight, needs up
    /// to 12 (at 6 such a step was left open by 3 to 9 mm).
    pub post_stabilisation: u32,
    /// Lane width of the contact solver (default [`SimdLevel::Auto`]: 8 lanes with AVX2, else
    /// 4). Every width gives bit-identical results; narrower ones exist to compare.
    pub simd: SimdLevel,
}

impl Default for IterativeParams {
    fn default() -> Self {
        Self {
            substeps: 4,
            iterations: 1,
            relax_iterations: 1,
            max_correction_speed: 3.0,
            post_stabilisation: 16,
            simd: SimdLevel::Auto,
        }
    }
}

impl IterativeParams {
    /// Checks every field, naming the first bad one.
    pub fn validate(&self) -> KeaResult<()> {
        let at_least_one = |arg: &'static str, v: u32| {
            if v == 0 {
                Err(KeaError::OutOfRange {
                    arg,
                    value: "0".into(),
                    expected: "must be >= 1",
                })
            } else {
                Ok(())
            }
        };
        at_least_one("substeps", self.substeps)?;
        at_least_one("iterations", self.iterations)?;
        if self.substeps > 64 {
            return Err(KeaError::OutOfRange {
                arg: "substeps",
                value: self.substeps.to_string(),
                expected: "must be <= 64",
            });
        }
        if self.iterations > 1000 || self.relax_iterations > 1000 {
            return Err(KeaError::OutOfRange {
                arg: "iterations",
                value: self.iterations.max(self.relax_iterations).to_string(),
                expected: "iterations and relax_iterations must be <= 1000",
            });
        }
        check_positive("max_correction_speed", self.max_correction_speed)?;
        if self.post_stabilisation > 64 {
            return Err(KeaError::OutOfRange {
                arg: "post_stabilisation",
                value: self.post_stabilisation.to_string(),
                expected: "must be <= 64",
            });
        }
        Ok(())
    }
}

/// Workspace of the iterative path.
#[derive(Debug, Default, Clone)]
pub(crate) struct IterativeWorkspace {
    states: BodyStates,
    rows: JointRows,
    contacts: ContactSolver,
    /// The split islands' joint rows as one direct system.
    direct: ComponentSystems,
    /// Blocks of the islands solved here, island after island.
    blocks: Vec<u32>,
    /// The substep of the last solve.
    hs: Real,
}

/// What the iterative path did in one step.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct IterativeReport {
    pub(crate) sweeps: u32,
    pub(crate) colours: u32,
    pub(crate) overflow: u32,
    pub(crate) lanes: u32,
    /// The direct solves of split islands' joints, summed over the step.
    pub(crate) direct: DirectReport,
}

/// What the direct solves of split islands' joint rows did in one step.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct DirectReport {
    /// Rows in the direct system.
    pub(crate) rows: u32,
    /// Solves (two per substep).
    pub(crate) solves: u32,
    /// Factorisations over all solves.
    pub(crate) iterations: u32,
    /// Pivots over all solves.
    pub(crate) pivots: u32,
    /// Solves whose system was singular and regularised.
    pub(crate) singular: u32,
    /// Solves that cycled.
    pub(crate) cycled: u32,
    /// Solves that hit the iteration cap unconverged.
    pub(crate) capped: u32,
    /// Solves whose Coulomb bounds still moved at the cap.
    pub(crate) bounds_moving: u32,
    /// Largest joint error post-stabilisation started from.
    pub(crate) worst_error: Real,
}

impl DirectReport {
    fn add(&mut self, r: LcpReport) {
        self.solves += 1;
        self.iterations += r.iterations;
        self.pivots += r.pivots;
        self.singular += u32::from(r.singular);
        self.cycled += u32::from(r.cycled);
        self.capped += u32::from(r.capped && !r.converged);
        self.bounds_moving += u32::from(r.bounds_moving);
    }

    /// Adds another group's direct solves to these (the worst error the larger).
    pub(crate) fn absorb(&mut self, d: &DirectReport) {
        self.rows += d.rows;
        self.solves += d.solves;
        self.iterations += d.iterations;
        self.pivots += d.pivots;
        self.singular += d.singular;
        self.cycled += d.cycled;
        self.capped += d.capped;
        self.bounds_moving += d.bounds_moving;
        self.worst_error = self.worst_error.max(d.worst_error);
    }
}

/// How the joint rows stand at the poses the step reached.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RowsLeft {
    /// Linearised earlier (the rows need writing again).
    Stale,
    /// Written at these poses (the direct system assembled from them or from those of the
    /// pass before, under post-stabilisation's tolerance away).
    Fresh,
}

/// Joint error below which post-stabilisation stops, m (or rad): a hundredth of a millimetre.
const STABILISATION_TOLERANCE: Real = 1.0e-5;

impl IterativeWorkspace {
    /// Gathers the islands' joint rows and contacts, with their bodies' local states.
    fn gather_islands(
        &mut self,
        (islands, split, all): (&[u32], &[bool], &Islands),
        step: &StepInputs<'_>,
        scratch: &BodyScratch,
        hs: Real,
    ) {
        let (bodies, params) = (step.bodies, step.params);
        self.states.begin(bodies.len());
        self.rows.begin();
        self.contacts.begin();
        self.blocks.clear();
        for (&k, &direct) in islands.iter().zip(split) {
            let k = k as usize;
            self.blocks.extend_from_slice(all.blocks(k));
            let (first_body, first_row) = (self.states.len(), self.rows.len());
            self.rows.gather(
                all.blocks(k),
                step.blocks,
                step.rows,
                bodies,
                &mut self.states,
                scratch,
                params,
                hs,
                step.lambda,
                direct,
            );
            if all.contacts(k).is_empty() {
                self.states.synchronise_from(first_body);
                self.rows.synchronise_from(first_row);
            }
            for &c in all.contacts(k) {
                let sc = &step.contacts[c as usize];
                let a = self.states.local(sc.bodies[0], bodies, scratch, params, hs);
                let b = self.states.local(sc.bodies[1], bodies, scratch, params, hs);
                self.contacts.add(c, sc, a, b);
            }
        }
    }

    /// The rows' forces and reactions, the contacts' forces and the bodies' new states and
    /// constraint forces, written back.
    pub(crate) fn write_out(&mut self, step: &mut StepArrays<'_>, scratch: &mut BodyScratch) {
        let (h, params, hs) = (step.params.dt, step.params, self.hs);
        self.rows.write_out(
            &self.states,
            step.blocks,
            &self.blocks,
            step.rows,
            scratch,
            h,
            step.lambda,
            step.reactions,
        );
        self.contacts.store(
            step.contacts,
            &self.states,
            scratch,
            (h, hs),
            params.body_forces,
        );
        self.states.write_out(step.bodies, scratch, h);
        for &g in &self.states.global[1..] {
            let b = &mut step.bodies[g as usize];
            if !b.is_fixed() {
                b.constraint_force = from_f64(scratch.constraint_force[g as usize]);
                b.constraint_torque = from_f64(scratch.constraint_torque[g as usize]);
            }
        }
    }

    /// Post-stabilisation of the split islands' joints (see
    /// [`IterativeParams::post_stabilisation`]): rows written again at the new poses (with a
    /// row source; else their tracked errors on the last substep's Jacobians, one pass), then
    /// one Newton step on positions per pass.
    fn post_stabilise(
        &mut self,
        plan: &SubstepPlan<'_>,
        bodies: &[SolverBody],
        report: &mut DirectReport,
    ) -> RowsLeft {
        let (source, blocks, params, limits) = (plan.source, plan.blocks, plan.params, plan.limits);
        // Where the relax stage needed fresh rows, the last substep left them linearised (and
        // assembled) at these poses.
        let linearised_now = self.states.has_fast_spin();
        let passes = match source {
            Some(_) => params.iterative.post_stabilisation,
            None => params.iterative.post_stabilisation.min(1),
        };
        // Far from the origin a position's last bit is more than the tolerance (in f32, 31 µm
        // at 300 m, where a whipped 333-link chain reaches): no pass can close what the
        // numbers cannot hold, and it spent all sixteen on it.
        let tolerance =
            STABILISATION_TOLERANCE.max(4.0 * Real::EPSILON * self.states.extent(bodies));
        for pass in 0..passes {
            let fresh = source.is_some() && (pass > 0 || !linearised_now);
            if let (Some(source), true) = (source, fresh) {
                self.rows
                    .relinearise(source, blocks, bodies, &mut self.states, params);
            }
            // Measured before assembling, so that a closed island costs one re-linearisation.
            let worst = self.rows.direct_error(&self.states);
            if pass == 0 {
                report.worst_error = report.worst_error.max(worst);
            }
            if worst < tolerance {
                return if source.is_some() {
                    RowsLeft::Fresh
                } else {
                    RowsLeft::Stale
                };
            }
            if fresh {
                self.rows.assemble_direct(&self.states, &mut self.direct);
            }
            let r = self
                .rows
                .stabilise(&mut self.states, &mut self.direct, limits);
            report.add(r);
        }
        RowsLeft::Stale
    }

    pub(crate) fn reserve(&mut self, bodies: usize, rows: usize, contacts: usize) {
        self.states.reserve(bodies);
        self.rows.reserve(bodies, rows);
        self.contacts.reserve(bodies, contacts);
        super::reserve(&mut self.blocks, rows);
    }

    pub(crate) fn bytes(&self) -> usize {
        self.states.bytes()
            + self.rows.bytes()
            + self.contacts.bytes()
            + self.direct.bytes()
            + self.blocks.capacity() * 4
    }

    pub(crate) fn bytes_for(bodies: usize, rows: usize, contacts: usize) -> usize {
        BodyStates::bytes_for(bodies)
            + JointRows::bytes_for(bodies, rows)
            + ContactSolver::bytes_for(bodies, contacts)
            + rows * 4
    }

    /// Solves the islands `islands` (ids in `all`) together and integrates their bodies in
    /// this workspace; the joints of those marked in `split` (one flag per island) are solved
    /// directly. Reads the step's arrays only: [`IterativeWorkspace::write_out`] then writes
    /// the rows' forces (`step.lambda` holds their warm start here), the contacts' forces and
    /// the bodies' new states. Workspaces given islands that share no body can run side by
    /// side.
    pub(crate) fn solve(
        &mut self,
        (islands, split, all): (&[u32], &[bool], &Islands),
        step: &StepInputs<'_>,
        scratch: &BodyScratch,
    ) -> IterativeReport {
        let params = step.params;
        let it = &params.iterative;
        let hs = params.dt / it.substeps as Real;
        self.hs = hs;
        self.gather_islands((islands, split, all), step, scratch, hs);
        let kinds = (self.rows.has_direct(), self.states.has_fast_spin());
        let mut plan = SubstepPlan::new(params, step.blocks, step.source, hs, kinds);
        self.contacts.prepare(
            step.contacts,
            step.bodies,
            &mut self.states,
            it.simd,
            &plan.prepare,
        );
        let mut report = DirectReport::default();
        self.run_substeps(step.bodies, &mut plan, &mut report);
        report.rows = self.direct.len() as u32;
        self.contacts
            .run(Stage::Restitution, &mut self.states, &plan.kernel);
        self.rows.restitution(&mut self.states, params.dt);
        let rows_left = if plan.direct {
            self.post_stabilise(&plan, step.bodies, &mut report)
        } else {
            RowsLeft::Stale
        };
        if plan.synchronised(&self.states) {
            self.synchronise(step.bodies, &plan, rows_left, &mut report);
        }
        let (colours, overflow) = self.contacts.colour_stats();
        IterativeReport {
            sweeps: it.substeps * (it.iterations + it.relax_iterations),
            colours,
            overflow,
            lanes: self.contacts.lanes(),
            direct: report,
        }
    }
}
