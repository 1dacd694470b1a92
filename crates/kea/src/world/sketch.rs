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
        let at = Poses {
            world: self,
            bodies: [b1, b2],
            kind: entry.kind.name(),
        };
        match &entry.kind {
            ConstraintKind::Contact(_) => Err(wrong_kind(h, "joint", "contact")),
            ConstraintKind::Custom(_) => Ok(None),
            kind => Ok(at.sketch(kind)),
        }
    }
}

/// A joint's two bodies at their present poses, turning its body-frame geometry into the
/// world frame.
struct Poses<'a> {
    world: &'a World,
    bodies: [Option<BodyHandle>; 2],
    kind: &'static str,
}

impl Poses<'_> {
    /// Body `side`'s point `p` in the world (the static world's points are world points).
    fn point(&self, side: usize, p: Vec3) -> Vec3 {
        match self.bodies[side].and_then(|b| self.world.body(b).ok()) {
            Some(body) => body.point_to_world(p),
            None => p,
        }
    }

    /// Body `side`'s direction `v` in the world, unit.
    fn vector(&self, side: usize, v: Vec3) -> Vec3 {
        match self.bodies[side].and_then(|b| self.world.body(b).ok()) {
            Some(body) => (body.orientation() * v).normalize_or_zero(),
            None => v.normalize_or_zero(),
        }
    }

    fn with(
        &self,
        anchors: (Vec3, Vec3),
        axes: [Option<Vec3>; 2],
        range: Option<JointRange>,
    ) -> JointSketch {
        JointSketch {
            kind: self.kind,
            anchors: [self.point(0, anchors.0), self.point(1, anchors.1)],
            axes,
            range,
        }
    }

    /// The sketch of a joint; `None` for a contact or a custom constraint.
    fn sketch(&self, kind: &ConstraintKind) -> Option<JointSketch> {
        Some(match kind {
            ConstraintKind::Ball(j) => {
                let range = j.limits.as_ref().and_then(|l| {
                    let (_, upper) = stops(&l.cone)?;
                    Some(JointRange::Cone {
                        axis: self.vector(1, l.primary2),
                        half_angle: upper,
                        now: self.vector(0, l.primary1),
                    })
                });
                self.with((j.local_anchor1, j.local_anchor2), [None, None], range)
            }
            ConstraintKind::Hinge(j) => {
                let range = stops(j.limit()).map(|stops| JointRange::Angle {
                    zero: self.vector(1, j.local_ref2),
                    stops,
                    now: j.angle(),
                });
                let axis = Some(self.vector(1, j.local_axis2));
                self.with((j.local_anchor1, j.local_anchor2), [axis, None], range)
            }
            ConstraintKind::Prismatic(j) => {
                let range = stops(j.limit()).map(|stops| JointRange::Slide {
                    stops,
                    now: j.distance(),
                });
                let axis = Some(self.vector(1, j.local_axis2));
                self.with((j.local_anchor1, j.local_anchor2), [axis, None], range)
            }
            ConstraintKind::Fixed(j) => {
                self.with((j.local_anchor1, j.local_anchor2), [None, None], None)
            }
            ConstraintKind::Universal(j) => {
                let axes = [
                    Some(self.vector(0, j.local_axis1)),
                    Some(self.vector(1, j.local_axis2)),
                ];
                self.with((j.local_anchor1, j.local_anchor2), axes, None)
            }
            ConstraintKind::Linear1(j) => {
                let axis = Some(self.vector(1, j.local_normal2));
                self.with((j.local_anchor1, j.local_anchor2), [axis, None], None)
            }
            ConstraintKind::Planar(j) => {
                let axis = Some(self.vector(1, j.local_normal2));
                self.with((j.local_anchor1, j.local_anchor2), [axis, None], None)
            }
            ConstraintKind::Linear2(j) => {
                let axis = Some(self.vector(1, j.local_direction2));
                self.with((j.local_anchor1, j.local_anchor2), [axis, None], None)
            }
            ConstraintKind::Path(j) => JointSketch {
                kind: self.kind,
                anchors: [self.point(0, j.local_anchor1), j.path_position],
                axes: [None, None],
                range: None,
            },
            ConstraintKind::Wheel(j) => {
                // The wheel's anchor is its centre: body 2's origin.
                let axes = [
                    Some(self.vector(0, j.local_steering1)),
                    Some(self.vector(1, j.local_axle2)),
                ];
                self.with((j.local_anchor1, Vec3::ZERO), axes, None)
            }
            ConstraintKind::Contact(_) | ConstraintKind::Custom(_) => return None,
        })
    }
}
