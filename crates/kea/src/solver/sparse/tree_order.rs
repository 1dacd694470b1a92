//! The tree solve's analysis: an island whose constraint blocks join its bodies without a loop,
//! laid out once for a factorisation with no fill (Baraff's observation for the maximal
//! coordinate system, here on the constraint side, `A = J M⁻¹ Jᵀ`).
//!
//! Nodes. The blocks that act on the same pair of bodies (a joint and its limit, the contact
//! manifolds between two boxes of a stack) are one node; blocks on one body alone (a joint to
//! the world, a box's contact with the ground) are one node per body. Two nodes couple in `A`
//! when they share a body, so each body's nodes form a clique.
//!
//! Order. The body graph is walked depth-first from its lowest body; each body's nodes other
//! than the one it was reached by are its *children*, and every node is eliminated after the
//! nodes below it (post-order). When a node is eliminated, its neighbours still in the system
//! are its later siblings and its body's parent node, which already couple to each other: the
//! factor has no fill, and `L` has a block only where `A` has one. A chain is block
//! tridiagonal; a ragdoll's torso is one small clique.
//!
//! Each position keeps its off-diagonal blocks (targets ascending, the first one its parent in
//! the elimination tree) and, for the left-looking factorisation, the lists of earlier blocks
//! whose products update its diagonal and each of its off-diagonal blocks. A changed position
//! changes only its ancestors in the elimination tree: a limit that engages refactorises the
//! branch from it to the root, not the island.

/// No body, no node, no position.
pub(crate) const NONE: u32 = u32::MAX;

/// Most rows in one node: a box resting on another with four contact points and their
/// friction has 12; more, and the island takes the general system.
const MAX_NODE_ROWS: usize = 24;

/// Most nodes on one body: a body's nodes form a dense clique in the factor (its cost grows
/// with the square of their number); past this, the general system's ordering does better.
const MAX_NODES_PER_BODY: usize = 16;

/// The analysis (module docs), kept while the island's blocks and their sizes are unchanged.
#[derive(Debug, Default, Clone)]
pub(crate) struct TreeOrder {
    /// What was analysed: the blocks' bodies and sizes, and the number of bodies.
    key: Vec<[u32; 2]>,
    sizes: Vec<u32>,
    bodies: usize,
    /// Whether the blocks form a forest the tree solve takes.
    pub(crate) ok: bool,
    /// Per position: its first row (in position order; `positions + 1` entries), its first
    /// value (the diagonal block, then the off-diagonal blocks), its first off-diagonal block
    /// and first diagonal update (both `positions + 1` entries), and its elimination parent.
    pub(crate) row_start: Vec<u32>,
    pub(crate) value_start: Vec<u32>,
    pub(crate) off_start: Vec<u32>,
    pub(crate) diag_update_start: Vec<u32>,
    pub(crate) parent: Vec<u32>,
    /// Per off-diagonal block `L_tk`: its target position `t`, source position `k`, first
    /// value, the shared body's slot in the source's node and in the target's, and its first
    /// pair update (`blocks + 1` entries).
    pub(crate) off_target: Vec<u32>,
    pub(crate) off_source: Vec<u32>,
    pub(crate) off_value: Vec<u32>,
    pub(crate) off_slots: Vec<[u8; 2]>,
    pub(crate) pair_update_start: Vec<u32>,
    /// Updates: the blocks `L_kc` whose `L_kc L_kcᵀ` a diagonal loses, and the pairs
    /// `(L_tc, L_kc)` whose `L_tc L_kcᵀ` an off-diagonal block `L_tk` loses.
    pub(crate) diag_update: Vec<u32>,
    pub(crate) pair_update: Vec<[u32; 2]>,
    /// Per position: its node's bodies (island-local; [`NONE`] for none).
    pub(crate) position_bodies: Vec<[u32; 2]>,
    /// Per row in position order: the caller's row, its position, and whether its block names
    /// the node's bodies the other way round.
    pub(crate) row_of: Vec<u32>,
    pub(crate) row_position: Vec<u32>,
    pub(crate) row_swapped: Vec<bool>,
    /// Per caller row: its row in position order.
    pub(crate) position_of_row: Vec<u32>,
    /// Values the factor holds.
    pub(crate) values: usize,
    scratch: Scratch,
}

/// The analysis's working memory, kept so that a repeated analysis allocates nothing.
#[derive(Debug, Default, Clone)]
struct Scratch {
    node_of_block: Vec<u32>,
    block_swapped: Vec<bool>,
    node_bodies: Vec<[u32; 2]>,
    node_rows: Vec<u32>,
    node_row_start: Vec<u32>,
    node_fill: Vec<u32>,
    body_start: Vec<u32>,
    body_nodes: Vec<u32>,
    body_fill: Vec<u32>,
    parent_node: Vec<u32>,
    home: Vec<u32>,
    visited: Vec<bool>,
    stack: Vec<(u32, u32)>,
    order: Vec<u32>,
    position_of_node: Vec<u32>,
    count: Vec<u32>,
}

