//! Ball-and-socket joint (the guide's `MdtBSJoint`, `MdtBclBSJoint`): removes 3 DOF.
//!
//! Math. With anchors `a₁ = x₁ + R₁p₁` and `a₂ = x₂ + R₂p₂` (p in body frames; for the world,
//! `p₂` is a world point), the constraint is `C = a₁ − a₂ = 0`. Its time derivative
//! `Ċ = v₁ + ω₁ × r₁ − v₂ − ω₂ × r₂` (r = a − x) gives, for each world axis `e`:
//! `J₁ = (e, r₁ × e)`, `J₂ = (−e, −(r₂ × e))`, `xi = e·C`, unbounded λ, zero target.
//! The λ of the three rows are the world components of the force on body 1 at the anchor.
//! Both lever arms are taken to the anchors' midpoint, so the force pair has no net moment.

use super::{Jacobian, Limit, Row, RowBody, RowContext, RowWriter};
use crate::math::{Quat, Real, Vec3, PI};

/// A ball-and-socket joint: a point of body 1 held at a point of body 2 (or of the world).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BallJoint {
    /// Anchor in body 1's frame.
    pub local_anchor1: Vec3,
    /// Anchor in body 2's frame (a world point when body 2 is the world).
    pub local_anchor2: Vec3,
    /// Optional twist, cone and segment limits (the guide's `MdtBSJointSetLimit`).
    pub limits: Option<BallLimits>,
}

/// The optional angular limits of a ball joint (the guide's ρ twist, θ cone, φ segment), about
/// a primary axis fixed in each body (the axes coincide when the limits are set) and an
/// orthogonal axis of body 2 that zeroes the segment angle.
///
/// * **cone** θ = angle between the primary axes; `θ̇ = (ω₁ − ω₂)·(m × n)/sin θ`;
/// * **segment** φ = longitude of body 1's primary axis about body 2's, from the orthogonal axis
///   `o`: with `x = o·n`, `y = (m × o)·n`, `φ = atan2(y, x)` and
///   `φ̇ = (ω₁ − ω₂)·(x (n × (m × o)) − y (n × o))/(x² + y²)`;
/// * **twist** ρ = rotation of body 1 about its primary axis relative to body 2 (swing-twist
///   split of the relative rotation since the limits were set, about body 1's axis);
///   its rate is `(ω₁ − ω₂)·g` with `g` the swing-twist split's exact gradient (the primary
///   axis `n` for a pure twist, tilted by a large swing).
///
/// Each coordinate has a [`Limit`]: stops (hard or soft) and, if wanted, a motor.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BallLimits {
    /// Primary axis, body 1's frame.
    pub primary1: Vec3,
    /// Primary axis, body 2's frame.
    pub primary2: Vec3,
    /// Orthogonal axis (⊥ primary), body 1's frame: the twist is zero where it lies along
    /// body 2's orthogonal axis as both were when the axes were set (zero in snapshots made
    /// before it was kept: read through [`BallLimits::orthogonal1`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub orthogonal1: Vec3,
    /// Orthogonal axis (⊥ primary), body 2's frame: where the segment angle is zero.
    pub orthogonal2: Vec3,
    /// Relative orientation `q₂⁻¹ q₁` when the limits were set (zero twist).
    pub reference: Quat,
    /// Twist (ρ) limit and motor.
    pub twist: Limit,
    /// Cone (θ) limit; only its upper stop matters (θ ≥ 0).
    pub cone: Limit,
    /// Segment (φ) limit and motor.
    pub segment: Limit,
}

impl BallLimits {
    /// Limits about world unit `primary` with world unit `orthogonal` (⊥), for bodies at the
    /// given states; every limit starts off.
    #[must_use]
    pub fn new(ctx: &RowContext, primary: Vec3, orthogonal: Vec3) -> Self {
        let [b1, b2] = &ctx.bodies;
        Self {
            primary1: b1.orientation.inverse() * primary,
            primary2: b2.orientation.inverse() * primary,
            orthogonal1: b1.orientation.inverse() * orthogonal,
            orthogonal2: b2.orientation.inverse() * orthogonal,
            reference: b2.orientation.inverse() * b1.orientation,
            twist: Limit::default(),
            cone: Limit::default(),
            segment: Limit::default(),
        }
    }

