//! Hinge (the guide's `MdtHinge`, `MdtBclHinge`): removes 5 DOF, leaving rotation about one
//! axis, with limits and a motor on the angle.
//!
//! Rows: the anchor point (3, [`super::ball::write_anchor_rows`]) and the axis alignment (2,
//! [`super::joint::write_alignment_rows`]); then the [`Limit`]'s motor and stops on the angle,
//! with `J = (0, u), (0, −u)` so that `J·v = θ̇ = (ω₁ − ω₂)·u`.
//!
//! The angle θ is body 1's reference direction measured from body 2's about the axis. It is
//! tracked continuously: each step unwraps the raw angle in (−π, π] against the last one, so
//! limits hold near and beyond ±π and over many turns (the guide's known weakness, fixed) as long
//! as the hinge turns less than half a turn per step.

use super::ball::write_anchor_rows;
use super::joint::{rate, spin_axle, wrap_angle, write_alignment_rows};
use super::{Jacobian, Limit, RowContext, RowWriter};
use crate::math::{orthonormal_basis, Real, Vec3};

/// A hinge between body 1 and body 2 (or the world).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Hinge {
    /// Anchor in body 1's frame.
    pub local_anchor1: Vec3,
    /// Anchor in body 2's frame (world point for the world).
    pub local_anchor2: Vec3,
    /// Axis in body 1's frame.
    pub local_axis1: Vec3,
    /// Axis in body 2's frame.
    pub local_axis2: Vec3,
    /// Reference direction (⊥ axis) in body 1's frame: the angle is measured from it.
    pub local_ref1: Vec3,
    /// Reference direction in body 2's frame.
    pub local_ref2: Vec3,
    pub(crate) angle: Real,
    pub(crate) limit: Limit,
}

impl Hinge {
    /// A hinge at world `anchor` about world unit `axis`, for bodies at the given states; its
    /// angle starts at 0.
    #[must_use]
    pub fn new(ctx: &RowContext, anchor: Vec3, axis: Vec3) -> Self {
        let [local_anchor1, local_anchor2] = ctx.local_points(anchor);
        let [local_axis1, local_axis2] = ctx.local_vectors(axis);
        let [local_ref1, local_ref2] = ctx.local_vectors(orthonormal_basis(axis).0);
        Self {
            local_anchor1,
            local_anchor2,
            local_axis1,
            local_axis2,
            local_ref1,
            local_ref2,
            angle: 0.0,
            limit: Limit::default(),
        }
    }
    /// The limits and motor on the angle.
    #[must_use]
    pub fn limit(&self) -> &Limit {
        &self.limit
    }
    /// The hinge angle after the last step, rad (continuous: may exceed ±π).
    #[must_use]
    pub fn angle(&self) -> Real {
        self.angle
    }
    /// The axis (world frame, body 2's) for the given state.
    #[must_use]
    pub fn axis(&self, ctx: &RowContext) -> Vec3 {
        ctx.bodies[1].vector_to_world(self.local_axis2)
    }

    /// The continuous angle and its rate at the given state.
    #[must_use]
    pub fn angle_and_rate(&self, ctx: &RowContext) -> (Real, Real) {
        let [b1, b2] = &ctx.bodies;
        let u = b2.vector_to_world(self.local_axis2);
        let r1 = b1.vector_to_world(self.local_ref1);
        let r2 = b2.vector_to_world(self.local_ref2);
        let raw = r2.cross(r1).dot(u).atan2(r1.dot(r2));
        let angle = self.angle + wrap_angle(raw - self.angle);
        let j = self.angle_jacobian(u);
        (angle, rate(&j, b1, b2))
    }

    fn angle_jacobian(&self, u: Vec3) -> [Jacobian; 2] {
        [Jacobian::new(Vec3::ZERO, u), Jacobian::new(Vec3::ZERO, -u)]
    }

    /// Writes the hinge's rows (5 + motor + active stops).
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        let a1 = b1.point_to_world(self.local_anchor1);
        let a2 = b2.point_to_world(self.local_anchor2);
        write_anchor_rows(b1, b2, a1, a2, ctx.dt, out);
        let u1 = b1.vector_to_world(self.local_axis1);
        let u2 = b2.vector_to_world(self.local_axis2);
        // The free axis: a spinning body's own axle when it has one (see `RowBody`).
        let free = spin_axle(b1, u1)
            .or_else(|| spin_axle(b2, u2))
            .unwrap_or(u2);
        write_alignment_rows(u1, u2, free, out);
        let (angle, rate) = self.angle_and_rate(ctx);
        self.limit
            .write_rows(angle, rate, self.angle_jacobian(u2), ctx.dt, out);
    }

    /// Records the angle reached by a step (the state after it).
    pub(crate) fn commit(&mut self, ctx: &RowContext) {
        let (angle, rate) = self.angle_and_rate(ctx);
        self.angle = angle;
        self.limit.record(angle, rate);
    }
}
