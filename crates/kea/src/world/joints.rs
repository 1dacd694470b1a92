//! The world's joint API: creating each joint of the guide from world-frame anchors and axes
//! (stored in each body's frame), and reaching their limits and motors.

use super::constraint_entry::ConstraintKind;
use super::constraints::wrong_kind;
use super::World;
use crate::constraint::ball::BallLimits;
use crate::constraint::{
    CarWheel, FixedJoint, FixedPath, Hinge, Limit, Linear1, Linear2, Planar, Prismatic, RowBody,
    RowContext, UniversalJoint,
};
use crate::error::{
    check_coordinate, check_finite, check_non_negative, check_positive, check_unit, check_vec3,
    KeaError, KeaResult,
};
use crate::handle::{BodyHandle, ConstraintHandle};
use crate::math::{Real, Vec3};

impl World {
    /// The row-writing view of two bodies at their current poses (for building joint frames).
    pub(super) fn pair_context(
        &self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
    ) -> KeaResult<RowContext> {
        let view = |h: BodyHandle| -> KeaResult<RowBody> {
            let b = self.bodies.get(h)?;
            Ok(RowBody::fixed(b.position(), b.orientation()))
        };
        Ok(RowContext {
            bodies: [view(body1)?, body2.map_or(Ok(RowBody::STATIC), view)?],
            dt: 1.0,
            epsilon: self.epsilon,
            gamma: self.gamma,
            contact_spring: self.contact_spring,
        })
    }

    /// Checks both bodies, builds the joint from their current poses, and inserts it: the shared
    /// tail of every `create_*` joint function.
    fn insert_joint(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        make: impl FnOnce(&RowContext) -> ConstraintKind,
    ) -> KeaResult<ConstraintHandle> {
        self.check_pair(body1, body2)?;
        let kind = make(&self.pair_context(body1, body2)?);
        self.insert_constraint(kind, body1, body2)
    }

    /// Creates a hinge at a world point about a world unit axis (the guide's `MdtHingeCreate`
    /// + `SetPosition` + `SetAxis`); its angle starts at 0.
    pub fn create_hinge(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        anchor: Vec3,
        axis: Vec3,
    ) -> KeaResult<ConstraintHandle> {
        check_coordinate("anchor", anchor)?;
        let axis = check_unit("axis", axis)?;
        self.insert_joint(body1, body2, |ctx| {
            ConstraintKind::Hinge(Hinge::new(ctx, anchor, axis))
        })
    }

    /// Creates a prismatic joint (slider) through a world point along a world unit axis; its
    /// distance starts at 0.
    pub fn create_prismatic(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        anchor: Vec3,
        axis: Vec3,
    ) -> KeaResult<ConstraintHandle> {
        check_coordinate("anchor", anchor)?;
        let axis = check_unit("axis", axis)?;
        self.insert_joint(body1, body2, |ctx| {
            ConstraintKind::Prismatic(Prismatic::new(ctx, anchor, axis))
        })
    }

    /// Creates a fixed joint (weld) at a world point, keeping the current relative orientation.
    pub fn create_fixed_joint(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        anchor: Vec3,
    ) -> KeaResult<ConstraintHandle> {
        check_coordinate("anchor", anchor)?;
        self.insert_joint(body1, body2, |ctx| {
            ConstraintKind::Fixed(FixedJoint::new(ctx, anchor))
        })
    }

    /// Creates a universal joint at a world point with perpendicular world unit axes
    /// `axis1` (body 1) and `axis2` (body 2).
    pub fn create_universal_joint(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        anchor: Vec3,
        axis1: Vec3,
        axis2: Vec3,
    ) -> KeaResult<ConstraintHandle> {
        check_coordinate("anchor", anchor)?;
        let axis1 = check_unit("axis1", axis1)?;
        let axis2 = check_unit("axis2", axis2)?;
        check_perpendicular("axis2", axis2, axis1, "must be perpendicular to axis1")?;
        self.insert_joint(body1, body2, |ctx| {
            ConstraintKind::Universal(UniversalJoint::new(ctx, anchor, axis1, axis2))
        })
    }

