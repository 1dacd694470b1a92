//! Which trees the reduced path may take this step: each body's role, the sets of links that
//! reducible joints join, and the sets that are trees hanging from one base by one joint.

use super::ReducedScratch;
use crate::body::Body;
use crate::constraint::{Actuator, Limit};
use crate::world::body_constraints::visited;
use crate::world::constraint_entry::{ConstraintEntry, ConstraintKind};
use crate::world::constraint_index::{EMPTY, NO_BODY};
use crate::world::World;

/// What a body slot is to the reduced path this step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) enum Role {
    /// Cannot be in a tree (asleep, kinematic, damped, touched by something else, no body).
    #[default]
    Blocked,
    /// A fixed base: a disabled body (the static world is `NO_BODY`).
    Base,
    /// May be a link.
    Link,
}

impl World {
    /// Fills `roots` with the root slot of every set of links that is a tree the reduced path
    /// may take: no blocked body, one joint to a base, one joint fewer than links, at most
    /// `limit` links.
    pub(super) fn find_trees(&mut self, limit: u32) {
        self.classify_bodies();
        self.group_links();
        self.count_sets();
        let floating = self.settings.reduced_free_trees;
        let fewest = if self.lone_bodies_reduce() { 1 } else { 2 };
        let listed = self.scratch.awake_constraints_listed;
        let awake = self.awake.slots();
        let r = &mut self.scratch.reduced;
        r.roots.clear();
        // A set with links has an awake root: while no body wakes, only those are looked at.
        for i in visited(listed, awake, r.links.len()) {
            let slot = i as u32;
            // Held to a base by one joint, or (floating) by none.
            let held = r.base_joints[i] == 1
                || (floating && r.base_joints[i] == 0 && r.links[i] >= fewest);
            let qualifies = r.links[i] > 0
                && r.sets.find(slot) == slot
                && !r.set_blocked[i]
                && held
                && r.inner_joints[i] + 1 == r.links[i]
                && r.links[i] <= limit;
            if qualifies {
                r.roots.push(slot);
            }
        }
    }

    /// Whether a floating body with no joint is a tree of its own
    /// ([`crate::WorldSettings::reduced_lone_bodies`]).
    pub(super) fn lone_bodies_reduce(&self) -> bool {
        self.settings.reduced_free_trees && self.settings.reduced_lone_bodies
    }

    /// Whether any joint could be part of a tree (cached by joint revision).
    pub(super) fn has_reducible_joints(&mut self) -> bool {
        let revision = self.joint_revision;
        if let Some((seen, any)) = self.scratch.reduced.candidates {
            if seen == revision {
                return any;
            }
        }
        let any = self.tree_joint_slots.iter().any(|&t| t);
        self.scratch.reduced.candidates = Some((revision, any));
        any
    }

    /// Each body slot's role, before the joints are looked at.
    fn classify_bodies(&mut self) {
        let n = self.bodies.slot_count();
        let s = &mut self.scratch;
        s.reduced.role.clear();
        if s.awake_constraints_listed {
            // No body wakes: the awake ones may be links, and the bodies their constraints
            // reach may be bases; the rest touch nothing a tree could take.
            s.reduced.role.resize(n, Role::Blocked);
            for &slot in self.awake.slots() {
                if self.bodies.at(slot as usize).is_some_and(plain) {
                    s.reduced.role[slot as usize] = Role::Link;
                }
            }
            for &slot in &s.awake_constraints {
                for x in self.constraint_bodies[slot as usize] {
                    let base = x < EMPTY
                        && !self.awake.is_awake(x)
                        && self
                            .bodies
                            .at(x as usize)
                            .is_some_and(|b| !b.enabled && !b.sleeping);
                    if base {
                        s.reduced.role[x as usize] = Role::Base;
                    }
                }
            }
            return;
        }
        for slot in 0..n {
            let waking = s.wake.get(slot).copied().unwrap_or(false);
            let role = match self.bodies.at(slot) {
                Some(b) if !b.enabled && !b.sleeping => Role::Base,
                Some(b) if b.enabled && (!b.sleeping || waking) && plain(b) => Role::Link,
                _ => Role::Blocked,
            };
            s.reduced.role.push(role);
        }
    }

