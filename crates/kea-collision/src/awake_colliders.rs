//! Which colliders an update must look at: those of the bodies that may have changed since
//! the last update (`kea::World::bodies_changed_since`: the awake bodies and the ones
//! touched), found through an index from body to colliders. A collider of a body asleep or
//! disabled and untouched since is still as it was, so a sleeping pile's colliders cost an
//! update nothing.

use crate::collider::Slot;
use crate::collision_world::CollisionWorld;
use kea::World;

/// The colliders of each body slot, as offsets into one list (built again when colliders
/// are added or removed).
#[derive(Debug, Default)]
pub(crate) struct BodyColliders {
    /// Per body slot `b`, its colliders are `list[first[b]..first[b + 1]]`.
    first: Vec<u32>,
    list: Vec<u32>,
    /// Whether it matches the colliders (false after one was added or removed).
    valid: bool,
}

impl Clone for BodyColliders {
    fn clone(&self) -> Self {
        let mut out = Self::default();
        out.clone_from(self);
        out
    }

    /// Into this index's own buffers (a batch's worker copies states in at every step).
    fn clone_from(&mut self, o: &Self) {
        self.first.clone_from(&o.first);
        self.list.clone_from(&o.list);
        self.valid = o.valid;
    }
}

impl BodyColliders {
    /// The index is out of date: a collider was added or removed.
    pub(crate) fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Whether it matches the colliders.
    pub(crate) fn is_valid(&self) -> bool {
        self.valid
    }

    /// Builds the index from the collider slots.
    pub(crate) fn build(&mut self, slots: &[Slot]) {
        let body_of = |s: &Slot| s.collider.as_ref().and_then(|c| c.def.body);
        let bodies = slots
            .iter()
            .filter_map(body_of)
            .map(|b| b.index() as usize + 1)
            .max()
            .unwrap_or(0);
        self.first.clear();
        self.first.resize(bodies + 1, 0);
        for b in slots.iter().filter_map(body_of) {
            self.first[b.index() as usize + 1] += 1;
        }
        for k in 1..self.first.len() {
            self.first[k] += self.first[k - 1];
        }
        self.list.clear();
        self.list.resize(self.first[bodies] as usize, 0);
        let mut next = self.first.clone();
        for (i, b) in slots
            .iter()
            .enumerate()
            .filter_map(|(i, s)| Some((i, body_of(s)?)))
        {
            let at = &mut next[b.index() as usize];
            self.list[*at as usize] = i as u32;
            *at += 1;
        }
        self.valid = true;
    }

    /// The collider slots of body slot `b`, ascending.
    pub(crate) fn of(&self, b: u32) -> &[u32] {
        let b = b as usize;
        match (self.first.get(b), self.first.get(b + 1)) {
            (Some(&lo), Some(&hi)) => &self.list[lo as usize..hi as usize],
            _ => &[],
        }
    }
}

impl CollisionWorld {
    /// Lists in `self.changed` (ascending) the colliders this update must look at, if the
    /// world can tell which bodies changed since the last update; returns false when every
    /// collider must be looked at (the first update, colliders added or removed, a restored
    /// world, or more than one step since).
    pub(crate) fn list_changed_colliders(&mut self, world: &World) -> bool {
        if !self.by_body.is_valid() || self.still.len() != self.slots.len() {
            return false;
        }
        let Some(bodies) = self
            .bodies_seen_at
            .and_then(|since| world.bodies_changed_since(since))
        else {
            return false;
        };
        self.changed.clear();
        for b in bodies {
            self.changed.extend_from_slice(self.by_body.of(b));
        }
        self.changed.sort_unstable();
        self.changed.dedup();
        true
    }

    /// Checks (debug builds) that every collider left out of this update is still: static, or
    /// on a body asleep or disabled, and marked still.
    #[cfg(debug_assertions)]
    pub(crate) fn check_left_out(&self, world: &World) {
        for (i, s) in self.slots.iter().enumerate() {
            let Some(c) = &s.collider else { continue };
            if self.changed.binary_search(&(i as u32)).is_ok() {
                continue;
            }
            let Some(b) = c.def.body else { continue };
            let body = world.body(b).expect("a destroyed body is a changed one");
            assert!(
                (body.is_sleeping() || !body.is_enabled()) && self.still[i],
                "collider {i} left out of the update, but its body moves"
            );
        }
    }
}
