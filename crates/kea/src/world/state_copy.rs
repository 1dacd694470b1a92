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
        let (a, b) = (self, other);
        macro_rules! copy {
            ($f:ident) => {
                a.$f.clone_from(&b.$f)
            };
        }
        macro_rules! copy_scratch {
            ($f:ident) => {
                a.scratch.$f.clone_from(&b.scratch.$f)
            };
        }
        each_state_field!(copy);
        each_scratch_state_field!(copy_scratch);
        a.bodies.copy_from(&b.bodies);
        a.constraints.copy_from(&b.constraints);
        a.scratch
            .reduced
            .copy_kept_from(&b.scratch.reduced, workspace);
    }
}

/// Calls `$m!(field)` for every field of a world that is its state (what a snapshot holds),
/// but for the arenas of bodies and constraints and the kept trees, which each move their
/// own way: the one list that copying, trading and trimming states all follow.
macro_rules! each_state_field {
    ($m:ident) => {
        $m!(id);
        $m!(constraint_bodies);
        $m!(tree_joint_slots);
        $m!(body_constraints);
        $m!(joint_revision);
        $m!(settings);
        $m!(max_island_rows);
        $m!(quarantine);
        $m!(quarantine_roots);
        $m!(tendons);
        $m!(time);
        $m!(steps);
        $m!(awake);
    };
}

/// Calls `$m!(field)` for every field of the step's scratch that is state: the last step's
/// forces and what it broke and wrote, which read-outs and the next warm start use.
macro_rules! each_scratch_state_field {
    ($m:ident) => {
        $m!(lambda);
        $m!(contact_lambda);
        $m!(contact_rows);
        $m!(contact_reactions);
        $m!(broken);
        $m!(written);
    };
}
use {each_scratch_state_field, each_state_field};

impl World {
    /// Trades states with `other` — everything [`World::copy_state_from`] copies — each
    /// keeping its own step scratch, with no copy: a batch's hot worker takes a world's
    /// state in, steps it, and gives it back (the model/data split: the worker's scratch,
    /// sized once, serves every world, and each world keeps only its state). Stepping this
    /// world then gives the bits stepping `other` would have given; `other` holds this
    /// world's former state and can step it too (its kept trees size their scratch first).
    pub fn swap_state(&mut self, other: &mut World) {
        self.swap_state_but_arenas(other);
        std::mem::swap(&mut self.bodies, &mut other.bodies);
        std::mem::swap(&mut self.constraints, &mut other.constraints);
    }

    /// [`World::swap_state`] but for the arenas of bodies and constraints, which a held
    /// world's record moves its own way (`held.rs`).
    pub(super) fn swap_state_but_arenas(&mut self, other: &mut World) {
        let (a, b) = (self, other);
        macro_rules! trade {
            ($f:ident) => {
                std::mem::swap(&mut a.$f, &mut b.$f)
            };
        }
        macro_rules! trade_scratch {
            ($f:ident) => {
                std::mem::swap(&mut a.scratch.$f, &mut b.scratch.$f)
            };
        }
        each_state_field!(trade);
        each_scratch_state_field!(trade_scratch);
        a.scratch.reduced.swap_kept(&mut b.scratch.reduced);
    }
}

impl World {
    /// Drops the step's scratch (the solver's workspace, the step's arrays, each kept tree's
    /// factor and recursions) and keeps the state: what a world that only holds a state
    /// between steps needs (a batch's world, stepped by a worker through
    /// [`World::swap_state`]). It still steps on the same bits; its first step sizes the
    /// scratch again, and allocates.
    pub fn trim_to_state(&mut self) {
        let mut lean = super::StepScratch::default();
        let s = &mut self.scratch;
        macro_rules! keep {
            ($f:ident) => {
                std::mem::swap(&mut lean.$f, &mut s.$f)
            };
        }
        each_scratch_state_field!(keep);
        lean.reduced.swap_kept(&mut s.reduced);
        *s = lean;
        self.solver = Default::default();
    }
}
