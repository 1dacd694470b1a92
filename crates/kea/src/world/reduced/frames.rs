//! Where a joint puts its link, in the tree's terms: the link's frame in its parent's as the
//! joint holds it now (drift off the joint taken out), and the joint's kind, axis and point
//! (hinges, sliders, ball joints, planar joints).

use super::convert::{d3, dq};
use crate::articulation::TreeJointKind;
use crate::body::Body;
use crate::handle::{Arena, BodyHandle};
use crate::world::constraint_entry::{ConstraintEntry, ConstraintKind};
use glam::{DQuat, DVec3};

/// A joint as the tree takes it: kind, axis and point in the link's frame, and the link's
/// frame in its parent's.
pub(super) struct TreeJoint {
    pub kind: TreeJointKind,
    pub axis: DVec3,
    pub anchor: DVec3,
    pub origin: (DVec3, DQuat),
}

/// The joint carrying `link`, in the tree's terms. The link's frame in its parent's (`parent`:
/// the parent body's pose, `None` for the world) is where the joint puts it now: its present
/// turn or travel, with any drift off the joint (a rounding's worth a step, or what the
/// maximal path left) taken out, so that stepping in reduced coordinates never accumulates it.
pub(super) fn joint_frame(
    entry: &ConstraintEntry,
    sign: f64,
    link: &Body,
    parent: Option<(DVec3, DQuat)>,
    bodies: &Arena<Body, BodyHandle>,
) -> TreeJoint {
    let first = sign > 0.0;
    let seen = seen_from(entry, first, link, parent, bodies);
    match &entry.kind {
        ConstraintKind::Hinge(j) => hinge_frame(j, first, &seen),
        ConstraintKind::Prismatic(j) => slider_frame(j, first, &seen),
        ConstraintKind::Ball(j) => ball_frame(j, first, &seen),
        // Its first slider's (`build_tree` makes the rest).
        ConstraintKind::Planar(j) => {
            let f = planar_frame(j, &seen);
            TreeJoint {
                kind: TreeJointKind::Slider,
                axis: f.axes[0],
                anchor: DVec3::ZERO,
                origin: f.origin,
            }
        }
        _ => unreachable!("planned joints are hinges, sliders, balls or planar"),
    }
}

/// A ball joint in the tree's terms: the link turned as it is now, its anchor put on the
/// parent's. The kind and axis are its first hinge's (`build_tree` makes the three).
fn ball_frame(j: &crate::constraint::BallJoint, first: bool, seen: &Seen) -> TreeJoint {
    let (anchor, parent_anchor) = if first {
        (j.local_anchor1, j.local_anchor2)
    } else {
        (j.local_anchor2, j.local_anchor1)
    };
    let anchor = d3(anchor);
    let parent_anchor = seen.point(d3(parent_anchor));
    TreeJoint {
        kind: TreeJointKind::Hinge,
        axis: DVec3::X,
        anchor,
        origin: (parent_anchor - seen.rotation * anchor, seen.rotation),
    }
}

/// How the parent's frame sees `link` and the joint's other side.
pub(super) fn seen_from(
    entry: &ConstraintEntry,
    first: bool,
    link: &Body,
    parent: Option<(DVec3, DQuat)>,
    bodies: &Arena<Body, BodyHandle>,
) -> Seen {
    let (parent_position, parent_rotation) = parent.unwrap_or((DVec3::ZERO, DQuat::IDENTITY));
    let to_parent = parent_rotation.inverse();
    // The root's other body is the static world or a disabled base, whose frame its joint
    // holds vectors and points in: seen from the world's.
    let other = entry.bodies[usize::from(first)].and_then(|h| bodies.get(h).ok());
    Seen {
        rotation: (to_parent * dq(link.orientation)).normalize(),
        position: to_parent * (d3(link.position) - parent_position),
        base: match (parent, other) {
            (None, Some(b)) => Some((dq(b.orientation), d3(b.position))),
            _ => None,
        },
    }
}