    /// Body 1's orthogonal axis in its frame (for limits from before it was kept: the one
    /// that lay along body 2's when the axes were set).
    #[must_use]
    pub fn orthogonal1(&self) -> Vec3 {
        if self.orthogonal1 == Vec3::ZERO {
            self.reference.inverse() * self.orthogonal2
        } else {
            self.orthogonal1
        }
    }

    /// Turns body 1's orthogonal axis to `axis` (body 1's frame, unit, ⊥ its primary axis):
    /// the twist's zero turns with it, so that the twist reads zero where the new axis lies
    /// along body 2's orthogonal axis as it was when the axes were set.
    pub(crate) fn turn_orthogonal1(&mut self, axis: Vec3) {
        let p = self.primary1;
        let old = self.orthogonal1();
        let turn = p.dot(old.cross(axis)).atan2(old.dot(axis));
        self.reference = (self.reference * Quat::from_axis_angle(p, -turn)).normalize();
        self.orthogonal1 = axis;
    }

    /// (coordinate, rate, Jacobian) for twist, cone and segment at a state.
    fn coordinates(&self, b1: &RowBody, b2: &RowBody) -> [(Real, Real, [Jacobian; 2]); 3] {
        let n = b1.vector_to_world(self.primary1);
        let m = b2.vector_to_world(self.primary2);
        let o = b2.vector_to_world(self.orthogonal2);
        let jac = |g: Vec3| [Jacobian::new(Vec3::ZERO, g), Jacobian::new(Vec3::ZERO, -g)];
        let rel = b1.angular_velocity - b2.angular_velocity;
        // Twist: the relative rotation since the reference, split about the primary axis.
        let q = self.reference.inverse() * (b2.orientation.inverse() * b1.orientation);
        let v = Vec3::new(q.x, q.y, q.z);
        // q = rot(primary1, ρ) for a pure twist: it is expressed in body 1's frame.
        let twist = 2.0 * v.dot(self.primary1).atan2(q.w);
        let twist = if twist > PI {
            twist - 2.0 * PI
        } else if twist < -PI {
            twist + 2.0 * PI
        } else {
            twist
        };
        // Its rate: with `q̇ = ½ q ⊗ ω_b` (ω_b the relative spin in body 1's frame), ρ̇ = g·ω_b
        // with g = (w² p + w p×v + (v·p) v)/((v·p)² + w²): the primary axis itself only for a
        // pure twist. Past a large swing (a shoulder) the primary axis alone stops the wrong
        // rotation and the twist runs through its stop.
        let p1 = self.primary1;
        let (a, w) = (v.dot(p1), q.w);
        let den = a * a + w * w;
        let twist_axis = if den > 1.0e-6 {
            b1.vector_to_world((p1 * (w * w) + p1.cross(v) * w + v * a) / den)
        } else {
            n
        };
        // Cone.
        let axis = m.cross(n);
        let sin = axis.length();
        let cone = sin.atan2(n.dot(m));
        let k = if sin > 1.0e-6 { axis / sin } else { Vec3::ZERO };
        // Segment.
        let p = m.cross(o);
        let (x, y) = (o.dot(n), p.dot(n));
        let r2 = x * x + y * y;
        let g = if r2 > 1.0e-12 {
            (n.cross(p) * x - n.cross(o) * y) / r2
        } else {
            Vec3::ZERO
        };
        [
            (twist, rel.dot(twist_axis), jac(twist_axis)),
            (cone, rel.dot(k), jac(k)),
            (y.atan2(x), rel.dot(g), jac(g)),
        ]
    }

    fn write_rows(&self, b1: &RowBody, b2: &RowBody, dt: Real, out: &mut RowWriter<'_>) {
        let [(t, tv, tj), (c, cv, cj), (s, sv, sj)] = self.coordinates(b1, b2);
        self.twist.write_rows(t, tv, tj, dt, out);
        if cj[0].angular != Vec3::ZERO {
            self.cone.write_rows(c, cv, cj, dt, out);
        }
        if sj[0].angular != Vec3::ZERO {
            self.segment.write_rows(s, sv, sj, dt, out);
        }
    }

    pub(crate) fn commit(&mut self, b1: &RowBody, b2: &RowBody) {
        let [(t, tv, _), (c, cv, _), (s, sv, _)] = self.coordinates(b1, b2);
        self.twist.record(t, tv);
        self.cone.record(c, cv);
        self.segment.record(s, sv);
    }
}

