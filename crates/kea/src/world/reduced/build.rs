//! Building a tree for the reduced path: its links laid out parents first from the joint to
//! its base, each joint measured and put in the tree's terms (kind, axis, anchor, the link's
//! frame in its parent's), and each step the joints' stops, motors and drives.

use super::convert::{d3, dm, dq};
use super::frames::{joint_frame, planar_frame, seen_from};
use super::qualify::Role;
use super::{CachedTree, LinkPlan, FREE_ROOT};
use crate::articulation::{LinkDrive, TreeJointKind, TreeLink};
use crate::body::Body;
use crate::constraint::{Actuator, Limit, RowBody, RowContext};
use crate::math::{wide, Real};
use crate::world::constraint_entry::{ConstraintEntry, ConstraintKind};
use crate::world::constraint_index::NO_BODY;
use crate::world::World;
use glam::{DMat3, DQuat, DVec3};

impl World {
    /// Builds `cache` for the tree of set `root`, at the bodies' present state: coordinates
    /// measured from here (so `q = 0`), rates from the bodies. False if a joint cannot be
    /// measured, or the tree has more than `max_reduced_links` coordinates (the set then goes
    /// to the solver).
    ///
    /// A ball joint becomes three hinges about the child's x, y and z axes through its point,
    /// the first two on massless links, their chart centred on the present turn (angles 0,
    /// where the axes are orthogonal) and their rates the child's spin relative to its
    /// parent in its own axes: a step turns the child by far less than the chart's
    /// singularity (a quarter turn about y), and the next step is built again from the
    /// bodies, centred again. Such a tree is not kept from step to step.
    pub(super) fn build_tree(&self, root: u32, cache: &mut CachedTree) -> bool {
        if !self.plan_tree(root, &mut cache.plan) {
            return false;
        }
        let (bodies, constraints) = (&self.bodies, &self.constraints);
        let plan = &cache.plan;
        cache.building.clear();
        cache.link_of.clear();
        cache.first_link.clear();
        cache.qd.clear();
        cache.kick.clear();
        cache.rebuilt_each_step = false;
        for p in plan {
            let b = bodies.at(p.body as usize).expect("planned bodies are live");
            if p.free {
                cache.first_link.push(cache.building.len());
                free_root(b, &mut cache.building, &mut cache.qd);
                cache.kick.push((DVec3::ZERO, DVec3::ZERO));
                cache.link_of.push(cache.building.len() - 1);
                continue;
            }
            // The parent's frame: its body's, or the world's for the root.
            let parent_body = p.parent.map(|k| {
                bodies
                    .at(plan[k as usize].body as usize)
                    .expect("planned bodies are live")
            });
            let parent = parent_body.map(|pb| (d3(pb.position), dq(pb.orientation)));
            let entry = constraints
                .at(p.joint as usize)
                .expect("planned joints are live");
            let joint = joint_frame(entry, p.sign, b, parent, bodies);
            let parent_link = p.parent.map(|k| cache.link_of[k as usize]);
            cache.first_link.push(cache.building.len());
            let body_link = TreeLink {
                parent: parent_link,
                kind: joint.kind,
                origin: joint.origin,
                axis: joint.axis,
                anchor: joint.anchor,
                mass: wide(b.mass),
                com: DVec3::ZERO,
                inertia: dm(b.inertia),
                ..TreeLink::default()
            };
            if let (Some(more), ConstraintKind::Planar(j)) = (p.planar, &entry.kind) {
                let seen = seen_from(entry, true, b, parent, bodies);
                let f = planar_frame(j, &seen);
                let first = cache.building.len();
                let massless = TreeLink {
                    mass: 0.0,
                    inertia: DMat3::ZERO,
                    ..body_link
                };
                let second = TreeLink {
                    parent: Some(first),
                    origin: (DVec3::ZERO, DQuat::IDENTITY),
                    kind: TreeJointKind::Slider,
                    axis: f.axes[1],
                    ..if j.rotates { massless } else { body_link }
                };
                cache.building.push(massless);
                cache.building.push(second);
                cache.qd.extend([p.rate, more[1]]);
                cache.kick.push((DVec3::ZERO, DVec3::ZERO));
                if j.rotates {
                    cache.building.push(TreeLink {
                        parent: Some(first + 1),
                        origin: (DVec3::ZERO, DQuat::IDENTITY),
                        kind: TreeJointKind::Hinge,
                        axis: f.axes[2],
                        anchor: f.anchor,
                        ..body_link
                    });
                    cache.qd.push(more[3]);
                }
            } else if p.ball {
                cache.rebuilt_each_step = true;
                let (spin, kick) = ball_spin(b, parent_body, joint.anchor);
                cache.kick.push(kick);
                let first = cache.building.len();
                let massless = TreeLink {
                    mass: 0.0,
                    inertia: DMat3::ZERO,
                    ..body_link
                };
                cache.building.push(TreeLink {
                    axis: DVec3::X,
                    ..massless
                });
                cache.building.push(TreeLink {
                    parent: Some(first),
                    origin: (DVec3::ZERO, DQuat::IDENTITY),
                    axis: DVec3::Y,
                    ..massless
                });
                cache.building.push(TreeLink {
                    parent: Some(first + 1),
                    origin: (DVec3::ZERO, DQuat::IDENTITY),
                    axis: DVec3::Z,
                    ..body_link
                });
                cache.qd.extend([spin.x, spin.y, spin.z]);
            } else {
                cache.building.push(body_link);
                cache.qd.push(p.sign * p.rate);
                cache.kick.push((DVec3::ZERO, DVec3::ZERO));
            }
            cache.link_of.push(cache.building.len() - 1);
        }
        let n = cache.building.len();
        if n > self.settings.routing.max_reduced_links as usize {
            return false;
        }
        cache
            .tree
            .refill(&cache.building, d3(self.settings.gravity));
        cache.q.clear();
        cache.q.resize(n, 0.0);
        cache.base_joint = if plan[0].free {
            FREE_ROOT
        } else {
            self.scratch.reduced.base_joint[root as usize]
        };
        cache.revision = self.joint_revision;
        true
    }

