//! The reduced path's contacts (`WorldSettings::reduced_contacts`): which of the world's
//! contacts a tree takes into its joint space this step (`qualify.rs` lists them), each point
//! as a [`TreeContact`] on its link (and, between two links, the other's), and the forces the
//! tree's step gave them, written back to the contacts once the step succeeds.

use super::convert::{d3, dq, v3};
use super::CachedTree;
use crate::articulation::{ArticulatedTree, TreeContact};
use crate::body::Body;
use crate::constraint::{ContactType, PointForce};
use crate::handle::{Arena, ConstraintHandle};
use crate::math::{wide, Real, Vec3};
use crate::world::constraint_entry::{ConstraintEntry, ConstraintKind};
use crate::BodyHandle;
use glam::DVec3;

/// No tree link.
const NONE: u32 = u32::MAX;

/// Where a tree contact came from: the contact's slot, its point, and whether the link is the
/// contact's first body.
#[derive(Debug, Clone, Copy)]
struct ContactRef {
    slot: u32,
    point: u8,
    first: bool,
}

/// The reduced path's contact scratch, reused every step.
#[derive(Clone, Default)]
pub(super) struct TreeContacts {
    /// Contacts of links with a base (or two links of one tree) this step, by constraint slot.
    pub(super) slots: Vec<u32>,
    /// Contacts between two links, kept once both are known to be in one tree.
    pub(super) pending: Vec<u32>,
    /// Per body slot, the tree link that carries it while its tree's contacts are gathered.
    link_body: Vec<u32>,
    /// The tree in flight's contacts, and where each came from.
    pub(super) tree: Vec<TreeContact>,
    refs: Vec<ContactRef>,
    /// The contacts' force on each link of the tree in flight, world frame.
    pub(super) on_link: Vec<DVec3>,
    /// Each stepped tree's contact forces (slot, point, force on the contact's first body),
    /// written once the step succeeds.
    pub(super) results: Vec<(u32, u8, PointForce)>,
}

impl TreeContacts {
    /// Fills `tree` with tree `t`'s contacts this step: each point of each listed contact
    /// between one of its links and a base or another of its links, in the link's frame.
    pub(super) fn gather(
        &mut self,
        t: &CachedTree,
        bodies: &Arena<Body, BodyHandle>,
        constraints: &Arena<ConstraintEntry, ConstraintHandle>,
    ) {
        self.tree.clear();
        self.refs.clear();
        if self.slots.is_empty() {
            return;
        }
        if self.link_body.len() < bodies.slot_count() {
            self.link_body.resize(bodies.slot_count(), NONE);
        }
        for (k, p) in t.plan.iter().enumerate() {
            self.link_body[p.body as usize] = t.link_of[k] as u32;
        }
        for &slot in &self.slots {
            let Some(e) = constraints.at(slot as usize) else {
                continue;
            };
            let ConstraintKind::Contact(c) = &e.kind else {
                continue;
            };
            let link_body = &self.link_body;
            let on = |h: Option<BodyHandle>| {
                h.map(|h| h.index() as usize)
                    .filter(|&b| link_body.get(b).is_some_and(|&l| l != NONE))
            };
            let second = on(e.bodies[1]);
            let (body, first) = match (on(e.bodies[0]), second) {
                (Some(b), _) => (b, true),
                (None, Some(b)) => (b, false),
                (None, None) => continue,
            };
            // Between two links of this tree: the second one's link and frame.
            let other = match (first, second) {
                (true, Some(o)) => bodies.at(o).map(|ob| (link_body[o] as usize, ob)),
                _ => None,
            };
            let Some(b) = bodies.at(body) else {
                continue;
            };
            let link = link_body[body] as usize;
            let to_link = dq(b.orientation).inverse();
            let normal = if first { c.normal() } else { -c.normal() };
            let friction = match c.params().contact_type {
                ContactType::Frictionless => 0.0,
                _ => c.coulomb_mu(0).map_or(0.0, wide),
            };
            for (i, (p, w)) in c.points().iter().zip(c.warm_forces()).enumerate() {
                // The point's force on the contact's first body last step, on the link.
                let on_first = d3(c.normal() * w.normal + w.friction);
                let warm = if first { on_first } else { -on_first };
                let at = if first {
                    p.position
                } else {
                    p.position + p.to_second
                };
                self.tree.push(TreeContact {
                    link,
                    point: to_link * d3(at - b.position),
                    normal: d3(normal),
                    distance: -wide(p.penetration),
                    friction,
                    warm,
                    other: other.map(|(o, ob)| {
                        let held = p.position + p.to_second;
                        (o, dq(ob.orientation).inverse() * d3(held - ob.position))
                    }),
                });
                self.refs.push(ContactRef {
                    slot,
                    point: i as u8,
                    first,
                });
            }
        }
        for p in &t.plan {
            self.link_body[p.body as usize] = NONE;
        }
    }

    /// After the tree's step: each link's contact force (`on_link`) and each contact point's
    /// force for the results; returns where this tree's results start.
    pub(super) fn record(
        &mut self,
        tree: &ArticulatedTree,
        constraints: &Arena<ConstraintEntry, ConstraintHandle>,
    ) -> usize {
        let from = self.results.len();
        self.on_link.clear();
        self.on_link.resize(tree.len(), DVec3::ZERO);
        for ((c, at), &force) in self.tree.iter().zip(&self.refs).zip(tree.contact_forces()) {
            self.on_link[c.link] += force;
            if let Some((o, _)) = c.other {
                self.on_link[o] -= force;
            }
            // The contact's force on its first body.
            let on_first = if at.first { force } else { -force };
            let normal = constraints
                .at(at.slot as usize)
                .and_then(|e| match &e.kind {
                    ConstraintKind::Contact(k) => Some(k.normal()),
                    _ => None,
                })
                .unwrap_or(Vec3::Y);
            let along = on_first.dot(d3(normal));
            self.results.push((
                at.slot,
                at.point,
                PointForce {
                    normal: along as Real,
                    friction: v3(on_first - d3(normal) * along),
                },
            ));
        }
        from
    }

    /// Writes the step's contact forces to their contacts (the step succeeded).
    pub(super) fn write_back(
        &mut self,
        constraints: &mut Arena<ConstraintEntry, ConstraintHandle>,
    ) {
        for &(slot, point, force) in &self.results {
            if let Some(ConstraintKind::Contact(c)) =
                constraints.at_mut(slot as usize).map(|e| &mut e.kind)
            {
                c.set_point_force(usize::from(point), force, force);
            }
        }
        self.results.clear();
    }
}
