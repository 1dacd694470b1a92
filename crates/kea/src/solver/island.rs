//! Islands (the guide's partitions): bodies coupled through constraints, found with union-find.
//! Static bodies (and the world) never join an island, so a floor does not merge every pile into
//! one problem. Island ids follow the lowest body index in each island: deterministic.

use super::{reserve, ConstraintBlock};
use crate::union_find::UnionFind;

/// Union-find with path halving over preallocated arrays.
#[derive(Debug, Default)]
pub(crate) struct Islands {
    sets: UnionFind,
    island_of_root: Vec<u32>,
    /// Island id of each body, or `u32::MAX` for a body in no constraint.
    pub(crate) body_island: Vec<u32>,
    /// Block indices sorted by island (stable: original order within an island).
    pub(crate) block_order: Vec<u32>,
    /// `block_order[island_start[k]..island_start[k+1]]` are island k's blocks.
    pub(crate) island_start: Vec<u32>,
    /// Island of each block, `u32::MAX` when it touches no dynamic body.
    pub(crate) block_island: Vec<u32>,
    /// Number of bodies in each island.
    pub(crate) island_bodies: Vec<u32>,
}

impl Islands {
    pub(crate) fn reserve(&mut self, bodies: usize, blocks: usize) {
        self.sets.reserve(bodies);
        reserve(&mut self.island_of_root, bodies);
        reserve(&mut self.body_island, bodies);
        reserve(&mut self.block_order, blocks);
        reserve(&mut self.block_island, blocks.max(bodies));
        reserve(&mut self.island_start, bodies + 1);
        reserve(&mut self.island_bodies, bodies);
    }

    pub(crate) fn bytes(&self) -> usize {
        self.sets.bytes()
            + 4 * (self.island_of_root.capacity()
                + self.body_island.capacity()
                + self.block_order.capacity()
                + self.block_island.capacity()
                + self.island_start.capacity()
                + self.island_bodies.capacity())
    }

    /// Number of islands found by the last [`Islands::build`].
    pub(crate) fn count(&self) -> usize {
        self.island_start.len().saturating_sub(1)
    }

    /// Groups bodies and blocks. `dynamic(i)` says whether body i can join islands.
    #[allow(clippy::needless_range_loop)]
    pub(crate) fn build(
        &mut self,
        body_count: usize,
        dynamic: impl Fn(usize) -> bool,
        blocks: &[ConstraintBlock],
        partition: bool,
    ) {
        self.sets.reset(body_count);
        let dyn_body = |b: Option<u32>| b.filter(|&i| dynamic(i as usize));
        // Without partitioning (the guide's MdtDEMModeNoPartition) every block joins one island.
        let mut first_dynamic = None;
        for blk in blocks {
            let (a, b) = (dyn_body(blk.bodies[0]), dyn_body(blk.bodies[1]));
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
        // Bodies in at least one block get an island, numbered by first appearance.
        self.body_island.clear();
        self.body_island.resize(body_count, u32::MAX);
        self.island_of_root.clear();
        self.island_of_root.resize(body_count, u32::MAX);
        let mut in_block = std::mem::take(&mut self.block_island);
        in_block.clear();
        in_block.resize(body_count.max(blocks.len()), 0);
        for blk in blocks {
            for b in blk.bodies.iter().flatten() {
                if dynamic(*b as usize) {
                    in_block[*b as usize] = 1;
                }
            }
        }
        let mut islands = 0u32;
        for i in 0..body_count {
            if in_block[i] == 0 {
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
        // Island of each block (u32::MAX when it touches no dynamic body).
        in_block.clear();
        for blk in blocks {
            let island = blk
                .bodies
                .iter()
                .flatten()
                .find(|&&b| dynamic(b as usize))
                .map_or(u32::MAX, |&b| self.body_island[b as usize]);
            in_block.push(island);
        }
        // Counting sort of blocks by island, stable.
        self.island_start.clear();
        self.island_start.resize(islands as usize + 1, 0);
        for &k in &in_block {
            if k != u32::MAX {
                self.island_start[k as usize + 1] += 1;
            }
        }
        for k in 0..islands as usize {
            self.island_start[k + 1] += self.island_start[k];
        }
        self.block_order.clear();
        self.block_order
            .resize(self.island_start[islands as usize] as usize, 0);
        // Use island_of_root as the running cursor per island.
        self.island_of_root.clear();
        self.island_of_root
            .extend_from_slice(&self.island_start[..islands as usize]);
        for (bi, &k) in in_block.iter().enumerate() {
            if k != u32::MAX {
                let pos = &mut self.island_of_root[k as usize];
                self.block_order[*pos as usize] = bi as u32;
                *pos += 1;
            }
        }
        self.block_island = in_block;
    }

    /// The blocks of island `k`.
    pub(crate) fn blocks(&self, k: usize) -> &[u32] {
        &self.block_order[self.island_start[k] as usize..self.island_start[k + 1] as usize]
    }
}
