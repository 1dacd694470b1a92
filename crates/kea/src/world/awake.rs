//! The awake set: the slots of the bodies a step simulates (enabled and awake), kept as
//! bodies change rather than found by a scan of every body at every step, so that a step's
//! cost follows what moves and a sleeping pile costs nothing per body.
//!
//! Every change to a body's enabled or sleeping flag, or to its applied forces, passes
//! through the world (`World::body_mut`, waking, sleeping, quarantine, creation and
//! destruction), which marks the body touched; the set takes the touched bodies in before
//! a step reads it. The set is derived from the bodies: a world restored from a snapshot
//! builds it again from them, once.

use crate::body::Body;
use crate::handle::{Arena, BodyHandle};

/// What a body slot holds, as the set last saw it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Seen {
    /// No body, or a disabled one.
    #[default]
    Out,
    /// An enabled body, awake.
    Awake,
    /// An enabled body, asleep.
    Asleep,
}

impl Seen {
    fn of(body: Option<&Body>) -> Self {
        match body {
            Some(b) if b.enabled && b.sleeping => Seen::Asleep,
            Some(b) if b.enabled => Seen::Awake,
            _ => Seen::Out,
        }
    }
}

/// The awake bodies' slots, ascending, with the bodies touched since forces were last
/// cleared.
#[derive(Debug, Default)]
pub(crate) struct AwakeSet {
    /// Slots of enabled, awake bodies, ascending (the order a step visits bodies in).
    slots: Vec<u32>,
    /// Per slot, what the set last saw there.
    seen: Vec<Seen>,
    /// Enabled bodies asleep.
    asleep: u32,
    /// Slots touched since the last step that cleared the applied forces: their flags may
    /// have changed, and they may hold forces.
    touched: Vec<u32>,
    /// Per slot, whether it is in `touched`.
    is_touched: Vec<bool>,
    /// What `touched` held when forces were last cleared (what a collision layer that
    /// updates once per step has not yet seen).
    touched_before: Vec<u32>,
    /// Steps that cleared the applied forces (completed steps).
    clears: u64,
    /// The set must be built again from the bodies (a new or restored world).
    stale: bool,
}

impl Clone for AwakeSet {
    fn clone(&self) -> Self {
        let mut out = Self::default();
        out.clone_from(self);
        out
    }

    /// Into this set's own buffers: a batch's worker copies states in at every step.
    fn clone_from(&mut self, o: &Self) {
        self.slots.clone_from(&o.slots);
        self.seen.clone_from(&o.seen);
        self.asleep = o.asleep;
        self.touched.clone_from(&o.touched);
        self.is_touched.clone_from(&o.is_touched);
        self.touched_before.clone_from(&o.touched_before);
        self.clears = o.clears;
        self.stale = o.stale;
    }
}

impl AwakeSet {
    /// A set to be built from the bodies before it is first read.
    pub(crate) fn stale() -> Self {
        Self {
            stale: true,
            ..Self::default()
        }
    }

    /// Marks body slot `slot` as possibly changed (its flags or its forces).
    pub(crate) fn touch(&mut self, slot: u32) {
        if self.stale {
            return; // everything is looked at again
        }
        let i = slot as usize;
        if self.is_touched.len() <= i {
            self.is_touched.resize(i + 1, false);
        }
        if !self.is_touched[i] {
            self.is_touched[i] = true;
            self.touched.push(slot);
        }
    }

    /// Marks `h`'s slot as possibly changed.
    pub(crate) fn touch_body(&mut self, h: BodyHandle) {
        self.touch(h.index());
    }

    /// Marks every body as possibly changed (a change to all of them at once).
    pub(crate) fn touch_all(&mut self) {
        self.stale = true;
    }

    /// Takes in the touched bodies' flags (or builds the set from every body when stale).
    pub(crate) fn refresh(&mut self, bodies: &Arena<Body, BodyHandle>) {
        if self.stale {
            self.rebuild(bodies);
            return;
        }
        for k in 0..self.touched.len() {
            let slot = self.touched[k];
            self.update(slot, Seen::of(bodies.at(slot as usize)));
        }
        #[cfg(debug_assertions)]
        if let Some(d) = self.disagreement(bodies) {
            panic!("a body changed without touching the awake set: {d}");
        }
    }

    fn rebuild(&mut self, bodies: &Arena<Body, BodyHandle>) {
        let n = bodies.slot_count();
        self.slots.clear();
        self.seen.clear();
        self.seen.resize(n, Seen::Out);
        self.asleep = 0;
        for slot in 0..n {
            let seen = Seen::of(bodies.at(slot));
            self.seen[slot] = seen;
            match seen {
                Seen::Awake => self.slots.push(slot as u32),
                Seen::Asleep => self.asleep += 1,
                Seen::Out => {}
            }
        }
        // Every body may hold forces: all are cleared at the next clearing step.
        self.touched.clear();
        self.is_touched.clear();
        self.is_touched.resize(n, true);
        self.touched.extend(0..n as u32);
        self.stale = false;
    }

