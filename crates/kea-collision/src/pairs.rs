//! The pairs of colliders whose fat boxes overlap, kept from step to step: each with the Kea
//! contacts its manifolds became and what is needed to update them cheaply.
//!
//! Pairs live in slots (reused after removal, so a warm world allocates nothing) and are
//! visited in slot order, which depends only on the order in which pairs were found:
//! deterministic. A hash map finds a pair by its two collider slots when the broad phase
//! reports it again.

use crate::capacity::reserve_total;
use crate::parry::math::Pose;
use kea::{ConstraintHandle, Vec3};
use smallvec::SmallVec;
use std::collections::HashMap;

/// One point of a manifold as generated, in each collider's own frame.
#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct CachedPoint {
    pub local_a: Vec3,
    pub local_b: Vec3,
    /// The point relative to each collider's origin, world frame, as generated: the lever
    /// arms frozen while the manifold is reused.
    pub arms: [Vec3; 2],
    pub id: u32,
}

/// A manifold as generated (reduced), in the colliders' own frames: enough to move it with the
/// colliders while they barely move relative to each other (the manifold cache).
#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct ManifoldCache {
    /// Sub-shapes (triangles of a mesh or height field; 0 otherwise).
    pub sub: (u32, u32),
    /// The normal in the world frame as generated, from the first collider to the second
    /// (frozen while reused).
    pub normal: Vec3,
    pub points: [CachedPoint; kea::MAX_CONTACT_POINTS],
    pub count: u8,
}

/// One manifold of a pair and the Kea contact it became.
#[derive(Debug, Clone, Copy)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct PairManifold {
    pub cache: ManifoldCache,
    pub handle: ConstraintHandle,
    /// Generated again (or kept) this step.
    pub seen: bool,
}

/// A pair of colliders whose fat boxes overlap.
#[derive(Debug, Default, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct PairState {
    /// Collider slots, first < second.
    pub colliders: (u32, u32),
    /// Its manifolds: one inline (a pair of convex shapes has one), more on the heap (a shape
    /// against a mesh, a compound): a pair that starts touching allocates nothing.
    pub manifolds: SmallVec<[PairManifold; 1]>,
    /// The colliders' poses when the manifolds were generated.
    pub generated_at: Option<Generated>,
    /// Touching last step, and this step.
    pub touching: bool,
    pub touching_now: bool,
    /// The first collider's body is body 2 of the pair's contacts (it is static).
    pub flipped: bool,
    /// Neither collider could move this step: its contacts were left as they are.
    pub resting: bool,
    pub alive: bool,
    /// The pair's contact parameters and fixed friction direction, for material table
    /// revision `params_revision` (`u64::MAX`: not yet).
    pub params: kea::ContactParams,
    pub direction: Option<Vec3>,
    pub params_revision: u64,
    /// Most points per manifold for this pair's materials (0: the world's strategy).
    #[cfg_attr(feature = "serde", serde(default))]
    pub max_points: u8,
    /// The slot was made with room for several manifolds, or its pair once held more than
    /// one: a freed slot goes back to the list of such slots. Kept as state, not read from
    /// the heap room (which a clone or a snapshot does not carry), so that a copied world
    /// reuses the same slots as the original and steps on the same bits.
    #[cfg_attr(feature = "serde", serde(default))]
    pub roomy: bool,
}

impl PairState {
    /// Adds a manifold, marking the slot roomy once it holds more than one.
    pub(crate) fn push_manifold(&mut self, m: PairManifold) {
        self.manifolds.push(m);
        self.roomy |= self.manifolds.len() > 1;
    }
}

/// Manifolds a pre-made multi-manifold slot has room for.
const MULTI_MANIFOLDS: usize = 16;

/// The live pairs (module docs).
#[derive(Debug, Default, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Pairs {
    pub slots: Vec<PairState>,
    /// Free slots whose manifolds are inline, and those that keep heap room for several: a
    /// pair that may have several manifolds takes one of the latter first, so that pairs
    /// coming and going in a warm world stop allocating once every slot has the room its
    /// kind of pair needs.
    free: Vec<u32>,
    free_spilled: Vec<u32>,
    #[cfg_attr(feature = "serde", serde(with = "crate::snapshot::pair_map"))]
    map: HashMap<(u32, u32), u32>,
    /// Each collider's live pairs (items: pair slots; ends: first and second collider),
    /// while `by_collider_kept`: made on first use (`Pairs::of_collider`), not saved.
    #[cfg_attr(feature = "serde", serde(skip))]
    by_collider: kea::edge_lists::EdgeLists,
    #[cfg_attr(feature = "serde", serde(skip))]
    by_collider_kept: bool,
    /// Slots of the pairs removed since the events were last recorded (`events.rs`).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub removed: Vec<u32>,
}

impl Pairs {
    /// Reserves room for `n` pairs.
    pub(crate) fn reserve(&mut self, n: usize) {
        reserve_total(&mut self.slots, n);
        reserve_total(&mut self.free, n);
        reserve_total(&mut self.free_spilled, n);
        if self.map.capacity() < n {
            self.map.reserve(n - self.map.len());
        }
    }

    /// Reserves room in each collider's list of pairs for `colliders` colliders and
    /// `pairs` pairs.
    pub(crate) fn reserve_lists(&mut self, colliders: usize, pairs: usize) {
        self.by_collider.reserve(colliders, pairs);
        reserve_total(&mut self.removed, pairs);
    }

