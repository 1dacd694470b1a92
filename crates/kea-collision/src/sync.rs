//! Keeping the world's contacts in step with the manifolds: update the persisting ones (same
//! handle, so the solvers warm-start), create the new ones, destroy the vanished ones, and
//! record began / persisted / ended events per collider pair.

use crate::collision_world::{handle_of, CollisionWorld, PairContact};
use crate::error::CollisionResult;
use crate::events::{ContactEvent, ContactEventKind};
use kea::World;

impl CollisionWorld {
    /// Writes the wanted contacts into the world, after checking that they fit.
    pub(crate) fn apply(&mut self, world: &mut World) -> CollisionResult<()> {
        self.check_capacity(world)?;
        for state in self.pairs.values_mut() {
            let keep_all = state.seen && state.resting;
            for c in &mut state.contacts {
                c.seen = keep_all;
            }
        }
        for w in &self.wanted {
            let state = self
                .pairs
                .get_mut(&w.pair)
                .expect("pair recorded in narrow phase");
            if let Some(c) = state.contacts.iter_mut().find(|c| c.key == w.key) {
                c.seen = true;
            }
        }
        // Destroy first, so their capacity is free for the new ones.
        for state in self.pairs.values_mut() {
            state.contacts.retain(|c| {
                let keep = c.seen && world.contact(c.handle).is_ok();
                if !keep {
                    let _ = world.destroy_constraint(c.handle); // may already be gone with its body
                }
                keep
            });
        }
        for state in self.pairs.values_mut() {
            state.touching_now = state.seen && state.resting && state.touching;
        }
        for w in &self.wanted {
            let state = self
                .pairs
                .get_mut(&w.pair)
                .expect("pair recorded in narrow phase");
            state.touching_now |= w.contact.penetration() > -self.touch_distance;
            match state.contacts.iter().find(|c| c.key == w.key) {
                Some(c) => {
                    let target = world.contact_mut(c.handle)?;
                    target.set_position(w.contact.position())?;
                    target.set_normal(w.contact.normal())?;
                    target.set_penetration(w.contact.penetration())?;
                    target.set_params(*w.contact.params())?;
                    target.set_direction(w.contact.direction())?;
                }
                None => {
                    let handle = world.create_contact(w.bodies.0, w.bodies.1, w.contact)?;
                    state.contacts.push(PairContact {
                        key: w.key,
                        handle,
                        seen: true,
                    });
                }
            }
        }
        self.record_events();
        self.pairs.retain(|_, s| s.seen);
        Ok(())
    }

    /// Refuses, before anything changes, an update whose new contacts would not fit.
    fn check_capacity(&self, world: &World) -> CollisionResult<()> {
        let live = |c: &PairContact| world.contact(c.handle).is_ok();
        let mut matched = 0;
        for w in &self.wanted {
            let state = &self.pairs[&w.pair];
            if state.contacts.iter().any(|c| c.key == w.key && live(c)) {
                matched += 1;
            }
        }
        let creations = self.wanted.len() - matched;
        let kept_resting: usize = self
            .pairs
            .values()
            .filter(|s| s.seen && s.resting)
            .map(|s| s.contacts.iter().filter(|c| live(c)).count())
            .sum();
        let ours: usize = self
            .pairs
            .values()
            .map(|s| s.contacts.iter().filter(|c| live(c)).count())
            .sum();
        let destroyed = ours - matched - kept_resting;
        let after = world.constraint_count() - destroyed + creations;
        if after > world.constraint_capacity() {
            return Err(kea::KeaError::CapacityExceeded {
                what: "constraints (collision asked for more contacts)",
                capacity: world.constraint_capacity(),
            }
            .into());
        }
        Ok(())
    }

    fn record_events(&mut self) {
        self.events.clear();
        self.events.append(&mut self.pending_events);
        for (&(a, b), state) in &mut self.pairs {
            let now = state.seen && state.touching_now;
            let kind = match (state.touching, now) {
                (false, true) => Some(ContactEventKind::Began),
                (true, true) => Some(ContactEventKind::Persisted),
                (true, false) => Some(ContactEventKind::Ended),
                (false, false) => None,
            };
            state.touching = now;
            if let Some(kind) = kind {
                let colliders = [handle_of(&self.slots, a), handle_of(&self.slots, b)];
                self.events.push(ContactEvent { kind, colliders });
            }
        }
    }
}
