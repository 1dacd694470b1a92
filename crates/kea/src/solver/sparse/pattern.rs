//! The block structure of an island's exact system: which constraint blocks couple (they share a
//! dynamic body), the order in which the factorisation eliminates them, and which blocks of the
//! factor are non-zero.
//!
//! The unknowns come in blocks, one per constraint (a joint's rows, a contact's rows), and two
//! blocks couple exactly when they share a dynamic body, so the system `J M⁻¹ Jᵀ` is a sparse
//! matrix of dense blocks. The order is a minimum-degree one on that block graph, each block
//! weighted by its rows: it eliminates a tree (chain, ragdoll, vehicle) from its leaves and so
//! creates no fill at all, and keeps fill low in graphs with loops. Computing it is the symbolic
//! analysis; [`PatternCache`] keeps the last few so an island whose graph did not change reuses
//! its analysis.

// Dense kernels over row and block indices read clearest as index loops.
#![allow(clippy::needless_range_loop)]

/// One block of an island's system as the analysis sees it: the dynamic bodies it touches, as
/// island-local body numbers (`u32::MAX` for none).
pub(crate) type BlockBodies = [u32; 2];

/// The analysis of one block graph.
#[derive(Debug, Default, Clone)]
pub(crate) struct Pattern {
    /// The graph it analyses and its blocks' row counts (the elimination's weights), for
    /// cache hits: an order depends on both, so that a cached one is the order a fresh
    /// analysis would give (a restored snapshot, whose cache starts empty, steps the same).
    key: Vec<BlockBodies>,
    rows: Vec<u32>,
    /// Elimination position → block.
    pub(crate) order: Vec<u32>,
    /// `later[later_start[k]..later_start[k + 1]]`: positions, ascending, of the blocks below
    /// position `k`'s pivot in the factor (its neighbours still present when it is eliminated).
    later_start: Vec<u32>,
    later: Vec<u32>,
    /// For each position `k`, in the order [`Pattern::updates`] gives them, the slot that each
    /// pair `(a, b)`, `b ≤ a`, of its later blocks updates.
    update_start: Vec<u32>,
    update_slots: Vec<u32>,
}

impl Pattern {
    /// Block count.
    pub(crate) fn len(&self) -> usize {
        self.order.len()
    }

    /// The later blocks of position `k` (positions, ascending). Their slots are
    /// `off_slot(k, i)` for `i` in `0..later(k).len()`.
    pub(crate) fn later(&self, k: usize) -> &[u32] {
        &self.later[self.later_start[k] as usize..self.later_start[k + 1] as usize]
    }

    /// Total slots: one diagonal block per position, then one per `later` entry.
    pub(crate) fn slot_count(&self) -> usize {
        self.len() + self.later.len()
    }

    /// The slot of the `i`-th later block of position `k`.
    pub(crate) fn off_slot(&self, k: usize, i: usize) -> usize {
        self.len() + self.later_start[k] as usize + i
    }

    /// The slot of the block at positions `(a, b)`, `a ≥ b`, if the factor holds one.
    pub(crate) fn slot(&self, a: usize, b: usize) -> Option<usize> {
        if a == b {
            return Some(a);
        }
        let (a, b) = if a > b { (a, b) } else { (b, a) };
        let later = self.later(b);
        later
            .binary_search(&(a as u32))
            .ok()
            .map(|i| self.off_slot(b, i))
    }

    /// The slots that eliminating position `k` updates, pair by pair: for `ia` over its later
    /// blocks and `ib ≤ ia`, in that order.
    pub(crate) fn updates(&self, k: usize) -> &[u32] {
        &self.update_slots[self.update_start[k] as usize..self.update_start[k + 1] as usize]
    }

    /// Whether the analysis is of graph `key` with blocks of `rows` rows.
    fn is_for(&self, key: &[BlockBodies], rows: &[u32]) -> bool {
        self.key == key && self.rows == rows
    }
}

/// Scratch for the minimum-degree elimination.
#[derive(Debug, Default, Clone)]
struct Elimination {
    /// Each block's current neighbours (block ids, ascending).
    adjacency: Vec<Vec<u32>>,
    /// Blocks touching each body (local ids).
    body_blocks: Vec<Vec<u32>>,
    eliminated: Vec<bool>,
    /// Each block's degree, weighted by the neighbours' rows.
    score: Vec<u64>,
    merged: Vec<u32>,
    position: Vec<u32>,
    /// Neighbour lists at elimination, block ids, by position.
    later_blocks: Vec<u32>,
}

/// The last few analyses, most recently used first.
#[derive(Debug, Default, Clone)]
pub(crate) struct PatternCache {
    patterns: Vec<Pattern>,
    elimination: Elimination,
    /// Analyses run (not found in the cache) since creation.
    pub(crate) analyses: u64,
}

/// Analyses kept: enough for the exact islands of a scene to keep theirs from step to step.
const CACHED_PATTERNS: usize = 16;

impl PatternCache {
    /// The analysis [`PatternCache::get`] gave last.
    pub(crate) fn current(&self) -> &Pattern {
        &self.patterns[0]
    }