/// A planar joint in the tree's terms, its moving side the link: the link's frame where the
/// joint holds it now (turned as it is about the normal, or as the joint holds it if it does
/// not turn; its point put back in the plane), the two travels' directions and the normal in
/// the link's frame, and its point.
pub(super) struct PlanarFrame {
    pub origin: (DVec3, DQuat),
    pub axes: [DVec3; 3],
    pub anchor: DVec3,
}

pub(super) fn planar_frame(j: &crate::constraint::Planar, seen: &Seen) -> PlanarFrame {
    let normal = seen.vector(d3(j.local_normal2)).normalize();
    let e1 = seen.vector(d3(j.local_axis2)).normalize();
    let e2 = normal.cross(e1);
    let rotation = if j.rotates {
        let align =
            DQuat::from_rotation_arc(seen.rotation * d3(j.local_normal1).normalize(), normal);
        (align * seen.rotation).normalize()
    } else {
        let held = dq(j.relative_orientation);
        seen.base.map_or(held, |(r, _)| (r * held).normalize())
    };
    let anchor = d3(j.local_anchor1);
    let point = seen.position + rotation * anchor;
    let plane = seen.point(d3(j.local_anchor2));
    let point = point - normal * (point - plane).dot(normal);
    let to_link = rotation.inverse();
    PlanarFrame {
        origin: (point - rotation * anchor, rotation),
        axes: [to_link * e1, to_link * e2, to_link * normal],
        anchor,
    }
}

/// A link as its parent's frame sees it now, and the frame the joint's other side holds its
/// vectors and points in, seen from the parent's (`None`: the same).
pub(super) struct Seen {
    rotation: DQuat,
    position: DVec3,
    base: Option<(DQuat, DVec3)>,
}

impl Seen {
    fn vector(&self, v: DVec3) -> DVec3 {
        self.base.map_or(v, |(r, _)| r * v)
    }
    fn point(&self, p: DVec3) -> DVec3 {
        self.base.map_or(p, |(r, t)| r * p + t)
    }
}

/// A hinge in the tree's terms: the link's axis brought onto the parent's, then its anchor
/// onto the parent's.
fn hinge_frame(j: &crate::constraint::Hinge, first: bool, seen: &Seen) -> TreeJoint {
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
    let parent_axis = seen.vector(d3(parent_axis)).normalize();
    let parent_anchor = seen.point(d3(parent_anchor));
    let align = DQuat::from_rotation_arc(seen.rotation * axis, parent_axis);
    let rotation = (align * seen.rotation).normalize();
    TreeJoint {
        kind: TreeJointKind::Hinge,
        axis,
        anchor,
        origin: (parent_anchor - rotation * anchor, rotation),
    }
}

/// A slider in the tree's terms: the link turned as the joint holds it, and the anchors' gap
/// kept along the axis only.
fn slider_frame(j: &crate::constraint::Prismatic, first: bool, seen: &Seen) -> TreeJoint {
    // relative_orientation turns body 1's frame into body 2's.
    let held = dq(j.relative_orientation);
    let (axis, anchor, parent_anchor, turn) = if first {
        let axis = held.inverse() * d3(j.local_axis2);
        (axis, j.local_anchor1, j.local_anchor2, held)
    } else {
        let turn = held.inverse();
        (d3(j.local_axis2), j.local_anchor2, j.local_anchor1, turn)
    };
    let axis = axis.normalize();
    let parent_anchor = seen.point(d3(parent_anchor));
    let rotation = seen.base.map_or(turn, |(r, _)| (r * turn).normalize());
    let along = rotation * axis;
    let gap = seen.position + rotation * d3(anchor) - parent_anchor;
    let gap = along * gap.dot(along);
    TreeJoint {
        kind: TreeJointKind::Slider,
        axis,
        anchor: DVec3::ZERO,
        origin: (parent_anchor + gap - rotation * d3(anchor), rotation),
    }
}
