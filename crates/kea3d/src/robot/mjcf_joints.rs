//! An MJCF body's joints as one Kea joint: one joint, two perpendicular slides, or two slides
//! and a hinge about their normal (a planar root, as in Hopper and Walker2d).

use super::spec::{Coordinate, JointType};
use super::xml::Source;
use super::ImportError;
use kea::Vec3;
use roxmltree::Node;

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
