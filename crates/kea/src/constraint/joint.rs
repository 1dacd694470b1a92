//! Row builders shared by the joints: each removes one kind of relative motion, and a joint is a
//! composition of them.
//!
//! * **point** (3 rows, [`super::ball::write_point_rows`]): `a₁ = a₂`;
//! * **orientation** (3 rows): the relative orientation `q₂⁻¹ q₁` stays `q_rel`. With the error
//!   rotation `e` (world frame) that takes body 1 from its target to its current orientation,
//!   rows `J = (0, eₖ), (0, −eₖ)`, `xi = e·eₖ` for each world axis `eₖ`;
//! * **alignment** (2 rows): axis `u₁` of body 1 stays parallel to axis `u₂` of body 2: for two
//!   directions `p, q ⊥ u₂`, `J = (0, p), (0, −p)`, `xi = (u₂ × u₁)·p` (the small rotation that
//!   would align them);
//! * **on plane / on line** (1 or 2 rows): the point `a₁` of body 1 stays on a plane (normal `n`)
//!   or line of body 2: `C = (a₁ − a₂)·n`, `J₁ = (n, r₁ × n)`, `J₂ = (−n, −(a₁ − x₂) × n)` (the
//!   lever of body 2 reaches `a₁`, since `n` turns with body 2).

use super::{Jacobian, Row, RowBody, RowWriter};
use crate::math::{orthonormal_basis, Quat, Real, Vec3};

/// Three rows holding the relative orientation `q₂⁻¹ q₁` at `q_rel`.
pub fn write_orientation_rows(b1: &RowBody, b2: &RowBody, q_rel: Quat, out: &mut RowWriter<'_>) {
    // Target orientation of body 1 and the rotation from it to the current one, in world.
    let target = b2.orientation * q_rel;
    let mut d = b1.orientation * target.inverse();
    if d.w < 0.0 {
        d = -d;
    }
    let e = 2.0 * Vec3::new(d.x, d.y, d.z);
    for (axis, xi) in [(Vec3::X, e.x), (Vec3::Y, e.y), (Vec3::Z, e.z)] {
        out.push(
            Row::new(
                Jacobian::new(Vec3::ZERO, axis),
                Jacobian::new(Vec3::ZERO, -axis),
            )
            .with_error(xi),
        );
    }
}

/// Two rows keeping `u1` (body 1's axis, world) parallel to `u2` (body 2's, world), about the
/// two directions perpendicular to `free` (the axis left free: normally `u2`; a spinning
/// body's own axle when it has a fast-spin axis, see [`spin_axle`]).
///
/// The error is the rotation vector taking `u2` to `u1` (angle times unit axis), not the cross
/// product: the cross product's length, sin θ, falls back to zero as the axes turn past 90°
/// towards anti-parallel, which would make a hinge folded back on itself a false rest state
/// that stabilisation holds instead of undoing.
pub fn write_alignment_rows(u1: Vec3, u2: Vec3, free: Vec3, out: &mut RowWriter<'_>) {
    let (p, q) = orthonormal_basis(free);
    let cross = u2.cross(u1);
    let sin = cross.length();
    let angle = sin.atan2(u2.dot(u1));
    let e = if sin > 1.0e-6 {
        cross * (angle / sin)
    } else if angle > 1.0 {
        p * angle // anti-parallel: any perpendicular axis undoes it
    } else {
        cross
    };
    for d in [p, q] {
        out.push(
            Row::new(Jacobian::new(Vec3::ZERO, d), Jacobian::new(Vec3::ZERO, -d))
                .with_error(e.dot(d)),
        );
    }
}

/// The Jacobian of `(a₁ − a₂)·n` for a direction `n` fixed in body 2.
#[must_use]
pub fn relative_point_jacobian(b1: &RowBody, b2: &RowBody, a1: Vec3, n: Vec3) -> [Jacobian; 2] {
    [
        Jacobian::new(n, (a1 - b1.position).cross(n)),
        Jacobian::new(-n, -(a1 - b2.position).cross(n)),
    ]
}

/// Rows keeping `(a₁ − a₂)·n = 0` for each direction `n` in `normals` (fixed in body 2).
pub fn write_plane_rows(
    b1: &RowBody,
    b2: &RowBody,
    a1: Vec3,
    a2: Vec3,
    normals: &[Vec3],
    out: &mut RowWriter<'_>,
) {
    for &n in normals {
        let [j1, j2] = relative_point_jacobian(b1, b2, a1, n);
        out.push(Row::new(j1, j2).with_error((a1 - a2).dot(n)));
    }
}

/// Two directions perpendicular to the unit vector `u`.
#[must_use]
pub fn perpendiculars(u: Vec3) -> [Vec3; 2] {
    let (p, q) = orthonormal_basis(u);
    [p, q]
}

/// `J·v` for a row's Jacobian and its bodies' current velocities.
#[must_use]
pub fn rate(j: &[Jacobian; 2], b1: &RowBody, b2: &RowBody) -> Real {
    j[0].linear.dot(b1.linear_velocity)
        + j[0].angular.dot(b1.angular_velocity)
        + j[1].linear.dot(b2.linear_velocity)
        + j[1].angular.dot(b2.angular_velocity)
}

/// `x` wrapped into (−π, π].
#[must_use]
pub fn wrap_angle(x: Real) -> Real {
    let two_pi = 2.0 * crate::math::PI;
    let mut y = x % two_pi;
    if y > crate::math::PI {
        y -= two_pi;
    } else if y <= -crate::math::PI {
        y += two_pi;
    }
    y
}

/// The body's fast-spin axis when it is (nearly) the joint axis `u` it carries, oriented
/// along `u`: the free axis its joint should leave it.
#[must_use]
pub fn spin_axle(b: &RowBody, u: Vec3) -> Option<Vec3> {
    let a = b.fast_spin_axis?;
    let c = a.dot(u);
    (c.abs() > 0.9).then(|| if c > 0.0 { a } else { -a })
}
