//! Broad phase: a dynamic AABB tree of *fat* boxes (each collider's box enlarged by a margin),
//! after Box2D's `b2DynamicTree`.
//!
//! A collider's fat box changes only when its tight box (swept by its motion over the step)
//! leaves it; only those moved colliders are looked up in the tree for new pairs, so a pile at
//! rest, or asleep, costs nothing here, and colliders are inserted one by one in `O(log n)`
//! each (the first step of a big scene is `O(n log n)`). A pair found stays a pair until the
//! two fat boxes stop overlapping (checked by the pair's owner), so pairs persist from step to
//! step.
//!
//! The tree is binary; an inserted leaf goes down the side whose surface area grows least
//! (the surface area heuristic, branch and bound), and nodes are rebalanced with AVL-style
//! rotations on the way up, so its height stays logarithmic whatever the insertion order.
//! Everything is deterministic: same operations in the same order, same tree, same pairs.

use crate::capacity::reserve_total;
use kea::{Real, Vec3};

const NULL: u32 = u32::MAX;

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub(crate) fn overlaps(&self, o: &Aabb) -> bool {
        self.min.x <= o.max.x
            && o.min.x <= self.max.x
            && self.min.y <= o.max.y
            && o.min.y <= self.max.y
            && self.min.z <= o.max.z
            && o.min.z <= self.max.z
    }

    pub(crate) fn contains(&self, o: &Aabb) -> bool {
        self.min.x <= o.min.x
            && self.min.y <= o.min.y
            && self.min.z <= o.min.z
            && o.max.x <= self.max.x
            && o.max.y <= self.max.y
            && o.max.z <= self.max.z
    }

    fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// Half the surface area (the heuristic's cost).
    fn area(&self) -> Real {
        let d = self.max - self.min;
        d.x * d.y + d.y * d.z + d.z * d.x
    }

    /// The box grown by `m` on every side.
    pub(crate) fn grown(&self, m: Real) -> Aabb {
        Aabb {
            min: self.min - Vec3::splat(m),
            max: self.max + Vec3::splat(m),
        }
    }
}

#[derive(Debug, Clone, Copy)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Node {
    aabb: Aabb,
    parent: u32,
    /// Children (`NULL` for a leaf).
    left: u32,
    right: u32,
    /// Height above the leaves (0 for a leaf).
    height: u32,
    /// The collider slot of a leaf.
    item: u32,
}

impl Node {
    fn is_leaf(&self) -> bool {
        self.left == NULL
    }
}

/// The dynamic tree (module docs).
#[derive(Debug, Default, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct DynamicTree {
    nodes: Vec<Node>,
    free: Vec<u32>,
    root: u32,
    stack: Vec<u32>,
}

impl DynamicTree {
    pub(crate) fn new() -> Self {
        Self {
            root: NULL,
            ..Default::default()
        }
    }

    /// Reserves room for `leaves` leaves.
    pub(crate) fn reserve(&mut self, leaves: usize) {
        let nodes = 2 * leaves;
        reserve_total(&mut self.nodes, nodes);
        reserve_total(&mut self.free, nodes);
        reserve_total(&mut self.stack, 64);
    }

    fn allocate(&mut self, node: Node) -> u32 {
        match self.free.pop() {
            Some(i) => {
                self.nodes[i as usize] = node;
                i
            }
            None => {
                self.nodes.push(node);
                (self.nodes.len() - 1) as u32
            }
        }
    }

    /// Inserts a leaf for `item` with box `aabb`; returns the leaf's id.
    pub(crate) fn insert(&mut self, aabb: Aabb, item: u32) -> u32 {
        let leaf = self.allocate(Node {
            aabb,
            parent: NULL,
            left: NULL,
            right: NULL,
            height: 0,
            item,
        });
        self.insert_leaf(leaf);
        leaf
    }

    /// Removes leaf `leaf`.
    pub(crate) fn remove(&mut self, leaf: u32) {
        self.remove_leaf(leaf);
        self.free.push(leaf);
    }

    /// Moves leaf `leaf` to box `aabb` (remove and insert again, keeping its id).
    pub(crate) fn update(&mut self, leaf: u32, aabb: Aabb) {
        self.remove_leaf(leaf);
        self.nodes[leaf as usize].aabb = aabb;
        self.insert_leaf(leaf);
    }

