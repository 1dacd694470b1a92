//! An MJCF body's joints as one Kea joint: one joint, two perpendicular slides, or two slides
//! and a hinge about their normal (a planar root, as in Hopper and Walker2d); or, for any
//! other set of hinges and slides (a humanoid's hip: three hinges at one point), a chain of
//! single joints in the file's order through light links of their own, as MuJoCo composes them.

use super::spec::{Coordinate, Inertial, JointSpec, JointType, LinkSpec, Pose, RobotSpec};
use super::xml::Source;
use super::ImportError;
use kea::{Mat3, Quat, Vec3};
use roxmltree::Node;

/// The mass of a link carried between a body's joints, kg (MuJoCo's are massless; Kea's bodies
/// have mass), and its inertia's diagonal: far below any limb's, far above Kea's least.
pub(crate) const CHAIN_LINK_MASS: kea::Real = 1.0e-4;
const CHAIN_LINK_INERTIA: kea::Real = 1.0e-8;

/// A body's hinges and slides `parts` (two or more) as a chain of single joints from `parent`
/// to `link`, each carrying a light link of its own (added to `spec`, named
/// `<body>/<joint>`, marked so that the body's parent and the body do not collide, as MuJoCo's
/// parent and child do not): at zero every link's frame is the body's, so each joint keeps the
/// file's axis and point, and the body turns as MuJoCo turns it, joint after joint.
pub(crate) fn chain(
    spec: &mut RobotSpec,
    src: &Source<'_>,
    parts: &[JointPart<'_>],
    (parent, link): (usize, usize),
    origin: Pose,
) -> Vec<JointSpec> {
    let body = spec.links[link].name.clone();
    let mut joints = Vec::with_capacity(parts.len());
    let mut from = parent;
    for (k, (name, kind, coord, anchor, node)) in parts.iter().enumerate() {
        let child = if k + 1 == parts.len() {
            link
        } else {
            spec.links.push(LinkSpec {
                name: format!("{body}/{name}"),
                line: src.line(*node),
                inertial: Some(Inertial {
                    mass: CHAIN_LINK_MASS,
                    com: Vec3::ZERO,
                    inertia: Mat3::from_diagonal(Vec3::splat(CHAIN_LINK_INERTIA)),
                }),
                geoms: Vec::new(),
            });
            spec.chain_links.push(spec.links.len() - 1);
            spec.links.len() - 1
        };
        let kind = match (*kind, coord.limits) {
            ("slide", _) => JointType::Prismatic,
            (_, Some(_)) => JointType::Revolute,
            _ => JointType::Continuous,
        };
        joints.push(JointSpec {
            line: src.line(*node),
            name: name.clone(),
            parts: vec![name.clone()],
            kind,
            parent: from,
            child,
            origin: if k == 0 {
                origin
            } else {
                Pose::new(Vec3::ZERO, Quat::IDENTITY)
            },
            anchor: *anchor,
            coords: vec![*coord],
        });
        from = child;
    }
    spec.skipped.push(format!(
        "{}:{}: body \"{body}\": its {} joints as a chain of single joints through {} links of {CHAIN_LINK_MASS} kg (MuJoCo's are massless)",
        src.file.display(),
        parts.first().map_or(0, |p| src.line(p.4)),
        parts.len(),
        parts.len() - 1
    ));
    joints
}

/// One of a body's joints as the file gives it: name, type, coordinate, point, element.
pub(crate) type JointPart<'n> = (String, &'static str, Coordinate, Vec3, Node<'n, 'n>);

/// The Kea joint a body's joints make together, and its point: one joint, two perpendicular
/// slides, or two slides and a hinge about their normal; anything else is refused.
pub(crate) fn combined(
    src: &Source<'_>,
    body: Node<'_, '_>,
    parts: &[JointPart<'_>],
    parent: usize,
    link_name: &str,
) -> Result<(JointType, Vec3), ImportError> {
    let kinds: Vec<&str> = parts.iter().map(|p| p.1).collect();
    Ok(match kinds.as_slice() {
        [] => (JointType::Fixed, Vec3::ZERO),
        ["hinge"] => (
            if parts[0].2.limits.is_some() { JointType::Revolute } else { JointType::Continuous },
            parts[0].3,
        ),
        ["slide"] => (JointType::Prismatic, parts[0].3),
        ["ball"] => (JointType::Ball, parts[0].3),
        ["free"] => {
            if parent != 0 {
                return Err(src.error(parts[0].4, "a free joint belongs to a body at the top of the worldbody"));
            }
            (JointType::Free, Vec3::ZERO)
        }
        ["slide", "slide"] if perpendicular(parts[0].2.axis, parts[1].2.axis) => {
            (JointType::Slide2, parts[0].3)
        }
        ["slide", "slide", "hinge"]
            if perpendicular(parts[0].2.axis, parts[1].2.axis)
                && parts[2].2.axis.cross(parts[0].2.axis.cross(parts[1].2.axis)).length() < 1e-6 =>
        {
            (JointType::Planar, parts[2].3)
        }
        _ => {
            return Err(src.error(
                body,
                format!(
                    "{} joints in body \"{link_name}\" ({}): one joint, two perpendicular slides, or two slides and a hinge about their normal are supported",
                    parts.len(),
                    kinds.join(", ")
                ),
            ))
        }
    })
}

fn perpendicular(a: Vec3, b: Vec3) -> bool {
    a.dot(b).abs() < 1e-6
}