    /// Creates a Linear1 joint: the world point `anchor` of body 1 stays on the plane through it
    /// with world unit `normal`, fixed in body 2.
    pub fn create_linear1(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        anchor: Vec3,
        normal: Vec3,
    ) -> KeaResult<ConstraintHandle> {
        check_coordinate("anchor", anchor)?;
        let normal = check_unit("normal", normal)?;
        self.insert_joint(body1, body2, |ctx| {
            ConstraintKind::Linear1(Linear1::new(ctx, anchor, normal))
        })
    }

    /// Creates a Linear2 (cylindrical) joint: the world point `anchor` of body 1 stays on the
    /// line through it with world unit `direction`, fixed in body 2.
    pub fn create_linear2(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        anchor: Vec3,
        direction: Vec3,
    ) -> KeaResult<ConstraintHandle> {
        check_coordinate("anchor", anchor)?;
        let direction = check_unit("direction", direction)?;
        self.insert_joint(body1, body2, |ctx| {
            ConstraintKind::Linear2(Linear2::new(ctx, anchor, direction))
        })
    }

    /// Creates a fixed-path joint: the world point `anchor` of body 1 will follow a path set
    /// with [`World::set_path`] (3 DOF removed); with `fixed_orientation`, the bodies' current
    /// relative orientation is held too (the guide's fixed-path-fixed-orientation joint, 6 DOF).
    pub fn create_fixed_path(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        anchor: Vec3,
        fixed_orientation: bool,
    ) -> KeaResult<ConstraintHandle> {
        check_coordinate("anchor", anchor)?;
        self.insert_joint(body1, body2, |ctx| {
            ConstraintKind::Path(FixedPath::new(ctx, anchor, fixed_orientation))
        })
    }

    /// Moves a fixed-path joint's path point to world `position`, moving at world `velocity`
    /// (the guide's `MdtFixedPathSetPosition`/`SetVelocity`; give the velocity, or the point
    /// lags a step behind a moving path).
    pub fn set_path(
        &mut self,
        h: ConstraintHandle,
        position: Vec3,
        velocity: Vec3,
    ) -> KeaResult<()> {
        check_coordinate("position", position)?;
        check_vec3("velocity", velocity)?;
        let body2 = self.constraints.get(h)?.bodies[1];
        let (x2, q2) = match body2 {
            Some(b) => {
                let b = self.bodies.get(b)?;
                (b.position(), b.orientation())
            }
            None => (Vec3::ZERO, crate::math::Quat::IDENTITY),
        };
        match &mut self.constraints.get_mut(h)?.kind {
            ConstraintKind::Path(j) => {
                j.path_position = q2.inverse() * (position - x2);
                j.path_velocity = q2.inverse() * velocity;
                Ok(())
            }
            other => Err(wrong_kind(h, "fixed-path joint", other.name())),
        }
    }

    /// Creates a car wheel joint: `chassis` is body 1, `wheel` body 2, attached at the wheel's
    /// centre, with world unit `steering_axis` (the suspension slides along it) and world unit
    /// `axle` (⊥), a suspension spring of stiffness `k` (N/m, > 0) and damping `d` (N·s/m,
    /// ≥ 0). Steering starts locked.
    pub fn create_car_wheel(
        &mut self,
        chassis: BodyHandle,
        wheel: BodyHandle,
        steering_axis: Vec3,
        axle: Vec3,
        k: Real,
        d: Real,
    ) -> KeaResult<ConstraintHandle> {
        let s = check_unit("steering_axis", steering_axis)?;
        let u = check_unit("axle", axle)?;
        check_perpendicular("axle", u, s, "must be perpendicular to steering_axis")?;
        check_positive("k", k)?;
        check_non_negative("d", d)?;
        self.insert_joint(chassis, Some(wheel), |ctx| {
            ConstraintKind::Wheel(Box::new(CarWheel::new(ctx, s, u, k, d)))
        })
    }

    /// A car wheel joint, read-only.
    pub fn car_wheel(&self, h: ConstraintHandle) -> KeaResult<&CarWheel> {
        match &self.constraints.get(h)?.kind {
            ConstraintKind::Wheel(j) => Ok(j),
            other => Err(wrong_kind(h, "car wheel joint", other.name())),
        }
    }

