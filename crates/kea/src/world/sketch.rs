//! What a joint looks like, for viewers: its anchors, axes and limit range in world
//! coordinates at the bodies' present poses. Drawing code needs this for every joint kind and
//! should not have to know each kind's fields.

use super::constraint_entry::ConstraintKind;
use super::constraints::wrong_kind;
use super::World;
use crate::constraint::Limit;
use crate::error::KeaResult;
use crate::handle::{BodyHandle, ConstraintHandle};
use crate::math::{Real, Vec3};

/// A joint's geometry in world coordinates, from [`World::joint_sketch`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointSketch {
    /// The joint's kind, as [`World::constraint_kind`] names it.
    pub kind: &'static str,
    /// Body 1's anchor and body 2's (or the world's, or a path's) anchor: together when the
    /// joint holds, apart by the joint's position error.
    pub anchors: [Vec3; 2],
    /// The joint's axes, unit: a hinge's or slider's axis first; a universal joint's or car
    /// wheel's second axis (the wheel's axle) second.
    pub axes: [Option<Vec3>; 2],
    /// The range its limits allow, when they are on.
    pub range: Option<JointRange>,
}

/// The range a joint's limits allow, and where the joint is in it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointRange {
    /// An angle about `axes[0]`, measured from `zero` (unit, ⊥ axis, fixed in body 2): the
    /// direction at angle θ is `zero` turned by θ about the axis.
    Angle {
        /// Where the angle is zero.
        zero: Vec3,
        /// Lower and upper stops, rad.
        stops: (Real, Real),
        /// The angle now, rad.
        now: Real,
    },
    /// A distance along `axes[0]` from body 2's anchor.
    Slide {
        /// Lower and upper stops, m.
        stops: (Real, Real),
        /// The distance now, m.
        now: Real,
    },
    /// A ball joint's cone: body 1's primary axis must stay within `half_angle` of body 2's.
    Cone {
        /// Body 2's primary axis, unit.
        axis: Vec3,
        /// The cone's half angle, rad.
        half_angle: Real,
        /// Body 1's primary axis now, unit.
        now: Vec3,
    },
}

fn stops(limit: &Limit) -> Option<(Real, Real)> {
    limit
        .is_limited()
        .then(|| (limit.lower().stop, limit.upper().stop))
}

impl World {
    /// Where joint `h` is and how it is set up, at the bodies' present poses; `None` for a
    /// custom constraint (its geometry is its own). Errors for a contact or a stale handle.
    pub fn joint_sketch(&self, h: impl Into<ConstraintHandle>) -> KeaResult<Option<JointSketch>> {
        let h = h.into();
        let entry = self.constraints.get(h)?;
        let [b1, b2] = entry.bodies;
        let point = |b: Option<BodyHandle>, p: Vec3| -> Vec3 {
            match b.and_then(|b| self.body(b).ok()) {
                Some(body) => body.point_to_world(p),
                None => p,
            }
        };
        let vector = |b: Option<BodyHandle>, v: Vec3| -> Vec3 {
            match b.and_then(|b| self.body(b).ok()) {
                Some(body) => (body.orientation() * v).normalize_or_zero(),
                None => v.normalize_or_zero(),
            }
        };
        let sketch = |anchors: (Vec3, Vec3), axes, range| JointSketch {
            kind: entry.kind.name(),
            anchors: [point(b1, anchors.0), point(b2, anchors.1)],
            axes,
            range,
        };
        Ok(Some(match &entry.kind {
            ConstraintKind::Contact(_) => return Err(wrong_kind(h, "joint", "contact")),
            ConstraintKind::Custom(_) => return Ok(None),
            ConstraintKind::Ball(j) => {
                let range = j.limits.as_ref().and_then(|l| {
                    let (_, upper) = stops(&l.cone)?;
                    Some(JointRange::Cone {
                        axis: vector(b2, l.primary2),
                        half_angle: upper,
                        now: vector(b1, l.primary1),
                    })
                });
                sketch((j.local_anchor1, j.local_anchor2), [None, None], range)
            }
            ConstraintKind::Hinge(j) => {
                let range = stops(j.limit()).map(|stops| JointRange::Angle {
                    zero: vector(b2, j.local_ref2),
                    stops,
                    now: j.angle(),
                });
                let axis = Some(vector(b2, j.local_axis2));
                sketch((j.local_anchor1, j.local_anchor2), [axis, None], range)
            }
            ConstraintKind::Prismatic(j) => {
                let range = stops(j.limit()).map(|stops| JointRange::Slide {
                    stops,
                    now: j.distance(),
                });
                let axis = Some(vector(b2, j.local_axis2));
                sketch((j.local_anchor1, j.local_anchor2), [axis, None], range)
            }
            ConstraintKind::Fixed(j) => {
                sketch((j.local_anchor1, j.local_anchor2), [None, None], None)
            }
            ConstraintKind::Universal(j) => {
                let axes = [
                    Some(vector(b1, j.local_axis1)),
                    Some(vector(b2, j.local_axis2)),
                ];
                sketch((j.local_anchor1, j.local_anchor2), axes, None)
            }
            ConstraintKind::Linear1(j) => {
                let axis = Some(vector(b2, j.local_normal2));
                sketch((j.local_anchor1, j.local_anchor2), [axis, None], None)
            }
            ConstraintKind::Planar(j) => {
                let axis = Some(vector(b2, j.local_normal2));
                sketch((j.local_anchor1, j.local_anchor2), [axis, None], None)
            }
            ConstraintKind::Linear2(j) => {
                let axis = Some(vector(b2, j.local_direction2));
                sketch((j.local_anchor1, j.local_anchor2), [axis, None], None)
            }
            ConstraintKind::Path(j) => JointSketch {
                kind: entry.kind.name(),
                anchors: [point(b1, j.local_anchor1), j.path_position],
                axes: [None, None],
                range: None,
            },
            ConstraintKind::Wheel(j) => {
                // The wheel's anchor is its centre: body 2's origin.
                let axes = [
                    Some(vector(b1, j.local_steering1)),
                    Some(vector(b2, j.local_axle2)),
                ];
                sketch((j.local_anchor1, Vec3::ZERO), axes, None)
            }
        }))
    }
}
