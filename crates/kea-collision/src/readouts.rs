//! What the last collision update found: its events, the impulses between pairs, the contacts
//! of a pair, the deepest overlap, its statistics and the pairs that failed.

use crate::collision_world::{ColliderHandle, CollisionWorld};
use crate::error::CollisionResult;
use crate::events::ContactEvent;
use kea::{BodyHandle, CollisionStats, ConstraintHandle, Contact, Real, Vec3, World};

impl CollisionWorld {
    /// The contact events of the last update (began, persisted, ended), in pair order.
    #[must_use]
    pub fn events(&self) -> &[ContactEvent] {
        &self.events
    }

    /// The total contact impulse on collider `a`'s body from collider `b` over the last step,
    /// N·s (zero if they did not touch): their contacts' forces in `world` times the step.
    /// Read from the contacts when asked, so the step itself does no bookkeeping for it.
    pub fn pair_impulse(
        &self,
        world: &World,
        a: ColliderHandle,
        b: ColliderHandle,
    ) -> CollisionResult<Vec3> {
        self.get(a)?;
        self.get(b)?;
        let key = (a.index.min(b.index), a.index.max(b.index));
        let on_first = self
            .pairs
            .find(key)
            .map_or(Vec3::ZERO, |s| self.impulse_on_first(world, s));
        Ok(if a.index <= b.index {
            on_first
        } else {
            -on_first
        })
    }

    /// The total contact impulse on `body` from `other` (`None`: the static world) over the
    /// last step, summed over all their colliders' pairs, N·s.
    #[must_use]
    pub fn body_pair_impulse(
        &self,
        world: &World,
        body: BodyHandle,
        other: Option<BodyHandle>,
    ) -> Vec3 {
        let mut total = Vec3::ZERO;
        for (slot, state) in self.pairs.live() {
            let (ia, ib) = state.colliders;
            let (Some(a), Some(b)) = (
                &self.slots[ia as usize].collider,
                &self.slots[ib as usize].collider,
            ) else {
                continue;
            };
            if a.def.body == Some(body) && b.def.body == other {
                total += self.impulse_on_first(world, slot);
            } else if b.def.body == Some(body) && a.def.body == other {
                total -= self.impulse_on_first(world, slot);
            }
        }
        total
    }

    /// Pair `slot`'s impulse on its first collider over the last step. Contact forces act on
    /// the contacts' body 1: the first collider's, unless the pair is flipped. A resting
    /// pair's contacts kept their forces, so it keeps its impulse.
    fn impulse_on_first(&self, world: &World, slot: u32) -> Vec3 {
        let state = &self.pairs.slots[slot as usize];
        let force: Vec3 = state
            .manifolds
            .iter()
            .filter_map(|m| world.contact_force(m.handle).ok())
            .sum();
        let impulse = force * self.last_dt;
        if state.flipped {
            -impulse
        } else {
            impulse
        }
    }

    /// Each contact the last update made and the colliders it is between: `(first, second,
    /// contact)`, `first` the collider on the contact's body 1 (its points' forces act on
    /// it), in pair order.
    pub fn contact_colliders(
        &self,
    ) -> impl Iterator<Item = (ColliderHandle, ColliderHandle, ConstraintHandle)> + '_ {
        self.pairs.live().flat_map(move |(_, state)| {
            let handle = |i: u32| ColliderHandle {
                index: i,
                generation: self.slots[i as usize].generation,
            };
            let (a, b) = (handle(state.colliders.0), handle(state.colliders.1));
            let (first, second) = if state.flipped { (b, a) } else { (a, b) };
            state
                .manifolds
                .iter()
                .map(move |m| (first, second, m.handle))
        })
    }

    /// The deepest penetration among the contacts this collision world made, m (0 if none
    /// overlap): the contact constraints' largest error.
    #[must_use]
    pub fn deepest_penetration(&self, world: &World) -> Real {
        self.pairs
            .live()
            .flat_map(|(_, p)| p.manifolds.iter())
            .filter_map(|m| world.contact(m.handle).ok())
            .map(Contact::penetration)
            .fold(0.0, Real::max)
    }

    /// The Kea contacts currently generated between two colliders.
    pub fn contacts_between(
        &self,
        a: ColliderHandle,
        b: ColliderHandle,
    ) -> CollisionResult<Vec<ConstraintHandle>> {
        self.get(a)?;
        self.get(b)?;
        let key = (a.index.min(b.index), a.index.max(b.index));
        Ok(self
            .pairs
            .find(key)
            .map(|s| {
                self.pairs.slots[s as usize]
                    .manifolds
                    .iter()
                    .map(|m| m.handle)
                    .collect()
            })
            .unwrap_or_default())
    }

    /// What the last [`CollisionWorld::update_contacts`] did.
    #[must_use]
    pub fn stats(&self) -> &CollisionStats {
        &self.stats
    }

    /// The collider pairs whose contact generation failed inside parry in the last update (a
    /// panic caught, or a non-finite point). Each got no contacts for that step and is tried
    /// again the next; the step itself went on. Empty in a healthy world.
    #[must_use]
    pub fn failed_pairs(&self) -> &[(ColliderHandle, ColliderHandle)] {
        &self.failed_pairs
    }
}
