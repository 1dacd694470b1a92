//! The gather stage of a step (the guide's Bcl): every enabled joint writes its rows at its
//! bodies' states, every enabled contact is filed for the solver; and the same rows written
//! again at the bodies' present poses, to measure the joints' error and, through
//! `JointSource`, to re-linearise joints inside the iterative path's substeps.

use super::body_constraints::visited;
use super::constraint_entry::{ConstraintEntry, ConstraintKind};
use super::constraint_index::EMPTY;
use super::World;
use crate::body::Body;
use crate::constraint::{Row, RowBody, RowContext, RowWriter};
use crate::handle::{Arena, BodyHandle, ConstraintHandle};
use crate::math::Real;
use crate::solver::{ConstraintBlock, RowSource, SolverContact, SolverParams};

impl World {
    /// The row-writing view of a body slot: dynamic if simulated, fixed if disabled.
    pub(super) fn row_body(&self, slot: Option<u32>, h: Real) -> (RowBody, Option<u32>) {
        let Some(slot) = slot else {
            return (RowBody::STATIC, None);
        };
        let b = self
            .bodies
            .at(slot as usize)
            .expect("constraint bodies are live");
        let solver_index = self.scratch.slot_to_solver[slot as usize];
        if solver_index == u32::MAX {
            return (RowBody::fixed(b.position, b.orientation), None);
        }
        if b.kinematic {
            // Moves at its set velocity whatever acts on it.
            let rb = RowBody {
                linear_velocity: b.linear_velocity,
                angular_velocity: b.angular_velocity,
                free_linear_velocity: b.linear_velocity,
                free_angular_velocity: b.angular_velocity,
                ..RowBody::fixed(b.position, b.orientation)
            };
            return (rb, Some(solver_index));
        }
        let inv_iw = {
            let r = crate::math::Mat3::from_quat(b.orientation);
            r * b.inv_inertia * r.transpose()
        };
        let rb = RowBody {
            position: b.position,
            orientation: b.orientation,
            linear_velocity: b.linear_velocity,
            angular_velocity: b.angular_velocity,
            free_linear_velocity: b.linear_velocity
                + h * (self.settings.gravity + b.inv_mass * b.force),
            free_angular_velocity: b.angular_velocity + h * (inv_iw * b.torque),
            dynamic: true,
            fast_spin_axis: b.fast_spin_axis.map(|a| b.orientation * a),
        };
        (rb, Some(solver_index))
    }

    /// The largest position error of any enabled joint's rigid rows at the bodies' present
    /// poses (per row, so per axis for a ball joint's gap), m or rad (contacts, limits and motors excluded): how far the joints have come
    /// apart. It writes every constraint's rows, so it costs about a fifth of a step; it
    /// allocates nothing once the world has stepped.
    pub fn joint_error(&mut self) -> Real {
        let params = self.solver_params(1.0 / 60.0);
        self.scratch.wake.clear(); // the next step plans its own waking
        self.awake.refresh(&self.bodies);
        // The listing of the awake bodies' constraints as they are now (the last step's may
        // name slots since changed, or a world since copied in).
        self.list_awake_constraints();
        self.collect_bodies();
        self.gather_rows(&params);
        let s = &self.scratch;
        let mut worst: Real = 0.0;
        for (block, &slot) in s.blocks.iter().zip(&s.block_constraint) {
            let is_joint = self
                .constraints
                .at(slot as usize)
                .is_some_and(|e| !matches!(e.kind, ConstraintKind::Contact(_)));
            if !is_joint {
                continue;
            }
            let first = block.first_row as usize;
            for row in &s.rows[first..first + block.row_count as usize] {
                let rigid = row.lo == Real::NEG_INFINITY
                    && row.hi == Real::INFINITY
                    && row.gamma != Some(0.0)
                    && row.softness.is_none_or(|e| e == 0.0);
                if rigid {
                    worst = worst.max(row.xi.abs());
                }
            }
        }
        worst
    }