impl BallJoint {
    /// Writes the three rows for the current body states.
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        let a1 = b1.point_to_world(self.local_anchor1);
        let a2 = b2.point_to_world(self.local_anchor2);
        write_anchor_rows(b1, b2, a1, a2, ctx.dt, out);
        if let Some(l) = &self.limits {
            l.write_rows(b1, b2, ctx.dt, out);
        }
    }

    pub(crate) fn commit(&mut self, ctx: &RowContext) {
        if let Some(l) = &mut self.limits {
            l.commit(&ctx.bodies[0], &ctx.bodies[1]);
        }
    }

    /// The joint's anchor on body 1 and on body 2, world frame.
    #[must_use]
    pub fn world_anchors(&self, ctx: &RowContext) -> (Vec3, Vec3) {
        (
            ctx.bodies[0].point_to_world(self.local_anchor1),
            ctx.bodies[1].point_to_world(self.local_anchor2),
        )
    }
}

/// The anchor rows of [`write_anchor_rows`] for anchors given in each body's frame.
pub fn write_anchor_rows_local(
    ctx: &RowContext,
    (local1, local2): (Vec3, Vec3),
    out: &mut RowWriter<'_>,
) {
    let [b1, b2] = &ctx.bodies;
    let (a1, a2) = (b1.point_to_world(local1), b2.point_to_world(local2));
    write_anchor_rows(b1, b2, a1, a2, ctx.dt, out);
}

/// The three rows of any joint that holds anchor `a1` of body 1 on anchor `a2` of body 2,
/// over a step of `h` (for their curvature, [`Row::curvature`]).
///
/// Both bodies are pushed at the same point, the anchors' midpoint: the joint's force on the
/// pair then has no net moment even while the anchors are apart, so the pair's angular momentum
/// is kept (a first-order change of the Jacobian, of the size of the gap, that the error term
/// corrects anyway). A joint to the world, or one torn far apart, keeps its own anchors.
pub fn write_anchor_rows(
    b1: &RowBody,
    b2: &RowBody,
    a1: Vec3,
    a2: Vec3,
    h: Real,
    out: &mut RowWriter<'_>,
) {
    let (r1, r2) = (a1 - b1.position, a2 - b2.position);
    let gap = (a1 - a2).length();
    let reach = r1.length().max(r2.length());
    let (r1, r2) = if b2.dynamic && gap <= 0.1 * reach {
        let mid = 0.5 * (a1 + a2);
        (mid - b1.position, mid - b2.position)
    } else {
        (r1, r2)
    };
    let first = out.len();
    write_point_rows(r1, r2, a1 - a2, out);
    // The anchors' centripetal accelerations: the rows' J̇·v (see `Row::curvature`), while
    // a step turns the bodies little enough for the chord to be a second-order correction.
    let (w1, w2) = (b1.angular_velocity, b2.angular_velocity);
    let turn = w1.length().max(w2.length()) * h;
    let weight = ((CHORD_TURN_END - turn) / (CHORD_TURN_END - CHORD_TURN_FULL)).clamp(0.0, 1.0);
    if weight > 0.0 {
        let k = w1.cross(w1.cross(r1)) - w2.cross(w2.cross(r2));
        out.set_curvatures(first, (weight * k).to_array());
    }
}

/// Up to this turn of either body in one step (rad) an anchor's rows carry their whole
/// curvature; from it to [`CHORD_TURN_END`] less and less, and past it none. The chord is a
/// second-order correction: a link whipped at a radian and more a step (the tip of a
/// released chain at 60 Hz) is past what one linearisation follows, and the term there fed
/// the motion until the chain tore.
const CHORD_TURN_FULL: Real = 0.25;

/// See [`CHORD_TURN_FULL`].
const CHORD_TURN_END: Real = 0.5;

/// Writes the three rows that hold a point of body 1 (lever arm `r1`) on a point of body 2
/// (lever arm `r2`), with current separation `error = a₁ − a₂`. Shared by every joint that
/// removes the three translations.
pub fn write_point_rows(r1: Vec3, r2: Vec3, error: Vec3, out: &mut RowWriter<'_>) {
    for (axis, xi) in [(Vec3::X, error.x), (Vec3::Y, error.y), (Vec3::Z, error.z)] {
        out.push(
            Row::new(
                Jacobian::new(axis, r1.cross(axis)),
                Jacobian::new(-axis, -r2.cross(axis)),
            )
            .with_error(xi),
        );
    }
}
