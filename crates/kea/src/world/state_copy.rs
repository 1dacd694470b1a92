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
