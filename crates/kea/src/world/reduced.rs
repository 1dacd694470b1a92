//! The reduced-coordinate path of a step: trees of hinges and sliders hanging from the static
//! world, stepped in their joint coordinates ([`crate::articulation`]) instead of as bodies held
//! together by constraint rows.
//!
//! A tree qualifies, step by step, when (hybrid routing, [`crate::Routing::max_reduced_links`]):
//! its bodies are awake, dynamic, undamped and plain (no fast-spin axis); they are joined by
//! enabled hinges and prismatic joints with hard stops (no restitution), motors, joint
//! dynamics and actuators (servos without a force cap), none breakable; exactly one of those
//! joints holds the tree to the static world or a disabled body, and the joints make no loop;
//! and nothing else touches its bodies — no contact, no other joint. A tree that stops
//! qualifying (a link touches something) goes to the maximal path in the same step, from the
//! same state: the state lives in the bodies and the joints' tracked coordinates, never in a
//! cache, so snapshots, clones and user edits need nothing more.
//!
//! Each step the tree is built at its present pose (coordinates measured from where the joints
//! are now, so a joint's small drift is kept, not corrected), stepped by `h`, and its links'
//! poses and velocities are written by forward kinematics; the joints keep their tracked
//! coordinate and rate, and their reactions come from Newton–Euler at the accelerations the
//! step took. Nothing is written until the solver accepted the rest of the world's rows: an
//! `Err` step leaves the world as it was.

use super::constraint_entry::{ConstraintEntry, ConstraintKind};
use super::constraint_index::{EMPTY, NO_BODY};
use super::World;
use crate::articulation::{ArticulatedTree, TreeJointKind, TreeLink};
use crate::body::Body;
use crate::constraint::{Actuator, Limit, RowBody, RowContext};
use crate::handle::{Arena, BodyHandle};
use crate::math::{Mat3, Quat, Real, Vec3};
use crate::solver::{Reaction, SolverMode};
use crate::union_find::UnionFind;
use glam::{DMat3, DQuat, DVec3};

/// What a body slot is to the reduced path this step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Role {
    /// Cannot be in a tree (asleep, kinematic, damped, touched by something else, no body).
    #[default]
    Blocked,
    /// A fixed base: a disabled body (the static world is `NO_BODY`).
    Base,
    /// May be a link.
    Link,
}

/// One link of a tree this step: its body and joint slots and how the joint's coordinate
/// maps to the tree's (`tree = sign · (joint − at)`).
#[derive(Debug, Clone, Copy)]
struct LinkPlan {
    body: u32,
    joint: u32,
    parent: Option<u32>,
    /// +1 when the link is the joint's first body, −1 when its second.
    sign: f64,
    /// The joint's coordinate and rate at the step's start.
    at: f64,
    rate: f64,
}

/// A link's state after the tree's step, committed once the step succeeds.
#[derive(Debug, Clone, Copy)]
struct LinkResult {
    body: u32,
    joint: u32,
    position: Vec3,
    orientation: Quat,
    linear_velocity: Vec3,
    angular_velocity: Vec3,
    linear_acceleration: Vec3,
    angular_acceleration: Vec3,
    coordinate: Real,
    rate: Real,
    reaction: [Reaction; 2],
}

/// The reduced path's buffers, reused every step.
#[derive(Clone, Default)]
pub(super) struct ReducedScratch {
    /// Per body slot: stepped here this step, so the solver leaves it out.
    pub(super) reduced: Vec<bool>,
    role: Vec<Role>,
    sets: UnionFind,
    /// Per set root: links, joints between links, joints to a base, and whether blocked.
    links: Vec<u32>,
    inner_joints: Vec<u32>,
    base_joints: Vec<u32>,
    set_blocked: Vec<bool>,
    /// Per set root: the joint that holds it to its base.
    base_joint: Vec<u32>,
    /// The roots of the sets that qualify this step.
    roots: Vec<u32>,
    /// Joints between links, by body: `adjacency[start[b]..start[b + 1]]` = (joint, other).
    start: Vec<u32>,
    adjacency: Vec<(u32, u32)>,
    fill: Vec<u32>,
    plan: Vec<LinkPlan>,
    tree: ArticulatedTree,
    q: Vec<f64>,
    qd: Vec<f64>,
    tau: Vec<f64>,
    results: Vec<LinkResult>,
    /// The joint revision last looked at, and whether the world then held any hinge or slider.
    candidates: Option<(u64, bool)>,
}