    /// Calls `found(item)` for every leaf whose box overlaps `aabb`.
    pub(crate) fn query(&mut self, aabb: &Aabb, mut found: impl FnMut(u32)) {
        if self.root == NULL {
            return;
        }
        self.stack.clear();
        self.stack.push(self.root);
        while let Some(i) = self.stack.pop() {
            let n = &self.nodes[i as usize];
            if !n.aabb.overlaps(aabb) {
                continue;
            }
            if n.is_leaf() {
                found(n.item);
            } else {
                self.stack.push(n.right);
                self.stack.push(n.left);
            }
        }
    }

    fn insert_leaf(&mut self, leaf: u32) {
        if self.root == NULL {
            self.root = leaf;
            self.nodes[leaf as usize].parent = NULL;
            return;
        }
        let aabb = self.nodes[leaf as usize].aabb;
        // Find the best sibling: descend while the cost of going deeper beats stopping here.
        let mut index = self.root;
        while !self.nodes[index as usize].is_leaf() {
            let n = self.nodes[index as usize];
            let area = n.aabb.area();
            let combined = n.aabb.union(&aabb).area();
            // Cost of making a new parent here, and the inheritance pushed down otherwise.
            let cost = 2.0 * combined;
            let inherit = 2.0 * (combined - area);
            let child_cost = |c: u32, nodes: &[Node]| {
                let cn = &nodes[c as usize];
                let grown = cn.aabb.union(&aabb).area();
                if cn.is_leaf() {
                    grown + inherit
                } else {
                    grown - cn.aabb.area() + inherit
                }
            };
            let cost_left = child_cost(n.left, &self.nodes);
            let cost_right = child_cost(n.right, &self.nodes);
            if cost < cost_left && cost < cost_right {
                break;
            }
            index = if cost_left <= cost_right {
                n.left
            } else {
                n.right
            };
        }
        let sibling = index;
        let old_parent = self.nodes[sibling as usize].parent;
        let new_parent = self.allocate(Node {
            aabb: self.nodes[sibling as usize].aabb.union(&aabb),
            parent: old_parent,
            left: sibling,
            right: leaf,
            height: self.nodes[sibling as usize].height + 1,
            item: NULL,
        });
        if old_parent == NULL {
            self.root = new_parent;
        } else {
            let p = &mut self.nodes[old_parent as usize];
            if p.left == sibling {
                p.left = new_parent;
            } else {
                p.right = new_parent;
            }
        }
        self.nodes[sibling as usize].parent = new_parent;
        self.nodes[leaf as usize].parent = new_parent;
        self.refit_from(new_parent);
    }

    fn remove_leaf(&mut self, leaf: u32) {
        if leaf == self.root {
            self.root = NULL;
            return;
        }
        let parent = self.nodes[leaf as usize].parent;
        let p = self.nodes[parent as usize];
        let sibling = if p.left == leaf { p.right } else { p.left };
        let grand = p.parent;
        if grand == NULL {
            self.root = sibling;
            self.nodes[sibling as usize].parent = NULL;
        } else {
            let g = &mut self.nodes[grand as usize];
            if g.left == parent {
                g.left = sibling;
            } else {
                g.right = sibling;
            }
            self.nodes[sibling as usize].parent = grand;
            self.refit_from(grand);
        }
        self.free.push(parent);
    }

    /// Walks up from `index`, rebalancing and refitting boxes and heights.
    fn refit_from(&mut self, mut index: u32) {
        while index != NULL {
            index = self.balance(index);
            let n = self.nodes[index as usize];
            let (l, r) = (self.nodes[n.left as usize], self.nodes[n.right as usize]);
            let node = &mut self.nodes[index as usize];
            node.height = 1 + l.height.max(r.height);
            node.aabb = l.aabb.union(&r.aabb);
            index = node.parent;
        }
    }

