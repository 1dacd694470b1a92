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
    /// Per position, in elimination order (module docs).
    pub(crate) position: Vec<Position>,
    /// The off-diagonal blocks `L_tk`, position by position.
    pub(crate) off: Vec<OffBlock>,
    /// Updates: the blocks `L_kc` whose `L_kc L_kcᵀ` a diagonal loses, and the pairs
    /// `(L_tc, L_kc)` whose `L_tc L_kcᵀ` an off-diagonal block `L_tk` loses.
    pub(crate) diag_update: Vec<Update>,
    pub(crate) pair_update: Vec<PairUpdate>,
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

/// A position of the elimination order.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Position {
    /// First row (in position order) and rows.
    pub(crate) row: u32,
    pub(crate) size: u32,
    /// First value: the diagonal block, then the off-diagonal blocks.
    pub(crate) value: u32,
    /// Its off-diagonal blocks (`off`), and the updates of its diagonal (`diag_update`).
    pub(crate) blocks: [u32; 2],
    pub(crate) diag_updates: [u32; 2],
    /// Its parent in the elimination tree ([`NONE`]: a root).
    pub(crate) parent: u32,
}

/// An off-diagonal block `L_tk` of source position `k`, `size(t) × size(k)`.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct OffBlock {
    /// The target position `t`, its first row and rows.
    pub(crate) target: u32,
    pub(crate) target_row: u32,
    pub(crate) target_size: u32,
    /// The source position `k`.
    pub(crate) source: u32,
    /// First value.
    pub(crate) value: u32,
    /// The shared body's slot in the source's node and in the target's.
    pub(crate) slots: [u8; 2],
    /// Its pair updates (`pair_update`).
    pub(crate) pairs: [u32; 2],
}

/// A block whose product with itself a diagonal loses: its first value, columns and source
/// position.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Update {
    pub(crate) value: u32,
    pub(crate) columns: u32,
    pub(crate) source: u32,
}

