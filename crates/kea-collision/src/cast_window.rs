//! Keeps a shape cast against a height field bounded. parry walks the field cell by cell along
//! the cast's path, one step per cell, so a long path over fine cells (or a path that starts far
//! outside the field) could take any time. The path is first clipped to the field's bounds grown
//! by the other shape's; a path that still crosses too many cells is refused by name.

use crate::parry::math::Pose;
use crate::parry::shape::{HeightField, Shape as ParryShape};
use kea::{Real, Vec3};

/// Most height-field cells a shape cast may walk across.
pub const MAX_CAST_CELLS: Real = 1.0e5;

/// The part of a cast's time that can touch a height field.
pub(crate) enum Window {
    /// The path never comes near the field.
    Miss,
    /// The times `[start, end]` of the path that reach the field's bounds.
    Times(Real, Real),
    /// The clipped path still crosses this many cells.
    TooLong(Real),
}

/// Clips `other`, at `other_pose` and moving at `velocity` relative to the field for
/// `0 ≤ t ≤ max_time`, to the bounds of `field` at `field_pose`.
pub(crate) fn height_field_window(
    field: &HeightField,
    field_pose: &Pose,
    other: &dyn ParryShape,
    other_pose: &Pose,
    velocity: Vec3,
    max_time: Real,
) -> Window {
    let local_pose = field_pose.inv_mul(other_pose);
    let v = field_pose.rotation.inverse() * velocity;
    let shape_box = other.compute_aabb(&local_pose);
    let half = shape_box.half_extents();
    let start = shape_box.center();
    let bounded = half.max_element() <= 2.0 * kea::error::MAX_COORDINATE;
    if !(bounded && start.is_finite()) {
        // An unbounded shape (a plane, whose box parry makes huge): parry's cast between it
        // and a height field overflows its cell indices, so the pair is not cast.
        return Window::Miss;
    }
    let bounds = field.root_aabb();
    // A little slack, so that a path grazing the bounds still starts outside them.
    let slack = (half + bounds.half_extents()) * 0.01 + Vec3::splat(1.0e-6);
    let (lo, hi) = (bounds.mins - half - slack, bounds.maxs + half + slack);
    let (mut t0, mut t1) = (0.0 as Real, max_time);
    for axis in 0..3 {
        let (p, d) = (start[axis], v[axis]);
        if d == 0.0 {
            if p < lo[axis] || p > hi[axis] {
                return Window::Miss;
            }
            continue;
        }
        let (a, b) = ((lo[axis] - p) / d, (hi[axis] - p) / d);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    // (NaN times, from a degenerate pose, count as a miss.)
    if t0
        .partial_cmp(&t1)
        .is_none_or(|o| o == std::cmp::Ordering::Greater)
    {
        return Window::Miss;
    }
    let cell = field.cell_width().min(field.cell_height());
    let cells = (v.x.abs() + v.z.abs()) * (t1 - t0) / cell;
    if cells > MAX_CAST_CELLS || !cells.is_finite() {
        return Window::TooLong(cells);
    }
    Window::Times(t0, t1)
}
