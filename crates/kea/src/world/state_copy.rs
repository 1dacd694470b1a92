//! A world's state copied into another without its step buffers: the model/data split of
//! batches (one hot worker world per thread steps many worlds' states in turn).
//!
//! The state is what a snapshot holds (`snapshot.rs`) — bodies, constraints with their
//! tracked coordinates, controls and read-outs, settings, tendons, quarantine, the last
//! step's λ and contact forces, the clock, the kept trees' coordinates, rates and marks —
//! kept in place rather than serialised: the buffers of the world copied into are reused,
//! and its step scratch (the solver's workspace, the step's arrays, each kept tree's
//! workspace) stays its own. As for a restored snapshot, that scratch changes no result: a
//! world that takes another's state steps on the same bits as that world would. What the
//! solver keeps as read-outs of the last step (`World::island_reports`) is not part of it.

use super::World;

impl World {
    /// Makes this world `other` as it is now — every body, constraint, setting, tendon, the
    /// clock and the last step's forces and kept trees — reusing this world's buffers and
    /// keeping its own step scratch. Stepping it then gives the bits stepping `other` would,
    /// and read-outs answer as `other`'s (but for [`World::island_reports`], the solver's
    /// record of this world's last step). Handles of `other` work in it.
    pub fn copy_state_from(&mut self, other: &World) {
        self.copy_state(other, true);
    }

    /// [`World::copy_state_from`] for a world that holds a state and is not stepped before it
    /// takes one again: its kept trees' step scratch is not sized.
    pub fn copy_state_only(&mut self, other: &World) {
        self.copy_state(other, false);
    }

    /// Asks the processor for the cache lines of this world's bodies, constraints and kept
    /// trees: a batch that steps many small worlds in turn asks for the next world's while it
    /// steps this one. A hint: nothing changes.
    pub fn prefetch(&self) {
        use crate::prefetch::slice;
        slice(std::slice::from_ref(self));
        self.bodies.prefetch();
        self.constraints.prefetch();
        slice(&self.constraint_bodies);
        slice(&self.tree_joint_slots);
        slice(&self.scratch.lambda);
        slice(&self.scratch.solver_bodies);
        slice(&self.scratch.slot_to_solver);
        self.scratch.reduced.prefetch();
    }

    fn copy_state(&mut self, other: &World, workspace: bool) {
        self.id = other.id;
        self.bodies.copy_from(&other.bodies);
        self.constraints.copy_from(&other.constraints);
        self.constraint_bodies.clone_from(&other.constraint_bodies);
        self.tree_joint_slots.clone_from(&other.tree_joint_slots);
        self.joint_revision = other.joint_revision;
        self.settings.clone_from(&other.settings);
        self.max_island_rows = other.max_island_rows;
        self.quarantine.clone_from(&other.quarantine);
        self.quarantine_roots.clone_from(&other.quarantine_roots);
        self.tendons.clone_from(&other.tendons);
        self.time = other.time;
        self.steps = other.steps;
        let (s, o) = (&mut self.scratch, &other.scratch);
        s.lambda.clone_from(&o.lambda);
        s.contact_lambda.clone_from(&o.contact_lambda);
        s.contact_rows.clone_from(&o.contact_rows);
        s.contact_reactions.clone_from(&o.contact_reactions);
        s.broken.clone_from(&o.broken);
        s.written.clone_from(&o.written);
        s.reduced.copy_kept_from(&o.reduced, workspace);
    }
}

impl World {
    /// Trades states with `other` — everything [`World::copy_state_from`] copies — each
    /// keeping its own step scratch, with no copy: a batch's hot worker takes a world's
    /// state in, steps it, and gives it back (the model/data split: the worker's scratch,
    /// sized once, serves every world, and each world keeps only its state). Stepping this
    /// world then gives the bits stepping `other` would have given; `other` holds this
    /// world's former state and can step it too (its kept trees size their scratch first).
    pub fn swap_state(&mut self, other: &mut World) {
        use std::mem::swap;
        swap(&mut self.id, &mut other.id);
        swap(&mut self.bodies, &mut other.bodies);
        swap(&mut self.constraints, &mut other.constraints);
        swap(&mut self.constraint_bodies, &mut other.constraint_bodies);
        swap(&mut self.tree_joint_slots, &mut other.tree_joint_slots);
        swap(&mut self.joint_revision, &mut other.joint_revision);
        swap(&mut self.settings, &mut other.settings);
        swap(&mut self.max_island_rows, &mut other.max_island_rows);
        swap(&mut self.quarantine, &mut other.quarantine);
        swap(&mut self.quarantine_roots, &mut other.quarantine_roots);
        swap(&mut self.tendons, &mut other.tendons);
        swap(&mut self.time, &mut other.time);
        swap(&mut self.steps, &mut other.steps);
        let (s, o) = (&mut self.scratch, &mut other.scratch);
        swap(&mut s.lambda, &mut o.lambda);
        swap(&mut s.contact_lambda, &mut o.contact_lambda);
        swap(&mut s.contact_rows, &mut o.contact_rows);
        swap(&mut s.contact_reactions, &mut o.contact_reactions);
        swap(&mut s.broken, &mut o.broken);
        swap(&mut s.written, &mut o.written);
        s.reduced.swap_kept(&mut o.reduced);
    }
}

impl World {
    /// Drops the step's scratch (the solver's workspace, the step's arrays, each kept tree's
    /// factor and recursions) and keeps the state: what a world that only holds a state
    /// between steps needs (a batch's world, stepped by a worker through
    /// [`World::swap_state`]). It still steps on the same bits; its first step sizes the
    /// scratch again, and allocates.
    pub fn trim_to_state(&mut self) {
        use std::mem::take;
        let s = &mut self.scratch;
        let mut lean = super::StepScratch {
            lambda: take(&mut s.lambda),
            contact_lambda: take(&mut s.contact_lambda),
            contact_rows: take(&mut s.contact_rows),
            contact_reactions: take(&mut s.contact_reactions),
            broken: take(&mut s.broken),
            written: take(&mut s.written),
            ..Default::default()
        };
        lean.reduced.swap_kept(&mut s.reduced);
        *s = lean;
        self.solver = Default::default();
    }
}
