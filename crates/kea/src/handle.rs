//! Typed generational handles and the fixed-capacity slot arena behind them.
//!
//! A handle is `(world, index, generation)`. Destroying an object bumps its slot's generation, so
//! every handle to it becomes stale; a handle from another world is rejected by its world id. The
//! arena reserves its full capacity when the world is created (the guide's `MdtWorldCreate`
//! pool), so creating and destroying objects never allocates.

use crate::error::{KeaError, KeaResult};
use std::sync::atomic::{AtomicU32, Ordering};

/// Largest capacity a world accepts for bodies or for constraints. Storage is reserved up
/// front (a constraint reserves room for six rows), so a million constraints already take
/// about a gigabyte.
pub const MAX_CAPACITY: usize = 1 << 20;

static NEXT_WORLD_ID: AtomicU32 = AtomicU32::new(1);

/// A fresh id for a new world, so handles from different worlds never mix.
pub(crate) fn next_world_id() -> u32 {
    NEXT_WORLD_ID.fetch_add(1, Ordering::Relaxed)
}

/// Keeps new worlds' ids past `id` (a world restored from a snapshot keeps its own).
#[cfg(feature = "serde")]
pub(crate) fn reserve_world_id(id: u32) {
    NEXT_WORLD_ID.fetch_max(id.saturating_add(1), Ordering::Relaxed);
}