    /// Lays out the tree of set `root` into `plan`, parents first from its base joint,
    /// measuring each joint.
    fn plan_tree(&self, root: u32, plan: &mut Vec<LinkPlan>) -> bool {
        let r = &self.scratch.reduced;
        plan.clear();
        let link = if r.base_joints[root as usize] == 0 {
            // Floating: the set's first body is the root, free.
            LinkPlan {
                body: r.root_body[root as usize],
                joint: FREE_ROOT,
                parent: None,
                sign: 1.0,
                at: 0.0,
                rate: 0.0,
                ball: false,
                planar: None,
                free: true,
            }
        } else {
            let base_joint = r.base_joint[root as usize];
            let [a, b] = self.constraint_bodies[base_joint as usize];
            let first = if r.role_of(a) == Role::Link { a } else { b };
            debug_assert!(first != NO_BODY);
            let Some(link) = self.measure(first, base_joint, None) else {
                return false;
            };
            link
        };
        plan.push(link);
        let mut k = 0;
        while k < plan.len() {
            let LinkPlan { body, joint, .. } = plan[k];
            for (j, other) in r.joints_of(body) {
                if j == joint {
                    continue; // the way back to the parent
                }
                let Some(link) = self.measure(other, j, Some(k as u32)) else {
                    return false;
                };
                plan.push(link);
            }
            k += 1;
        }
        true
    }

