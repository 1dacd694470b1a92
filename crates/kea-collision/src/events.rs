//! Contact events per collider pair: a pair *begins* touching when one of its contact points
//! comes within [`CollisionWorld::touch_distance`](crate::CollisionWorld::touch_distance) of
//! overlap, *persists* while it stays so, and *ends* when none does (or a collider goes away).
//! Speculative contacts of a pair that is still apart do not count as touching.
//!
//! The events are recorded after each update, pending ones (a pair forgotten) first, then one
//! per touching (or just parted) pair in slot order. A pair the narrow phase passed by rests
//! as it did: its event is the last one carried on (began → persisted, ended → none). When
//! the narrow phase listed the pairs it looked at, only those are read; the others' events
//! are merged in from the last update's, so a sleeping pile beside a moving body costs a copy
//! of its events, not a visit to its pairs.

use crate::collider::ColliderHandle;
use crate::collision_world::{handle_of, CollisionWorld};
use kea::World;

/// What happened to a pair this step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ContactEventKind {
    /// The pair started touching this step.
    Began,
    /// The pair was touching last step and still is.
    Persisted,
    /// The pair stopped touching this step.
    Ended,
}

/// One event of the last contact update.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactEvent {
    /// What happened.
    pub kind: ContactEventKind,
    /// The two colliders, in slot order.
    pub colliders: [ColliderHandle; 2],
}

/// What the recorded events need to be merged with the next update's (`record_events`):
/// each pair event's slot, and the buffers the next list is built in.
#[derive(Debug, Default)]
pub(crate) struct EventRecord {
    /// Per event after the first `pending` of `CollisionWorld::events`: its pair's slot.
    slots: Vec<u32>,
    /// Events at the head of the list that are no pair's (pending ones: a pair forgotten).
    pending: usize,
    /// `slots` and `pending` describe `CollisionWorld::events` (not after a restore).
    kept: bool,
    /// Every pair event persisted: none began or ended.
    steady: bool,
    spare_events: Vec<ContactEvent>,
    spare_slots: Vec<u32>,
    /// The visited pairs' events of an update, before they are merged in.
    fresh: Vec<(u32, Option<ContactEvent>)>,
}

impl Clone for EventRecord {
    fn clone(&self) -> Self {
        let mut out = Self::default();
        out.clone_from(self);
        out
    }

    /// Into this one's own buffers (a batch's worker copies states in at every step).
    fn clone_from(&mut self, o: &Self) {
        self.slots.clone_from(&o.slots);
        self.pending = o.pending;
        self.kept = o.kept;
        self.steady = o.steady;
        self.spare_events.clear();
        self.spare_events.reserve(o.spare_events.capacity());
        self.spare_slots.clear();
        self.spare_slots.reserve(o.spare_slots.capacity());
        self.fresh.clear();
        self.fresh.reserve(o.fresh.capacity());
    }
}

impl EventRecord {
    /// Room for `events` events.
    pub(crate) fn reserve(&mut self, events: usize) {
        for v in [&mut self.slots, &mut self.spare_slots] {
            v.reserve(events.saturating_sub(v.len()));
        }
        self.spare_events.reserve(events);
        self.fresh.reserve(events);
    }

    /// The events no longer match the record (they were cleared).
    pub(crate) fn forget(&mut self) {
        self.kept = false;
    }
}

impl CollisionWorld {
    /// Destroys the manifolds no longer generated, and records the pairs' events (`listed`:
    /// only the pairs in `visited_pairs` may have changed; module docs).
    pub(crate) fn record_events(&mut self, world: &mut World, quiet: bool, listed: bool) {
        // A quiet update after a quiet one: every pair rests as it did, touching as it
        // did, so the events are the last update's (each touching pair persisting).
        let same = quiet && self.events_quiet && self.pending_events.is_empty();
        self.events_quiet = quiet && self.pending_events.is_empty();
        if same {
            return;
        }
        if listed && self.event_record.kept {
            self.merge_events(world);
        } else {
            self.rebuild_events(world);
        }
        self.pairs.clear_removed();
    }

    /// Every live pair's event, read from the pairs.
    fn rebuild_events(&mut self, world: &mut World) {
        self.events.clear();
        self.event_record.slots.clear();
        self.event_record.pending = self.pending_events.len();
        self.events.append(&mut self.pending_events);
        let mut steady = true;
        for slot in 0..self.pairs.slots.len() as u32 {
            if let Some(event) = self.pair_event(world, slot) {
                steady &= event.kind == ContactEventKind::Persisted;
                self.events.push(event);
                self.event_record.slots.push(slot);
            }
        }
        let r = &mut self.event_record;
        (r.kept, r.steady) = (true, steady);
    }