impl World {
    /// Steps every tree that qualifies (module docs) by `h` into the scratch, marking its
    /// bodies for the solver to leave out. Returns the number of trees.
    pub(super) fn step_reduced_trees(&mut self, h: Real) -> u32 {
        let n = self.bodies.slot_count();
        let r = &mut self.scratch.reduced;
        r.reduced.clear();
        r.reduced.resize(n, false);
        r.results.clear();
        let limit = self.routing.max_reduced_links;
        if self.routing.mode != SolverMode::Hybrid || limit == 0 || !self.has_reducible_joints() {
            return 0;
        }
        self.classify_bodies();
        self.group_links();
        let r = &mut self.scratch.reduced;
        r.roots.clear();
        for slot in 0..n as u32 {
            let i = slot as usize;
            let qualifies = r.links[i] > 0
                && r.sets.find(slot) == slot
                && !r.set_blocked[i]
                && r.base_joints[i] == 1
                && r.inner_joints[i] + 1 == r.links[i]
                && r.links[i] <= limit;
            if qualifies {
                r.roots.push(slot);
            }
        }
        let mut trees = 0;
        for k in 0..self.scratch.reduced.roots.len() {
            let root = self.scratch.reduced.roots[k];
            if self.plan_tree(root) && self.step_tree(h) {
                trees += 1;
            }
        }
        trees
    }

    /// Forgets a step's trees (the step failed): nothing was written.
    pub(super) fn discard_reduced_trees(&mut self) {
        let r = &mut self.scratch.reduced;
        r.results.clear();
        r.reduced.iter_mut().for_each(|x| *x = false);
    }

    /// Whether any joint could be part of a tree (cached by joint revision).
    fn has_reducible_joints(&mut self) -> bool {
        let revision = self.joint_revision;
        if let Some((seen, any)) = self.scratch.reduced.candidates {
            if seen == revision {
                return any;
            }
        }
        let any = (0..self.constraints.slot_count()).any(|slot| {
            self.constraints.at(slot).is_some_and(|e| {
                matches!(
                    e.kind,
                    ConstraintKind::Hinge(_) | ConstraintKind::Prismatic(_)
                )
            })
        });
        self.scratch.reduced.candidates = Some((revision, any));
        any
    }

