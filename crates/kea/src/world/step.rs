//! One world step, as a table of contents:
//!
//! ```text
//! World::step(h)
//!   step_reduced_trees  trees of hinges and sliders alone on the world, stepped in their
//!                    joint coordinates (reduced/), their bodies left out below
//!   collect_bodies   enabled bodies → compact solver array (hot data)
//!   gather_rows      each enabled constraint writes its rows (the guide's Bcl; gather.rs)
//!   solver.step      islands → exact LCP per island → semi-implicit integration
//!   write_back       new states to bodies, forces to constraints, accumulators cleared
//! ```

use super::gather::JointSource;
use super::StepSize;
use super::World;
use crate::constraint::RowContext;
use crate::error::KeaResult;
use crate::math::{is_finite3, wide, Mat3, Real, Vec3};
use crate::solver::{Reaction, SolverBody, SolverParams, SolverStats, StepArrays};
use crate::timing::Stamp;
use std::time::Duration;

/// Joint error, m (or rad), below which position projection stops early.
pub const PROJECTION_TOLERANCE: Real = 1.0e-6;

/// What a collision layer did before a step (filled by `kea-collision`; zero when contacts
/// come from elsewhere).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CollisionStats {
    /// Time updating bounds and finding new pairs.
    pub time_broad_phase: Duration,
    /// Time generating manifolds and updating the world's contacts.
    pub time_narrow_phase: Duration,
    /// Pairs of colliders whose bounds overlap.
    pub pairs: u32,
    /// Pairs found this step.
    pub new_pairs: u32,
    /// Manifolds (contacts) kept up to date.
    pub manifolds: u32,
    /// Of those, manifolds moved with their bodies instead of generated again (the pair
    /// barely moved relative to itself).
    pub reused_manifolds: u32,
    /// Pairs whose manifold failed inside the collision library this step (they got no
    /// contacts; the step went on).
    pub failed_pairs: u32,
    /// Manifolds left out because the world's constraint capacity was full (they are tried
    /// again next step).
    pub dropped_manifolds: u32,
}

/// What one [`World::step`] did: counts, solver warnings and per-stage times.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepStats {
    /// Bodies simulated this step (enabled and awake).
    pub bodies: u32,
    /// Trees of hinges and sliders stepped in reduced coordinates (see
    /// [`crate::Routing::max_reduced_links`]).
    pub reduced_trees: u32,
    /// Enabled bodies asleep after this step (disabled automatically).
    pub sleeping_bodies: u32,
    /// Constraints that wrote rows.
    pub constraints: u32,
    /// Rows written.
    pub rows: u32,
    /// What the solver did, its warnings and its stage times.
    pub solver: SolverStats,
    /// Time copying bodies into the solver array.
    pub time_collect: Duration,
    /// Time writing constraint rows.
    pub time_gather: Duration,
    /// Time copying results back.
    pub time_write_back: Duration,
    /// Time in position projection.
    pub time_projection: Duration,
    /// Breakable constraints that broke in this step (they are now disabled; see
    /// [`World::broken_last_step`]).
    pub broken_joints: u32,
    /// Bodies quarantined by this step: their islands blew up (non-finite, or faster than the
    /// world's [`crate::SpeedLimits`]) and were put back to their state before the step and
    /// frozen (see [`World::quarantine_report`]).
    pub quarantined_bodies: u32,
    /// Largest error of a rigid joint row after the velocity step, before projection (0 when no
    /// projection ran).
    pub max_joint_error: Real,
    /// Whole step (the collision update not included).
    pub time_total: Duration,
    /// The collision layer's work before the step, when one ran.
    pub collision: CollisionStats,
}

impl World {
    /// Advances the world by `dt` seconds (the guide's `MdtWorldStep`). Any finite `dt > 0` is
    /// allowed and it may change from step to step.
    ///
    /// Solver trouble (singular systems, cycles, caps) never aborts: it is counted in the
    /// returned [`StepStats`] and logged. An `Err` means bad input (a bad `dt`, or a custom
    /// constraint that wrote a NaN row) and the world is unchanged: nothing is committed until
    /// the solver has accepted every row.
    pub fn step(&mut self, dt: Real) -> KeaResult<StepStats> {
        self.step_by(StepSize::new(dt)?)
    }

    /// [`World::step`] by a step already checked: [`crate::WorldSettings::world_substeps`] steps of `dt / n`.
    pub fn step_by(&mut self, dt: StepSize) -> KeaResult<StepStats> {
        self.step_with(dt, true)
    }

