//! Linear2 joint (the guide's `MdtLinear2`, the cylindrical joint): a point of body 1 stays on a
//! line fixed in body 2. 2 DOF removed; sliding along the line and all rotation are free. Two rows
//! from [`super::joint::write_plane_rows`], along two perpendiculars of the line.

use super::joint::{perpendiculars, write_plane_rows};
use super::{RowContext, RowWriter};
use crate::math::Vec3;

/// Keeps a point of body 1 on a line of body 2.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Linear2 {
    /// The point, in body 1's frame.
    pub local_anchor1: Vec3,
    /// A point of the line, in body 2's frame.
    pub local_anchor2: Vec3,
    /// The line's unit direction, in body 2's frame.
    pub local_direction2: Vec3,
}

impl Linear2 {
    /// A joint whose line passes through world `anchor` along world unit `direction`.
    #[must_use]
    pub fn new(ctx: &RowContext, anchor: Vec3, direction: Vec3) -> Self {
        let [b1, b2] = &ctx.bodies;
        Self {
            local_anchor1: b1.orientation.inverse() * (anchor - b1.position),
            local_anchor2: b2.orientation.inverse() * (anchor - b2.position),
            local_direction2: b2.orientation.inverse() * direction,
        }
    }

    /// Writes the two rows.
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        let a1 = b1.point_to_world(self.local_anchor1);
        let a2 = b2.point_to_world(self.local_anchor2);
        let d = b2.vector_to_world(self.local_direction2);
        write_plane_rows(b1, b2, a1, a2, &perpendiculars(d), out);
    }
}
