//! Prismatic joint (the guide's `MdtPrismatic`, `MdtBclPrism`): removes 5 DOF, leaving
//! translation along one axis, with limits and a motor on the distance.
//!
//! Rows: the relative orientation (3, [`super::joint::write_orientation_rows`]) and the anchor of
//! body 1 on the line of body 2 (2, [`super::joint::write_plane_rows`] with the two directions
//! ⊥ axis); then the [`Limit`]'s motor and stops on the distance `d = (a₁ − a₂)·u` with
//! [`super::joint::relative_point_jacobian`].

use super::joint::{
    perpendiculars, rate, relative_point_jacobian, write_orientation_rows, write_plane_rows,
};
use super::{Limit, RowContext, RowWriter};
use crate::math::{Quat, Real, Vec3};

/// A slider between body 1 and body 2 (or the world).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Prismatic {
    /// Anchor in body 1's frame.
    pub local_anchor1: Vec3,
    /// Anchor in body 2's frame.
    pub local_anchor2: Vec3,
    /// Sliding axis in body 2's frame.
    pub local_axis2: Vec3,
    /// Relative orientation `q₂⁻¹ q₁` the joint keeps.
    pub relative_orientation: Quat,
    pub(crate) limit: Limit,
}

impl Prismatic {
    /// A slider through world `anchor` along world unit `axis`, for bodies at the given states;
    /// its distance starts at 0.
    #[must_use]
    pub fn new(ctx: &RowContext, anchor: Vec3, axis: Vec3) -> Self {
        let [b1, b2] = &ctx.bodies;
        Self {
            local_anchor1: b1.orientation.inverse() * (anchor - b1.position),
            local_anchor2: b2.orientation.inverse() * (anchor - b2.position),
            local_axis2: b2.orientation.inverse() * axis,
            relative_orientation: b2.orientation.inverse() * b1.orientation,
            limit: Limit::default(),
        }
    }
    /// The limits and motor on the distance.
    #[must_use]
    pub fn limit(&self) -> &Limit {
        &self.limit
    }
    /// Distance along the axis after the last step, m.
    #[must_use]
    pub fn distance(&self) -> Real {
        self.limit.position()
    }

    /// Distance and its rate at the given state.
    #[must_use]
    pub fn distance_and_rate(&self, ctx: &RowContext) -> (Real, Real) {
        let [b1, b2] = &ctx.bodies;
        let a1 = b1.point_to_world(self.local_anchor1);
        let a2 = b2.point_to_world(self.local_anchor2);
        let u = b2.vector_to_world(self.local_axis2);
        let j = relative_point_jacobian(b1, b2, a1, u);
        ((a1 - a2).dot(u), rate(&j, b1, b2))
    }

    /// Writes the slider's rows (5 + motor + active stops).
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        write_orientation_rows(b1, b2, self.relative_orientation, out);
        let a1 = b1.point_to_world(self.local_anchor1);
        let a2 = b2.point_to_world(self.local_anchor2);
        let u = b2.vector_to_world(self.local_axis2);
        write_plane_rows(b1, b2, a1, a2, &perpendiculars(u), out);
        let (d, v) = self.distance_and_rate(ctx);
        self.limit
            .write_rows(d, v, relative_point_jacobian(b1, b2, a1, u), ctx.dt, out);
    }

    pub(crate) fn commit(&mut self, ctx: &RowContext) {
        let (d, v) = self.distance_and_rate(ctx);
        self.limit.record(d, v);
    }
}