    /// `steps` steps of `dt` (at least one), as many calls of [`World::step`] give them, bit for
    /// bit; only the last works out the joint reactions of trees on the reduced path (a
    /// Newton–Euler pass per tree, whose results each step overwrites), so the read-outs after
    /// it are the last step's, as they would be. Returns the last step's statistics; on an
    /// `Err` the steps before it stand.
    pub fn step_many(&mut self, dt: Real, steps: u32) -> KeaResult<StepStats> {
        let dt = StepSize::new(dt)?;
        if steps == 0 {
            return Err(crate::error::KeaError::OutOfRange {
                arg: "steps",
                value: "0".into(),
                expected: "at least one step",
            });
        }
        for _ in 1..steps {
            self.step_with(dt, false)?;
        }
        self.step_with(dt, true)
    }

    /// A step of `dt`, working out the reduced trees' joint reactions on its last substep
    /// when `reactions` (earlier substeps' are never read: the next one overwrites them).
    fn step_with(&mut self, dt: StepSize, reactions: bool) -> KeaResult<StepStats> {
        let n = self.settings.world_substeps;
        let h = dt.seconds() / n as Real;
        // Inside the pool (a pipeline that hopped already) it stays where it is.
        crate::threads::on_pool(self.awake_body_count(), || {
            let mut stats = self.step_here(h, n == 1, reactions && n == 1)?;
            for k in 1..n {
                let last = k + 1 == n;
                stats = self.step_here(h, last, reactions && last)?;
            }
            Ok(stats)
        })
    }

    /// One substep of `h` for a pipeline that runs its own stages between substeps (collision,
    /// drivers): the applied forces are kept for the next substep unless this is the `last`.
    /// A pipeline calls it [`crate::WorldSettings::world_substeps`] times with `h = dt / n`.
    pub fn substep_by(&mut self, h: StepSize, last: bool) -> KeaResult<StepStats> {
        self.substep_with(h, last, last)
    }

    /// [`World::substep_by`], working out the reduced trees' joint reactions only when
    /// `reactions` (a pipeline asks for them on the last substep of a step whose read-outs
    /// may be read; see [`World::step_many`]).
    pub fn substep_with(
        &mut self,
        h: StepSize,
        last: bool,
        reactions: bool,
    ) -> KeaResult<StepStats> {
        crate::threads::on_pool(self.awake_body_count(), || {
            self.step_here(h.seconds(), last, reactions)
        })
    }

    /// One (sub)step on the calling thread, `dt` checked; the applied forces are cleared after
    /// it when `last`; the reduced trees' joint reactions worked out when `reactions`.
    fn step_here(&mut self, dt: Real, last: bool, reactions: bool) -> KeaResult<StepStats> {
        let _flush = crate::float_mode::FlushSubnormals::new();
        self.scratch.reduced.reactions = reactions;
        let t0 = Stamp::now(self.settings.step_timing);
        let params = self.solver_params(dt);
        let auto_disable = self.settings.dem.mode == super::DemMode::PartitionAutoDisable;
        self.awake.refresh(&self.bodies);
        self.list_awake_constraints();
        if auto_disable {
            self.plan_wake();
        } else {
            self.scratch.wake.clear();
        }
        let reduced_trees = self.step_reduced_trees(dt);
        self.load_tendon_forces(dt);
        self.collect_bodies();
        let t1 = Stamp::now(self.settings.step_timing);
        let constraints = self.gather_rows(&params);
        let t2 = Stamp::now(self.settings.step_timing);
        let solver_stats = self.solve_gathered(&params)?;
        let t3 = Stamp::now(self.settings.step_timing);
        // The step succeeded: from here on the world changes. Islands that blew up go back to
        // where they were, frozen.
        let quarantined_bodies = self.quarantine_bad_islands();
        self.apply_wake();
        self.write_back(last);
        let reduced_bodies = self.reduced_body_count();
        self.commit_reduced_trees();
        let t_proj = Stamp::now(self.settings.step_timing);
        let projected = if solver_stats.exact_islands > 0 {
            self.project_positions(&params)
        } else {
            0.0
        };
        let max_joint_error = projected.max(solver_stats.direct_joint_error);
        self.commit_joints(dt);
        let broken_joints = self.break_overloaded();
        let time_projection = t_proj.elapsed();
        if auto_disable {
            self.disable_resting_islands(dt);
        }
        self.time += wide(dt);
        self.steps += 1;
        let t4 = Stamp::now(self.settings.step_timing);
        let sleeping_bodies = if auto_disable {
            self.awake.refresh(&self.bodies);
            self.awake.asleep()
        } else {
            0
        };
        Ok(StepStats {
            bodies: self.scratch.solver_bodies.len() as u32 + reduced_bodies,
            reduced_trees,
            sleeping_bodies,
            constraints,
            rows: self.scratch.rows.len() as u32 + 3 * solver_stats.contact_points,
            solver: solver_stats,
            time_collect: t0.until(t1),
            time_gather: t1.until(t2),
            time_write_back: t3.until(t4).saturating_sub(time_projection),
            time_projection,
            max_joint_error,
            broken_joints,
            quarantined_bodies,
            time_total: t0.until(t4),
            collision: CollisionStats::default(),
        })
    }

