//! Ball-and-socket joint (the guide's `MdtBSJoint`, `MdtBclBSJoint`): removes 3 DOF.
//!
//! Math. With anchors `a₁ = x₁ + R₁p₁` and `a₂ = x₂ + R₂p₂` (p in body frames; for the world,
//! `p₂` is a world point), the constraint is `C = a₁ − a₂ = 0`. Its time derivative
//! `Ċ = v₁ + ω₁ × r₁ − v₂ − ω₂ × r₂` (r = a − x) gives, for each world axis `e`:
//! `J₁ = (e, r₁ × e)`, `J₂ = (−e, −(r₂ × e))`, `xi = e·C`, unbounded λ, zero target.
//! The λ of the three rows are the world components of the force on body 1 at the anchor.
//! Both lever arms are taken to the anchors' midpoint, so the force pair has no net moment.

use super::{Jacobian, Row, RowBody, RowContext, RowWriter};
use crate::math::Vec3;

/// A ball-and-socket joint: a point of body 1 held at a point of body 2 (or of the world).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BallJoint {
    /// Anchor in body 1's frame.
    pub local_anchor1: Vec3,
    /// Anchor in body 2's frame (a world point when body 2 is the world).
    pub local_anchor2: Vec3,
}

impl BallJoint {
    /// Number of rows the joint writes.
    pub const ROWS: usize = 3;

    /// Writes the three rows for the current body states.
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        let a1 = b1.point_to_world(self.local_anchor1);
        let a2 = b2.point_to_world(self.local_anchor2);
        write_anchor_rows(b1, b2, a1, a2, out);
    }

    /// The joint's anchor on body 1 and on body 2, world frame.
    #[must_use]
    pub fn world_anchors(&self, ctx: &RowContext) -> (Vec3, Vec3) {
        (
            ctx.bodies[0].point_to_world(self.local_anchor1),
            ctx.bodies[1].point_to_world(self.local_anchor2),
        )
    }
}

/// The three rows of any joint that holds anchor `a1` of body 1 on anchor `a2` of body 2.
///
/// Both bodies are pushed at the same point, the anchors' midpoint: the joint's force on the
/// pair then has no net moment even while the anchors are apart, so the pair's angular momentum
/// is kept (a first-order change of the Jacobian, of the size of the gap, that the error term
/// corrects anyway). A joint to the world, or one torn far apart, keeps its own anchors.
pub fn write_anchor_rows(b1: &RowBody, b2: &RowBody, a1: Vec3, a2: Vec3, out: &mut RowWriter<'_>) {
    let (r1, r2) = (a1 - b1.position, a2 - b2.position);
    let gap = (a1 - a2).length();
    let reach = r1.length().max(r2.length());
    if b2.dynamic && gap <= 0.1 * reach {
        let mid = 0.5 * (a1 + a2);
        write_point_rows(mid - b1.position, mid - b2.position, a1 - a2, out);
    } else {
        write_point_rows(r1, r2, a1 - a2, out);
    }
}

/// Writes the three rows that hold a point of body 1 (lever arm `r1`) on a point of body 2
/// (lever arm `r2`), with current separation `error = a₁ − a₂`. Shared by every joint that
/// removes the three translations.
pub fn write_point_rows(r1: Vec3, r2: Vec3, error: Vec3, out: &mut RowWriter<'_>) {
    for (axis, xi) in [(Vec3::X, error.x), (Vec3::Y, error.y), (Vec3::Z, error.z)] {
        out.push(
            Row::new(
                Jacobian::new(axis, r1.cross(axis)),
                Jacobian::new(-axis, -r2.cross(axis)),
            )
            .with_error(xi),
        );
    }
}