    /// Joins links by reducible joints into sets; anything else touching a link (a contact,
    /// another joint, a joint to a body that cannot be a link or a base) blocks it.
    fn group_links(&mut self) {
        let takes_contacts = self.settings.reduced_contacts.is_some()
            && self.settings.integrator != crate::Integrator::Implicit;
        let r = &mut self.scratch.reduced;
        r.sets.reset(self.bodies.slot_count());
        r.contacts.slots.clear();
        r.contacts.pending.clear();
        // A constraint with no link joins nor blocks anything: while no body wakes, the
        // awake bodies' constraints (listed) are all there are.
        let listed = self.scratch.awake_constraints_listed;
        let listing = &self.scratch.awake_constraints;
        for slot in visited(listed, listing, self.constraint_bodies.len()) {
            let [a, b] = self.constraint_bodies[slot];
            if a == EMPTY {
                continue;
            }
            // Only a hinge or a slider can be a tree's: a contact's entry is not read.
            let reducible =
                self.tree_joint_slots[slot] && self.constraints.at(slot).is_some_and(tree_joint);
            let roles = [a, b].map(|x| r.role_of(x));
            match roles {
                [Role::Link, Role::Link] if reducible => r.sets.union(a, b),
                [Role::Link, Role::Base] | [Role::Base, Role::Link] if reducible => {}
                [Role::Link, Role::Base] | [Role::Base, Role::Link]
                    if takes_contacts && self.constraints.at(slot).is_some_and(plain_contact) =>
                {
                    r.contacts.slots.push(slot as u32);
                }
                // Between two links: kept if they are in one tree (known once every joint is
                // seen).
                [Role::Link, Role::Link]
                    if takes_contacts && self.constraints.at(slot).is_some_and(plain_contact) =>
                {
                    r.contacts.pending.push(slot as u32);
                }
                _ => {
                    for (x, role) in [a, b].into_iter().zip(roles) {
                        if role == Role::Link {
                            r.role[x as usize] = Role::Blocked;
                        }
                    }
                }
            }
        }
        self.group_tendon_links();
        let r = &mut self.scratch.reduced;
        for k in 0..r.contacts.pending.len() {
            let slot = r.contacts.pending[k] as usize;
            let [a, b] = self.constraint_bodies[slot];
            if r.sets.find(a) == r.sets.find(b) {
                r.contacts.slots.push(slot as u32);
            } else {
                r.role[a as usize] = Role::Blocked;
                r.role[b as usize] = Role::Blocked;
            }
        }
    }

    /// Per set root: its links, the joints between them and to a base, whether a blocked
    /// body is in it.
    fn count_sets(&mut self) {
        let n = self.bodies.slot_count();
        let r = &mut self.scratch.reduced;
        for v in [
            &mut r.links,
            &mut r.inner_joints,
            &mut r.base_joints,
            &mut r.base_joint,
        ] {
            v.clear();
            v.resize(n, 0);
        }
        // A floating set's root: its first body (an importer's root link, made first).
        r.root_body.clear();
        r.root_body.resize(n, u32::MAX);
        r.set_blocked.clear();
        r.set_blocked.resize(n, false);
        // While no body wakes, a body that is not awake is no link and in no set of links
        // (sets join links only): the awake bodies and their constraints are all there are.
        let listed = self.scratch.awake_constraints_listed;
        let awake = self.awake.slots();
        for slot in visited(listed, awake, n) {
            let root = r.sets.find(slot as u32) as usize;
            match r.role[slot] {
                Role::Link => {
                    r.links[root] += 1;
                    r.root_body[root] = r.root_body[root].min(slot as u32);
                }
                Role::Blocked => r.set_blocked[root] = true,
                Role::Base => {}
            }
        }
        let listing = &self.scratch.awake_constraints;
        for slot in visited(listed, listing, self.constraint_bodies.len()) {
            let [a, b] = self.constraint_bodies[slot];
            if a == EMPTY {
                continue;
            }
            match [a, b].map(|x| r.role_of(x)) {
                // Joints only: a contact between links of a tree is no joint of it.
                [Role::Link, Role::Link] if self.tree_joint_slots[slot] => {
                    let root = r.sets.find(a) as usize;
                    r.inner_joints[root] += 1;
                }
                [Role::Link, Role::Base] | [Role::Base, Role::Link]
                    if self.tree_joint_slots[slot] =>
                {
                    let link = if r.role_of(a) == Role::Link { a } else { b };
                    let root = r.sets.find(link) as usize;
                    r.base_joints[root] += 1;
                    r.base_joint[root] = slot as u32;
                }
                _ => {}
            }
        }
    }

    /// The joints between links, by body: (body, joint slot, other body), sorted, so that a
    /// body's are a run (`ReducedScratch::joints_of`), for laying trees out. Only the joints'
    /// slots are read, not every contact's nor every body's (a tree built every step, a ball
    /// joint's, beside a sleeping pile costs its joints).
    pub(super) fn link_adjacency(&mut self) {
        self.list_joint_slots();
        let r = &mut self.scratch.reduced;
        let bodies = &self.constraint_bodies;
        r.adjacency.clear();
        for k in 0..r.joint_slots.len() {
            let slot = r.joint_slots[k];
            let [a, b] = bodies[slot as usize];
            // Joints between links (a contact between two links of a tree joins nothing).
            if a != EMPTY && r.role_of(a) == Role::Link && r.role_of(b) == Role::Link {
                r.adjacency.push((a, slot, b));
                r.adjacency.push((b, slot, a));
            }
        }
        r.adjacency.sort_unstable();
    }