    /// Each body slot's role, before the joints are looked at.
    fn classify_bodies(&mut self) {
        let n = self.bodies.slot_count();
        let s = &mut self.scratch;
        s.reduced.role.clear();
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

    /// Groups links joined by reducible joints into sets and counts each set's links and
    /// joints; anything else touching a link blocks its set.
    fn group_links(&mut self) {
        let n = self.bodies.slot_count();
        let r = &mut self.scratch.reduced;
        r.sets.reset(n);
        for slot in 0..self.constraint_bodies.len() {
            let [a, b] = self.constraint_bodies[slot];
            if a == EMPTY {
                continue;
            }
            let reducible = self
                .constraints
                .at(slot)
                .is_some_and(|e| reducible(e).is_some());
            let roles = [a, b].map(|x| {
                if x == NO_BODY {
                    Role::Base
                } else {
                    r.role[x as usize]
                }
            });
            match roles {
                [Role::Link, Role::Link] if reducible => r.sets.union(a, b),
                [Role::Link, Role::Base] | [Role::Base, Role::Link] if reducible => {}
                _ => {
                    // Touched by something a tree cannot hold: its links go to the solver.
                    for (x, role) in [a, b].into_iter().zip(roles) {
                        if role == Role::Link {
                            r.role[x as usize] = Role::Blocked;
                        }
                    }
                }
            }
        }
        for v in [
            &mut r.links,
            &mut r.inner_joints,
            &mut r.base_joints,
            &mut r.base_joint,
        ] {
            v.clear();
            v.resize(n, 0);
        }
        r.set_blocked.clear();
        r.set_blocked.resize(n, false);
        for slot in 0..n {
            let root = r.sets.find(slot as u32) as usize;
            match r.role[slot] {
                Role::Link => r.links[root] += 1,
                Role::Blocked => r.set_blocked[root] = true,
                Role::Base => {}
            }
        }
        // Joints counted once the blocking is known; the adjacency of links, by body.
        r.start.clear();
        r.start.resize(n + 1, 0);
        for slot in 0..self.constraint_bodies.len() {
            let [a, b] = self.constraint_bodies[slot];
            if a == EMPTY {
                continue;
            }
            let roles = [a, b].map(|x| {
                if x == NO_BODY {
                    Role::Base
                } else {
                    r.role[x as usize]
                }
            });
            match roles {
                [Role::Link, Role::Link] => {
                    let root = r.sets.find(a) as usize;
                    r.inner_joints[root] += 1;
                    r.start[a as usize + 1] += 1;
                    r.start[b as usize + 1] += 1;
                }
                [Role::Link, Role::Base] | [Role::Base, Role::Link] => {
                    let link = if roles[0] == Role::Link { a } else { b };
                    let root = r.sets.find(link) as usize;
                    r.base_joints[root] += 1;
                    r.base_joint[root] = slot as u32;
                }
                _ => {}
            }
        }
        for i in 0..n {
            r.start[i + 1] += r.start[i];
        }
        r.adjacency.clear();
        r.adjacency.resize(r.start[n] as usize, (0, 0));
        r.fill.clear();
        r.fill.extend_from_slice(&r.start[..n]);
        for slot in 0..self.constraint_bodies.len() {
            let [a, b] = self.constraint_bodies[slot];
            if a == EMPTY || a == NO_BODY || b == NO_BODY {
                continue;
            }
            if r.role[a as usize] == Role::Link && r.role[b as usize] == Role::Link {
                for (x, y) in [(a, b), (b, a)] {
                    let k = r.fill[x as usize] as usize;
                    r.adjacency[k] = (slot as u32, y);
                    r.fill[x as usize] += 1;
                }
            }
        }
    }

    /// Lays out the tree of set `root` parents first from its base joint, measuring each
    /// joint. False if a joint cannot be measured (then the set goes to the solver).
    fn plan_tree(&mut self, root: u32) -> bool {
        let base_joint = self.scratch.reduced.base_joint[root as usize];
        let [a, _] = self.constraint_bodies[base_joint as usize];
        let first = if a != NO_BODY && self.scratch.reduced.role[a as usize] == Role::Link {
            a
        } else {
            self.constraint_bodies[base_joint as usize][1]
        };
        self.scratch.reduced.plan.clear();
        let Some(link) = self.measure(first, base_joint, None) else {
            return false;
        };
        self.scratch.reduced.plan.push(link);
        let mut k = 0;
        while k < self.scratch.reduced.plan.len() {
            let LinkPlan { body, joint, .. } = self.scratch.reduced.plan[k];
            let r = &self.scratch.reduced;
            let (from, to) = (r.start[body as usize], r.start[body as usize + 1]);
            for e in from..to {
                let (j, other) = self.scratch.reduced.adjacency[e as usize];
                if j == joint {
                    continue; // the way back to the parent
                }
                let Some(link) = self.measure(other, j, Some(k as u32)) else {
                    return false;
                };
                self.scratch.reduced.plan.push(link);
            }
            k += 1;
        }
        true
    }

    /// The plan of the link on body slot `body` carried by joint slot `joint`.
    fn measure(&self, body: u32, joint: u32, parent: Option<u32>) -> Option<LinkPlan> {
        let entry = self.constraints.at(joint as usize)?;
        let sides = entry.bodies.map(|h| h.map(|h| h.index()));
        let sign = if sides[0] == Some(body) { 1.0 } else { -1.0 };
        let row_body = |side: Option<u32>| match side.and_then(|s| self.bodies.at(s as usize)) {
            None => RowBody::STATIC,
            Some(b) => RowBody {
                linear_velocity: b.linear_velocity,
                angular_velocity: b.angular_velocity,
                dynamic: b.enabled,
                ..RowBody::fixed(b.position, b.orientation)
            },
        };
        let ctx = RowContext {
            bodies: sides.map(row_body),
            dt: 1.0,
            epsilon: self.epsilon,
            gamma: self.gamma,
            contact_spring: self.contact_spring,
        };
        let (at, rate) = match &entry.kind {
            ConstraintKind::Hinge(j) => j.angle_and_rate(&ctx),
            ConstraintKind::Prismatic(j) => j.distance_and_rate(&ctx),
            _ => return None,
        };
        (at.is_finite() && rate.is_finite()).then_some(LinkPlan {
            body,
            joint,
            parent,
            sign,
            at: f64::from(at),
            rate: f64::from(rate),
        })
    }

    /// Steps the planned tree by `h` into the results; false (nothing kept) if its inertia
    /// is singular or anything comes out non-finite.
    fn step_tree(&mut self, h: Real) -> bool {
        let gravity = d3(self.gravity);
        let r = &mut self.scratch.reduced;
        let bodies = &self.bodies;
        let constraints = &self.constraints;
        let links = r.plan.iter().map(|p| {
            let b = bodies.at(p.body as usize).expect("planned bodies are live");
            // The parent's frame: its body's, or the world's for the root (its base's anchor
            // and axis are then taken to world coordinates).
            let parent = match p.parent {
                Some(k) => {
                    let pb = bodies
                        .at(r.plan[k as usize].body as usize)
                        .expect("planned bodies are live");
                    Some((d3(pb.position), dq(pb.orientation)))
                }
                None => None,
            };
            let entry = constraints
                .at(p.joint as usize)
                .expect("planned joints are live");
            let joint = joint_frame(entry, p.sign, b, parent, bodies);
            let mut link = TreeLink {
                parent: p.parent.map(|k| k as usize),
                kind: joint.kind,
                origin: joint.origin,
                axis: joint.axis,
                anchor: joint.anchor,
                mass: f64::from(b.mass),
                com: DVec3::ZERO,
                inertia: dm(b.inertia),
                ..TreeLink::default()
            };
            drive(joint.limit, p, &mut link);
            link
        });
        r.tree.refill(links, gravity);
        let n = r.plan.len();
        r.q.clear();
        r.q.resize(n, 0.0);
        r.qd.clear();
        r.tau.clear();
        for (k, p) in r.plan.iter().enumerate() {
            r.qd.push(p.sign * p.rate);
            let entry = constraints
                .at(p.joint as usize)
                .expect("planned joints are live");
            let limit = match &entry.kind {
                ConstraintKind::Hinge(j) => j.limit(),
                ConstraintKind::Prismatic(j) => j.limit(),
                _ => unreachable!("planned joints are hinges or sliders"),
            };
            let force = match limit.actuator() {
                Some(Actuator::Force(f)) => f64::from(f),
                _ => 0.0,
            };
            r.tau.push(p.sign * force);
            let b = bodies.at(p.body as usize).expect("planned bodies are live");
            let turn = dq(b.orientation).inverse();
            let set = r
                .tree
                .set_external(k, turn * d3(b.torque), turn * d3(b.force));
            if set.is_err() {
                return false;
            }
        }
        let h64 = f64::from(h);
        let (q, qd, tau) = (&mut r.q, &mut r.qd, &r.tau);
        if r.tree.step_with_reactions(q, qd, tau, h64, true).is_err() {
            return false;
        }
        r.tree.forward(&r.q, &r.qd);
        let first = r.results.len();
        for (k, p) in r.plan.iter().enumerate() {
            let b = bodies.at(p.body as usize).expect("planned bodies are live");
            let (t, rot) = r.tree.frame(k);
            let [w, v] = r.tree.velocity(k);
            let (w, v) = (rot * w, rot * v);
            let [n0, f0] = r.tree.reaction(k);
            let start = dq(b.orientation);
            let (force, torque) = (v3(start * f0), v3(start * n0));
            let mut reaction = [Reaction::default(); 2];
            let (child, parent) = if p.sign > 0.0 { (0, 1) } else { (1, 0) };
            reaction[child] = Reaction { force, torque };
            if let Some(k) = p.parent {
                let pb = bodies
                    .at(r.plan[k as usize].body as usize)
                    .expect("planned bodies are live");
                let lever = b.position - pb.position;
                reaction[parent] = Reaction {
                    force: -force,
                    torque: -(torque + lever.cross(force)),
                };
            }
            let (lv, av) = (v3(v), v3(w));
            r.results.push(LinkResult {
                body: p.body,
                joint: p.joint,
                position: v3(t),
                orientation: Quat::from_xyzw(
                    rot.x as Real,
                    rot.y as Real,
                    rot.z as Real,
                    rot.w as Real,
                )
                .normalize(),
                linear_velocity: lv,
                angular_velocity: av,
                linear_acceleration: (lv - b.linear_velocity) / h,
                angular_acceleration: (av - b.angular_velocity) / h,
                coordinate: (p.at + p.sign * r.q[k]) as Real,
                rate: (p.sign * r.qd[k]) as Real,
                reaction,
            });
        }
        let finite = r.results[first..].iter().all(|x| {
            x.position.is_finite()
                && x.orientation.is_finite()
                && x.linear_velocity.is_finite()
                && x.angular_velocity.is_finite()
                && x.coordinate.is_finite()
                && x.reaction
                    .iter()
                    .all(|y| y.force.is_finite() && y.torque.is_finite())
        });
        if !finite {
            r.results.truncate(first);
            return false;
        }
        for p in &r.plan {
            r.reduced[p.body as usize] = true;
        }
        true
    }

    /// Writes the trees' new states to their bodies and joints (after the solver succeeded),
    /// and clears the marks so that read-outs between steps see every body.
    pub(super) fn commit_reduced_trees(&mut self) {
        let r = &mut self.scratch.reduced;
        for x in &r.results {
            if let Some(b) = self.bodies.at_mut(x.body as usize) {
                b.position = x.position;
                b.orientation = x.orientation;
                b.linear_velocity = x.linear_velocity;
                b.angular_velocity = x.angular_velocity;
                b.linear_acceleration = x.linear_acceleration;
                b.angular_acceleration = x.angular_acceleration;
                b.update_transform();
            }
            if let Some(e) = self.constraints.at_mut(x.joint as usize) {
                match &mut e.kind {
                    ConstraintKind::Hinge(j) => {
                        j.angle = x.coordinate;
                        j.limit.record(x.coordinate, x.rate);
                    }
                    ConstraintKind::Prismatic(j) => j.limit.record(x.coordinate, x.rate),
                    _ => {}
                }
                e.last_rows = None;
                e.reaction = x.reaction;
            }
            self.scratch.written.push(x.joint);
        }
        let r = &mut self.scratch.reduced;
        r.results.clear();
        r.reduced.iter_mut().for_each(|x| *x = false);
    }

    /// Bodies the reduced path stepped this step.
    pub(super) fn reduced_body_count(&self) -> u32 {
        self.scratch.reduced.results.len() as u32
    }
}

/// Whether a body may be a link: dynamic, undamped, without a fast-spin axis.
fn plain(b: &Body) -> bool {
    !b.kinematic
        && b.inv_mass > 0.0
        && b.linear_damping == 0.0
        && b.angular_damping == 0.0
        && b.fast_spin_axis.is_none()
}

/// A joint's kind and limit if a tree can hold it (module docs).
fn reducible(e: &ConstraintEntry) -> Option<(TreeJointKind, &Limit)> {
    if e.break_force.is_some() || e.break_torque.is_some() {
        return None;
    }
    let (kind, limit) = match &e.kind {
        ConstraintKind::Hinge(j) => (TreeJointKind::Hinge, j.limit()),
        ConstraintKind::Prismatic(j) => (TreeJointKind::Slider, j.limit()),
        _ => return None,
    };
    let hard = |s: &crate::constraint::SingleLimit| s.is_hard() && s.restitution == 0.0;
    if limit.is_limited() && !(hard(limit.lower()) && hard(limit.upper())) {
        return None;
    }
    if let Some(Actuator::Servo { max_force, .. }) = limit.actuator() {
        if max_force.is_finite() {
            return None;
        }
    }
    Some((kind, limit))
}

/// A joint as the tree holds it: kind, unit axis and anchor in the link's frame, the link's
/// frame in its parent's at the present coordinate, and the limit.
struct TreeJoint<'a> {
    kind: TreeJointKind,
    axis: DVec3,
    anchor: DVec3,
    origin: (DVec3, DQuat),
    limit: &'a Limit,
}

