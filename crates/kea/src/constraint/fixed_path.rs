//! Fixed-path joints (the guide's `MdtFixedPath` and `MdtFPFOJoint`): a point of body 1 follows a
//! path point that the user moves every step, with its velocity, to attach simulated bodies to
//! animation. 3 DOF removed; with a fixed orientation, 6.
//!
//! Rows: for each world axis `e`, `J₁ = (e, r₁ × e)`, `J₂ = (−e, −r₂ × e)`, `xi = (a₁ − p)·e`,
//! target velocity `c = ṗ·e` (the path's own velocity, relative to body 2), so the point moves
//! with the path within the step instead of lagging behind it, and γ = 1; then, optionally, the
//! orientation rows of [`super::joint::write_orientation_rows`].

use super::ball::write_point_rows;
use super::joint::write_orientation_rows;
use super::{RowContext, RowWriter};
use crate::math::{Quat, Vec3};

/// A point of body 1 driven along a path given in body 2's frame (the world's, when body 2 is
/// the world).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FixedPath {
    /// The driven point, in body 1's frame.
    pub local_anchor1: Vec3,
    /// Where the path is now, in body 2's frame.
    pub path_position: Vec3,
    /// The path's velocity, in body 2's frame.
    pub path_velocity: Vec3,
    /// Relative orientation `q₂⁻¹ q₁` to hold as well (fixed-path-fixed-orientation), if any.
    pub orientation: Option<Quat>,
}

impl FixedPath {
    /// A path joint whose path starts at world `anchor`, at rest; with `fixed_orientation` it
    /// also holds the bodies' current relative orientation.
    #[must_use]
    pub fn new(ctx: &RowContext, anchor: Vec3, fixed_orientation: bool) -> Self {
        let [b1, b2] = &ctx.bodies;
        Self {
            local_anchor1: b1.orientation.inverse() * (anchor - b1.position),
            path_position: b2.orientation.inverse() * (anchor - b2.position),
            path_velocity: Vec3::ZERO,
            orientation: fixed_orientation.then(|| b2.orientation.inverse() * b1.orientation),
        }
    }

    /// Writes 3 rows (6 with a fixed orientation).
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        let a1 = b1.point_to_world(self.local_anchor1);
        let p = b2.point_to_world(self.path_position);
        let first = out.len();
        write_point_rows(a1 - b1.position, p - b2.position, a1 - p, out);
        let v = b2.vector_to_world(self.path_velocity);
        // The path is kinematic: its whole error is corrected each step (γ = 1), so the point
        // lags only by the path's own curvature, h²·a/2, instead of h²·a/(2γ).
        out.set_targets(first, [v.x, v.y, v.z], Some(1.0));
        if let Some(q) = self.orientation {
            write_orientation_rows(b1, b2, q, out);
        }
    }
}