/// Two blocks of one source, `L_tc` and `L_kc`, whose product `L_tc L_kcᵀ` a block `L_tk`
/// loses: their first values, their (shared) columns and the source position.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct PairUpdate {
    pub(crate) target_side: u32,
    pub(crate) source_side: u32,
    pub(crate) columns: u32,
    pub(crate) source: u32,
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
            + std::mem::size_of::<Position>() * self.position.capacity()
            + std::mem::size_of::<OffBlock>() * self.off.capacity()
            + std::mem::size_of::<Update>() * self.diag_update.capacity()
            + std::mem::size_of::<PairUpdate>() * self.pair_update.capacity()
            + self.row_swapped.capacity()
            + s.block_swapped.capacity()
            + s.visited.capacity()
    }

    /// Makes room for the analysis of systems of up to `rows` rows (as many blocks, nodes
    /// and positions at most, twice as many bodies, a few off-diagonal blocks a node).
    pub(crate) fn reserve(&mut self, rows: usize) {
        use crate::solver::reserve;
        let (n, s) = (rows, &mut self.scratch);
        for v in [
            &mut self.sizes,
            &mut self.row_of,
            &mut self.row_position,
            &mut self.position_of_row,
            &mut s.node_of_block,
            &mut s.node_rows,
            &mut s.node_row_start,
            &mut s.order,
            &mut s.position_of_node,
            &mut s.home,
        ] {
            reserve(v, n + 1);
        }
        for v in [
            &mut s.body_start,
            &mut s.body_nodes,
            &mut s.body_fill,
            &mut s.parent_node,
            &mut s.node_fill,
        ] {
            reserve(v, 2 * n + 1);
        }
        reserve(&mut s.count, 8 * n + 1);
        reserve(&mut self.key, n);
        reserve(&mut self.position_bodies, n);
        reserve(&mut self.row_swapped, n);
        reserve(&mut s.block_swapped, n);
        reserve(&mut s.node_bodies, n);
        reserve(&mut s.visited, 2 * n);
        reserve(&mut s.stack, 2 * n);
        reserve(&mut self.position, n);
        reserve(&mut self.off, 4 * n);
        reserve(&mut self.diag_update, 4 * n);
        reserve(&mut self.pair_update, 8 * n);
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
        self.ok =
            self.make_nodes(key, first, size, bodies) && self.walk(bodies) && self.lay_out() && {
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
        self.position.clear();
        self.off.clear();
        self.row_of.clear();
        self.row_position.clear();
        self.position_bodies.clear();
        self.row_swapped.clear();
        let rows = s.node_row_start[positions] as usize;
        self.position_of_row.clear();
        self.position_of_row.resize(rows, 0);
        // Each node's first row in position order, for the blocks aimed at it.
        s.count.clear();
        s.count.resize(positions, 0);
        let mut row = 0u32;
        for &n in &s.order {
            s.count[n as usize] = row;
            row += s.node_row_start[n as usize + 1] - s.node_row_start[n as usize];
        }
        let size_of =
            |s: &Scratch, n: u32| s.node_row_start[n as usize + 1] - s.node_row_start[n as usize];
        let mut value = 0u32;
        for (k, &n) in s.order.iter().enumerate() {
            let (r0, r1) = (
                s.node_row_start[n as usize],
                s.node_row_start[n as usize + 1],
            );
            let first_row = self.row_of.len() as u32;
            for &r in &s.node_rows[r0 as usize..r1 as usize] {
                let caller = r & !(1 << 31);
                self.position_of_row[caller as usize] = self.row_of.len() as u32;
                self.row_of.push(caller);
                self.row_position.push(k as u32);
                self.row_swapped.push(r >> 31 != 0);
            }
            let rk = r1 - r0;
            self.position_bodies.push(s.node_bodies[n as usize]);
            let first_block = self.off.len() as u32;
            let diagonal = value;
            value += rk * rk;
            let home = s.home[n as usize];
            if home != NONE {
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
                    let ts = size_of(s, t);
                    self.off.push(OffBlock {
                        target: s.position_of_node[t as usize],
                        target_row: s.count[t as usize],
                        target_size: ts,
                        source: k as u32,
                        value,
                        slots: [
                            slot_at(s.node_bodies[n as usize]),
                            slot_at(s.node_bodies[t as usize]),
                        ],
                        pairs: [0, 0],
                    });
                    value += ts * rk;
                }
            }
            let blocks = &self.off[first_block as usize..];
            if blocks.windows(2).any(|w| w[0].target >= w[1].target)
                || blocks.iter().any(|b| b.target as usize <= k)
            {
                debug_assert!(false, "off-diagonal targets out of order");
                return false;
            }
            self.position.push(Position {
                row: first_row,
                size: rk,
                value: diagonal,
                blocks: [first_block, self.off.len() as u32],
                diag_updates: [0, 0],
                parent: blocks.first().map_or(NONE, |b| b.target),
            });
        }
        self.values = value as usize;
        true
    }

    /// The left-looking factorisation's update lists (module docs).
    fn list_updates(&mut self) {
        let positions = self.position.len();
        // Diagonal updates, by destination position, in source order.
        let mut count = std::mem::take(&mut self.scratch.count);
        count.clear();
        count.resize(positions + 1, 0);
        for b in &self.off {
            count[b.target as usize + 1] += 1;
        }
        for k in 0..positions {
            count[k + 1] += count[k];
            self.position[k].diag_updates = [count[k], count[k + 1]];
        }
        self.diag_update.clear();
        self.diag_update.resize(self.off.len(), Update::default());
        for b in &self.off {
            let at = &mut count[b.target as usize];
            self.diag_update[*at as usize] = Update {
                value: b.value,
                columns: self.position[b.source as usize].size,
                source: b.source,
            };
            *at += 1;
        }
        // Pair updates, by destination block: source c's blocks to s < t update block (s → t).
        let find = |me: &Self, s: u32, t: u32| -> usize {
            let [a, b] = me.position[s as usize].blocks;
            (a as usize..b as usize)
                .find(|&q| me.off[q].target == t)
                .expect("siblings and the parent node couple")
        };
        let blocks = self.off.len();
        count.clear();
        count.resize(blocks + 1, 0);
        for c in 0..positions {
            let [a, b] = self.position[c].blocks.map(|x| x as usize);
            for i in a..b {
                for j in i + 1..b {
                    count[find(self, self.off[i].target, self.off[j].target) + 1] += 1;
                }
            }
        }
        for q in 0..blocks {
            count[q + 1] += count[q];
            self.off[q].pairs = [count[q], count[q + 1]];
        }
        self.pair_update.clear();
        self.pair_update
            .resize(count[blocks] as usize, PairUpdate::default());
        for c in 0..positions {
            let [a, b] = self.position[c].blocks.map(|x| x as usize);
            let columns = self.position[c].size;
            for i in a..b {
                for j in i + 1..b {
                    let dest = find(self, self.off[i].target, self.off[j].target);
                    let at = &mut count[dest];
                    self.pair_update[*at as usize] = PairUpdate {
                        target_side: self.off[j].value,
                        source_side: self.off[i].value,
                        columns,
                        source: c as u32,
                    };
                    *at += 1;
                }
            }
        }
        self.scratch.count = count;
    }

    /// The off-diagonal blocks of position `p`.
    pub(crate) fn blocks_of(&self, p: &Position) -> &[OffBlock] {
        &self.off[p.blocks[0] as usize..p.blocks[1] as usize]
    }

    /// Positions (nodes) in the analysis.
    pub(crate) fn positions(&self) -> usize {
        self.position.len()
    }
}
