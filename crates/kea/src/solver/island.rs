//! Islands (the guide's partitions): bodies coupled through constraints or contacts, found with
//! union-find. Static bodies (and the world) never join an island, so a floor does not merge
//! every pile into one problem. Island ids follow the lowest body index in each island:
//! deterministic.

use super::{reserve, ConstraintBlock, SolverContact};
use crate::union_find::UnionFind;

/// Union-find with path halving over preallocated arrays.
#[derive(Debug, Default, Clone)]
pub(crate) struct Islands {
    sets: UnionFind,
    island_of_root: Vec<u32>,
    /// Island id of each body, or `u32::MAX` for a body in no constraint.
    pub(crate) body_island: Vec<u32>,
    /// Block indices sorted by island (stable: original order within an island).
    block_order: Vec<u32>,
    /// `block_order[island_start[k]..island_start[k+1]]` are island k's blocks.
    island_start: Vec<u32>,
    /// Island of each block, `u32::MAX` when it touches no dynamic body.
    pub(crate) block_island: Vec<u32>,
    /// Contact indices sorted by island, with their starts, as for blocks.
    contact_order: Vec<u32>,
    contact_start: Vec<u32>,
    /// Island of each contact, `u32::MAX` when it touches no dynamic body.
    pub(crate) contact_island: Vec<u32>,
    /// Number of bodies in each island.
    pub(crate) island_bodies: Vec<u32>,
    scratch: Vec<u32>,
}

impl Islands {
    pub(crate) fn reserve(&mut self, bodies: usize, blocks: usize, contacts: usize) {
        self.sets.reserve(bodies);
        reserve(&mut self.island_of_root, bodies);
        reserve(&mut self.body_island, bodies);
        reserve(&mut self.block_order, blocks);
        reserve(&mut self.block_island, blocks);
        reserve(&mut self.island_start, bodies + 1);
        reserve(&mut self.contact_order, contacts);
        reserve(&mut self.contact_island, contacts);
        reserve(&mut self.contact_start, bodies + 1);
        reserve(&mut self.island_bodies, bodies);
        reserve(&mut self.scratch, bodies.max(blocks).max(contacts) + 1);
    }

    pub(crate) fn bytes(&self) -> usize {
        self.sets.bytes()
            + 4 * (self.island_of_root.capacity()
                + self.body_island.capacity()
                + self.block_order.capacity()
                + self.block_island.capacity()
                + self.island_start.capacity()
                + self.contact_order.capacity()
                + self.contact_island.capacity()
                + self.contact_start.capacity()
                + self.island_bodies.capacity()
                + self.scratch.capacity())
    }

    /// Number of islands found by the last [`Islands::build`].
    pub(crate) fn count(&self) -> usize {
        self.island_start.len().saturating_sub(1)
    }

    /// Groups bodies, blocks and contacts. `dynamic(i)` says whether body i can join islands.
    #[allow(clippy::needless_range_loop)]
    pub(crate) fn build(
        &mut self,
        body_count: usize,
        dynamic: impl Fn(usize) -> bool,
        blocks: &[ConstraintBlock],
        contacts: &[SolverContact],
        partition: bool,
    ) {
        self.sets.reset(body_count);
        let dyn_body = |b: Option<u32>| b.filter(|&i| dynamic(i as usize));
        let edges = || {
            blocks
                .iter()
                .map(|b| b.bodies)
                .chain(contacts.iter().map(|c| c.bodies))
        };
        // Without partitioning (the guide's MdtDEMModeNoPartition) everything is one island.
        let mut first_dynamic = None;
        for pair in edges() {
            let (a, b) = (dyn_body(pair[0]), dyn_body(pair[1]));
            if let (Some(a), Some(b)) = (a, b) {
                self.sets.union(a, b);
            }
            if !partition {
                for x in [a, b].into_iter().flatten() {
                    let f = *first_dynamic.get_or_insert(x);
                    self.sets.union(f, x);
                }
            }
        }
        let islands = self.number_islands(body_count, &dynamic, edges());
        let island_of = |pair: [Option<u32>; 2], body_island: &[u32]| {
            pair.iter()
                .flatten()
                .find(|&&b| dynamic(b as usize))
                .map_or(u32::MAX, |&b| body_island[b as usize])
        };
        self.block_island.clear();
        for blk in blocks {
            self.block_island
                .push(island_of(blk.bodies, &self.body_island));
        }
        self.contact_island.clear();
        for c in contacts {
            self.contact_island
                .push(island_of(c.bodies, &self.body_island));
        }
        group(
            &self.block_island,
            islands as usize,
            &mut self.island_start,
            &mut self.block_order,
            &mut self.scratch,
        );
        group(
            &self.contact_island,
            islands as usize,
            &mut self.contact_start,
            &mut self.contact_order,
            &mut self.scratch,
        );
    }

    /// Numbers the islands of the bodies in at least one constraint by first appearance, and
    /// counts their bodies; returns how many there are.
    #[allow(clippy::needless_range_loop)]
    fn number_islands(
        &mut self,
        body_count: usize,
        dynamic: impl Fn(usize) -> bool,
        edges: impl Iterator<Item = [Option<u32>; 2]>,
    ) -> u32 {
        self.body_island.clear();
        self.body_island.resize(body_count, u32::MAX);
        self.island_of_root.clear();
        self.island_of_root.resize(body_count, u32::MAX);
        self.scratch.clear();
        self.scratch.resize(body_count, 0);
        for pair in edges {
            for b in pair.iter().flatten() {
                if dynamic(*b as usize) {
                    self.scratch[*b as usize] = 1;
                }
            }
        }
        let mut islands = 0u32;
        for i in 0..body_count {
            if self.scratch[i] == 0 {
                continue;
            }
            let r = self.sets.find(i as u32) as usize;
            if self.island_of_root[r] == u32::MAX {
                self.island_of_root[r] = islands;
                islands += 1;
            }
            self.body_island[i] = self.island_of_root[r];
        }
        self.island_bodies.clear();
        self.island_bodies.resize(islands as usize, 0);
        for &k in &self.body_island {
            if k != u32::MAX {
                self.island_bodies[k as usize] += 1;
            }
        }
        islands
    }

    /// The blocks of island `k`.
    pub(crate) fn blocks(&self, k: usize) -> &[u32] {
        &self.block_order[self.island_start[k] as usize..self.island_start[k + 1] as usize]
    }

    /// The contacts of island `k`.
    pub(crate) fn contacts(&self, k: usize) -> &[u32] {
        &self.contact_order[self.contact_start[k] as usize..self.contact_start[k + 1] as usize]
    }
}

/// Counting sort of items by island, stable: `order[start[k]..start[k + 1]]` are island k's.
fn group(
    island: &[u32],
    islands: usize,
    start: &mut Vec<u32>,
    order: &mut Vec<u32>,
    cursor: &mut Vec<u32>,
) {
    start.clear();
    start.resize(islands + 1, 0);
    for &k in island {
        if k != u32::MAX {
            start[k as usize + 1] += 1;
        }
    }
    for k in 0..islands {
        start[k + 1] += start[k];
    }
    order.clear();
    order.resize(start[islands] as usize, 0);
    cursor.clear();
    cursor.extend_from_slice(&start[..islands]);
    for (i, &k) in island.iter().enumerate() {
        if k != u32::MAX {
            let pos = &mut cursor[k as usize];
            order[*pos as usize] = i as u32;
            *pos += 1;
        }
    }
}
