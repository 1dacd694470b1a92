//! Planar joint (URDF's `planar`; MJCF's two slides and a hinge in one body): a point of body 1
//! moves in a plane fixed in body 2, and body 1 turns only about the plane's normal — or not at
//! all. 3 DOF removed (4 without the turn).
//!
//! Rows: the point on the plane (1, [`super::joint::write_plane_rows`]), then the normal kept
//! aligned (2, [`super::joint::write_alignment_rows`]) or the relative orientation held (3,
//! [`super::joint::write_orientation_rows`]). Its coordinates — the point's travel along two
//! in-plane axes `e₁`, `e₂` of body 2 and the turn θ about the normal — each carry a
//! [`Limit`] (stops, motor, joint dynamics), on the Jacobians of `(a₁ − a₂)·eₖ` and of the
//! hinge angle.

use super::joint::{
    rate, relative_point_jacobian, wrap_angle, write_alignment_rows, write_orientation_rows,
    write_plane_rows,
};
use super::{Jacobian, Limit, RowContext, RowWriter};
use crate::math::{Quat, Real, Vec3};

/// A planar joint between body 1 and body 2 (or the world).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Planar {
    /// The moving point, in body 1's frame.
    pub local_anchor1: Vec3,
    /// A point of the plane, in body 2's frame.
    pub local_anchor2: Vec3,
    /// The plane's unit normal in body 1's frame.
    pub local_normal1: Vec3,
    /// The plane's unit normal in body 2's frame.
    pub local_normal2: Vec3,
    /// The first in-plane axis in body 2's frame (the second is `normal × first`).
    pub local_axis2: Vec3,
    /// The turn's reference direction in body 1's frame.
    pub local_ref1: Vec3,
    /// Relative orientation `q₂⁻¹ q₁` at creation (held when the joint does not turn).
    pub relative_orientation: Quat,
    /// Whether body 1 may turn about the normal.
    pub rotates: bool,
    pub(crate) angle: Real,
    pub(crate) limits: [Limit; 3],
}

impl Planar {
    /// A planar joint through world `anchor`, with world unit `normal` and first in-plane
    /// world unit `axis` (made perpendicular to the normal), turning about the normal when
    /// `rotates`; its coordinates start at 0.
    #[must_use]
    pub fn new(ctx: &RowContext, anchor: Vec3, normal: Vec3, axis: Vec3, rotates: bool) -> Self {
        let axis = (axis - normal * axis.dot(normal)).normalize();
        let [local_anchor1, local_anchor2] = ctx.local_points(anchor);
        let [local_normal1, local_normal2] = ctx.local_vectors(normal);
        let [local_ref1, local_axis2] = ctx.local_vectors(axis);
        Self {
            local_anchor1,
            local_anchor2,
            local_normal1,
            local_normal2,
            local_axis2,
            local_ref1,
            relative_orientation: ctx.bodies[1].orientation.inverse() * ctx.bodies[0].orientation,
            rotates,
            angle: 0.0,
            limits: [Limit::default(); 3],
        }
    }

    /// The limits, motor and dynamics of coordinate `k` (0, 1: the in-plane travels, m; 2: the
    /// turn, rad), or `None` past 2.
    #[must_use]
    pub fn limit(&self, k: usize) -> Option<&Limit> {
        self.limits.get(k)
    }

    /// Coordinate `k`'s limit, to change.
    pub fn limit_mut(&mut self, k: usize) -> Option<&mut Limit> {
        self.limits.get_mut(k)
    }

    /// The coordinates after the last step: two travels, m, and the turn, rad.
    #[must_use]
    pub fn coordinates(&self) -> [Real; 3] {
        [
            self.limits[0].position(),
            self.limits[1].position(),
            self.angle,
        ]
    }

    /// Each coordinate's value and rate at the given state (the turn unwrapped against the
    /// last step's).
    pub(crate) fn coordinates_and_rates(&self, ctx: &RowContext) -> [(Real, Real); 3] {
        self.coordinates_at(ctx).map(|(p, v, _)| (p, v))
    }

    /// Each coordinate's value, rate and Jacobian at the given state.
    fn coordinates_at(&self, ctx: &RowContext) -> [(Real, Real, [Jacobian; 2]); 3] {
        let [b1, b2] = &ctx.bodies;
        let a1 = b1.point_to_world(self.local_anchor1);
        let a2 = b2.point_to_world(self.local_anchor2);
        let n = b2.vector_to_world(self.local_normal2);
        let e1 = b2.vector_to_world(self.local_axis2);
        let e2 = n.cross(e1);
        let travel = |e: Vec3| {
            let j = relative_point_jacobian(b1, b2, a1, e);
            ((a1 - a2).dot(e), rate(&j, b1, b2), j)
        };
        let r1 = b1.vector_to_world(self.local_ref1);
        let raw = e1.cross(r1).dot(n).atan2(r1.dot(e1));
        let angle = self.angle + wrap_angle(raw - self.angle);
        let j = [Jacobian::new(Vec3::ZERO, n), Jacobian::new(Vec3::ZERO, -n)];
        [travel(e1), travel(e2), (angle, rate(&j, b1, b2), j)]
    }

    /// Writes the joint's rows (3 or 4, then each coordinate's drive and active stops).
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        let a1 = b1.point_to_world(self.local_anchor1);
        let a2 = b2.point_to_world(self.local_anchor2);
        let n2 = b2.vector_to_world(self.local_normal2);
        write_plane_rows(b1, b2, a1, a2, &[n2], out);
        if self.rotates {
            write_alignment_rows(b1.vector_to_world(self.local_normal1), n2, n2, out);
        } else {
            write_orientation_rows(b1, b2, self.relative_orientation, out);
        }
        let coords = self.coordinates_at(ctx);
        let used = if self.rotates { 3 } else { 2 };
        for (limit, (p, v, j)) in self.limits.iter().zip(coords).take(used) {
            limit.write_rows(p, v, j, ctx.dt, out);
        }
    }

    /// Records the coordinates reached by a step.
    pub(crate) fn commit(&mut self, ctx: &RowContext) {
        let coords = self.coordinates_at(ctx);
        self.angle = coords[2].0;
        for (limit, (p, v, _)) in self.limits.iter_mut().zip(coords) {
            limit.record(p, v);
        }
    }

    /// Records coordinates (value, rate) reached by a step taken elsewhere (the reduced path).
    pub(crate) fn record(&mut self, coordinates: [(Real, Real); 3]) {
        self.angle = coordinates[2].0;
        for (limit, (p, v)) in self.limits.iter_mut().zip(coordinates) {
            limit.record(p, v);
        }
    }

    /// Sets the turn the joint unwraps against (after its bodies were re-posed by hand).
    pub(crate) fn rebase(&mut self, angle: Real) {
        self.angle = angle;
        self.limits[2].record(angle, 0.0);
    }
}
