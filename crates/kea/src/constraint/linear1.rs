//! Linear1 joint (the guide's `MdtLinear1`): a point of body 1 stays on a plane fixed in body 2.
//! 1 DOF removed; orientation and the two in-plane directions are free. One row from
//! [`super::joint::write_plane_rows`] along the plane's normal.

use super::joint::write_plane_rows;
use super::{RowContext, RowWriter};
use crate::math::Vec3;

/// Keeps a point of body 1 on a plane of body 2.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Linear1 {
    /// The point, in body 1's frame.
    pub local_anchor1: Vec3,
    /// A point of the plane, in body 2's frame.
    pub local_anchor2: Vec3,
    /// The plane's unit normal, in body 2's frame.
    pub local_normal2: Vec3,
}

impl Linear1 {
    /// A joint whose plane passes through world `anchor` with world unit `normal`.
    #[must_use]
    pub fn new(ctx: &RowContext, anchor: Vec3, normal: Vec3) -> Self {
        let [b1, b2] = &ctx.bodies;
        Self {
            local_anchor1: b1.orientation.inverse() * (anchor - b1.position),
            local_anchor2: b2.orientation.inverse() * (anchor - b2.position),
            local_normal2: b2.orientation.inverse() * normal,
        }
    }

    /// Writes the one row.
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        let a1 = b1.point_to_world(self.local_anchor1);
        let a2 = b2.point_to_world(self.local_anchor2);
        write_plane_rows(
            b1,
            b2,
            a1,
            a2,
            &[b2.vector_to_world(self.local_normal2)],
            out,
        );
    }
}