    /// Asks every enabled joint for its rows and files every enabled contact for the solver.
    /// Returns how many constraints take part.
    pub(super) fn gather_rows(&mut self, params: &SolverParams) -> u32 {
        let mut rows = std::mem::take(&mut self.scratch.rows);
        let mut blocks = std::mem::take(&mut self.scratch.blocks);
        let mut block_constraint = std::mem::take(&mut self.scratch.block_constraint);
        rows.clear();
        blocks.clear();
        block_constraint.clear();
        self.scratch.unwritable.clear();
        self.scratch.contacts.clear();
        self.scratch.contact_constraint.clear();
        // A constraint takes part only with a simulated body: none, none to look at.
        // Without a sleeping body waking, only the constraints of awake bodies (listed).
        let listed = self.scratch.awake_constraints_listed;
        let scanned = if self.scratch.solver_bodies.is_empty() {
            0
        } else {
            self.constraint_bodies.len()
        };
        let listing = std::mem::take(&mut self.scratch.awake_constraints);
        let listed = listed && scanned > 0;
        for slot in visited(listed, &listing, scanned) {
            // Through the dense index: a constraint with no body in the solver (both asleep,
            // disabled or static) is passed without reading its entry.
            let [a, b] = self.constraint_bodies[slot];
            let simulated =
                |s: u32| s < EMPTY && self.scratch.slot_to_solver[s as usize] != u32::MAX;
            if a == EMPTY || !(simulated(a) || simulated(b)) {
                continue;
            }
            let Some(entry) = self.constraints.at(slot) else {
                continue;
            };
            debug_assert!(entry.enabled, "the constraint index lists a disabled slot");
            let slots = entry.bodies.map(|b| b.map(|h| h.index()));
            if let ConstraintKind::Contact(c) = &entry.kind {
                let solver_slot = |s: Option<u32>| {
                    s.map(|s| self.scratch.slot_to_solver[s as usize])
                        .filter(|&i| i != u32::MAX)
                };
                let bodies = slots.map(solver_slot);
                if bodies != [None, None] {
                    self.scratch.contacts.push(SolverContact {
                        bodies,
                        contact: *c,
                    });
                    self.scratch.contact_constraint.push(slot as u32);
                }
                continue;
            }
            if let Some(block) = self.gather_joint(slot, slots, params, &mut rows) {
                blocks.push(block);
                block_constraint.push(slot as u32);
            }
        }
        self.scratch.awake_constraints = listing;
        let n = (blocks.len() + self.scratch.contacts.len()) as u32;
        self.scratch.rows = rows;
        self.scratch.blocks = blocks;
        self.scratch.block_constraint = block_constraint;
        n
    }

    /// Writes joint `slot`'s rows at its bodies' states (`slots`) onto `rows`; its block, or
    /// `None` when nothing it holds moves, it wrote no row, or it could not write them (a
    /// degenerate pose: it sits this step out and the step disables it, reported as broken).
    fn gather_joint(
        &mut self,
        slot: usize,
        slots: [Option<u32>; 2],
        params: &SolverParams,
        rows: &mut Vec<Row>,
    ) -> Option<ConstraintBlock> {
        let (rb0, s0) = self.row_body(slots[0], params.dt);
        let (rb1, s1) = self.row_body(slots[1], params.dt);
        if s0.is_none() && s1.is_none() {
            return None; // nothing that moves
        }
        let ctx = RowContext {
            bodies: [rb0, rb1],
            dt: params.dt,
            epsilon: params.epsilon,
            gamma: params.gamma,
            contact_spring: params.contact_spring,
        };
        let first = rows.len();
        let entry = self.constraints.at(slot).expect("occupied");
        let mut writer = RowWriter::new(rows);
        entry.kind.write_rows(&ctx, &mut writer);
        if let Some(g) = entry.gamma {
            for r in &mut rows[first..] {
                r.gamma.get_or_insert(g);
            }
        }
        let custom = matches!(entry.kind, ConstraintKind::Custom(_));
        if !custom && rows[first..].iter().any(|r| r.invalid_field().is_some()) {
            rows.truncate(first);
            self.scratch.unwritable.push(slot as u32);
            return None;
        }
        let count = rows.len() - first;
        (count > 0).then_some(ConstraintBlock {
            bodies: [s0, s1],
            first_row: first as u32,
            row_count: count as u32,
        })
    }
}

/// The world's joints as a [`RowSource`]: block k is constraint `block_constraint[k]`, written
/// again at the poses the solver gives (joints re-linearised inside the substeps).
pub(super) struct JointSource<'a> {
    pub(super) constraints: &'a Arena<ConstraintEntry, ConstraintHandle>,
    pub(super) block_constraint: &'a [u32],
    /// The world's bodies and their solver indices: a joint's body the solver does not hold
    /// (a disabled one, or any the step leaves out) is no body to the solver, which gives its slot
    /// the static world's frame; the joint is rewritten with that body's own pose instead.
    pub(super) bodies: &'a Arena<Body, BodyHandle>,
    pub(super) slot_to_solver: &'a [u32],
}

impl RowSource for JointSource<'_> {
    fn rewrite(&self, block: usize, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let Some(entry) = self
            .block_constraint
            .get(block)
            .and_then(|&slot| self.constraints.at(slot as usize))
        else {
            return;
        };
        // A body outside the solver stays where the step found it.
        let outside = entry.bodies.map(|h| {
            let slot = h?.index() as usize;
            let b = self.bodies.at(slot)?;
            (self.slot_to_solver.get(slot) == Some(&u32::MAX))
                .then(|| RowBody::fixed(b.position, b.orientation))
        });
        if outside.iter().all(Option::is_none) {
            entry.kind.write_rows(ctx, out);
        } else {
            let mut ctx = *ctx;
            for (rb, fixed) in ctx.bodies.iter_mut().zip(outside) {
                if let Some(fixed) = fixed {
                    *rb = fixed;
                }
            }
            entry.kind.write_rows(&ctx, out);
        }
        if let Some(g) = entry.gamma {
            out.set_default_gamma(g);
        }
    }
}
