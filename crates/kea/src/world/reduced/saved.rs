//! Kept trees in a snapshot (feature `serde`): a restored world steps its trees on the same
//! bits as the world it was taken of, so their coordinates, rates and geometry travel with it.
//! Drives are not saved: every step reads them from the joints again.

use super::{CachedTree, LinkPlan, Mark, FREE_ROOT};
use crate::articulation::{TreeJointKind, TreeLink};
use crate::error::{KeaError, KeaResult};
use crate::world::constraint_entry::ConstraintKind;
use crate::world::World;
use glam::{DMat3, DQuat, DVec3};
use serde::{Deserialize, Serialize};

/// A kept tree as a snapshot holds it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(crate) struct SavedTree {
    base_joint: u32,
    links: Vec<SavedLink>,
    q: Vec<f64>,
    qd: Vec<f64>,
    marks: Vec<Mark>,
    /// Tree links past each plan entry's first (a planar joint's second travel and turn), in
    /// tree order, with their plan entry (absent in older snapshots, which kept no planar
    /// tree).
    #[serde(default)]
    more: Vec<(usize, SavedGeometry)>,
}

/// A tree link's own geometry.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct SavedGeometry {
    slider: bool,
    origin: (DVec3, DQuat),
    axis: DVec3,
    anchor: DVec3,
    mass: f64,
    inertia: DMat3,
}

impl SavedGeometry {
    fn of(l: &TreeLink) -> Self {
        Self {
            slider: l.kind == TreeJointKind::Slider,
            origin: l.origin,
            axis: l.axis,
            anchor: l.anchor,
            mass: l.mass,
            inertia: l.inertia,
        }
    }

    fn link(&self, parent: Option<usize>) -> TreeLink {
        TreeLink {
            parent,
            kind: if self.slider {
                TreeJointKind::Slider
            } else {
                TreeJointKind::Hinge
            },
            origin: self.origin,
            axis: self.axis,
            anchor: self.anchor,
            mass: self.mass,
            com: DVec3::ZERO,
            inertia: self.inertia,
            ..TreeLink::default()
        }
    }

    fn valid(&self, massless: bool) -> bool {
        self.origin.0.is_finite()
            && self.origin.1.is_finite()
            && (self.axis.length() - 1.0).abs() < 1e-6
            && self.anchor.is_finite()
            && self.mass.is_finite()
            && (self.mass > 0.0 || (massless && self.mass == 0.0))
            && self.inertia.is_finite()
    }
}

/// One link: its plan and its geometry in the tree.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct SavedLink {
    plan: LinkPlan,
    slider: bool,
    origin: (DVec3, DQuat),
    axis: DVec3,
    anchor: DVec3,
    mass: f64,
    inertia: DMat3,
}

impl SavedLink {
    /// A plan entry and its first tree link's geometry (the format keeps them side by side).
    fn new(plan: LinkPlan, g: SavedGeometry) -> Self {
        let SavedGeometry {
            slider,
            origin,
            axis,
            anchor,
            mass,
            inertia,
        } = g;
        Self {
            plan,
            slider,
            origin,
            axis,
            anchor,
            mass,
            inertia,
        }
    }

    fn geometry(&self) -> SavedGeometry {
        SavedGeometry {
            slider: self.slider,
            origin: self.origin,
            axis: self.axis,
            anchor: self.anchor,
            mass: self.mass,
            inertia: self.inertia,
        }
    }
}

impl World {
    /// The kept trees that the next step would step again.
    pub(crate) fn saved_trees(&self) -> Vec<SavedTree> {
        let r = &self.scratch.reduced;
        r.trees
            .iter()
            .filter(|t| t.revision == self.joint_revision && t.marks.len() == t.plan.len())
            .map(|t| SavedTree {
                base_joint: t.base_joint,
                links: t
                    .plan
                    .iter()
                    .zip(&t.first_link)
                    .map(|(p, &first)| {
                        let l = t.tree.link_geometry(first);
                        SavedLink::new(*p, SavedGeometry::of(&l))
                    })
                    .collect(),
                more: (0..t.plan.len())
                    .flat_map(|k| {
                        (t.first_link[k] + 1..=t.link_of[k])
                            .map(move |i| (k, SavedGeometry::of(&t.tree.link_geometry(i))))
                    })
                    .collect(),
                q: t.q.clone(),
                qd: t.qd.clone(),
                marks: t.marks.clone(),
            })
            .collect()
    }

