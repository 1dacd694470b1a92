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
        let (a, b) = (self, other);
        macro_rules! copy {
            ($f:ident) => {
                a.$f.clone_from(&b.$f)
            };
        }
        each_state_field!(copy);
        a.materials.copy_from(&b.materials);
        a.pairs.copy_from(&b.pairs);
        a.tree.copy_from(&b.tree);
    }

    /// Trades states with `other` — everything [`CollisionWorld::copy_state_from`] copies —
    /// each keeping its narrow-phase workers, with no copy (a batch's hot worker, see
    /// `kea::World::swap_state`).
    pub fn swap_state(&mut self, other: &mut CollisionWorld) {
        let (a, b) = (self, other);
        macro_rules! trade {
            ($f:ident) => {
                std::mem::swap(&mut a.$f, &mut b.$f)
            };
        }
        each_state_field!(trade);
        std::mem::swap(&mut a.materials, &mut b.materials);
        std::mem::swap(&mut a.pairs, &mut b.pairs);
        std::mem::swap(&mut a.tree, &mut b.tree);
    }
}

/// Calls `$m!(field)` for every field of a collision world that is its state, but for the
/// materials, the pairs and the broad phase, which copy their own way: the one list that
/// copying and trading states follow.
macro_rules! each_state_field {
    ($m:ident) => {
        $m!(slots);
        $m!(free);
        $m!(strategy);
        $m!(margin);
        $m!(touch_distance);
        $m!(moved);
        $m!(still);
        $m!(last_dt);
        $m!(jointed_changed);
        $m!(jointed_revision);
        $m!(new_pairs);
        $m!(events);
        $m!(pending_events);
        $m!(jointed);
        $m!(previously_jointed);
        $m!(colliding_joints);
        $m!(excluded);
        $m!(stats);
        $m!(failed_pairs);
        $m!(generated_with);
        $m!(by_body);
        $m!(bodies_seen_at);
        $m!(all_still);
        $m!(unrest);
        $m!(unrested);
        $m!(events_quiet);
        $m!(event_record);
        $m!(pairable);
        $m!(bounds_stale);
    };
}
use each_state_field;

impl CollisionWorld {
    /// Drops the narrow phase's workers (scratch) and keeps the state (see
    /// `kea::World::trim_to_state`): the next update makes them again, and allocates.
    pub fn trim_to_state(&mut self) {
        self.workers = Vec::new();
        self.active_workers = 0;
    }
}