    /// The visited pairs' events read from the pairs, the others' carried on from the last
    /// update's list, in slot order: what `rebuild_events` would make.
    fn merge_events(&mut self, world: &mut World) {
        // The visited pairs' events first, read from the pairs.
        let visited = std::mem::take(&mut self.visited_pairs);
        let mut fresh = std::mem::take(&mut self.event_record.fresh);
        fresh.clear();
        for &slot in &visited {
            fresh.push((slot, self.pair_event(world, slot)));
        }
        let mut removed = std::mem::take(&mut self.pairs.removed);
        removed.sort_unstable();
        let r = &mut self.event_record;
        // Last update's pair events all persisted and no pair went: the runs between the
        // visited pairs are copied whole, and if the visited pairs' events are as they were
        // (a pair that does not touch, or touches on) the list is.
        let whole = r.steady && removed.is_empty();
        let unchanged = whole
            && r.pending == 0
            && self.pending_events.is_empty()
            && fresh.iter().all(
                |&(slot, event)| match (r.slots.binary_search(&slot), event) {
                    (Ok(k), Some(e)) => self.events[k] == e,
                    (Err(_), None) => true,
                    _ => false,
                },
            );
        if !unchanged {
            self.merge_fresh(&fresh, whole, &removed);
        }
        self.event_record.fresh = fresh;
        self.visited_pairs = visited;
        self.pairs.removed = removed;
    }

    /// The new list: pending events, then the visited pairs' `fresh` events merged in slot
    /// order with the others' carried on (`whole`: copied as they are).
    fn merge_fresh(&mut self, fresh: &[(u32, Option<ContactEvent>)], whole: bool, removed: &[u32]) {
        let r = &mut self.event_record;
        let mut events = std::mem::take(&mut r.spare_events);
        let mut slots = std::mem::take(&mut r.spare_slots);
        events.clear();
        slots.clear();
        let pending = self.pending_events.len();
        events.append(&mut self.pending_events);
        let old_pair_events = &self.events[r.pending..];
        let old_slots = &r.slots;
        // Carried-on events all persist: the list is steady if the visited pairs' do.
        let mut steady = true;
        let mut i = 0;
        for &(slot, event) in fresh.iter().chain(std::iter::once(&(u32::MAX, None))) {
            let end = i + old_slots[i..].partition_point(|&s| s < slot);
            let run = (&old_pair_events[i..end], &old_slots[i..end]);
            carry_on(run, whole, removed, (&mut events, &mut slots));
            i = end + usize::from(old_slots.get(end) == Some(&slot));
            if let Some(event) = event {
                steady &= event.kind == ContactEventKind::Persisted;
                events.push(event);
                slots.push(slot);
            }
        }
        let old_events = std::mem::replace(&mut self.events, events);
        let old_slots = std::mem::replace(&mut r.slots, slots);
        (r.spare_events, r.spare_slots) = (old_events, old_slots);
        (r.pending, r.steady) = (pending, steady);
    }

    /// Pair `slot`'s event this update, if it is live: a pair the narrow phase looked at
    /// loses the manifolds it did not generate again.
    fn pair_event(&mut self, world: &mut World, slot: u32) -> Option<ContactEvent> {
        let p = &mut self.pairs.slots[slot as usize];
        if !p.alive {
            return None;
        }
        if !p.resting {
            p.manifolds.retain(|m| {
                if !m.seen {
                    let _ = world.destroy_constraint(m.handle); // may be gone with its body
                }
                m.seen
            });
        }
        // A resting pair touches as it did (the narrow phase passed it by).
        let now = if p.resting {
            p.touching
        } else {
            p.touching_now
        };
        let kind = match (p.touching, now) {
            (false, true) => ContactEventKind::Began,
            (true, true) => ContactEventKind::Persisted,
            (true, false) => ContactEventKind::Ended,
            (false, false) => return None,
        };
        p.touching = now;
        let (a, b) = p.colliders;
        let colliders = [handle_of(&self.slots, a), handle_of(&self.slots, b)];
        Some(ContactEvent { kind, colliders })
    }
}

/// Carries the events of pairs the narrow phase passed by into the next list: each still
/// touching, so persisting (one that began last update persists now, one that ended is
/// gone), but for pairs removed since. `whole`: every event persisted and none went, so the
/// run is copied as it is.
fn carry_on(
    (events, slots): (&[ContactEvent], &[u32]),
    whole: bool,
    removed: &[u32],
    (into_events, into_slots): (&mut Vec<ContactEvent>, &mut Vec<u32>),
) {
    if whole {
        into_events.extend_from_slice(events);
        into_slots.extend_from_slice(slots);
        return;
    }
    for (e, &slot) in events.iter().zip(slots) {
        if e.kind != ContactEventKind::Ended && removed.binary_search(&slot).is_err() {
            into_events.push(ContactEvent {
                kind: ContactEventKind::Persisted,
                colliders: e.colliders,
            });
            into_slots.push(slot);
        }
    }
}