    /// The plan of the link on body slot `body` carried by joint slot `joint`: which side of
    /// the joint it is, and the joint's coordinate and rate now.
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
            epsilon: self.settings.epsilon,
            gamma: self.settings.gamma,
            contact_spring: self.settings.contact_spring,
        };
        let mut planar = None;
        let (at, rate, ball) = match &entry.kind {
            ConstraintKind::Hinge(j) => {
                let (at, rate) = j.angle_and_rate(&ctx);
                (at, rate, false)
            }
            ConstraintKind::Prismatic(j) => {
                let (at, rate) = j.distance_and_rate(&ctx);
                (at, rate, false)
            }
            ConstraintKind::Ball(_) => (0.0, 0.0, true),
            // The tree holds a planar joint's moving side as the link (the importers' way).
            ConstraintKind::Planar(j) if sign > 0.0 => {
                let [(x, vx), (y, vy), (t, vt)] = j.coordinates_and_rates(&ctx);
                let more = [y, vy, t, vt].map(wide);
                if !more.iter().all(|v| v.is_finite()) {
                    return None;
                }
                planar = Some(more);
                (x, vx, false)
            }
            _ => return None,
        };
        (at.is_finite() && rate.is_finite()).then_some(LinkPlan {
            body,
            joint,
            parent,
            sign,
            at: wide(at),
            rate: wide(rate),
            ball,
            planar,
            free: false,
        })
    }
}

/// A floating root's six links: travels along the world's x, y and z (massless, the first
/// from the body's place), then turns about the body's own x, y and z through its centre (the
/// last carrying the body), their chart centred on its present turn; rates its velocity and
/// its spin in its own axes.
fn free_root(b: &Body, links: &mut Vec<TreeLink>, qd: &mut Vec<f64>) {
    let first = links.len();
    let massless = TreeLink {
        parent: None,
        kind: TreeJointKind::Slider,
        origin: (d3(b.position), DQuat::IDENTITY),
        axis: DVec3::X,
        anchor: DVec3::ZERO,
        mass: 0.0,
        com: DVec3::ZERO,
        inertia: DMat3::ZERO,
        ..TreeLink::default()
    };
    let at = |k: usize| (DVec3::ZERO, DQuat::IDENTITY, Some(first + k));
    links.push(massless);
    for (k, axis) in [(0, DVec3::Y), (1, DVec3::Z)] {
        let (t, r, parent) = at(k);
        links.push(TreeLink {
            parent,
            origin: (t, r),
            axis,
            ..massless
        });
    }
    links.push(TreeLink {
        parent: Some(first + 2),
        kind: TreeJointKind::Hinge,
        origin: (DVec3::ZERO, dq(b.orientation)),
        axis: DVec3::X,
        ..massless
    });
    links.push(TreeLink {
        parent: Some(first + 3),
        kind: TreeJointKind::Hinge,
        origin: (DVec3::ZERO, DQuat::IDENTITY),
        axis: DVec3::Y,
        ..massless
    });
    links.push(TreeLink {
        parent: Some(first + 4),
        kind: TreeJointKind::Hinge,
        origin: (DVec3::ZERO, DQuat::IDENTITY),
        axis: DVec3::Z,
        mass: wide(b.mass),
        inertia: dm(b.inertia),
        ..massless
    });
    let spin = dq(b.orientation).inverse() * d3(b.angular_velocity);
    let v = d3(b.linear_velocity);
    qd.extend([v.x, v.y, v.z, spin.x, spin.y, spin.z]);
}

/// The joint's tracked coordinates: a hinge's angle, a slider's travel, a planar joint's two
/// travels and turn (zeros past the joint's own; a ball joint has none).
pub(super) fn coordinates_of(entry: &ConstraintEntry) -> [Real; 3] {
    match &entry.kind {
        ConstraintKind::Hinge(j) => [j.angle(), 0.0, 0.0],
        ConstraintKind::Prismatic(j) => [j.limit().position(), 0.0, 0.0],
        ConstraintKind::Planar(j) => j.coordinates(),
        _ => [0.0; 3],
    }
}

