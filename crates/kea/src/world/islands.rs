//! The world's islands as lists of bodies (the guide's partitions, "lists of rigid bodies which
//! are decoupled from each other"): every enabled dynamic body belongs to exactly one island,
//! the bodies coupled to it through enabled joints and contacts; a body touching nothing is an
//! island of its own. Kinematic bodies and the world couple nothing, as in the solver, so a
//! floor or a moving platform does not merge the piles standing on it.
//!
//! The lists describe the world as it stands (the constraints it holds now, sleeping bodies
//! included), in a deterministic order: islands by their lowest body slot, bodies by slot.

use super::World;
use crate::handle::BodyHandle;
use crate::union_find::UnionFind;

/// Islands of a world, filled by [`World::islands`]. Keep one and pass it again: once it has
/// held a world's islands, refilling it allocates nothing.
#[derive(Debug, Default, Clone)]
pub struct IslandList {
    sets: UnionFind,
    /// Island of each body slot (`u32::MAX`: no enabled dynamic body there).
    island_of_slot: Vec<u32>,
    /// Every island's bodies, island after island.
    bodies: Vec<BodyHandle>,
    /// `bodies[start[k]..start[k + 1]]` are island k's.
    start: Vec<u32>,
    /// Whether every body of island k is asleep (disabled automatically).
    asleep: Vec<bool>,
    /// Scratch: each island's next free place, and the bodies' slots in list order.
    cursor: Vec<u32>,
    slots: Vec<u32>,
}

impl IslandList {
    /// Number of islands.
    #[must_use]
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// Whether there is no island (no enabled dynamic body).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The bodies of island `k` (`0..len()`), by slot; empty past the end.
    #[must_use]
    pub fn bodies(&self, k: usize) -> &[BodyHandle] {
        match (self.start.get(k), self.start.get(k + 1)) {
            (Some(&a), Some(&b)) => &self.bodies[a as usize..b as usize],
            _ => &[],
        }
    }

    /// Whether every body of island `k` is asleep (false past the end).
    #[must_use]
    pub fn is_asleep(&self, k: usize) -> bool {
        self.asleep.get(k).copied().unwrap_or(false)
    }

    /// The island holding body `h`, if `h` is an enabled dynamic body of the world these
    /// islands were taken from.
    #[must_use]
    pub fn island_of(&self, h: BodyHandle) -> Option<usize> {
        let k = *self.island_of_slot.get(h.index() as usize)?;
        // An island lists its bodies by slot: find the slot, then check it is the same body
        // (not one that took the slot over since).
        let island = self.bodies(k as usize);
        let at = island
            .binary_search_by_key(&h.index(), |b| b.index())
            .ok()?;
        (island[at] == h).then_some(k as usize)
    }

    /// Every island's bodies, in island order.
    pub fn iter(&self) -> impl Iterator<Item = &[BodyHandle]> + '_ {
        (0..self.len()).map(|k| self.bodies(k))
    }
}

impl World {
    /// Fills `out` with the world's islands as they stand now (module docs of
    /// [`IslandList`]): which bodies the solver would solve together, asleep or awake.
    pub fn islands(&self, out: &mut IslandList) {
        let n = self.bodies.slot_count();
        let couples = |slot: usize| {
            self.bodies
                .at(slot)
                .is_some_and(|b| b.enabled && !b.kinematic)
        };
        out.sets.reset(n);
        for slot in 0..self.constraints.slot_count() {
            let Some(c) = self.constraints.at(slot) else {
                continue;
            };
            if let (true, [Some(a), Some(b)]) = (c.enabled, c.bodies) {
                let (a, b) = (a.index(), b.index());
                if couples(a as usize) && couples(b as usize) {
                    out.sets.union(a, b);
                }
            }
        }
        // Roots are each set's lowest slot: numbering islands in slot order at their roots
        // numbers them by their lowest body.
        out.island_of_slot.clear();
        out.island_of_slot.resize(n, u32::MAX);
        out.start.clear();
        out.start.push(0);
        for slot in 0..n {
            if couples(slot) && out.sets.find(slot as u32) == slot as u32 {
                out.island_of_slot[slot] = (out.start.len() - 1) as u32;
                out.start.push(0);
            }
        }
        let islands = out.start.len() - 1;
        // Count, then place (a stable counting sort keeps slot order inside an island).
        for slot in 0..n {
            if couples(slot) {
                let k = out.island_of_slot[out.sets.find(slot as u32) as usize];
                out.island_of_slot[slot] = k;
                out.start[k as usize + 1] += 1;
            }
        }
        for k in 0..islands {
            out.start[k + 1] += out.start[k];
        }
        out.asleep.clear();
        out.asleep.resize(islands, true);
        // Place each body's slot at its island's cursor (slot order within an island), then
        // turn slots into handles in that order.
        out.cursor.clear();
        out.cursor.extend_from_slice(&out.start[..islands]);
        out.slots.clear();
        out.slots.resize(out.start[islands] as usize, 0);
        for slot in 0..n {
            let k = out.island_of_slot[slot];
            if k == u32::MAX {
                continue;
            }
            let pos = &mut out.cursor[k as usize];
            out.slots[*pos as usize] = slot as u32;
            *pos += 1;
            out.asleep[k as usize] &= self.bodies.at(slot).is_some_and(|b| b.sleeping);
        }
        out.bodies.clear();
        out.bodies.extend(
            out.slots
                .iter()
                .filter_map(|&slot| self.bodies.handle_at(slot as usize)),
        );
    }
}