    /// A car wheel joint, to set its steering lock, limits and motors.
    pub fn car_wheel_mut(&mut self, h: ConstraintHandle) -> KeaResult<&mut CarWheel> {
        match &mut self.constraints.get_mut(h)?.kind {
            ConstraintKind::Wheel(j) => Ok(j),
            other => Err(wrong_kind(h, "car wheel joint", other.name())),
        }
    }

    /// Sets up the ball joint's twist, cone and segment limits about world unit `primary` with
    /// world unit `orthogonal` (⊥) for the bodies' current poses (all limits start off; set them
    /// through [`World::ball_limits_mut`]).
    pub fn set_ball_limit_axes(
        &mut self,
        h: ConstraintHandle,
        primary: Vec3,
        orthogonal: Vec3,
    ) -> KeaResult<()> {
        let primary = check_unit("primary", primary)?;
        let orthogonal = check_unit("orthogonal", orthogonal)?;
        check_perpendicular(
            "orthogonal",
            orthogonal,
            primary,
            "must be perpendicular to primary",
        )?;
        let [b1, b2] = self.constraint_bodies(h)?;
        let ctx = self.pair_context(b1.expect("constraints have a first body"), b2)?;
        match &mut self.constraints.get_mut(h)?.kind {
            ConstraintKind::Ball(j) => {
                j.limits = Some(BallLimits::new(&ctx, primary, orthogonal));
                Ok(())
            }
            other => Err(wrong_kind(h, "ball joint", other.name())),
        }
    }

    /// A ball joint's angular limits, to set (after [`World::set_ball_limit_axes`]).
    pub fn ball_limits_mut(&mut self, h: ConstraintHandle) -> KeaResult<&mut BallLimits> {
        match &mut self.constraints.get_mut(h)?.kind {
            ConstraintKind::Ball(j) => j.limits.as_mut().ok_or(KeaError::InvalidState {
                operation: "ball_limits_mut",
                reason: "the joint has no limit axes; call set_ball_limit_axes first",
            }),
            other => Err(wrong_kind(h, "ball joint", other.name())),
        }
    }

    /// Resets a constraint to the guide's default table (`Mdt*Reset`), for its bodies' current
    /// poses: position at the world origin; hinge, prismatic and linear directions along +y;
    /// universal axes +x and +y; car wheel steering +y, axle +x; path at rest; relative
    /// orientations as they are now; limits and motors off; contacts to position 0, normal +y,
    /// no penetration, default parameters. Its γ override and breaking thresholds are cleared.
    /// Custom constraints have no table: an error, nothing changed.
    pub fn reset_constraint(&mut self, h: ConstraintHandle) -> KeaResult<()> {
        let [b1, b2] = self.constraint_bodies(h)?;
        let b1 = b1.expect("constraints have a first body");
        let ctx = self.pair_context(b1, b2)?;
        let o = Vec3::ZERO;
        let entry = self.constraints.get_mut(h)?;
        let kind = match &entry.kind {
            ConstraintKind::Contact(_) => {
                ConstraintKind::Contact(crate::constraint::Contact::default())
            }
            ConstraintKind::Ball(_) => {
                ConstraintKind::Ball(Box::new(crate::constraint::BallJoint {
                    local_anchor1: ctx.bodies[0].orientation.inverse()
                        * (o - ctx.bodies[0].position),
                    local_anchor2: ctx.bodies[1].orientation.inverse()
                        * (o - ctx.bodies[1].position),
                    limits: None,
                }))
            }
            ConstraintKind::Hinge(_) => ConstraintKind::Hinge(Hinge::new(&ctx, o, Vec3::Y)),
            ConstraintKind::Prismatic(_) => {
                ConstraintKind::Prismatic(Prismatic::new(&ctx, o, Vec3::Y))
            }
            ConstraintKind::Fixed(_) => ConstraintKind::Fixed(FixedJoint::new(&ctx, o)),
            ConstraintKind::Universal(_) => {
                ConstraintKind::Universal(UniversalJoint::new(&ctx, o, Vec3::X, Vec3::Y))
            }
            ConstraintKind::Linear1(_) => ConstraintKind::Linear1(Linear1::new(&ctx, o, Vec3::Y)),
            ConstraintKind::Planar(j) => {
                ConstraintKind::Planar(Planar::new(&ctx, o, Vec3::Y, Vec3::X, j.rotates))
            }
            ConstraintKind::Linear2(_) => ConstraintKind::Linear2(Linear2::new(&ctx, o, Vec3::Y)),
            ConstraintKind::Path(j) => {
                ConstraintKind::Path(FixedPath::new(&ctx, o, j.orientation.is_some()))
            }
            ConstraintKind::Wheel(w) => ConstraintKind::Wheel(Box::new(CarWheel::new(
                &ctx,
                Vec3::Y,
                Vec3::X,
                w.suspension_stiffness,
                w.suspension_damping,
            ))),
            ConstraintKind::Custom(_) => {
                return Err(KeaError::InvalidState {
                    operation: "reset_constraint",
                    reason: "a custom constraint has no default table",
                })
            }
        };
        entry.kind = kind;
        entry.gamma = None;
        entry.break_force = None;
        entry.break_torque = None;
        Ok(())
    }

