//! Kept trees copied or traded between worlds (`World::copy_state_from`,
//! `World::swap_state`): what a kept tree is between steps — its plan, links, coordinates,
//! rates and marks — without its step's scratch.

use super::{CachedTree, ReducedScratch};

impl ReducedScratch {
    /// Becomes `other`'s kept trees (and the caches found by joint revision, which are
    /// unique to a world's joints), reusing this scratch's trees; `workspace`: this one steps,
    /// so each tree's step scratch is sized.
    pub(in crate::world) fn copy_kept_from(&mut self, other: &ReducedScratch, workspace: bool) {
        let n = other.trees.len();
        if self.trees.len() > n {
            self.trees.truncate(n);
        }
        while self.trees.len() < n {
            self.trees.push(CachedTree::default());
        }
        for (t, o) in self.trees.iter_mut().zip(&other.trees) {
            t.copy_kept_from(o, workspace);
        }
        self.tree_of.clone_from(&other.tree_of);
        self.floating_of.clone_from(&other.floating_of);
        self.candidates = other.candidates;
        self.alone = other.alone;
    }
}

impl ReducedScratch {
    /// Trades kept trees with `other` (and the caches found by joint revision), each keeping
    /// its trees' step scratch: this one's are sized for the trees it takes.
    pub(in crate::world) fn swap_kept(&mut self, other: &mut ReducedScratch) {
        let (mine, theirs) = (self.trees.len(), other.trees.len());
        // Each side takes as many trees as the other had, from its spares first: a worker
        // keeps its trees' scratch whatever the counts of the worlds it trades with.
        for (side, want) in [(&mut *self, theirs), (&mut *other, mine)] {
            while side.trees.len() < want {
                let spare = side.spare_trees.pop().unwrap_or_default();
                side.trees.push(spare);
            }
        }
        for (t, o) in self.trees.iter_mut().zip(&mut other.trees) {
            t.swap_kept(o);
        }
        for (side, keep) in [(&mut *self, theirs), (&mut *other, mine)] {
            while side.trees.len() > keep {
                let spare = side.trees.pop().expect("more trees than kept");
                side.spare_trees.push(spare);
            }
        }
        std::mem::swap(&mut self.tree_of, &mut other.tree_of);
        std::mem::swap(&mut self.floating_of, &mut other.floating_of);
        std::mem::swap(&mut self.candidates, &mut other.candidates);
        std::mem::swap(&mut self.alone, &mut other.alone);
    }
}

impl CachedTree {
    fn swap_kept(&mut self, o: &mut CachedTree) {
        use std::mem::swap;
        swap(&mut self.base_joint, &mut o.base_joint);
        swap(&mut self.revision, &mut o.revision);
        swap(&mut self.plan, &mut o.plan);
        swap(&mut self.link_of, &mut o.link_of);
        swap(&mut self.first_link, &mut o.first_link);
        swap(&mut self.rebuilt_each_step, &mut o.rebuilt_each_step);
        swap(&mut self.kick, &mut o.kick);
        swap(&mut self.q, &mut o.q);
        swap(&mut self.qd, &mut o.qd);
        swap(&mut self.marks, &mut o.marks);
        self.stepped = false;
        o.stepped = false;
        self.tree.swap_model(&mut o.tree);
    }

    fn copy_kept_from(&mut self, o: &CachedTree, workspace: bool) {
        self.base_joint = o.base_joint;
        self.revision = o.revision;
        self.plan.clone_from(&o.plan);
        self.link_of.clone_from(&o.link_of);
        self.first_link.clone_from(&o.first_link);
        self.rebuilt_each_step = o.rebuilt_each_step;
        self.kick.clone_from(&o.kick);
        self.q.clone_from(&o.q);
        self.qd.clone_from(&o.qd);
        self.marks.clone_from(&o.marks);
        self.stepped = false;
        // A stale tree (revision 0) is built again before use: its links need not travel.
        if o.revision != 0 {
            self.tree.copy_model_from(&o.tree, workspace);
        }
    }
}

impl ReducedScratch {
    /// Asks for the cache lines of the kept trees a step reads first (`crate::prefetch`).
    pub(in crate::world) fn prefetch(&self) {
        use crate::prefetch::slice;
        slice(&self.trees);
        for t in &self.trees {
            slice(&t.plan);
            slice(&t.link_of);
            slice(&t.first_link);
            slice(&t.q);
            slice(&t.qd);
            slice(&t.q_next);
            slice(&t.qd_next);
            slice(&t.marks);
            t.tree.prefetch();
        }
        slice(&self.tree_of);
        slice(&self.reduced);
        slice(&self.tau);
    }
}
