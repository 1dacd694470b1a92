//! Which enabled constraints touch each body: a list per body slot, threaded through two
//! links per constraint slot (one per side), kept in step with the dense index of
//! constraints' bodies (`constraint_index.rs`) at every change of a constraint. A step reads
//! the constraints of its awake bodies from it (`World::list_awake_constraints`), so that the
//! passes over constraints — the sleep grouping, the reduced path's search, the gather — visit
//! only those an awake body has: a sleeping pile beside a moving body costs nothing per
//! contact. Box2D v3 threads the same lists through its bodies' contact and joint edges.
//!
//! Changing a list is O(1) (`crate::edge_lists`); a step's listing is O(awake bodies'
//! constraints), sorted so that every pass visits them in the order a scan of every
//! slot would, and its results are the scan's, bit for bit.

use super::constraint_index::EMPTY;
use super::World;

use crate::edge_lists::EdgeLists;

/// The enabled constraints of every body slot (items: constraint slots; ends: a
/// constraint's two sides in the index).
#[derive(Debug, Default)]
pub(crate) struct BodyConstraints {
    lists: EdgeLists,
}

impl Clone for BodyConstraints {
    fn clone(&self) -> Self {
        Self {
            lists: self.lists.clone(),
        }
    }

    /// Into this one's own buffers (a batch's worker copies states in at every step).
    fn clone_from(&mut self, o: &Self) {
        self.lists.clone_from(&o.lists);
    }
}

/// Whether an index entry's side is a body (not the static world, not an empty slot).
fn is_body(x: u32) -> bool {
    x < EMPTY
}

impl BodyConstraints {
    /// Room for `bodies` bodies and `constraints` constraints before anything allocates.
    pub(crate) fn with_capacity(bodies: usize, constraints: usize) -> Self {
        Self {
            lists: EdgeLists::with_capacity(bodies, constraints),
        }
    }

    /// Room for `bodies` bodies and `constraints` constraints in all.
    pub(crate) fn reserve(&mut self, bodies: usize, constraints: usize) {
        self.lists.reserve(bodies, constraints);
    }

    /// Forgets every edge.
    #[cfg(feature = "serde")]
    pub(crate) fn clear(&mut self) {
        self.lists.clear();
    }

    /// Moves constraint slot `slot` from the bodies of index entry `old` to those of `new`.
    pub(crate) fn relink(&mut self, slot: usize, old: [u32; 2], new: [u32; 2]) {
        if old == new {
            return;
        }
        for (side, body) in old.into_iter().enumerate() {
            if is_body(body) {
                self.lists.unlink(slot as u32, side, body);
            }
        }
        for (side, body) in new.into_iter().enumerate() {
            if is_body(body) {
                self.lists.link(slot as u32, side, body);
            }
        }
    }

    /// How many enabled constraints touch body slot `body` (a side each).
    pub(crate) fn degree(&self, body: u32) -> u32 {
        self.lists.degree(body)
    }

    /// The edges of body slot `body`: (constraint slot, side).
    pub(crate) fn edges(&self, body: u32) -> impl Iterator<Item = (u32, usize)> + '_ {
        self.lists.edges(body)
    }
}

/// The slots a pass visits: those of `list` when `listed`, else every one below `all`.
pub(super) fn visited(listed: bool, list: &[u32], all: usize) -> impl Iterator<Item = usize> + '_ {
    let list = if listed { list } else { &[] };
    let all = if listed { 0 } else { all };
    list.iter().map(|&slot| slot as usize).chain(0..all)
}

/// A step's listing is worth it only while the awake bodies' edges are this share of the
/// slots or fewer: past it, sorting them costs about what scanning every slot does.
const LIST_SHARE: usize = 4;

impl World {
    /// Lists, ascending, the slots of the enabled constraints with a body in the awake set
    /// (after `AwakeSet::refresh`), for the passes of this step that visit only those
    /// (`StepScratch::awake_constraints`). Lists nothing, and says so, when the awake bodies'
    /// constraints are so many of the slots that scanning every slot is as cheap.
    pub(super) fn list_awake_constraints(&mut self) {
        let s = &mut self.scratch;
        s.awake_constraints.clear();
        s.awake_constraints_listed = false;
        let slots = self.constraint_bodies.len();
        let awake = self.awake.slots();
        let mut edges = 0usize;
        for &b in awake {
            edges += self.body_constraints.degree(b) as usize;
            if edges * LIST_SHARE > slots {
                return;
            }
        }
        for &b in awake {
            for (slot, side) in self.body_constraints.edges(b) {
                let other = self.constraint_bodies[slot as usize][1 - side];
                // Each constraint once: from its lower awake side (side 0 of one that has a
                // body on both sides).
                let twice = is_body(other) && self.awake.is_awake(other);
                if twice && (other < b || (other == b && side == 1)) {
                    continue;
                }
                s.awake_constraints.push(slot);
            }
        }
        s.awake_constraints.sort_unstable();
        s.awake_constraints_listed = true;
        debug_assert!(
            self.awake_constraints_agree(),
            "the body-to-constraint lists disagree with the constraint index"
        );
    }

    /// Whether the listing is what a scan of every slot finds (debug builds check it).
    fn awake_constraints_agree(&self) -> bool {
        let awake = |x: u32| is_body(x) && self.awake.is_awake(x);
        let scanned = (0..self.constraint_bodies.len() as u32).filter(|&slot| {
            let [a, b] = self.constraint_bodies[slot as usize];
            a != EMPTY && (awake(a) || awake(b))
        });
        scanned.eq(self.scratch.awake_constraints.iter().copied())
    }
}
