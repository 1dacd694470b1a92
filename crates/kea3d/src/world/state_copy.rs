//! A physics world's state copied into another without its step scratch: what a batch's hot
//! worker world takes in before it steps a world, and gives back after (the model/data
//! split; `kea::World::copy_state_from` and `CollisionWorld::copy_state_from` do the two
//! layers). Buffers are reused: once the worker has held a world as big, a copy allocates
//! nothing (a named scene's names, which a step does not change, are compared first and
//! copied only when they differ).

use super::{BodyMeta, PhysicsWorld};

impl PhysicsWorld {
    /// Makes this world `other` as it is now — its dynamics and collision layers (see
    /// [`kea::World::copy_state_from`]) and the facade's records — keeping this world's step
    /// scratch: stepping it then gives the bits stepping `other` would.
    pub fn copy_state_from(&mut self, other: &PhysicsWorld) {
        self.copy_records(other);
        self.dynamics.copy_state_from(&other.dynamics);
    }

    /// [`PhysicsWorld::copy_state_from`] into a world that only holds a state (a batch's
    /// world between steps): its kept trees' step scratch is not sized.
    pub fn copy_state_only(&mut self, other: &PhysicsWorld) {
        self.copy_records(other);
        self.dynamics.copy_state_only(&other.dynamics);
    }

    /// Trades states with `other` — its dynamics and collision layers (see
    /// [`kea::World::swap_state`]) and the facade's records — each keeping its own step
    /// scratch, with no copy. A batch's hot worker takes a world's state in with it, steps,
    /// and gives it back: the worker's scratch, sized once, serves every world of the batch,
    /// and each world keeps only its state. Stepping either world then gives the bits
    /// stepping the other would have given.
    pub fn swap_state(&mut self, other: &mut PhysicsWorld) {
        self.dynamics.swap_state(&mut other.dynamics);
        self.swap_records(other);
    }

    /// Trades the collision layer's state and the facade's records with `other`: all of a
    /// state but the dynamics layer's.
    fn swap_records(&mut self, other: &mut PhysicsWorld) {
        self.collision.swap_state(&mut other.collision);
        self.swap_facade(other);
    }

    /// Trades the facade's records (of bodies, materials, drivers and names) with `other`.
    pub(super) fn swap_facade(&mut self, other: &mut PhysicsWorld) {
        use std::mem::swap;
        swap(&mut self.meta, &mut other.meta);
        swap(&mut self.surfaces, &mut other.surfaces);
        swap(&mut self.driven, &mut other.driven);
        swap(&mut self.paths, &mut other.paths);
        swap(&mut self.names, &mut other.names);
        swap(&mut self.joint_names, &mut other.joint_names);
    }

    /// Drops the step's scratch of both layers and keeps the state (see
    /// [`kea::World::trim_to_state`]): a batch's worlds hold only their states this way,
    /// and the workers that step them hold the scratch. It still steps on the same bits;
    /// its first step sizes the scratch again, and allocates.
    pub fn trim_to_state(&mut self) {
        self.dynamics.trim_to_state();
        self.collision.trim_to_state();
    }

    /// Asks the processor for the cache lines a step of this world reads first (its
    /// dynamics and collision layers' buffers, see [`kea::World::prefetch`]): a batch asks
    /// for the next world's while it steps this one. A hint: nothing changes.
    pub fn prefetch(&self) {
        kea::prefetch::slice(std::slice::from_ref(self));
        self.dynamics.prefetch();
        self.collision.prefetch();
        kea::prefetch::slice(&self.meta);
    }

    fn copy_records(&mut self, other: &PhysicsWorld) {
        self.collision.copy_state_from(&other.collision);
        self.copy_facade_from(other);
    }

    /// Copies the facade's records (of bodies, materials, drivers and names) from `other`,
    /// reusing this world's buffers: what [`PhysicsWorld::swap_facade`] trades.
    pub(super) fn copy_facade_from(&mut self, other: &PhysicsWorld) {
        if self.meta.len() != other.meta.len() {
            self.meta.resize(other.meta.len(), None);
        }
        for (m, o) in self.meta.iter_mut().zip(&other.meta) {
            match (m.as_mut(), o) {
                (Some(m), Some(o)) => m.copy_from(o),
                _ => m.clone_from(o),
            }
        }
        self.surfaces.clone_from(&other.surfaces);
        self.driven.clone_from(&other.driven);
        self.paths.clone_from(&other.paths);
        if self.names != other.names {
            self.names.clone_from(&other.names);
        }
        if self.joint_names != other.joint_names {
            self.joint_names.clone_from(&other.joint_names);
        }
    }
}

impl BodyMeta {
    fn copy_from(&mut self, other: &BodyMeta) {
        self.handle = other.handle;
        self.kind = other.kind;
        self.explicit_mass = other.explicit_mass;
        self.explicit_inertia = other.explicit_inertia;
        self.explicit_com = other.explicit_com;
        self.local_com = other.local_com;
        self.colliders.clone_from(&other.colliders);
        self.target = other.target;
    }
}
