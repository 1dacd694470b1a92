//! A batch's world held as a compact record beside the batch's model (the model/data split;
//! `kea::World::held` is the dynamics half): its bodies' and joints' definitions and the
//! facade's records of them (centres of mass, colliders, names) live once, in the worker
//! that steps every world; each world keeps what its steps change — the dynamics layer's
//! held state, its collision layer (contacts, the broad phase) whole, and its kinematic
//! bodies' targets.

use super::PhysicsWorld;
use kea::{Quat, Vec3};

/// A world of a batch, held beside the batch's model (see the module's text). A worker
/// world with the model's definitions steps, reads and writes it: [`PhysicsWorld::enter`]
/// takes it in, [`PhysicsWorld::leave`] gives it back.
///
/// Between the two, change only what a world's state is — poses, velocities, forces,
/// motors, actuators and controls, kinematic targets, contacts, the clock — or remove
/// joints (the world is then held whole, see [`HeldWorld::is_compact`]). A definition
/// changed in the worker (a mass, a collider, a joint's frames or stops) would be the
/// model's for every world it steps after; debug builds check.
#[derive(Clone)]
pub struct HeldWorld {
    /// The collision layer's state, and the facade's records when held whole (else empty:
    /// the model's serve). Its own dynamics layer is an empty stand-in.
    world: PhysicsWorld,
    dynamics: kea::HeldState,
    /// Each position-driven kinematic body's target, in the model's order.
    targets: Vec<Option<(Vec3, Quat)>>,
}

impl PhysicsWorld {
    /// This world's state as a held world (see [`HeldWorld`]), for workers made from this
    /// world (or a copy of it) to step.
    #[must_use]
    pub fn held(&self) -> HeldWorld {
        // The stand-in for its dynamics layer: as small as a world is, and no scratch.
        let least = kea::WorldDef {
            max_bodies: 1,
            max_constraints: 1,
            max_island_rows: 1,
            ..kea::WorldDef::default()
        };
        let mut world = PhysicsWorld::with_def(least).expect("the least capacities are valid");
        world.trim_to_state();
        world.collision.copy_state_from(&self.collision);
        let mut held = HeldWorld {
            world,
            dynamics: self.dynamics.held(),
            targets: Vec::new(),
        };
        held.record_targets(self);
        held
    }

    /// Takes `held` in: this world is then that world, bit for bit, until
    /// [`PhysicsWorld::leave`]. This world must have the model's definitions (a copy of the
    /// world `held` was made from) and hold no other held world.
    pub fn enter(&mut self, held: &mut HeldWorld) {
        let compact = held.is_compact();
        self.dynamics.enter(&mut held.dynamics);
        self.collision.swap_state(&mut held.world.collision);
        if compact {
            for (&h, target) in self.driven.iter().zip(&held.targets) {
                if let Some(Some(m)) = self.meta.get_mut(h.index() as usize) {
                    m.target = *target;
                }
            }
        } else {
            self.swap_facade(&mut held.world);
        }
    }

    /// Gives `held` back with what changed in it, taking back this world's own state;
    /// `model` is the world `held` was made from. A world whose joints no longer match the
    /// model's is held whole from now on (`kea::World::leave`), this world taking the
    /// model's definitions back.
    pub fn leave(&mut self, held: &mut HeldWorld, model: &PhysicsWorld) {
        let compact = held.is_compact();
        if compact {
            held.record_targets(self);
        }
        self.collision.swap_state(&mut held.world.collision);
        self.dynamics.leave(&mut held.dynamics, &model.dynamics);
        if !compact {
            self.swap_facade(&mut held.world);
        } else if !held.is_compact() {
            // Its dynamics went whole: so do the facade's records, and this world takes
            // the model's back.
            held.world.copy_facade_from(self);
            self.copy_facade_from(model);
        }
    }
}

impl HeldWorld {
    fn record_targets(&mut self, w: &PhysicsWorld) {
        self.targets.clear();
        for h in &w.driven {
            let target = w
                .meta
                .get(h.index() as usize)
                .and_then(|m| m.as_ref()?.target);
            self.targets.push(target);
        }
    }

    /// Becomes a copy of `other`, reusing its buffers (a batch's reset: nothing allocated
    /// once it has held a world as big).
    pub fn copy_from(&mut self, other: &HeldWorld) {
        self.world.copy_state_only(&other.world);
        self.dynamics.copy_from(&other.dynamics);
        self.targets.clone_from(&other.targets);
    }

    /// Whether its bodies and joints are kept beside the model's definitions; else it holds
    /// its own (its joints no longer match the model's).
    #[must_use]
    pub fn is_compact(&self) -> bool {
        self.dynamics.is_compact()
    }

    /// Asks for the cache lines a worker reads first when it takes this world in. A hint:
    /// nothing changes.
    pub fn prefetch(&self) {
        self.dynamics.prefetch();
        self.world.collision.prefetch();
        if !self.is_compact() {
            kea::prefetch::slice(&self.world.meta);
        }
    }
}