    /// The analysis of the island whose blocks touch `key` (one entry per block) and have
    /// `rows[i]` rows each, from the cache or computed now. `bodies` is the island's body count.
    pub(crate) fn get(&mut self, key: &[BlockBodies], rows: &[u32], bodies: usize) -> &Pattern {
        if let Some(i) = self.patterns.iter().position(|p| p.is_for(key, rows)) {
            // Most recently used first.
            self.patterns[..=i].rotate_right(1);
            return &self.patterns[0];
        }
        self.analyses += 1;
        if self.patterns.len() < CACHED_PATTERNS {
            self.patterns.push(Pattern::default());
        }
        // Reuse the least recently used one's memory.
        self.patterns.rotate_right(1);
        let p = &mut self.patterns[0];
        self.elimination.analyse(key, rows, bodies, p);
        &self.patterns[0]
    }
}

impl Elimination {
    /// Minimum-degree elimination of the block graph `key` (rows per block as weights) into `p`.
    fn analyse(&mut self, key: &[BlockBodies], rows: &[u32], bodies: usize, p: &mut Pattern) {
        let n = key.len();
        p.key.clear();
        p.key.extend_from_slice(key);
        p.rows.clear();
        p.rows.extend_from_slice(rows);
        self.build_graph(key, bodies);
        self.eliminated.clear();
        self.eliminated.resize(n, false);
        self.score.clear();
        for k in 0..n {
            let s = self.adjacency[k]
                .iter()
                .map(|&q| u64::from(rows[q as usize]))
                .sum();
            self.score.push(s);
        }
        p.order.clear();
        p.later_start.clear();
        p.later_start.push(0);
        self.later_blocks.clear();
        for _ in 0..n {
            // The live block of least weighted degree, the lowest id on a tie: deterministic.
            let mut best = usize::MAX;
            for k in 0..n {
                if !self.eliminated[k] && (best == usize::MAX || self.score[k] < self.score[best]) {
                    best = k;
                }
            }
            self.eliminate(best, rows);
            p.order.push(best as u32);
            self.later_blocks.extend_from_slice(&self.adjacency[best]);
            p.later_start.push(self.later_blocks.len() as u32);
        }
        self.position.clear();
        self.position.resize(n, 0);
        for (k, &b) in p.order.iter().enumerate() {
            self.position[b as usize] = k as u32;
        }
        // Later lists as sorted positions.
        p.later.clear();
        for k in 0..n {
            let range = p.later_start[k] as usize..p.later_start[k + 1] as usize;
            let start = p.later.len();
            p.later.extend(
                self.later_blocks[range]
                    .iter()
                    .map(|&b| self.position[b as usize]),
            );
            p.later[start..].sort_unstable();
        }
        p.update_start.clear();
        p.update_slots.clear();
        p.update_start.push(0);
        let mut slots = std::mem::take(&mut p.update_slots);
        for k in 0..n {
            let later = p.later(k);
            for ia in 0..later.len() {
                for ib in 0..=ia {
                    let slot = p
                        .slot(later[ia] as usize, later[ib] as usize)
                        .expect("the fill of an elimination is in its pattern");
                    slots.push(slot as u32);
                }
            }
            p.update_start.push(slots.len() as u32);
        }
        p.update_slots = slots;
    }

    /// Adjacency of blocks that share a body.
    fn build_graph(&mut self, key: &[BlockBodies], bodies: usize) {
        let n = key.len();
        grow_lists(&mut self.body_blocks, bodies);
        grow_lists(&mut self.adjacency, n);
        for (k, pair) in key.iter().enumerate() {
            for &b in pair {
                if b != u32::MAX {
                    self.body_blocks[b as usize].push(k as u32);
                }
            }
        }
        for list in &self.body_blocks[..bodies] {
            for &a in list {
                for &b in list {
                    if a != b {
                        self.adjacency[a as usize].push(b);
                    }
                }
            }
        }
        for list in &mut self.adjacency[..n] {
            list.sort_unstable();
            list.dedup();
        }
    }

    /// Removes block `p` from the graph, joining its neighbours into a clique.
    fn eliminate(&mut self, p: usize, rows: &[u32]) {
        self.eliminated[p] = true;
        let neighbours = std::mem::take(&mut self.adjacency[p]);
        for &q in &neighbours {
            let q = q as usize;
            // adjacency[q] ← (adjacency[q] ∪ neighbours) ∖ {p, q}
            self.merged.clear();
            let (mut i, mut j) = (0, 0);
            let a = &self.adjacency[q];
            while i < a.len() || j < neighbours.len() {
                let next = match (a.get(i), neighbours.get(j)) {
                    (Some(&x), Some(&y)) if x == y => {
                        i += 1;
                        j += 1;
                        x
                    }
                    (Some(&x), Some(&y)) if x < y => {
                        i += 1;
                        x
                    }
                    (Some(&x), None) => {
                        i += 1;
                        x
                    }
                    (_, Some(&y)) => {
                        j += 1;
                        y
                    }
                    (None, None) => unreachable!(),
                };
                if next as usize != p && next as usize != q {
                    self.merged.push(next);
                }
            }
            let list = &mut self.adjacency[q];
            list.clear();
            list.extend_from_slice(&self.merged);
            self.score[q] = list.iter().map(|&r| u64::from(rows[r as usize])).sum();
        }
        self.adjacency[p] = neighbours;
    }
}

/// Makes `lists` hold at least `n` lists and empties the first `n` (keeping their memory).
fn grow_lists(lists: &mut Vec<Vec<u32>>, n: usize) {
    if lists.len() < n {
        lists.resize_with(n, Vec::new);
    }
    for l in &mut lists[..n] {
        l.clear();
    }
}