    /// Forgets the pairs removed so far (their events are recorded).
    pub(crate) fn clear_removed(&mut self) {
        self.removed.clear();
    }

    /// Makes `n` free slots with heap room for [`MULTI_MANIFOLDS`] manifolds each, for pairs
    /// that may have several (a compound's, a mesh's).
    pub(crate) fn reserve_multi(&mut self, n: usize) {
        for _ in 0..n {
            let mut p = PairState {
                roomy: true,
                ..PairState::default()
            };
            p.manifolds.reserve_exact(MULTI_MANIFOLDS);
            self.free_spilled.push(self.slots.len() as u32);
            self.slots.push(p);
        }
    }

    /// The slot of the pair of colliders `key` (first < second), if it is live.
    pub(crate) fn find(&self, key: (u32, u32)) -> Option<u32> {
        self.map.get(&key).copied()
    }

    /// Adds the pair `key` (`multi`: a compound or mesh pair, which may have several
    /// manifolds); returns its slot.
    pub(crate) fn insert(&mut self, key: (u32, u32), multi: bool) -> u32 {
        let reused = if multi {
            self.free_spilled.pop().or_else(|| self.free.pop())
        } else {
            self.free.pop().or_else(|| self.free_spilled.pop())
        };
        let slot = match reused {
            Some(s) => s,
            None => {
                self.slots.push(PairState::default());
                (self.slots.len() - 1) as u32
            }
        };
        let p = &mut self.slots[slot as usize];
        p.colliders = key;
        p.manifolds.clear();
        p.generated_at = None;
        p.touching = false;
        p.touching_now = false;
        p.flipped = false;
        p.resting = false;
        p.alive = true;
        p.params_revision = u64::MAX;
        self.map.insert(key, slot);
        if self.by_collider_kept {
            self.by_collider.link(slot, 0, key.0);
            self.by_collider.link(slot, 1, key.1);
        }
        slot
    }

    /// Removes the pair in `slot` (its contacts must already be gone).
    pub(crate) fn remove(&mut self, slot: u32) {
        let p = &mut self.slots[slot as usize];
        if !p.alive {
            return;
        }
        p.alive = false;
        p.manifolds.clear();
        // A dead slot's flags as a new pair's: nothing reads them, and no update writes
        // them, so that worlds that went different ways to the same pairs hold the same.
        p.resting = false;
        p.touching = false;
        p.touching_now = false;
        self.map.remove(&p.colliders);
        self.removed.push(slot);
        if self.by_collider_kept {
            self.by_collider.unlink(slot, 0, p.colliders.0);
            self.by_collider.unlink(slot, 1, p.colliders.1);
        }
        if p.roomy {
            self.free_spilled.push(slot);
        } else {
            self.free.push(slot);
        }
    }

    /// Live pairs with their slots, in slot order.
    pub(crate) fn live(&self) -> impl Iterator<Item = (u32, &PairState)> {
        self.slots
            .iter()
            .enumerate()
            .filter(|(_, p)| p.alive)
            .map(|(i, p)| (i as u32, p))
    }

    /// Number of live pairs.
    pub(crate) fn len(&self) -> usize {
        self.map.len()
    }

    /// The slots of collider slot `collider`'s live pairs, in no set order (the lists are
    /// made from the live pairs on first use, then kept as pairs come and go).
    pub(crate) fn of_collider(&mut self, collider: u32) -> impl Iterator<Item = u32> + '_ {
        if !self.by_collider_kept {
            self.by_collider.clear();
            for (slot, p) in self.slots.iter().enumerate() {
                if p.alive {
                    self.by_collider.link(slot as u32, 0, p.colliders.0);
                    self.by_collider.link(slot as u32, 1, p.colliders.1);
                }
            }
            self.by_collider_kept = true;
        }
        self.by_collider.edges(collider).map(|(slot, _)| slot)
    }
}

/// The colliders' world poses when a pair's manifolds were generated, and the second's pose
/// in the first's frame then.
#[derive(Debug, Clone, Copy)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Generated {
    #[cfg_attr(feature = "serde", serde(with = "crate::snapshot::pose"))]
    pub a: Pose,
    #[cfg_attr(feature = "serde", serde(with = "crate::snapshot::pose"))]
    pub b: Pose,
    #[cfg_attr(feature = "serde", serde(with = "crate::snapshot::pose"))]
    pub relative: Pose,
}

impl Generated {
    pub(crate) fn new(a: Pose, b: Pose) -> Self {
        Self {
            a,
            b,
            relative: a.inv_mul(&b),
        }
    }
}

impl Pairs {
    /// Asks for the pairs' cache lines (`CollisionWorld::prefetch`).
    pub(crate) fn prefetch(&self) {
        kea::prefetch::slice(&self.slots);
    }

    /// Becomes a copy of `other`, reusing this one's buffers (`state_copy.rs`).
    pub(crate) fn copy_from(&mut self, other: &Self) {
        self.slots.clone_from(&other.slots);
        self.free.clone_from(&other.free);
        self.free_spilled.clone_from(&other.free_spilled);
        self.map.clone_from(&other.map);
        self.by_collider.clone_from(&other.by_collider);
        self.by_collider_kept = other.by_collider_kept;
        self.removed.clone_from(&other.removed);
    }
}
