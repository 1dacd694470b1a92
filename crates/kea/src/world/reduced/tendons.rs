//! Fixed tendons on the reduced path (`world/tendons.rs`): a tendon's joints must all be in
//! one tree for it to go there (its links are joined into one set, so a tendon over two
//! trees makes a set that is no tree), and each step its terms are put in the tree's
//! coordinates (`tree = sign · (joint − at)`).

use super::qualify::{tree_joint, Role};
use crate::articulation::TreeTendon;
use crate::math::wide;
use crate::world::constraint_entry::ConstraintKind;
use crate::world::constraint_index::EMPTY;
use crate::world::tendons::tendon_acts;
use crate::world::World;

impl World {
    /// Joins the links of each acting tendon's joints into one set; a tendon with a joint
    /// that cannot be a tree's blocks the links of all its joints.
    pub(super) fn group_tendon_links(&mut self) {
        for t in self.tendons.iter().flatten() {
            if !self.tendon_acts(t) {
                continue;
            }
            let r = &mut self.scratch.reduced;
            let mut first = None;
            let mut reducible = true;
            for term in &t.terms {
                let slot = term.joint.index() as usize;
                let [a, b] = self.constraint_bodies[slot];
                reducible &= a != EMPTY
                    && self.tree_joint_slots[slot]
                    && self.constraints.at(slot).is_some_and(tree_joint);
                for x in [a, b] {
                    if a != EMPTY && r.role_of(x) == Role::Link {
                        match first {
                            None => first = Some(x),
                            Some(f) => r.sets.union(f, x),
                        }
                    }
                }
            }
            if !reducible {
                for term in &t.terms {
                    let [a, b] = self.constraint_bodies[term.joint.index() as usize];
                    for x in [a, b] {
                        if a != EMPTY && r.role_of(x) == Role::Link {
                            r.role[x as usize] = Role::Blocked;
                        }
                    }
                }
            }
        }
    }

    /// Puts the tendons whose joints are all in kept tree `index` on its tree, in its
    /// coordinates, and lists them in `tendon_ids`.
    pub(super) fn tree_tendons(&mut self, index: usize) {
        let r = &mut self.scratch.reduced;
        r.tendon_ids.clear();
        r.tree_tendons.clear();
        r.tendon_terms.clear();
        let t = &mut r.trees[index];
        if self.tendons.is_empty() {
            t.tree.set_tendons(&[], &[]);
            return;
        }
        // Per joint slot: its plan entry + 1 in this tree (0: not in it).
        let slots = self.constraint_bodies.len();
        r.plan_of_joint.resize(slots, 0);
        for (k, p) in t.plan.iter().enumerate() {
            if !p.free && !p.ball {
                r.plan_of_joint[p.joint as usize] = k as u32 + 1;
            }
        }
        'tendons: for (i, tendon) in self.tendons.iter().enumerate() {
            let Some(tendon) = tendon else { continue };
            if !tendon_acts(&self.constraints, tendon) {
                continue;
            }
            let first = r.tendon_terms.len();
            let mut offset = 0.0;
            for term in &tendon.terms {
                let slot = term.joint.index() as usize;
                let Some(k) = r.plan_of_joint[slot].checked_sub(1).map(|k| k as usize) else {
                    r.tendon_terms.truncate(first);
                    continue 'tendons;
                };
                let (c, p) = (wide(term.coefficient), &t.plan[k]);
                let first_link = t.first_link[k];
                match (p.planar, self.constraints.at(slot).map(|e| &e.kind)) {
                    (Some(more), Some(ConstraintKind::Planar(_))) => {
                        let ci = term.coordinate;
                        offset += c * [p.at, more[0], more[2]][ci];
                        // A planar joint that does not turn has no tree link for its turn.
                        if first_link + ci <= t.link_of[k] {
                            r.tendon_terms.push((first_link + ci, c));
                        }
                    }
                    _ => {
                        offset += c * p.at;
                        r.tendon_terms.push((first_link, c * p.sign));
                    }
                }
            }
            let s = tendon.soft;
            r.tree_tendons.push(TreeTendon {
                first,
                count: r.tendon_terms.len() - first,
                offset,
                stiffness: wide(tendon.stiffness),
                damping: wide(tendon.damping),
                spring: (wide(tendon.spring_length[0]), wide(tendon.spring_length[1])),
                range: tendon.range.map(|[lo, hi]| (wide(lo), wide(hi))),
                soft: s,
            });
            r.tendon_ids.push(i as u32);
        }
        for p in &t.plan {
            if !p.free && !p.ball {
                r.plan_of_joint[p.joint as usize] = 0;
            }
        }
        t.tree.set_tendons(&r.tree_tendons, &r.tendon_terms);
    }

    /// Marks the tendons of the tree just stepped as the reduced path's this step.
    pub(super) fn mark_tree_tendons(&mut self) {
        let r = &self.scratch.reduced;
        let flags = &mut self.scratch.tendon_reduced;
        flags.resize(self.tendons.len(), false);
        for &i in &r.tendon_ids {
            flags[i as usize] = true;
        }
    }
}