    /// A fixed joint (weld), read-only.
    pub fn fixed_joint(&self, h: ConstraintHandle) -> KeaResult<&FixedJoint> {
        match &self.constraints.get(h)?.kind {
            ConstraintKind::Fixed(j) => Ok(j),
            other => Err(wrong_kind(h, "fixed joint", other.name())),
        }
    }

    /// Sets the relative orientation `q₂⁻¹ q₁` a fixed joint or a fixed-path-fixed-orientation
    /// joint holds (the guide's `MdtFPFOJointSetQuaternion`); `q` must be a unit quaternion.
    pub fn set_relative_orientation(
        &mut self,
        h: ConstraintHandle,
        q: crate::math::Quat,
    ) -> KeaResult<()> {
        let q = crate::error::check_quat("q", q)?;
        match &mut self.constraints.get_mut(h)?.kind {
            ConstraintKind::Fixed(j) => j.relative_orientation = q,
            ConstraintKind::Path(j) if j.orientation.is_some() => j.orientation = Some(q),
            other => {
                return Err(wrong_kind(
                    h,
                    "fixed or fixed-orientation joint",
                    other.name(),
                ))
            }
        }
        Ok(())
    }

    /// A fixed-path joint, read-only.
    pub fn fixed_path(&self, h: ConstraintHandle) -> KeaResult<&FixedPath> {
        match &self.constraints.get(h)?.kind {
            ConstraintKind::Path(j) => Ok(j),
            other => Err(wrong_kind(h, "fixed-path joint", other.name())),
        }
    }

    /// A universal joint, read-only.
    pub fn universal_joint(&self, h: ConstraintHandle) -> KeaResult<&UniversalJoint> {
        match &self.constraints.get(h)?.kind {
            ConstraintKind::Universal(j) => Ok(j),
            other => Err(wrong_kind(h, "universal joint", other.name())),
        }
    }

    /// A Linear1 joint, read-only.
    pub fn linear1_joint(&self, h: ConstraintHandle) -> KeaResult<&Linear1> {
        match &self.constraints.get(h)?.kind {
            ConstraintKind::Linear1(j) => Ok(j),
            other => Err(wrong_kind(h, "linear1 joint", other.name())),
        }
    }

    /// A Linear2 joint, read-only.
    pub fn linear2_joint(&self, h: ConstraintHandle) -> KeaResult<&Linear2> {
        match &self.constraints.get(h)?.kind {
            ConstraintKind::Linear2(j) => Ok(j),
            other => Err(wrong_kind(h, "linear2 joint", other.name())),
        }
    }

    /// A hinge, read-only.
    pub fn hinge(&self, h: ConstraintHandle) -> KeaResult<&Hinge> {
        match &self.constraints.get(h)?.kind {
            ConstraintKind::Hinge(j) => Ok(j),
            other => Err(wrong_kind(h, "hinge", other.name())),
        }
    }