macro_rules! define_handle {
    ($(#[$doc:meta])* $name:ident, $kind:literal) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
        pub struct $name {
            pub(crate) world: u32,
            pub(crate) index: u32,
            pub(crate) generation: u32,
        }

        impl $name {
            /// The slot index (stable while the object lives; reused after it is destroyed).
            #[must_use]
            pub fn index(self) -> u32 {
                self.index
            }
            /// The generation of the slot when the handle was made.
            #[must_use]
            pub fn generation(self) -> u32 {
                self.generation
            }
        }

        impl HandleKind for $name {
            const KIND: &'static str = $kind;
            fn parts(self) -> (u32, u32, u32) {
                (self.world, self.index, self.generation)
            }
            fn from_parts(world: u32, index: u32, generation: u32) -> Self {
                Self { world, index, generation }
            }
        }
    };
}

define_handle!(
    /// A handle to a body of a [`crate::World`] (the guide's `MdtBodyID`).
    BodyHandle,
    "body"
);
define_handle!(
    /// A handle to a constraint of a [`crate::World`]: a contact, a joint or a custom constraint
    /// (the guide's `MdtConstraintID`, `MdtContactID` and joint IDs).
    ConstraintHandle,
    "constraint"
);

/// What the arena needs from a handle type.
pub(crate) trait HandleKind: Copy {
    const KIND: &'static str;
    fn parts(self) -> (u32, u32, u32);
    fn from_parts(world: u32, index: u32, generation: u32) -> Self;
}

struct Slot<T> {
    generation: u32,
    value: Option<T>,
}

impl<T: Clone> Clone for Slot<T> {
    fn clone(&self) -> Self {
        Self {
            generation: self.generation,
            value: self.value.clone(),
        }
    }

    /// Reuses the value's own buffers (a boxed joint's box), so that copying a warm world's
    /// state into another allocates nothing.
    fn clone_from(&mut self, source: &Self) {
        self.generation = source.generation;
        self.value.clone_from(&source.value);
    }
}

/// An arena's slots and free list, as a snapshot holds them.
#[cfg(feature = "serde")]
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct ArenaState<T> {
    slots: Vec<(u32, Option<T>)>,
    free: Vec<u32>,
}

/// A slot arena with a capacity reserved up front, which doubles when full (up to
/// [`MAX_CAPACITY`]).
#[derive(Clone)]
pub(crate) struct Arena<T, H: HandleKind> {
    world: u32,
    slots: Vec<Slot<T>>,
    free: Vec<u32>,
    len: usize,
    capacity: usize,
    what: &'static str,
    _marker: std::marker::PhantomData<H>,
}

impl<T, H: HandleKind> Arena<T, H> {
    pub(crate) fn new(world: u32, capacity: usize, what: &'static str) -> Self {
        Self {
            world,
            slots: Vec::with_capacity(capacity),
            free: Vec::with_capacity(capacity),
            len: 0,
            capacity,
            what,
            _marker: std::marker::PhantomData,
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// The arena's slots (generation and value) and free list, for a snapshot.
    #[cfg(feature = "serde")]
    pub(crate) fn state(&self) -> ArenaState<T>
    where
        T: Clone,
    {
        ArenaState {
            slots: self
                .slots
                .iter()
                .map(|s| (s.generation, s.value.clone()))
                .collect(),
            free: self.free.clone(),
        }
    }

    /// An arena of `capacity` holding a snapshot's slots, checked: no more slots than the
    /// capacity, and a free list of distinct empty slots.
    #[cfg(feature = "serde")]
    pub(crate) fn from_state(
        world: u32,
        capacity: usize,
        what: &'static str,
        state: ArenaState<T>,
    ) -> KeaResult<Self> {
        let mut arena = Self::new(world, capacity, what);
        let bad = |reason: String| KeaError::Inconsistent {
            arg: "snapshot",
            reason,
        };
        if state.slots.len() > capacity {
            return Err(bad(format!(
                "{} slots of {what} for a capacity of {capacity}",
                state.slots.len()
            )));
        }
        for (generation, value) in state.slots {
            arena.len += usize::from(value.is_some());
            arena.slots.push(Slot { generation, value });
        }
        let mut seen = vec![false; arena.slots.len()];
        for &i in &state.free {
            let empty = arena
                .slots
                .get(i as usize)
                .is_some_and(|s| s.value.is_none());
            if !empty || std::mem::replace(&mut seen[i as usize], true) {
                return Err(bad(format!("free list of {what} names slot {i} wrongly")));
            }
        }
        if state.free.len() != arena.slots.len() - arena.len {
            return Err(bad(format!("free list of {what} misses empty slots")));
        }
        arena.free.extend_from_slice(&state.free);
        Ok(arena)
    }

    /// Becomes a copy of `other` (its slots, free list and capacity), reusing this arena's
    /// buffers.
    pub(crate) fn copy_from(&mut self, other: &Self)
    where
        T: Clone,
    {
        self.world = other.world;
        self.slots.clone_from(&other.slots);
        self.free.clone_from(&other.free);
        self.len = other.len;
        self.capacity = other.capacity;
    }

    /// Asks for the cache lines of the slots (`prefetch`).
    pub(crate) fn prefetch(&self) {
        crate::prefetch::slice(&self.slots);
    }

    pub(crate) fn capacity(&self) -> usize {
        self.capacity
    }

    /// Number of slots ever used: valid indices are `0..slot_count()`.
    pub(crate) fn slot_count(&self) -> usize {
        self.slots.len()
    }

    /// Grows the capacity to at least `capacity` (never past [`MAX_CAPACITY`]).
    pub(crate) fn reserve_total(&mut self, capacity: usize) {
        let capacity = capacity.min(MAX_CAPACITY);
        if capacity > self.capacity {
            self.capacity = capacity;
            self.slots
                .reserve(capacity.saturating_sub(self.slots.len()));
            self.free.reserve(capacity.saturating_sub(self.free.len()));
        }
    }

    pub(crate) fn insert(&mut self, value: T) -> KeaResult<H> {
        if self.len >= self.capacity {
            if self.capacity >= MAX_CAPACITY {
                return Err(KeaError::CapacityExceeded {
                    what: self.what,
                    capacity: self.capacity,
                });
            }
            // Full: double, so that a world sized too small keeps going (it allocates now,
            // and its step's buffers grow once at the next step).
            self.reserve_total(self.capacity.saturating_mul(2).max(1));
        }
        // Reuse the lowest freed slot last freed (LIFO): deterministic for the same call sequence.
        let index = if let Some(i) = self.free.pop() {
            let slot = &mut self.slots[i as usize];
            slot.value = Some(value);
            i
        } else {
            self.slots.push(Slot {
                generation: 0,
                value: Some(value),
            });
            (self.slots.len() - 1) as u32
        };
        self.len += 1;
        let generation = self.slots[index as usize].generation;
        Ok(H::from_parts(self.world, index, generation))
    }

    pub(crate) fn check(&self, h: H) -> KeaResult<usize> {
        let (world, index, generation) = h.parts();
        if world != self.world {
            return Err(KeaError::ForeignHandle {
                kind: H::KIND,
                index,
                generation,
                handle_world: world,
                world: self.world,
            });
        }
        match self.slots.get(index as usize) {
            Some(slot) if slot.generation == generation && slot.value.is_some() => {
                Ok(index as usize)
            }
            _ => Err(KeaError::StaleHandle {
                kind: H::KIND,
                index,
                generation,
            }),
        }
    }

    pub(crate) fn get(&self, h: H) -> KeaResult<&T> {
        let i = self.check(h)?;
        Ok(self.slots[i]
            .value
            .as_ref()
            .expect("checked slot is occupied"))
    }

    pub(crate) fn get_mut(&mut self, h: H) -> KeaResult<&mut T> {
        let i = self.check(h)?;
        Ok(self.slots[i]
            .value
            .as_mut()
            .expect("checked slot is occupied"))
    }

    pub(crate) fn remove(&mut self, h: H) -> KeaResult<T> {
        let i = self.check(h)?;
        let slot = &mut self.slots[i];
        slot.generation = slot.generation.wrapping_add(1);
        self.free.push(i as u32);
        self.len -= 1;
        Ok(slot.value.take().expect("checked slot is occupied"))
    }

    /// The value in slot `i`, if occupied.
    pub(crate) fn at(&self, i: usize) -> Option<&T> {
        self.slots.get(i).and_then(|s| s.value.as_ref())
    }

    /// The value in slot `i`, mutably, if occupied.
    pub(crate) fn at_mut(&mut self, i: usize) -> Option<&mut T> {
        self.slots.get_mut(i).and_then(|s| s.value.as_mut())
    }

    /// The handle of the object in slot `i`, if occupied.
    pub(crate) fn handle_at(&self, i: usize) -> Option<H> {
        let slot = self.slots.get(i)?;
        slot.value
            .as_ref()
            .map(|_| H::from_parts(self.world, i as u32, slot.generation))
    }

    /// Occupied slots in index order (deterministic).
    pub(crate) fn iter(&self) -> impl Iterator<Item = (H, &T)> + '_ {
        self.slots.iter().enumerate().filter_map(move |(i, s)| {
            s.value
                .as_ref()
                .map(|v| (H::from_parts(self.world, i as u32, s.generation), v))
        })
    }

    /// Slot `i`'s generation and value (`None` past the last slot): what a held world's
    /// record keeps of the slots it holds whole.
    pub(crate) fn raw_slot(&self, i: usize) -> Option<(u32, Option<&T>)> {
        self.slots.get(i).map(|s| (s.generation, s.value.as_ref()))
    }

    /// The free list, the live count and the capacity: the arena's shape beside its slots.
    pub(crate) fn shape(&self) -> (&[u32], usize, usize) {
        (&self.free, self.len, self.capacity)
    }

    /// Takes `slot_count` slots (new ones empty, later ones dropped), `free`, `len` and
    /// `capacity` from a held world's record; the caller then fills the slots that record
    /// holds (`set_raw_slot`), so that the arena is the one the record was made from.
    pub(crate) fn take_shape(
        &mut self,
        slot_count: usize,
        free: &[u32],
        len: usize,
        capacity: usize,
    ) where
        T: Clone,
    {
        self.slots.truncate(slot_count);
        while self.slots.len() < slot_count {
            self.slots.push(Slot {
                generation: 0,
                value: None,
            });
        }
        self.free.clear();
        self.free.extend_from_slice(free);
        self.len = len;
        self.capacity = capacity;
    }

    /// Puts `value` (a copy, reusing the slot's buffers) and `generation` in slot `i`, which
    /// must exist ([`Arena::take_shape`]).
    pub(crate) fn set_raw_slot(&mut self, i: usize, generation: u32, value: Option<&T>)
    where
        T: Clone,
    {
        let slot = &mut self.slots[i];
        slot.generation = generation;
        match (&mut slot.value, value) {
            (Some(mine), Some(v)) => mine.clone_from(v),
            (mine, v) => *mine = v.cloned(),
        }
    }

    /// An arena of no slots, for a world whose slots a held record keeps instead.
    pub(crate) fn emptied(&self) -> Self {
        Self::new(self.world, 0, self.what)
    }

    /// Approximate bytes reserved by the arena.
    pub(crate) fn reserved_bytes(&self) -> usize {
        self.capacity * (std::mem::size_of::<Slot<T>>() + std::mem::size_of::<u32>())
    }
}