    /// Keeps a snapshot's trees in a restored world, after checking that each fits it (its
    /// joints hinges or sliders between the bodies it names, parents first, numbers finite).
    pub(crate) fn restore_trees(&mut self, saved: Vec<SavedTree>) -> KeaResult<()> {
        for s in saved {
            self.check_saved(&s)
                .map_err(|reason| KeaError::Inconsistent {
                    arg: "snapshot",
                    reason: format!("reduced tree on joint slot {}: {reason}", s.base_joint),
                })?;
            // Kept trees hold no ball joint: one tree link per plan entry, a planar joint's
            // one to three.
            let mut tree = CachedTree::default();
            let mut links = Vec::with_capacity(s.q.len());
            let mut more = s.more.iter().peekable();
            for (k, l) in s.links.iter().enumerate() {
                tree.first_link.push(links.len());
                let first = l.geometry();
                let parent = l.plan.parent.map(|p| tree.link_of[p as usize]);
                links.push(first.link(parent));
                while let Some((_, g)) = more.next_if(|(entry, _)| *entry == k) {
                    links.push(g.link(Some(links.len() - 1)));
                }
                tree.link_of.push(links.len() - 1);
            }
            tree.tree.refill(&links, DVec3::ZERO);
            tree.plan = s.links.iter().map(|l| l.plan).collect();
            tree.kick = vec![(DVec3::ZERO, DVec3::ZERO); s.links.len()];
            tree.base_joint = s.base_joint;
            tree.revision = self.joint_revision;
            tree.q = s.q;
            tree.qd = s.qd;
            tree.marks = s.marks;
            let r = &mut self.scratch.reduced;
            let (map, key) = if s.base_joint == FREE_ROOT {
                (&mut r.floating_of, tree.plan[0].body as usize)
            } else {
                (&mut r.tree_of, s.base_joint as usize)
            };
            if map.len() <= key {
                map.resize(key + 1, 0);
            }
            map[key] = r.trees.len() as u32;
            r.trees.push(Box::new(tree));
        }
        Ok(())
    }

    fn check_saved(&self, s: &SavedTree) -> Result<(), &'static str> {
        let n = s.links.len();
        let links = n + s.more.len();
        if n == 0 || s.q.len() != links || s.qd.len() != links || s.marks.len() != n {
            return Err("its vectors differ in length");
        }
        // A planar entry's first link is massless when more follow it; at most two follow.
        let follow = |k: usize| s.more.iter().filter(|(e, _)| *e == k).count();
        let ordered = s.more.windows(2).all(|w| w[0].0 <= w[1].0);
        let finite = ordered
            && s.q.iter().chain(&s.qd).all(|x| x.is_finite())
            && s.more.iter().all(|(k, g)| *k < n && g.valid(true))
            && s.links.iter().enumerate().all(|(k, l)| {
                let planar = l
                    .plan
                    .planar
                    .is_some_and(|m| m.iter().all(|x| x.is_finite()));
                // A floating root: three travels and three turns, the first five massless.
                let free = k == 0 && l.plan.free && s.base_joint == FREE_ROOT;
                let extra = follow(k);
                let geometry = l.geometry();
                geometry.valid(planar || free)
                    && l.plan.at.is_finite()
                    && l.plan.rate.is_finite()
                    && !l.plan.ball
                    && (l.plan.planar.is_none() || planar)
                    && l.plan.free == free
                    && match extra {
                        0 => !free,
                        5 => free,
                        _ => planar && extra <= 2,
                    }
            });
        if !finite {
            return Err("a number is not finite or out of range");
        }
        for (k, l) in s.links.iter().enumerate() {
            if l.plan.free {
                // Held by no joint: its body must be there, and nothing else is checked.
                self.bodies
                    .at(l.plan.body as usize)
                    .ok_or("a body is gone")?;
                continue;
            }
            let joint = if k == 0 { s.base_joint } else { l.plan.joint };
            let entry = self
                .constraints
                .at(joint as usize)
                .ok_or("a joint is gone")?;
            let fits = match entry.kind {
                ConstraintKind::Hinge(_) | ConstraintKind::Prismatic(_) => l.plan.planar.is_none(),
                ConstraintKind::Planar(_) => l.plan.planar.is_some(),
                _ => false,
            };
            if !fits {
                return Err("a joint is not the hinge, slider or planar joint it was");
            }
            let sides = entry.bodies.map(|h| h.map(|h| h.index()));
            let side = if l.plan.sign > 0.0 { 0 } else { 1 };
            let parent = match l.plan.parent {
                Some(p) if (p as usize) < k => Some(s.links[p as usize].plan.body),
                Some(_) => return Err("a link comes before its parent"),
                None if k == 0 => None,
                None => return Err("two links have no parent"),
            };
            let other_matches = parent.is_none() || sides[1 - side] == parent;
            if l.plan.joint != joint || sides[side] != Some(l.plan.body) || !other_matches {
                return Err("a joint does not join the bodies it names");
            }
        }
        Ok(())
    }
}
