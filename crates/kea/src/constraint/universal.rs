//! Universal joint (the guide's `MdtUniversal`, `MdtBclUnivJoint`): removes 4 DOF. The anchor
//! point (3 rows) and one row keeping axis `u₁` of body 1 perpendicular to axis `u₂` of body 2:
//! `C = u₁·u₂`, `J = (0, u₁ × u₂), (0, −u₁ × u₂)` (two hinges back to back, torque transmitted
//! about the third direction).

use super::ball::write_anchor_rows_local;
use super::{Jacobian, Row, RowContext, RowWriter};
use crate::math::Vec3;

/// A universal joint between body 1 and body 2 (or the world).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct UniversalJoint {
    /// Anchor in body 1's frame.
    pub local_anchor1: Vec3,
    /// Anchor in body 2's frame.
    pub local_anchor2: Vec3,
    /// Axis of body 1, its frame.
    pub local_axis1: Vec3,
    /// Axis of body 2, its frame.
    pub local_axis2: Vec3,
}

impl UniversalJoint {
    /// A universal joint at world `anchor` with world unit axes `axis1` (body 1) and `axis2`
    /// (body 2), which must be perpendicular.
    #[must_use]
    pub fn new(ctx: &RowContext, anchor: Vec3, axis1: Vec3, axis2: Vec3) -> Self {
        let [b1, b2] = &ctx.bodies;
        Self {
            local_anchor1: b1.orientation.inverse() * (anchor - b1.position),
            local_anchor2: b2.orientation.inverse() * (anchor - b2.position),
            local_axis1: b1.orientation.inverse() * axis1,
            local_axis2: b2.orientation.inverse() * axis2,
        }
    }
    /// Writes the four rows.
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        write_anchor_rows_local(ctx, (self.local_anchor1, self.local_anchor2), out);
        let [b1, b2] = &ctx.bodies;
        let u1 = b1.vector_to_world(self.local_axis1);
        let u2 = b2.vector_to_world(self.local_axis2);
        let c = u1.cross(u2);
        out.push(
            Row::new(Jacobian::new(Vec3::ZERO, c), Jacobian::new(Vec3::ZERO, -c))
                .with_error(u1.dot(u2)),
        );
    }
}