/// The joint carrying `link`, in the tree's terms. The link's frame in its parent's (`parent`:
/// the parent body's pose, `None` for the world) is where the joint puts it now: its present
/// turn or travel, with any drift off the joint (a rounding's worth a step, or what the
/// maximal path left) taken out, so that stepping in reduced coordinates never accumulates it.
fn joint_frame<'a>(
    entry: &'a ConstraintEntry,
    sign: f64,
    link: &Body,
    parent: Option<(DVec3, DQuat)>,
    bodies: &Arena<Body, BodyHandle>,
) -> TreeJoint<'a> {
    let first = sign > 0.0;
    let (parent_position, parent_rotation) = parent.unwrap_or((DVec3::ZERO, DQuat::IDENTITY));
    let to_parent = parent_rotation.inverse();
    let rotation = (to_parent * dq(link.orientation)).normalize();
    let position = to_parent * (d3(link.position) - parent_position);
    // A vector or point held in the other body's frame, in the parent's frame (the world's
    // for the root, whose other body is the static world or a disabled base).
    let other = entry.bodies[usize::from(first)].and_then(|h| bodies.get(h).ok());
    let base = |v: DVec3, point: bool| match (parent, other) {
        (None, Some(b)) => dq(b.orientation) * v + if point { d3(b.position) } else { DVec3::ZERO },
        _ => v,
    };
    match &entry.kind {
        ConstraintKind::Hinge(j) => {
            let (axis, anchor, parent_axis, parent_anchor) = if first {
                (
                    j.local_axis1,
                    j.local_anchor1,
                    j.local_axis2,
                    j.local_anchor2,
                )
            } else {
                (
                    j.local_axis2,
                    j.local_anchor2,
                    j.local_axis1,
                    j.local_anchor1,
                )
            };
            let (axis, anchor) = (d3(axis).normalize(), d3(anchor));
            let parent_axis = base(d3(parent_axis), false).normalize();
            let parent_anchor = base(d3(parent_anchor), true);
            // The axes brought together, then the anchors.
            let align = DQuat::from_rotation_arc(rotation * axis, parent_axis);
            let rotation = (align * rotation).normalize();
            TreeJoint {
                kind: TreeJointKind::Hinge,
                axis,
                anchor,
                origin: (parent_anchor - rotation * anchor, rotation),
                limit: j.limit(),
            }
        }
        ConstraintKind::Prismatic(j) => {
            // relative_orientation turns body 1's frame into body 2's.
            let held = dq(j.relative_orientation);
            let (axis, anchor, parent_anchor, turn) = if first {
                let axis = held.inverse() * d3(j.local_axis2);
                (axis, j.local_anchor1, j.local_anchor2, held)
            } else {
                (
                    d3(j.local_axis2),
                    j.local_anchor2,
                    j.local_anchor1,
                    held.inverse(),
                )
            };
            let axis = axis.normalize();
            let parent_anchor = base(d3(parent_anchor), true);
            let rotation = match (parent, other) {
                (None, Some(b)) => (dq(b.orientation) * turn).normalize(),
                _ => turn,
            };
            // The anchors' gap kept along the axis only.
            let along = rotation * axis;
            let gap = position + rotation * d3(anchor) - parent_anchor;
            let gap = along * gap.dot(along);
            TreeJoint {
                kind: TreeJointKind::Slider,
                axis,
                anchor: DVec3::ZERO,
                origin: (parent_anchor + gap - rotation * d3(anchor), rotation),
                limit: j.limit(),
            }
        }
        _ => unreachable!("planned joints are hinges or sliders"),
    }
}

