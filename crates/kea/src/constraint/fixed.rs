//! Fixed joint (the guide's fixed-path-fixed-orientation `MdtFPFOJoint` used as a weld):
//! removes all 6 DOF. Rows: the anchor point (3) and the relative orientation (3).

use super::ball::write_anchor_rows_local;
use super::joint::write_orientation_rows;
use super::{RowContext, RowWriter};
use crate::math::{Quat, Vec3};

/// A weld between body 1 and body 2 (or the world).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FixedJoint {
    /// Anchor in body 1's frame.
    pub local_anchor1: Vec3,
    /// Anchor in body 2's frame.
    pub local_anchor2: Vec3,
    /// Relative orientation `q₂⁻¹ q₁` the joint keeps (settable: the guide's
    /// `MdtFPFOJointSetQuaternion`).
    pub relative_orientation: Quat,
}

impl FixedJoint {
    /// A weld at world `anchor`, keeping the bodies' current relative orientation.
    #[must_use]
    pub fn new(ctx: &RowContext, anchor: Vec3) -> Self {
        let [b1, b2] = &ctx.bodies;
        Self {
            local_anchor1: b1.orientation.inverse() * (anchor - b1.position),
            local_anchor2: b2.orientation.inverse() * (anchor - b2.position),
            relative_orientation: b2.orientation.inverse() * b1.orientation,
        }
    }
    /// Writes the six rows.
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        write_anchor_rows_local(ctx, (self.local_anchor1, self.local_anchor2), out);
        let [b1, b2] = &ctx.bodies;
        write_orientation_rows(b1, b2, self.relative_orientation, out);
    }
}
