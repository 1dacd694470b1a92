//! The colliders of each body, as an index an update uses to find the colliders of the
//! bodies that changed since the last one (`kea::World::bodies_changed_since`; see
//! `proxies.rs`).

use crate::collider::Slot;

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
