//! A collision world's state copied into another, or traded with it, without its narrow
//! phase's workers (their manifold caches are scratch, as a restored snapshot shows): the
//! collision half of a batch's model/data split (`kea::World::copy_state_from` and
//! `kea::World::swap_state` are the dynamics half).

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

impl CollisionWorld {
    /// Trades states with `other` — everything [`CollisionWorld::copy_state_from`] copies —
    /// each keeping its narrow-phase workers, with no copy (a batch's hot worker, see
    /// `kea::World::swap_state`).
    pub fn swap_state(&mut self, other: &mut CollisionWorld) {
        use std::mem::swap;
        swap(&mut self.slots, &mut other.slots);
        swap(&mut self.free, &mut other.free);
        swap(&mut self.materials, &mut other.materials);
        swap(&mut self.strategy, &mut other.strategy);
        swap(&mut self.margin, &mut other.margin);
        swap(&mut self.touch_distance, &mut other.touch_distance);
        swap(&mut self.pairs, &mut other.pairs);
        swap(&mut self.tree, &mut other.tree);
        swap(&mut self.moved, &mut other.moved);
        swap(&mut self.still, &mut other.still);
        swap(&mut self.last_dt, &mut other.last_dt);
        swap(&mut self.jointed_changed, &mut other.jointed_changed);
        swap(&mut self.jointed_revision, &mut other.jointed_revision);
        swap(&mut self.new_pairs, &mut other.new_pairs);
        swap(&mut self.events, &mut other.events);
        swap(&mut self.pending_events, &mut other.pending_events);
        swap(&mut self.jointed, &mut other.jointed);
        swap(&mut self.previously_jointed, &mut other.previously_jointed);
        swap(&mut self.colliding_joints, &mut other.colliding_joints);
        swap(&mut self.excluded, &mut other.excluded);
        swap(&mut self.stats, &mut other.stats);
        swap(&mut self.failed_pairs, &mut other.failed_pairs);
        swap(&mut self.generated_with, &mut other.generated_with);
    }
}

impl CollisionWorld {
    /// Drops the narrow phase's workers (scratch) and keeps the state (see
    /// `kea::World::trim_to_state`): the next update makes them again, and allocates.
    pub fn trim_to_state(&mut self) {
        self.workers = Vec::new();
        self.active_workers = 0;
    }
}