    /// The solver on the gathered bodies, rows and contacts, warm started from the last
    /// step's λ, its joints re-written inside the substeps. On error nothing was written: the
    /// last step's λ is back where the read-outs expect it and the kept trees are dropped.
    fn solve_gathered(&mut self, params: &SolverParams) -> KeaResult<SolverStats> {
        self.warm_start_lambda();
        let s = &mut self.scratch;
        s.reactions.clear();
        s.reactions.resize(s.blocks.len(), [Reaction::default(); 2]);
        let source = JointSource {
            constraints: &self.constraints,
            block_constraint: &s.block_constraint,
            bodies: &self.bodies,
            slot_to_solver: &s.slot_to_solver,
        };
        let solved = self.solver.step_world_arrays(StepArrays {
            bodies: &mut s.solver_bodies,
            blocks: &s.blocks,
            rows: &s.rows,
            contacts: &mut s.contacts,
            params,
            lambda: &mut s.lambda,
            reactions: &mut s.reactions,
            source: Some(&source),
        });
        if solved.is_err() {
            std::mem::swap(&mut s.lambda, &mut s.prev_lambda);
            self.discard_reduced_trees();
        }
        solved
    }

    pub(super) fn collect_bodies(&mut self) {
        let s = &mut self.scratch;
        s.solver_bodies.clear();
        s.solver_to_slot.clear();
        s.slot_to_solver.clear();
        s.slot_to_solver.resize(self.bodies.slot_count(), u32::MAX);
        // The awake set, unless sleeping bodies wake this step (then every slot, in order).
        let waking = s.wake.iter().any(|&w| w);
        let count = if waking {
            self.bodies.slot_count()
        } else {
            self.awake.slots().len()
        };
        for k in 0..count {
            let slot = if waking {
                k
            } else {
                self.awake.slots()[k] as usize
            };
            let Some(b) = self.bodies.at(slot) else {
                continue;
            };
            let waking = s.wake.get(slot).copied().unwrap_or(false);
            let reduced = s.reduced.reduced.get(slot).copied().unwrap_or(false);
            if !b.enabled || (b.sleeping && !waking) || reduced {
                continue;
            }
            s.slot_to_solver[slot] = s.solver_bodies.len() as u32;
            s.solver_to_slot.push(slot as u32);
            // A kinematic body is the solver's fixed body: it moves with its velocity only.
            let (inv_mass, inv_inertia) = if b.kinematic {
                (0.0, Mat3::ZERO)
            } else {
                (b.inv_mass, b.inv_inertia)
            };
            s.solver_bodies.push(SolverBody {
                position: b.position,
                orientation: b.orientation,
                linear_velocity: b.linear_velocity,
                angular_velocity: b.angular_velocity,
                inv_mass,
                inertia: b.inertia,
                inv_inertia,
                force: b.force,
                torque: b.torque,
                linear_damping: b.linear_damping,
                angular_damping: b.angular_damping,
                fast_spin_axis: b.fast_spin_axis,
                linear_acceleration: Vec3::ZERO,
                angular_acceleration: Vec3::ZERO,
                constraint_force: Vec3::ZERO,
                constraint_torque: Vec3::ZERO,
                prefer_exact: b.prefer_exact,
                last_path: b.last_path,
            });
        }
    }

    /// The solver's parameters for a step of `dt`.
    pub(super) fn solver_params(&self, dt: Real) -> SolverParams {
        self.settings.solver_params(dt)
    }

    /// Position projection for exact islands, up to `projection_iterations` Newton passes
    /// (stopping once the largest joint error is below [`PROJECTION_TOLERANCE`]): rows are
    /// written again at the new state and the solver moves bodies so that rigid joints close.
    /// Returns the largest joint error found by the first pass.
    fn project_positions(&mut self, params: &SolverParams) -> Real {
        let mut first = None;
        // Where each constraint's rows sat in the step, so that every projection pass finds
        // each row's λ even when a constraint writes a different number of rows at the new
        // state (a limit or a contact coming or going).
        let s = &mut self.scratch;
        s.step_layout.clear();
        for (b, &slot) in s.blocks.iter().zip(&s.block_constraint) {
            s.step_layout.push((slot, b.first_row, b.row_count));
        }
        for _ in 0..self.settings.projection_iterations {
            self.gather_rows(params);
            let s = &mut self.scratch;
            line_up_lambda(s);
            let worst = match self.solver.project(
                &mut s.solver_bodies,
                &s.blocks,
                &s.rows,
                &s.projection_lambda,
                params,
            ) {
                Ok(w) => w,
                Err(e) => {
                    // Rows were valid for the step; a constraint that writes bad rows at the
                    // new state only loses its projection.
                    log::warn!("kea: position projection skipped: {e}");
                    break;
                }
            };
            first.get_or_insert(worst as Real);
            if worst < wide(PROJECTION_TOLERANCE) {
                break; // already closed: this pass moved (almost) nothing
            }
            for (i, sb) in s.solver_bodies.iter().enumerate() {
                let slot = s.solver_to_slot[i] as usize;
                let b = self.bodies.at_mut(slot).expect("simulated bodies are live");
                if b.quarantined || !(is_finite3(sb.position) && sb.orientation.is_finite()) {
                    continue; // frozen, or a pass that failed for this body
                }
                b.position = sb.position;
                b.orientation = sb.orientation;
                b.update_transform();
            }
        }
        first.unwrap_or(0.0)
    }