    /// A hinge's limits and motor, to change.
    pub fn hinge_limit_mut(&mut self, h: ConstraintHandle) -> KeaResult<&mut Limit> {
        match &mut self.constraints.get_mut(h)?.kind {
            ConstraintKind::Hinge(j) => Ok(j.limit_mut()),
            other => Err(wrong_kind(h, "hinge", other.name())),
        }
    }

    /// Tells a hinge (or a planar joint, of its turn) the continuous angle it has now, rad,
    /// after its bodies were re-posed by hand (a robot set to new joint positions): the next
    /// step unwraps against it, so an angle past ±π is kept, and the limit's read-outs start
    /// from it (rate 0).
    pub fn rebase_joint_angle(&mut self, h: ConstraintHandle, angle: Real) -> KeaResult<()> {
        check_finite("angle", angle)?;
        match &mut self.constraints.get_mut(h)?.kind {
            ConstraintKind::Hinge(j) => {
                j.angle = angle;
                j.limit.record(angle, 0.0);
                Ok(())
            }
            ConstraintKind::Planar(j) => {
                j.rebase(angle);
                Ok(())
            }
            other => Err(wrong_kind(h, "hinge or planar joint", other.name())),
        }
    }

    /// Creates a planar joint: the world point `anchor` of body 1 moves in the plane through it
    /// with world unit `normal`, fixed in body 2; its first coordinate runs along world
    /// `axis` (in the plane), the second along `normal × axis`, and the third turns about the
    /// normal when `rotates` (else body 1 keeps its orientation).
    pub fn create_planar(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        anchor: Vec3,
        normal: Vec3,
        axis: Vec3,
        rotates: bool,
    ) -> KeaResult<ConstraintHandle> {
        check_coordinate("anchor", anchor)?;
        let normal = check_unit("normal", normal)?;
        let axis = check_unit("axis", axis)?;
        check_perpendicular("axis", axis, normal, "must be perpendicular to normal")?;
        self.insert_joint(body1, body2, |ctx| {
            ConstraintKind::Planar(Planar::new(ctx, anchor, normal, axis, rotates))
        })
    }

    /// A planar joint, read-only.
    pub fn planar_joint(&self, h: ConstraintHandle) -> KeaResult<&Planar> {
        match &self.constraints.get(h)?.kind {
            ConstraintKind::Planar(j) => Ok(j),
            other => Err(wrong_kind(h, "planar joint", other.name())),
        }
    }

    /// Coordinate `k`'s limits, motor and dynamics on a planar joint (0, 1: travels; 2: turn).
    pub fn planar_limit_mut(&mut self, h: ConstraintHandle, k: usize) -> KeaResult<&mut Limit> {
        match &mut self.constraints.get_mut(h)?.kind {
            ConstraintKind::Planar(j) => j.limit_mut(k).ok_or_else(|| KeaError::OutOfRange {
                arg: "k",
                value: format!("{k}"),
                expected: "a planar joint has coordinates 0, 1 and 2",
            }),
            other => Err(wrong_kind(h, "planar joint", other.name())),
        }
    }

    /// A prismatic joint, read-only.
    pub fn prismatic(&self, h: ConstraintHandle) -> KeaResult<&Prismatic> {
        match &self.constraints.get(h)?.kind {
            ConstraintKind::Prismatic(j) => Ok(j),
            other => Err(wrong_kind(h, "prismatic joint", other.name())),
        }
    }

    /// A prismatic joint's limits and motor, to change.
    pub fn prismatic_limit_mut(&mut self, h: ConstraintHandle) -> KeaResult<&mut Limit> {
        match &mut self.constraints.get_mut(h)?.kind {
            ConstraintKind::Prismatic(j) => Ok(j.limit_mut()),
            other => Err(wrong_kind(h, "prismatic joint", other.name())),
        }
    }
}

/// Checks that the unit vector `v` (argument `arg`) is perpendicular, within 1e-3, to `w`;
/// `expected` names `w` in the error.
fn check_perpendicular(
    arg: &'static str,
    v: Vec3,
    w: Vec3,
    expected: &'static str,
) -> KeaResult<()> {
    if v.dot(w).abs() > 1.0e-3 {
        return Err(KeaError::OutOfRange {
            arg,
            value: format!("{v}"),
            expected,
        });
    }
    Ok(())
}