    fn update(&mut self, slot: u32, now: Seen) {
        let i = slot as usize;
        if self.seen.len() <= i {
            self.seen.resize(i + 1, Seen::Out);
        }
        let was = self.seen[i];
        if was == now {
            return;
        }
        self.seen[i] = now;
        match was {
            Seen::Awake => {
                if let Ok(k) = self.slots.binary_search(&slot) {
                    self.slots.remove(k);
                }
            }
            Seen::Asleep => self.asleep -= 1,
            Seen::Out => {}
        }
        match now {
            Seen::Awake => {
                if let Err(k) = self.slots.binary_search(&slot) {
                    self.slots.insert(k, slot);
                }
            }
            Seen::Asleep => self.asleep += 1,
            Seen::Out => {}
        }
    }

    /// Slots of the enabled, awake bodies, ascending (after [`AwakeSet::refresh`]).
    pub(crate) fn slots(&self) -> &[u32] {
        &self.slots
    }

    /// Whether slot `slot` holds an enabled body, awake or asleep (after
    /// [`AwakeSet::refresh`]).
    pub(crate) fn is_enabled(&self, slot: u32) -> bool {
        self.seen
            .get(slot as usize)
            .is_some_and(|&s| s != Seen::Out)
    }

    /// Whether slot `slot` holds an enabled body awake (after [`AwakeSet::refresh`]).
    pub(crate) fn is_awake(&self, slot: u32) -> bool {
        self.seen.get(slot as usize) == Some(&Seen::Awake)
    }

    /// Whether slot `slot` holds an enabled body asleep (after [`AwakeSet::refresh`]).
    pub(crate) fn is_asleep(&self, slot: u32) -> bool {
        self.seen.get(slot as usize) == Some(&Seen::Asleep)
    }

    /// Enabled bodies asleep (after [`AwakeSet::refresh`]).
    pub(crate) fn asleep(&self) -> u32 {
        self.asleep
    }

    /// Bodies touched since forces were last cleared: the only ones, with the awake ones,
    /// that can hold applied forces.
    pub(crate) fn touched(&self) -> &[u32] {
        &self.touched
    }

    /// Forces are cleared and the touched bodies taken in ([`AwakeSet::refresh`]): the
    /// touched list starts again.
    pub(crate) fn forget_touched(&mut self) {
        for &slot in &self.touched {
            self.is_touched[slot as usize] = false;
        }
        std::mem::swap(&mut self.touched, &mut self.touched_before);
        self.touched.clear();
        self.clears += 1;
    }

    /// Steps that cleared the applied forces so far.
    pub(crate) fn clears(&self) -> u64 {
        self.clears
    }

    /// Slots of every body that may have changed since the step that made
    /// [`AwakeSet::clears`] `since` (its flags, pose, velocity or forces, or its existence):
    /// the awake bodies and those touched since. `None` when that cannot be told — more
    /// than one step since, or a set to be built again — and every body must be looked at.
    pub(crate) fn changed_since(&self, since: u64) -> Option<impl Iterator<Item = u32> + '_> {
        if self.stale || self.clears > since + 1 || self.clears < since {
            return None;
        }
        Some(
            self.slots
                .iter()
                .chain(&self.touched)
                .chain(&self.touched_before)
                .copied(),
        )
    }

    /// Where the set differs from what a scan of every body finds, if anywhere (checked in
    /// debug builds after every refresh: a change to a body that does not touch the set
    /// would show here).
    #[cfg(debug_assertions)]
    fn disagreement(&self, bodies: &Arena<Body, BodyHandle>) -> Option<String> {
        let mut asleep = 0;
        let mut awake = self.slots.iter();
        for slot in 0..bodies.slot_count() {
            let seen = Seen::of(bodies.at(slot));
            let kept = self.seen.get(slot).copied().unwrap_or_default();
            if kept != seen {
                return Some(format!("slot {slot}: kept {kept:?}, body {seen:?}"));
            }
            match seen {
                Seen::Awake if awake.next() != Some(&(slot as u32)) => {
                    return Some(format!("slot {slot} missing from {:?}", self.slots));
                }
                Seen::Asleep => asleep += 1,
                _ => {}
            }
        }
        if awake.next().is_some() || asleep != self.asleep {
            return Some(format!("{:?}, {} asleep", self.slots, self.asleep));
        }
        None
    }
}