    /// An AVL rotation at `a` if its children's heights differ by more than one; returns the
    /// node now at `a`'s place.
    fn balance(&mut self, a: u32) -> u32 {
        let na = self.nodes[a as usize];
        if na.is_leaf() || na.height < 2 {
            return a;
        }
        let (b, c) = (na.left, na.right);
        let balance = self.nodes[c as usize].height as i64 - self.nodes[b as usize].height as i64;
        if balance > 1 {
            self.rotate_up(a, c, b)
        } else if balance < -1 {
            self.rotate_up(a, b, c)
        } else {
            a
        }
    }

    /// Lifts `up` (the taller child of `a`; `other` is its sibling) above `a`.
    fn rotate_up(&mut self, a: u32, up: u32, other: u32) -> u32 {
        let nu = self.nodes[up as usize];
        let (f, g) = (nu.left, nu.right);
        let a_parent = self.nodes[a as usize].parent;
        // `up` takes `a`'s place.
        self.nodes[up as usize].parent = a_parent;
        self.nodes[a as usize].parent = up;
        if a_parent == NULL {
            self.root = up;
        } else {
            let p = &mut self.nodes[a_parent as usize];
            if p.left == a {
                p.left = up;
            } else {
                p.right = up;
            }
        }
        // The taller grandchild stays under `up`; the other goes to `a`.
        let (keep, give) = if self.nodes[f as usize].height > self.nodes[g as usize].height {
            (f, g)
        } else {
            (g, f)
        };
        {
            let nu = &mut self.nodes[up as usize];
            nu.left = a;
            nu.right = keep;
        }
        {
            let na = &mut self.nodes[a as usize];
            if na.left == up {
                na.left = give;
                na.right = other;
            } else {
                na.left = other;
                na.right = give;
            }
        }
        self.nodes[give as usize].parent = a;
        let (l, r) = (self.nodes[a as usize].left, self.nodes[a as usize].right);
        let (ln, rn) = (self.nodes[l as usize], self.nodes[r as usize]);
        {
            let na = &mut self.nodes[a as usize];
            na.aabb = ln.aabb.union(&rn.aabb);
            na.height = 1 + ln.height.max(rn.height);
        }
        let (ka, kk) = (self.nodes[a as usize], self.nodes[keep as usize]);
        let nu = &mut self.nodes[up as usize];
        nu.aabb = ka.aabb.union(&kk.aabb);
        nu.height = 1 + ka.height.max(kk.height);
        up
    }

    /// Height of the tree (0 for one leaf; for tests).
    #[cfg(test)]
    fn height(&self) -> u32 {
        if self.root == NULL {
            0
        } else {
            self.nodes[self.root as usize].height
        }
    }
}

impl DynamicTree {
    /// Asks for the nodes' cache lines (`CollisionWorld::prefetch`).
    pub(crate) fn prefetch(&self) {
        kea::prefetch::slice(&self.nodes);
    }

    /// Becomes a copy of `other`, reusing this one's buffers (`state_copy.rs`).
    pub(crate) fn copy_from(&mut self, other: &Self) {
        self.nodes.clone_from(&other.nodes);
        self.free.clone_from(&other.free);
        self.root = other.root;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(x: Real, y: Real) -> Aabb {
        Aabb {
            min: Vec3::new(x, y, 0.0),
            max: Vec3::new(x + 1.0, y + 1.0, 1.0),
        }
    }

    #[test]
    fn finds_exactly_the_overlapping_boxes_and_stays_balanced() {
        let mut t = DynamicTree::new();
        let mut leaves = Vec::new();
        // A sorted insertion order, the worst case for an unbalanced tree.
        for i in 0..1000u32 {
            leaves.push(t.insert(unit(i as Real * 1.5, 0.0), i));
        }
        assert!(t.height() <= 24, "height {}", t.height());
        let mut found = Vec::new();
        t.query(&unit(10.0 * 1.5 + 0.6, 0.0), |i| found.push(i));
        found.sort_unstable();
        assert_eq!(found, vec![10, 11]);
        // Move one far away; remove another.
        t.update(leaves[500], unit(5000.0, 5000.0));
        t.remove(leaves[11]);
        found.clear();
        t.query(&unit(10.0 * 1.5 + 0.6, 0.0), |i| found.push(i));
        assert_eq!(found, vec![10]);
        found.clear();
        t.query(&unit(5000.5, 5000.5), |i| found.push(i));
        assert_eq!(found, vec![500]);
    }
}