    /// Lists the slots that hold a joint a tree may take, ascending, once per joint revision
    /// (contacts, which come and go every step, never are one).
    fn list_joint_slots(&mut self) {
        let r = &mut self.scratch.reduced;
        if r.joint_slots_of == Some(self.joint_revision) {
            return;
        }
        r.joint_slots.clear();
        let slots = self.tree_joint_slots.iter().enumerate();
        r.joint_slots.extend(
            slots
                .filter(|&(_, &joint)| joint)
                .map(|(slot, _)| slot as u32),
        );
        r.joint_slots_of = Some(self.joint_revision);
    }
}

impl ReducedScratch {
    /// Body slot `body`'s joints to other links, by joint slot ascending: (joint slot,
    /// other body) (after `World::link_adjacency`).
    pub(super) fn joints_of(&self, body: u32) -> impl Iterator<Item = (u32, u32)> + '_ {
        let from = self.adjacency.partition_point(|&(b, _, _)| b < body);
        let run = self.adjacency[from..].iter();
        run.take_while(move |&&(b, _, _)| b == body)
            .map(|&(_, joint, other)| (joint, other))
    }

    /// The role of a constraint's side (`NO_BODY`: the static world, a base).
    pub(super) fn role_of(&self, x: u32) -> Role {
        if x == NO_BODY {
            Role::Base
        } else {
            self.role[x as usize]
        }
    }
}

/// Whether a contact of a link with a base or another link may be solved in the tree's joint
/// space (see
/// [`crate::WorldSettings::reduced_contacts`]): Coulomb friction equal both ways or none, and
/// nothing else a plain contact lacks.
fn plain_contact(e: &ConstraintEntry) -> bool {
    use crate::constraint::{ContactType, FrictionModel};
    let ConstraintKind::Contact(c) = &e.kind else {
        return false;
    };
    let p = c.params();
    let friction = match p.contact_type {
        ContactType::Frictionless => true,
        ContactType::Friction1D => false,
        ContactType::Friction2D => matches!(
            p.friction,
            [FrictionModel::Coulomb { mu: a }, FrictionModel::Coulomb { mu: b }] if a == b
        ),
    };
    friction
        && p.restitution == 0.0
        && p.softness.is_none()
        && p.max_adhesive_force == 0.0
        && p.slip == [0.0; 2]
        && p.slide == [0.0; 2]
        && c.direction().is_none()
}

/// Whether a body may be a link: dynamic, undamped, without a fast-spin axis.
pub(super) fn plain(b: &Body) -> bool {
    !b.kinematic
        && b.inv_mass > 0.0
        && b.linear_damping == 0.0
        && b.angular_damping == 0.0
        && b.fast_spin_axis.is_none()
}

/// Whether a tree can hold the joint: a hinge or slider [`reducible`], or a ball joint without
/// limits (its three turns as three hinges, see `build.rs`), none breakable, none with its
/// own γ (which asks for the maximal path's error reduction).
pub(super) fn tree_joint(e: &ConstraintEntry) -> bool {
    (reducible(e).is_some() || free_ball(e) || planar(e)) && e.gamma.is_none()
}

/// A planar joint whose used coordinates' limits a tree can hold, unbreakable (its travels and
/// turn as two sliders and a hinge, see `build.rs`).
pub(super) fn planar(e: &ConstraintEntry) -> bool {
    let ConstraintKind::Planar(j) = &e.kind else {
        return false;
    };
    let used = if j.rotates { 3 } else { 2 };
    e.break_force.is_none()
        && e.break_torque.is_none()
        && (0..used).all(|k| j.limit(k).is_some_and(holdable))
}

/// A ball joint without limits and unbreakable.
pub(super) fn free_ball(e: &ConstraintEntry) -> bool {
    matches!(&e.kind, ConstraintKind::Ball(j) if j.limits.is_none())
        && e.break_force.is_none()
        && e.break_torque.is_none()
}

/// A joint's limit if a tree can hold it (see the module docs).
pub(super) fn reducible(e: &ConstraintEntry) -> Option<&Limit> {
    if e.break_force.is_some() || e.break_torque.is_some() {
        return None;
    }
    let limit = match &e.kind {
        ConstraintKind::Hinge(j) => j.limit(),
        ConstraintKind::Prismatic(j) => j.limit(),
        _ => return None,
    };
    holdable(limit).then_some(limit)
}

/// Whether a tree holds a coordinate's limit: stops hard without restitution, servos uncapped.
fn holdable(limit: &Limit) -> bool {
    let hard = |s: &crate::constraint::SingleLimit| s.is_hard() && s.restitution == 0.0;
    if limit.is_limited() && !(hard(limit.lower()) && hard(limit.upper())) {
        return false;
    }
    !matches!(limit.actuator(), Some(Actuator::Servo { max_force, .. }) if max_force.is_finite())
}