    /// Disables every breakable constraint whose reaction on body 1 passed its threshold in
    /// this step (the guide's animated hand that lets go), and lists them.
    fn break_overloaded(&mut self) -> u32 {
        self.scratch.broken.clear();
        for k in 0..self.scratch.unwritable.len() {
            let slot = self.scratch.unwritable[k] as usize;
            let Some(h) = self.constraints.handle_at(slot) else {
                continue;
            };
            let Some(e) = self.constraints.at_mut(slot) else {
                continue;
            };
            e.enabled = false;
            log::warn!(
                "kea: {} {h:?} wrote non-finite rows at its bodies' poses: disabled",
                e.kind.name()
            );
            self.scratch.broken.push(h);
            self.index_constraint(slot, true);
        }
        for k in 0..self.scratch.blocks.len() {
            let slot = self.scratch.block_constraint[k] as usize;
            let Some(e) = self.constraints.at_mut(slot) else {
                continue;
            };
            let r = e.reaction[0];
            let over = e.break_force.is_some_and(|f| r.force.length() > f)
                || e.break_torque.is_some_and(|t| r.torque.length() > t);
            if over {
                e.enabled = false;
                if let Some(h) = self.constraints.handle_at(slot) {
                    self.scratch.broken.push(h);
                }
                let joint = self.is_joint_slot(slot);
                self.index_constraint(slot, joint);
            }
        }
        self.scratch.broken.len() as u32
    }

    /// Lets joints that track a coordinate (hinge angle, slider distance) record it at the state
    /// the step reached.
    fn commit_joints(&mut self, dt: Real) {
        for k in 0..self.scratch.blocks.len() {
            let slot = self.scratch.block_constraint[k] as usize;
            let Some(entry) = self.constraints.at(slot) else {
                continue;
            };
            if !entry.kind.tracks_state() {
                continue;
            }
            let slots = entry.bodies.map(|b| b.map(|h| h.index()));
            let ctx = RowContext {
                bodies: [self.row_body(slots[0], dt).0, self.row_body(slots[1], dt).0],
                dt,
                epsilon: self.settings.epsilon,
                gamma: self.settings.gamma,
                contact_spring: self.settings.contact_spring,
            };
            if let Some(entry) = self.constraints.at_mut(slot) {
                entry.kind.commit(&ctx);
            }
        }
    }

    /// Fills λ with each constraint's forces from the previous step (same constraint, same
    /// number of rows), keyed by the constraint's handle and row index; 0 otherwise.
    fn warm_start_lambda(&mut self) {
        let s = &mut self.scratch;
        std::mem::swap(&mut s.lambda, &mut s.prev_lambda);
        s.lambda.clear();
        s.lambda.resize(s.rows.len(), 0.0);
        for (k, blk) in s.blocks.iter().enumerate() {
            let slot = s.block_constraint[k] as usize;
            let entry = self
                .constraints
                .at(slot)
                .expect("gathered constraints are live");
            if let Some((first, count)) = entry.last_rows {
                if count == blk.row_count {
                    let from = &s.prev_lambda[first as usize..(first + count) as usize];
                    let to = blk.first_row as usize..(blk.first_row + count) as usize;
                    s.lambda[to].copy_from_slice(from);
                }
            }
        }
    }
}

/// Fills `projection_lambda` with the step's λ for each row gathered now: row `j` of a
/// constraint takes the λ of its row `j` in the step, or 0 if it has no such row (blocks of
/// both gathers are in constraint slot order).
fn line_up_lambda(s: &mut super::StepScratch) {
    s.projection_lambda.clear();
    let mut cursor = 0;
    for (b, &slot) in s.blocks.iter().zip(&s.block_constraint) {
        while s.step_layout.get(cursor).is_some_and(|l| l.0 < slot) {
            cursor += 1;
        }
        let step = s.step_layout.get(cursor).filter(|l| l.0 == slot).copied();
        for j in 0..b.row_count {
            let l = match step {
                Some((_, first, count)) if j < count => s.lambda[(first + j) as usize],
                _ => 0.0,
            };
            s.projection_lambda.push(l);
        }
    }
}
