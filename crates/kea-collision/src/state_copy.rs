//! A collision world's state copied into another without its narrow phase's workers (their
//! manifold caches are scratch, as a restored snapshot shows): the collision half of a
//! batch's model/data split (`kea::World::copy_state_from` is the dynamics half).

use crate::collision_world::CollisionWorld;

impl CollisionWorld {
    /// Asks the processor for the cache lines an update reads first: the colliders, the
    /// pairs and the broad phase's nodes (see [`kea::World::prefetch`]). A hint: nothing
    /// changes.
    pub fn prefetch(&self) {
        kea::prefetch::slice(std::slice::from_ref(self));
        kea::prefetch::slice(&self.slots);
        self.pairs.prefetch();
        self.tree.prefetch();
        kea::prefetch::slice(&self.still);
        kea::prefetch::slice(&self.jointed);
    }

    /// Makes this collision world `other` as it is now — colliders, materials, pairs and
    /// their manifolds, the broad phase, events and read-outs — reusing this world's buffers
    /// and keeping its narrow-phase workers. Updating it then gives the contacts `other`'s
    /// update would.
    pub fn copy_state_from(&mut self, other: &CollisionWorld) {
        self.slots.clone_from(&other.slots);
        self.free.clone_from(&other.free);
        self.materials.copy_from(&other.materials);
        self.strategy = other.strategy;
        self.margin = other.margin;
        self.touch_distance = other.touch_distance;
        self.pairs.copy_from(&other.pairs);
        self.tree.copy_from(&other.tree);
        self.moved.clone_from(&other.moved);
        self.still.clone_from(&other.still);
        self.last_dt = other.last_dt;
        self.jointed_changed = other.jointed_changed;
        self.jointed_revision = other.jointed_revision;
        self.new_pairs.clone_from(&other.new_pairs);
        self.events.clone_from(&other.events);
        self.pending_events.clone_from(&other.pending_events);
        self.jointed.clone_from(&other.jointed);
        self.previously_jointed
            .clone_from(&other.previously_jointed);
        self.colliding_joints.clone_from(&other.colliding_joints);
        self.excluded.clone_from(&other.excluded);
        self.stats = other.stats;
        self.failed_pairs.clone_from(&other.failed_pairs);
        self.generated_with = other.generated_with;
    }
}
