//! Linear joints (the guide's `MdtLinear1` and `MdtLinear2`): a point of body 1 kept on a plane
//! of body 2 (1 DOF removed) or on a line of body 2 (2 DOF removed: the cylindrical joint).
//! Rows from [`super::joint::write_plane_rows`]; orientation is free.

use super::joint::{perpendiculars, write_plane_rows};
use super::{RowContext, RowWriter};
use crate::math::Vec3;

/// Keeps a point of body 1 on a plane (`on_line == false`, normal `local_direction2`) or a line
/// (`on_line == true`, direction `local_direction2`) of body 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearJoint {
    /// The point, in body 1's frame.
    pub local_anchor1: Vec3,
    /// A point of the plane or line, in body 2's frame.
    pub local_anchor2: Vec3,
    /// The plane's normal or the line's direction, in body 2's frame.
    pub local_direction2: Vec3,
    /// Line (Linear2) rather than plane (Linear1).
    pub on_line: bool,
}

impl LinearJoint {
    /// A joint through world `anchor` with world unit `direction`.
    #[must_use]
    pub fn new(ctx: &RowContext, anchor: Vec3, direction: Vec3, on_line: bool) -> Self {
        let [b1, b2] = &ctx.bodies;
        Self {
            local_anchor1: b1.orientation.inverse() * (anchor - b1.position),
            local_anchor2: b2.orientation.inverse() * (anchor - b2.position),
            local_direction2: b2.orientation.inverse() * direction,
            on_line,
        }
    }
    /// Writes one (plane) or two (line) rows.
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        let a1 = b1.point_to_world(self.local_anchor1);
        let a2 = b2.point_to_world(self.local_anchor2);
        let d = b2.vector_to_world(self.local_direction2);
        if self.on_line {
            write_plane_rows(b1, b2, a1, a2, &perpendiculars(d), out);
        } else {
            write_plane_rows(b1, b2, a1, a2, &[d], out);
        }
    }
}
