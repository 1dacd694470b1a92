//! Lists of the two-ended items that touch each owner — the constraints on each body, the
//! collision pairs of each collider — threaded through two links per item (one per end), so
//! that adding or removing an item is O(1) and an owner's items are found without a scan of
//! every item. Box2D v3 threads its bodies' contact and joint edges the same way; a world uses
//! these to visit only what its awake bodies touch.

/// No edge.
const NONE: u32 = u32::MAX;

/// Per owner, the edges of the items that touch it. An edge is `2 · item + end`; items and
/// owners are slot indices. Every buffer grows only when an item or owner slot past the
/// reserved room appears, so a warm world's changes allocate nothing.
#[derive(Debug, Default)]
pub struct EdgeLists {
    /// Per owner: its first edge.
    first: Vec<u32>,
    /// Per owner: how many edges it has.
    degree: Vec<u32>,
    /// Per edge: the next and the previous edge of the same owner.
    next: Vec<u32>,
    prev: Vec<u32>,
}

impl Clone for EdgeLists {
    fn clone(&self) -> Self {
        let mut out = Self::default();
        out.clone_from(self);
        out
    }

    /// Into this one's own buffers (a batch's worker copies states in at every step).
    fn clone_from(&mut self, o: &Self) {
        self.first.clone_from(&o.first);
        self.degree.clone_from(&o.degree);
        self.next.clone_from(&o.next);
        self.prev.clone_from(&o.prev);
    }
}

impl EdgeLists {
    /// Room for `owners` owners and `items` items before anything allocates.
    #[must_use]
    pub fn with_capacity(owners: usize, items: usize) -> Self {
        Self {
            first: Vec::with_capacity(owners),
            degree: Vec::with_capacity(owners),
            next: Vec::with_capacity(2 * items),
            prev: Vec::with_capacity(2 * items),
        }
    }

    /// Room for `owners` owners and `items` items in all before anything allocates.
    pub fn reserve(&mut self, owners: usize, items: usize) {
        fn total(v: &mut Vec<u32>, n: usize) {
            v.reserve(n.saturating_sub(v.len()));
        }
        total(&mut self.first, owners);
        total(&mut self.degree, owners);
        total(&mut self.next, 2 * items);
        total(&mut self.prev, 2 * items);
    }

    /// Forgets every edge, keeping the buffers.
    pub fn clear(&mut self) {
        self.first.clear();
        self.degree.clear();
        self.next.clear();
        self.prev.clear();
    }

    /// Puts end `end` (0 or 1) of item `item` in owner `owner`'s list. The end must be in
    /// no list.
    pub fn link(&mut self, item: u32, end: usize, owner: u32) {
        let edge = 2 * item as usize + end.min(1);
        if self.next.len() <= edge {
            let len = (2 * item as usize + 2).max(self.next.len());
            self.next.resize(len, NONE);
            self.prev.resize(len, NONE);
        }
        let b = owner as usize;
        if self.first.len() <= b {
            self.first.resize(b + 1, NONE);
            self.degree.resize(b + 1, 0);
        }
        let head = self.first[b];
        self.next[edge] = head;
        self.prev[edge] = NONE;
        if head != NONE {
            self.prev[head as usize] = edge as u32;
        }
        self.first[b] = edge as u32;
        self.degree[b] += 1;
    }

    /// Takes end `end` of item `item` out of owner `owner`'s list, where
    /// [`EdgeLists::link`] put it.
    pub fn unlink(&mut self, item: u32, end: usize, owner: u32) {
        let edge = 2 * item as usize + end.min(1);
        let b = owner as usize;
        debug_assert!(
            self.degree.get(b).is_some_and(|&d| d > 0),
            "an edge taken out of an owner with none"
        );
        let (prev, next) = (self.prev[edge], self.next[edge]);
        if prev == NONE {
            self.first[b] = next;
        } else {
            self.next[prev as usize] = next;
        }
        if next != NONE {
            self.prev[next as usize] = prev;
        }
        self.degree[b] -= 1;
        self.next[edge] = NONE;
        self.prev[edge] = NONE;
    }

    /// How many item ends owner `owner` has.
    #[must_use]
    pub fn degree(&self, owner: u32) -> u32 {
        self.degree.get(owner as usize).copied().unwrap_or(0)
    }

    /// Owner `owner`'s edges, most recently linked first: (item, end).
    pub fn edges(&self, owner: u32) -> impl Iterator<Item = (u32, usize)> + '_ {
        let mut e = self.first.get(owner as usize).copied().unwrap_or(NONE);
        std::iter::from_fn(move || {
            (e != NONE).then(|| {
                let edge = e;
                e = self.next[edge as usize];
                (edge / 2, (edge % 2) as usize)
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::EdgeLists;

    fn items(l: &EdgeLists, owner: u32) -> Vec<(u32, usize)> {
        let mut v: Vec<_> = l.edges(owner).collect();
        v.sort_unstable();
        v
    }

    #[test]
    fn items_are_listed_with_their_owners_until_taken_out() {
        let mut l = EdgeLists::with_capacity(2, 2);
        l.link(0, 0, 3);
        l.link(0, 1, 5);
        l.link(7, 0, 3);
        l.link(7, 1, 3); // both ends on one owner
        l.link(2, 1, 5);
        assert_eq!(items(&l, 3), [(0, 0), (7, 0), (7, 1)]);
        assert_eq!(items(&l, 5), [(0, 1), (2, 1)]);
        assert_eq!(
            (l.degree(3), l.degree(5), l.degree(4), l.degree(99)),
            (3, 2, 0, 0)
        );
        l.unlink(7, 0, 3); // from the middle
        l.unlink(0, 1, 5); // the last one linked first... and the first
        assert_eq!(items(&l, 3), [(0, 0), (7, 1)]);
        assert_eq!(items(&l, 5), [(2, 1)]);
        l.unlink(2, 1, 5);
        assert_eq!(items(&l, 5), []);
        l.link(2, 1, 5); // an end taken out goes in again
        assert_eq!(items(&l, 5), [(2, 1)]);
        let copy = l.clone();
        assert_eq!(items(&copy, 3), items(&l, 3));
        l.clear();
        assert_eq!((items(&l, 3), l.degree(3)), (vec![], 0));
    }
}
