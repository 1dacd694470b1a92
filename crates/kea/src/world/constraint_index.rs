//! The dense index of constraints' bodies that a step scans, kept in step with the arena at
//! every change of a constraint (made, destroyed, enabled, disabled, re-bodied, broken,
//! restored), and the joint revision that tells collision layers when jointed pairs changed.
//!
//! A step visits only the constraints with a body it simulates; in a world that is mostly
//! asleep most are not, and reading their entries (hundreds of bytes each, a contact's points
//! inline) cost more than the rest of the step. The index holds 8 bytes per slot.

use super::constraint_entry::ConstraintKind;
use super::World;
use std::sync::atomic::{AtomicU64, Ordering};

/// A slot's bodies in the index when it is empty or disabled.
pub(super) const EMPTY: u32 = u32::MAX - 1;
/// The static world's side of a constraint in the index.
pub(super) const NO_BODY: u32 = u32::MAX;

/// Joint revisions are drawn from one counter for all worlds, so that a world made, cloned
/// apart or restored never shows a collision layer a revision it saw for other joints.
static JOINT_REVISIONS: AtomicU64 = AtomicU64::new(1);

pub(super) fn next_joint_revision() -> u64 {
    JOINT_REVISIONS.fetch_add(1, Ordering::Relaxed)
}

impl World {
    /// Writes constraint slot `slot`'s entry into the index; `joint_changed` (a joint was made,
    /// destroyed, enabled, disabled or re-bodied there) also moves the joint revision on.
    pub(super) fn index_constraint(&mut self, slot: usize, joint_changed: bool) {
        if self.constraint_bodies.len() <= slot {
            self.constraint_bodies
                .resize(self.constraints.slot_count().max(slot + 1), [EMPTY; 2]);
        }
        if self.tree_joint_slots.len() < self.constraint_bodies.len() {
            self.tree_joint_slots
                .resize(self.constraint_bodies.len(), false);
        }
        let old = self.constraint_bodies[slot];
        self.constraint_bodies[slot] = match self.constraints.at(slot) {
            Some(e) if e.enabled => e.bodies.map(|b| b.map_or(NO_BODY, |h| h.index())),
            _ => [EMPTY; 2],
        };
        self.body_constraints
            .relink(slot, old, self.constraint_bodies[slot]);
        self.tree_joint_slots[slot] = self.constraints.at(slot).is_some_and(|e| {
            matches!(
                e.kind,
                ConstraintKind::Hinge(_)
                    | ConstraintKind::Prismatic(_)
                    | ConstraintKind::Ball(_)
                    | ConstraintKind::Planar(_)
            )
        });
        if joint_changed {
            self.joint_revision = next_joint_revision();
        }
    }

    /// Rebuilds the whole index (a restored world).
    #[cfg(feature = "serde")]
    pub(super) fn reindex_constraints(&mut self) {
        self.constraint_bodies.clear();
        self.tree_joint_slots.clear();
        self.body_constraints.clear();
        for slot in 0..self.constraints.slot_count() {
            self.index_constraint(slot, false);
        }
        self.joint_revision = next_joint_revision();
    }

    /// Whether slot `slot` holds a joint (any constraint but a contact).
    pub(super) fn is_joint_slot(&self, slot: usize) -> bool {
        self.constraints
            .at(slot)
            .is_some_and(|e| !matches!(e.kind, ConstraintKind::Contact(_)))
    }

    /// A number that changes whenever a joint (any constraint but a contact) is made,
    /// destroyed, enabled, disabled or given other bodies, by the API or by breaking. A
    /// collision layer reads the jointed body pairs again only when it changed.
    #[must_use]
    pub fn joint_revision(&self) -> u64 {
        self.joint_revision
    }
}