/// The limit's stops, motor, dynamics and servo in the tree's coordinate
/// (`tree = sign · (joint − at)`).
fn drive(limit: &Limit, p: &LinkPlan, link: &mut TreeLink) {
    let tree = |x: Real| p.sign * (f64::from(x) - p.at);
    if limit.is_limited() {
        let (lo, hi) = (tree(limit.lower().stop), tree(limit.upper().stop));
        link.limits = Some((lo.min(hi), lo.max(hi)));
        link.stop_recovery_speed = f64::from(
            limit
                .lower()
                .recovery_speed
                .min(limit.upper().recovery_speed),
        );
    }
    link.motor = limit.motor().map(|m| {
        (
            p.sign * f64::from(m.desired_velocity),
            f64::from(m.max_force),
        )
    });
    let d = limit.dynamics();
    link.armature = f64::from(d.armature);
    link.damping = f64::from(d.damping);
    link.friction = f64::from(d.friction);
    // The joint's spring and a servo act as one spring (their stiffnesses add, towards the
    // stiffness-weighted target) and one damper towards the servo's rate.
    let (k, rest) = (f64::from(d.stiffness), tree(d.rest));
    let (kp, target, kv, rate) = match limit.actuator() {
        Some(Actuator::Servo {
            position,
            velocity,
            stiffness,
            damping,
            ..
        }) => (
            f64::from(stiffness),
            tree(position),
            f64::from(damping),
            p.sign * f64::from(velocity),
        ),
        _ => (0.0, 0.0, 0.0, 0.0),
    };
    let stiffness = k + kp;
    if stiffness > 0.0 || kv > 0.0 {
        let position = if stiffness > 0.0 {
            (k * rest + kp * target) / stiffness
        } else {
            0.0
        };
        link.servo = Some((position, rate, stiffness, kv));
    }
}

#[allow(clippy::unnecessary_cast)]
fn d3(v: Vec3) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

#[allow(clippy::unnecessary_cast)]
fn v3(v: DVec3) -> Vec3 {
    Vec3::new(v.x as Real, v.y as Real, v.z as Real)
}

#[allow(clippy::unnecessary_cast)]
fn dq(q: Quat) -> DQuat {
    DQuat::from_xyzw(q.x as f64, q.y as f64, q.z as f64, q.w as f64).normalize()
}

fn dm(m: Mat3) -> DMat3 {
    DMat3::from_cols(d3(m.x_axis), d3(m.y_axis), d3(m.z_axis))
}
