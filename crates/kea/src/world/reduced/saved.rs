//! Kept trees in a snapshot (feature `serde`): a restored world steps its trees on the same
//! bits as the world it was taken of, so their coordinates, rates and geometry travel with it.
//! Drives are not saved: every step reads them from the joints again.

use super::{CachedTree, LinkPlan, Mark};
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
                    .zip(t.tree.links())
                    .map(|(p, l)| SavedLink {
                        plan: *p,
                        slider: l.kind == TreeJointKind::Slider,
                        origin: l.origin,
                        axis: l.axis,
                        anchor: l.anchor,
                        mass: l.mass,
                        inertia: l.inertia,
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
            let links = s.links.iter().map(|l| TreeLink {
                parent: l.plan.parent.map(|k| k as usize),
                kind: if l.slider {
                    TreeJointKind::Slider
                } else {
                    TreeJointKind::Hinge
                },
                origin: l.origin,
                axis: l.axis,
                anchor: l.anchor,
                mass: l.mass,
                com: DVec3::ZERO,
                inertia: l.inertia,
                ..TreeLink::default()
            });
            let mut tree = CachedTree::default();
            tree.tree.refill(links, DVec3::ZERO);
            tree.plan = s.links.iter().map(|l| l.plan).collect();
            // Kept trees hold no ball joint: one tree link per plan entry.
            tree.link_of = (0..s.links.len()).collect();
            tree.first_link = (0..s.links.len()).collect();
            tree.kick = vec![(DVec3::ZERO, DVec3::ZERO); s.links.len()];
            tree.base_joint = s.base_joint;
            tree.revision = self.joint_revision;
            tree.q = s.q;
            tree.qd = s.qd;
            tree.marks = s.marks;
            let r = &mut self.scratch.reduced;
            if r.tree_of.len() <= s.base_joint as usize {
                r.tree_of.resize(s.base_joint as usize + 1, 0);
            }
            r.tree_of[s.base_joint as usize] = r.trees.len() as u32;
            r.trees.push(tree);
        }
        Ok(())
    }

    fn check_saved(&self, s: &SavedTree) -> Result<(), &'static str> {
        let n = s.links.len();
        if n == 0 || s.q.len() != n || s.qd.len() != n || s.marks.len() != n {
            return Err("its vectors differ in length");
        }
        let finite = s.q.iter().chain(&s.qd).all(|x| x.is_finite())
            && s.links.iter().all(|l| {
                l.origin.0.is_finite()
                    && l.origin.1.is_finite()
                    && (l.axis.length() - 1.0).abs() < 1e-6
                    && l.anchor.is_finite()
                    && l.mass.is_finite()
                    && l.mass > 0.0
                    && l.inertia.is_finite()
                    && l.plan.at.is_finite()
                    && l.plan.rate.is_finite()
                    && !l.plan.ball
                    && l.plan.planar.is_none()
            });
        if !finite {
            return Err("a number is not finite or out of range");
        }
        for (k, l) in s.links.iter().enumerate() {
            let joint = if k == 0 { s.base_joint } else { l.plan.joint };
            let entry = self
                .constraints
                .at(joint as usize)
                .ok_or("a joint is gone")?;
            if !matches!(
                entry.kind,
                ConstraintKind::Hinge(_) | ConstraintKind::Prismatic(_)
            ) {
                return Err("a joint is neither a hinge nor a slider");
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