impl TreeOrder {
    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        let s = &self.scratch;
        4 * (self.key.capacity() * 2
            + self.sizes.capacity()
            + self.row_start.capacity()
            + self.value_start.capacity()
            + self.off_start.capacity()
            + self.diag_update_start.capacity()
            + self.parent.capacity()
            + self.off_target.capacity()
            + self.off_source.capacity()
            + self.off_value.capacity()
            + self.pair_update_start.capacity()
            + self.diag_update.capacity()
            + self.pair_update.capacity() * 2
            + self.position_bodies.capacity() * 2
            + self.row_of.capacity()
            + self.row_position.capacity()
            + self.position_of_row.capacity()
            + s.node_of_block.capacity()
            + s.node_bodies.capacity() * 2
            + s.node_rows.capacity()
            + s.node_row_start.capacity()
            + s.node_fill.capacity()
            + s.body_start.capacity()
            + s.body_nodes.capacity()
            + s.body_fill.capacity()
            + s.parent_node.capacity()
            + s.home.capacity()
            + s.stack.capacity() * 2
            + s.order.capacity()
            + s.position_of_node.capacity()
            + s.count.capacity())
            + self.off_slots.capacity() * 2
            + self.row_swapped.capacity()
            + s.block_swapped.capacity()
            + s.visited.capacity()
    }

    /// Analyses the blocks (`key`: each block's island-local bodies, [`NONE`] for none; rows
    /// `first..first + size`), or keeps the last analysis if they are the same. Returns
    /// whether the tree solve takes them.
    pub(crate) fn analyse(
        &mut self,
        key: &[[u32; 2]],
        first: &[u32],
        size: &[u32],
        bodies: usize,
    ) -> bool {
        if self.bodies == bodies && self.key == key && self.sizes == size {
            return self.ok;
        }
        self.key.clear();
        self.key.extend_from_slice(key);
        self.sizes.clear();
        self.sizes.extend_from_slice(size);
        self.bodies = bodies;
        self.ok = self.make_nodes(key, first, size, bodies)
            && self.walk(bodies)
            && self.lay_out()
            && {
                self.list_updates();
                true
            };
        self.ok
    }

    /// Merges the blocks into nodes by body pair and lists each body's nodes; false if a node
    /// or a body has more than the tree solve takes.
    fn make_nodes(&mut self, key: &[[u32; 2]], first: &[u32], size: &[u32], bodies: usize) -> bool {
        let s = &mut self.scratch;
        s.node_of_block.clear();
        s.block_swapped.clear();
        s.node_bodies.clear();
        // Per body, its nodes as a linked list while merging (`body_fill` the heads,
        // `node_fill` the next node per node slot).
        s.body_fill.clear();
        s.body_fill.resize(bodies, NONE);
        s.node_fill.clear();
        for &[x, y] in key {
            let (pair, swapped) = match (x == NONE, y == NONE) {
                (false, false) => ([x.min(y), x.max(y)], x > y),
                (false, true) => ([x, NONE], false),
                (true, false) => ([y, NONE], true),
                (true, true) => ([NONE, NONE], false),
            };
            let mut node = NONE;
            if pair[0] != NONE {
                let mut at = s.body_fill[pair[0] as usize];
                while at != NONE {
                    if s.node_bodies[at as usize] == pair {
                        node = at;
                        break;
                    }
                    let slot = usize::from(s.node_bodies[at as usize][0] != pair[0]);
                    at = s.node_fill[2 * at as usize + slot];
                }
            }
            if node == NONE {
                node = s.node_bodies.len() as u32;
                s.node_bodies.push(pair);
                s.node_fill.extend([NONE, NONE]);
                for (slot, &b) in pair.iter().enumerate() {
                    if b != NONE {
                        s.node_fill[2 * node as usize + slot] = s.body_fill[b as usize];
                        s.body_fill[b as usize] = node;
                    }
                }
            }
            s.node_of_block.push(node);
            s.block_swapped.push(swapped);
        }
        // Each node's rows, block by block.
        let nodes = s.node_bodies.len();
        s.node_row_start.clear();
        s.node_row_start.resize(nodes + 1, 0);
        for (b, &node) in s.node_of_block.iter().enumerate() {
            s.node_row_start[node as usize + 1] += size[b];
        }
        for n in 0..nodes {
            if s.node_row_start[n + 1] as usize > MAX_NODE_ROWS {
                return false;
            }
            s.node_row_start[n + 1] += s.node_row_start[n];
        }
        s.count.clear();
        s.count.extend_from_slice(&s.node_row_start[..nodes]);
        s.node_rows.clear();
        s.node_rows.resize(s.node_row_start[nodes] as usize, 0);
        for (b, &node) in s.node_of_block.iter().enumerate() {
            for r in first[b]..first[b] + size[b] {
                let at = &mut s.count[node as usize];
                // Rows of a swapped block are marked by the top bit.
                s.node_rows[*at as usize] = r | (u32::from(s.block_swapped[b]) << 31);
                *at += 1;
            }
        }
        // Each body's nodes, in node order.
        s.body_start.clear();
        s.body_start.resize(bodies + 1, 0);
        for pair in &s.node_bodies {
            for &b in pair.iter().filter(|&&b| b != NONE) {
                s.body_start[b as usize + 1] += 1;
            }
        }
        for b in 0..bodies {
            if s.body_start[b + 1] as usize > MAX_NODES_PER_BODY {
                return false;
            }
            s.body_start[b + 1] += s.body_start[b];
        }
        s.body_fill.clear();
        s.body_fill.extend_from_slice(&s.body_start[..bodies]);
        s.body_nodes.clear();
        s.body_nodes.resize(s.body_start[bodies] as usize, 0);
        for (n, pair) in s.node_bodies.iter().enumerate() {
            for &b in pair.iter().filter(|&&b| b != NONE) {
                let at = &mut s.body_fill[b as usize];
                s.body_nodes[*at as usize] = n as u32;
                *at += 1;
            }
        }
        true
    }

    /// Walks the body graph depth-first, lowest body first, putting the nodes in post-order;
    /// false on a loop.
    fn walk(&mut self, bodies: usize) -> bool {
        let s = &mut self.scratch;
        let nodes = s.node_bodies.len();
        s.parent_node.clear();
        s.parent_node.resize(bodies, NONE);
        s.home.clear();
        s.home.resize(nodes, NONE);
        s.visited.clear();
        s.visited.resize(bodies, false);
        s.order.clear();
        for root in 0..bodies {
            if s.visited[root] {
                continue;
            }
            s.visited[root] = true;
            s.stack.clear();
            s.stack.push((root as u32, s.body_start[root]));
            while let Some(&mut (body, ref mut next)) = s.stack.last_mut() {
                let b = body as usize;
                if *next == s.body_start[b + 1] {
                    s.stack.pop();
                    if s.parent_node[b] != NONE {
                        s.order.push(s.parent_node[b]);
                    }
                    continue;
                }
                let node = s.body_nodes[*next as usize];
                *next += 1;
                if node == s.parent_node[b] {
                    continue;
                }
                s.home[node as usize] = body;
                let pair = s.node_bodies[node as usize];
                let other = if pair[0] == body { pair[1] } else { pair[0] };
                if other == NONE {
                    s.order.push(node);
                } else if s.visited[other as usize] {
                    return false;
                } else {
                    s.visited[other as usize] = true;
                    s.parent_node[other as usize] = node;
                    s.stack.push((other, s.body_start[other as usize]));
                }
            }
        }
        // Nodes on no body stand alone, after the rest.
        for n in 0..nodes {
            if s.node_bodies[n] == [NONE, NONE] {
                s.order.push(n as u32);
            }
        }
        debug_assert_eq!(s.order.len(), nodes);
        true
    }

    /// Positions, rows, values and off-diagonal blocks in elimination order.
    fn lay_out(&mut self) -> bool {
        let s = &mut self.scratch;
        let positions = s.order.len();
        s.position_of_node.clear();
        s.position_of_node.resize(positions, 0);
        for (k, &n) in s.order.iter().enumerate() {
            s.position_of_node[n as usize] = k as u32;
        }
        for v in [
            &mut self.row_start,
            &mut self.value_start,
            &mut self.off_start,
            &mut self.parent,
            &mut self.off_target,
            &mut self.off_source,
            &mut self.off_value,
            &mut self.row_of,
            &mut self.row_position,
            &mut self.position_of_row,
        ] {
            v.clear();
        }
        self.position_bodies.clear();
        self.off_slots.clear();
        self.row_swapped.clear();
        let rows = s.node_row_start[positions] as usize;
        self.position_of_row.resize(rows, 0);
        let size_of = |s: &Scratch, n: u32| s.node_row_start[n as usize + 1] - s.node_row_start[n as usize];
        let mut value = 0u32;
        for (k, &n) in s.order.iter().enumerate() {
            let (r0, r1) = (s.node_row_start[n as usize], s.node_row_start[n as usize + 1]);
            self.row_start.push(self.row_of.len() as u32);
            for &r in &s.node_rows[r0 as usize..r1 as usize] {
                let caller = r & !(1 << 31);
                self.position_of_row[caller as usize] = self.row_of.len() as u32;
                self.row_of.push(caller);
                self.row_position.push(k as u32);
                self.row_swapped.push(r >> 31 != 0);
            }
            let rk = r1 - r0;
            self.position_bodies.push(s.node_bodies[n as usize]);
            self.value_start.push(value);
            value += rk * rk;
            self.off_start.push(self.off_target.len() as u32);
            let home = s.home[n as usize];
            if home == NONE {
                self.parent.push(NONE);
                continue;
            }
            // Later siblings at the home body, then the body's parent node.
            let slot_at = |pair: [u32; 2]| u8::from(pair[0] != home);
            let (b0, b1) = (s.body_start[home as usize], s.body_start[home as usize + 1]);
            let siblings = &s.body_nodes[b0 as usize..b1 as usize];
            let after = siblings.iter().position(|&m| m == n).map_or(0, |p| p + 1);
            let parent_node = s.parent_node[home as usize];
            for &t in siblings[after..]
                .iter()
                .filter(|&&m| m != parent_node)
                .chain((parent_node != NONE).then_some(&parent_node))
            {
                let tk = s.position_of_node[t as usize];
                self.off_target.push(tk);
                self.off_source.push(k as u32);
                self.off_value.push(value);
                self.off_slots.push([
                    slot_at(s.node_bodies[n as usize]),
                    slot_at(s.node_bodies[t as usize]),
                ]);
                value += size_of(s, t) * rk;
            }
            let first = self.off_start[k] as usize;
            self.parent.push(self.off_target.get(first).copied().unwrap_or(NONE));
            if self.off_target[first..].windows(2).any(|w| w[0] >= w[1])
                || self.off_target[first..].iter().any(|&t| t as usize <= k)
            {
                debug_assert!(false, "off-diagonal targets out of order");
                return false;
            }
        }
        self.row_start.push(rows as u32);
        self.off_start.push(self.off_target.len() as u32);
        self.values = value as usize;
        true
    }

    /// The left-looking factorisation's update lists (module docs).
    fn list_updates(&mut self) {
        let positions = self.parent.len();
        let blocks = self.off_target.len();
        let count = &mut self.scratch.count;
        // Diagonal updates, by destination position.
        count.clear();
        count.resize(positions + 1, 0);
        for &t in &self.off_target {
            count[t as usize + 1] += 1;
        }
        for k in 0..positions {
            count[k + 1] += count[k];
        }
        self.diag_update_start.clear();
        self.diag_update_start.extend_from_slice(count);
        self.diag_update.clear();
        self.diag_update.resize(blocks, 0);
        for (q, &t) in self.off_target.iter().enumerate() {
            let at = &mut count[t as usize];
            self.diag_update[*at as usize] = q as u32;
            *at += 1;
        }
        // Pair updates, by destination block: source c's blocks to s < t update block (s → t).
        let find = |me: &Self, s: u32, t: u32| -> u32 {
            let (a, b) = (me.off_start[s as usize], me.off_start[s as usize + 1]);
            (a..b)
                .find(|&q| me.off_target[q as usize] == t)
                .expect("siblings and the parent node couple")
        };
        count.clear();
        count.resize(blocks + 1, 0);
        for c in 0..positions {
            let (a, b) = (self.off_start[c], self.off_start[c + 1]);
            for i in a..b {
                for j in i + 1..b {
                    let dest = find(self, self.off_target[i as usize], self.off_target[j as usize]);
                    self.scratch.count[dest as usize + 1] += 1;
                }
            }
        }
        let count = &mut self.scratch.count;
        for q in 0..blocks {
            count[q + 1] += count[q];
        }
        self.pair_update_start.clear();
        self.pair_update_start.extend_from_slice(count);
        self.pair_update.clear();
        self.pair_update
            .resize(self.pair_update_start[blocks] as usize, [0, 0]);
        for c in 0..positions {
            let (a, b) = (self.off_start[c], self.off_start[c + 1]);
            for i in a..b {
                for j in i + 1..b {
                    let dest = find(self, self.off_target[i as usize], self.off_target[j as usize]);
                    let at = &mut self.scratch.count[dest as usize];
                    self.pair_update[*at as usize] = [j, i];
                    *at += 1;
                }
            }
        }
    }

    /// Positions (nodes) in the analysis.
    pub(crate) fn positions(&self) -> usize {
        self.parent.len()
    }

    /// Rows of position `k`: first (in position order) and count.
    pub(crate) fn rows(&self, k: usize) -> (usize, usize) {
        let a = self.row_start[k] as usize;
        (a, self.row_start[k + 1] as usize - a)
    }

    /// Off-diagonal blocks of position `k`.
    pub(crate) fn blocks(&self, k: usize) -> std::ops::Range<usize> {
        self.off_start[k] as usize..self.off_start[k + 1] as usize
    }
}