/// A ball joint's child's spin relative to its parent (`None`: the world or a disabled base,
/// at rest), in the child's axes, after the impulse at the joint's point that brings the two
/// bodies' velocities there together (the child's velocity as the joint allows it: a bob
/// given a speed and no spin swings with the speed). `anchor` is the point in the child's
/// frame. Also returns the impulse (world frame) and its point from the child's centre.
fn ball_spin(child: &Body, parent: Option<&Body>, anchor: DVec3) -> (DVec3, (DVec3, DVec3)) {
    let turn = dq(child.orientation);
    let r = turn * anchor;
    let (v, w) = (d3(child.linear_velocity), d3(child.angular_velocity));
    let (parent_point, parent_spin) = parent.map_or((DVec3::ZERO, DVec3::ZERO), |pb| {
        let wp = d3(pb.angular_velocity);
        let lever = d3(child.position) + r - d3(pb.position);
        (d3(pb.linear_velocity) + wp.cross(lever), wp)
    });
    let gap = v + w.cross(r) - parent_point;
    let inv_inertia = {
        let rot = DMat3::from_quat(turn);
        (rot * dm(child.inertia) * rot.transpose()).inverse()
    };
    let skew = |a: DVec3| {
        DMat3::from_cols(
            DVec3::new(0.0, a.z, -a.y),
            DVec3::new(-a.z, 0.0, a.x),
            DVec3::new(a.y, -a.x, 0.0),
        )
    };
    // gap + K P = 0 with K = I/m − [r]× I⁻¹ [r]×.
    let k = DMat3::from_diagonal(DVec3::splat(1.0 / wide(child.mass)))
        - skew(r) * inv_inertia * skew(r);
    let impulse = -(k.inverse() * gap);
    let w = w + inv_inertia * r.cross(impulse);
    let spin = turn.inverse() * (w - parent_spin);
    if spin.is_finite() && impulse.is_finite() {
        (spin, (impulse, r))
    } else {
        let spin = turn.inverse() * (d3(child.angular_velocity) - parent_spin);
        (spin, (DVec3::ZERO, DVec3::ZERO))
    }
}

/// The joint's limit (a planned joint with a coordinate is a hinge or a slider).
pub(super) fn limit_of(entry: &ConstraintEntry) -> &Limit {
    match &entry.kind {
        ConstraintKind::Hinge(j) => j.limit(),
        ConstraintKind::Prismatic(j) => j.limit(),
        _ => unreachable!("planned joints are hinges or sliders"),
    }
}

/// Sets the link's stops, motor, dynamics and servo from the joint's limit, in the tree's
/// coordinate (`tree = sign · (joint − at)`); returns the actuator's set force in it.
pub(super) fn drive(limit: &Limit, p: &LinkPlan, link: &mut LinkDrive) -> f64 {
    let tree = |x: Real| p.sign * (wide(x) - p.at);
    link.limits = limit.is_limited().then(|| {
        let (lo, hi) = (tree(limit.lower().stop), tree(limit.upper().stop));
        (lo.min(hi), lo.max(hi))
    });
    link.stop_recovery_speed = wide(
        limit
            .lower()
            .recovery_speed
            .min(limit.upper().recovery_speed),
    );
    link.motor = limit
        .motor()
        .map(|m| (p.sign * wide(m.desired_velocity), wide(m.max_force)));
    let d = limit.dynamics();
    link.armature = wide(d.armature);
    link.damping = wide(d.damping);
    link.friction = wide(d.friction);
    link.soft_limit = d.soft_limit;
    // The joint's spring is explicit (MuJoCo's passive stiffness, in every integrator); a
    // servo is implicit.
    let (k, rest) = (wide(d.stiffness), tree(d.rest));
    link.spring = (k > 0.0).then_some((rest, k));
    let (kp, target, kv, rate, force) = match limit.actuator() {
        Some(Actuator::Servo {
            position,
            velocity,
            stiffness,
            damping,
            ..
        }) => (
            wide(stiffness),
            tree(position),
            wide(damping),
            p.sign * wide(velocity),
            0.0,
        ),
        Some(Actuator::Force(f)) => (0.0, 0.0, 0.0, 0.0, p.sign * wide(f)),
        None => (0.0, 0.0, 0.0, 0.0, 0.0),
    };
    link.servo = (kp > 0.0 || kv > 0.0).then_some((target, rate, kp, kv));
    force
}
