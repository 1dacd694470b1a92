//! What a joint is made from: its kind, world-frame anchor and axes, and optionally its limits
//! and motor, checked whole before the world changes.

use super::constraint_entry::ConstraintKind;
use super::joint_handle::{JointHandle, JointKind, OneCoordinate};
use super::World;
use crate::constraint::{
    BallJoint, CarWheel, FixedJoint, FixedPath, Hinge, Limit, Linear1, Linear2, Planar, Prismatic,
    RowContext, SingleLimit, UniversalJoint,
};
use crate::error::{
    check_coordinate, check_non_negative, check_perpendicular, check_positive, check_unit,
};
use crate::error::{KeaError, KeaResult};
use crate::handle::BodyHandle;
use crate::math::{Real, Vec3};
use std::marker::PhantomData;

/// A joint's geometry, in the world frame at creation.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    Ball(Vec3),
    Hinge(Vec3, Vec3),
    Prismatic(Vec3, Vec3),
    Fixed(Vec3),
    Universal(Vec3, Vec3, Vec3),
    Linear1(Vec3, Vec3),
    Linear2(Vec3, Vec3),
    Planar {
        anchor: Vec3,
        normal: Vec3,
        axis: Vec3,
        rotates: bool,
    },
    FixedPath(Vec3, bool),
    CarWheel {
        steering: Vec3,
        axle: Vec3,
        k: Real,
        d: Real,
    },
}

/// A joint to create with [`World::create_joint`], made by a builder:
/// `JointSpec::hinge(anchor, axis).limits(-1.0, 1.0)`.
///
/// Anchors and axes are in the world frame at creation, as in the guide; the joint stores
/// them in each body's frame. Every value is checked when the joint is created, and a refused
/// joint changes nothing.
///
/// ```
/// use kea::{BodyDef, Hinge, JointSpec, Vec3, World};
///
/// let mut world = World::with_capacity(4, 4)?;
/// let door = world.create_body(&BodyDef { position: Vec3::new(0.5, 1.0, 0.0), ..BodyDef::default() })?;
/// let hinge = world.create_joint(door, None, JointSpec::hinge(Vec3::Y, Vec3::Y).motor(1.0, 50.0))?;
/// for _ in 0..30 {
///     world.step(1.0 / 60.0)?;
/// }
/// let angle = hinge.angle(&world)?;
/// assert!((angle - 0.5).abs() < 0.02, "turned at 1 rad/s for 0.5 s: {angle}");
/// # Ok::<(), kea::KeaError>(())
/// ```
#[derive(Debug)]
#[must_use]
pub struct JointSpec<J> {
    shape: Shape,
    limits: Option<(SingleLimit, SingleLimit)>,
    motor: Option<(Real, Real)>,
    collide_connected: bool,
    _kind: PhantomData<fn() -> J>,
}

impl<J> Clone for JointSpec<J> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<J> Copy for JointSpec<J> {}
impl<J> PartialEq for JointSpec<J> {
    fn eq(&self, other: &Self) -> bool {
        (self.shape, self.limits, self.motor, self.collide_connected)
            == (
                other.shape,
                other.limits,
                other.motor,
                other.collide_connected,
            )
    }
}

impl<J> JointSpec<J> {
    fn of(shape: Shape) -> Self {
        Self {
            shape,
            limits: None,
            motor: None,
            collide_connected: false,
            _kind: PhantomData,
        }
    }

    /// Lets the two bodies collide with each other: read by a collision layer (kea3d) when it
    /// adds the joint; by default jointed bodies do not collide. The dynamics ignores it.
    pub fn collide_connected(mut self, collide: bool) -> Self {
        self.collide_connected = collide;
        self
    }

    /// Whether the bodies are to collide with each other (see
    /// [`JointSpec::collide_connected`]).
    #[must_use]
    pub fn collides_connected(&self) -> bool {
        self.collide_connected
    }
}

impl JointSpec<BallJoint> {
    /// A ball-and-socket joint at a world point.
    pub fn ball(anchor: impl Into<Vec3>) -> Self {
        Self::of(Shape::Ball(anchor.into()))
    }
}

impl JointSpec<Hinge> {
    /// A hinge at a world point about a world unit axis (the guide's `MdtHingeCreate` +
    /// `SetPosition` + `SetAxis`); its angle starts at 0.
    pub fn hinge(anchor: impl Into<Vec3>, axis: impl Into<Vec3>) -> Self {
        Self::of(Shape::Hinge(anchor.into(), axis.into()))
    }
}

impl JointSpec<Prismatic> {
    /// A prismatic joint (slider) through a world point along a world unit axis; its
    /// distance starts at 0.
    pub fn prismatic(anchor: impl Into<Vec3>, axis: impl Into<Vec3>) -> Self {
        Self::of(Shape::Prismatic(anchor.into(), axis.into()))
    }
}

impl JointSpec<FixedJoint> {
    /// A fixed joint (weld) at a world point, keeping the bodies' relative orientation.
    pub fn fixed(anchor: impl Into<Vec3>) -> Self {
        Self::of(Shape::Fixed(anchor.into()))
    }
}

impl JointSpec<UniversalJoint> {
    /// A universal joint at a world point with perpendicular world unit axes `axis1` (body 1)
    /// and `axis2` (body 2).
    pub fn universal(
        anchor: impl Into<Vec3>,
        axis1: impl Into<Vec3>,
        axis2: impl Into<Vec3>,
    ) -> Self {
        Self::of(Shape::Universal(anchor.into(), axis1.into(), axis2.into()))
    }
}

impl JointSpec<Linear1> {
    /// A Linear1 joint: the world point `anchor` of body 1 stays on the plane through it with
    /// world unit `normal`, fixed in body 2.
    pub fn linear1(anchor: impl Into<Vec3>, normal: impl Into<Vec3>) -> Self {
        Self::of(Shape::Linear1(anchor.into(), normal.into()))
    }
}

impl JointSpec<Linear2> {
    /// A Linear2 (cylindrical) joint: the world point `anchor` of body 1 stays on the line
    /// through it with world unit `direction`, fixed in body 2.
    pub fn linear2(anchor: impl Into<Vec3>, direction: impl Into<Vec3>) -> Self {
        Self::of(Shape::Linear2(anchor.into(), direction.into()))
    }
}

impl JointSpec<Planar> {
    /// A planar joint: the world point `anchor` of body 1 moves in the plane through it with
    /// world unit `normal`, fixed in body 2; its first coordinate runs along world unit `axis`
    /// (in the plane), the second along `normal × axis`, and the third turns about the normal
    /// when `rotates` (else body 1 keeps its orientation).
    pub fn planar(
        anchor: impl Into<Vec3>,
        normal: impl Into<Vec3>,
        axis: impl Into<Vec3>,
        rotates: bool,
    ) -> Self {
        Self::of(Shape::Planar {
            anchor: anchor.into(),
            normal: normal.into(),
            axis: axis.into(),
            rotates,
        })
    }
}

impl JointSpec<FixedPath> {
    /// A fixed-path joint: the world point `anchor` of body 1 follows a path point moved with
    /// [`JointHandle::set_path`] (3 DOF removed); with `fixed_orientation`, the bodies'
    /// relative orientation is held too (the guide's fixed-path-fixed-orientation joint).
    pub fn fixed_path(anchor: impl Into<Vec3>, fixed_orientation: bool) -> Self {
        Self::of(Shape::FixedPath(anchor.into(), fixed_orientation))
    }
}

impl JointSpec<CarWheel> {
    /// A car wheel: the chassis is body 1, the wheel body 2, attached at the wheel's centre,
    /// with world unit `steering_axis` (the suspension slides along it), world unit `axle`
    /// (⊥), a suspension spring of stiffness `k` (N/m, > 0) and damping `d` (N·s/m, ≥ 0).
    /// Steering starts locked.
    pub fn car_wheel(
        steering_axis: impl Into<Vec3>,
        axle: impl Into<Vec3>,
        k: Real,
        d: Real,
    ) -> Self {
        Self::of(Shape::CarWheel {
            steering: steering_axis.into(),
            axle: axle.into(),
            k,
            d,
        })
    }
}

/// Joints with one limited, motorised coordinate (a hinge's angle, a slider's distance).
impl<J: OneCoordinate> JointSpec<J> {
    /// Hard stops at `lower` and `upper` (rad or m), no bounce.
    pub fn limits(mut self, lower: Real, upper: Real) -> Self {
        self.limits = Some((SingleLimit::hard(lower, 0.0), SingleLimit::hard(upper, 0.0)));
        self
    }

    /// A motor driving it at `velocity` (rad/s or m/s) with at most `max_force` (N·m or N).
    pub fn motor(mut self, velocity: Real, max_force: Real) -> Self {
        self.motor = Some((velocity, max_force));
        self
    }
}

impl<J: JointKind> JointSpec<J> {
    /// Checks every value and builds the joint for the bodies' poses in `ctx`.
    fn build(&self, ctx: &RowContext, has_body2: bool) -> KeaResult<ConstraintKind> {
        let mut kind = self.shape.build(ctx, has_body2)?;
        if self.limits.is_some() || self.motor.is_some() {
            let limit = limit_of(&mut kind).expect("only hinges and sliders take limits");
            if let Some((lo, hi)) = self.limits {
                limit.set_limits(lo, hi)?;
            }
            if let Some((v, f)) = self.motor {
                limit.set_motor(v, f)?;
            }
        }
        Ok(kind)
    }
}

/// The one limit of a hinge or a slider.
fn limit_of(kind: &mut ConstraintKind) -> Option<&mut Limit> {
    match kind {
        ConstraintKind::Hinge(j) => Some(&mut j.limit),
        ConstraintKind::Prismatic(j) => Some(&mut j.limit),
        _ => None,
    }
}

impl Shape {
    /// Checks the geometry and builds the joint for the bodies' poses in `ctx`.
    fn build(self, ctx: &RowContext, has_body2: bool) -> KeaResult<ConstraintKind> {
        Ok(match self {
            Shape::Ball(anchor) => {
                let a = check_coordinate("anchor", anchor)?;
                let local =
                    |i: usize| ctx.bodies[i].orientation.inverse() * (a - ctx.bodies[i].position);
                ConstraintKind::Ball(Box::new(BallJoint {
                    local_anchor1: local(0),
                    local_anchor2: local(1),
                    limits: None,
                }))
            }
            Shape::Hinge(anchor, axis) => {
                let a = check_coordinate("anchor", anchor)?;
                ConstraintKind::Hinge(Hinge::new(ctx, a, check_unit("axis", axis)?))
            }
            Shape::Prismatic(anchor, axis) => {
                let a = check_coordinate("anchor", anchor)?;
                ConstraintKind::Prismatic(Prismatic::new(ctx, a, check_unit("axis", axis)?))
            }
            Shape::Fixed(anchor) => {
                ConstraintKind::Fixed(FixedJoint::new(ctx, check_coordinate("anchor", anchor)?))
            }
            Shape::Universal(anchor, axis1, axis2) => {
                let a = check_coordinate("anchor", anchor)?;
                let axis1 = check_unit("axis1", axis1)?;
                let axis2 = check_unit("axis2", axis2)?;
                check_perpendicular("axis2", axis2, axis1, "must be perpendicular to axis1")?;
                ConstraintKind::Universal(UniversalJoint::new(ctx, a, axis1, axis2))
            }
            Shape::Linear1(anchor, normal) => {
                let a = check_coordinate("anchor", anchor)?;
                ConstraintKind::Linear1(Linear1::new(ctx, a, check_unit("normal", normal)?))
            }
            Shape::Linear2(anchor, direction) => {
                let a = check_coordinate("anchor", anchor)?;
                let d = check_unit("direction", direction)?;
                ConstraintKind::Linear2(Linear2::new(ctx, a, d))
            }
            Shape::Planar {
                anchor,
                normal,
                axis,
                rotates,
            } => {
                let a = check_coordinate("anchor", anchor)?;
                let normal = check_unit("normal", normal)?;
                let axis = check_unit("axis", axis)?;
                check_perpendicular("axis", axis, normal, "must be perpendicular to normal")?;
                ConstraintKind::Planar(Box::new(Planar::new(ctx, a, normal, axis, rotates)))
            }
            Shape::FixedPath(anchor, fixed) => {
                let a = check_coordinate("anchor", anchor)?;
                ConstraintKind::Path(FixedPath::new(ctx, a, fixed))
            }
            Shape::CarWheel {
                steering,
                axle,
                k,
                d,
            } => {
                if !has_body2 {
                    return Err(KeaError::InvalidState {
                        operation: "create_joint",
                        reason:
                            "a car wheel joins a chassis (body1) to a wheel (body2): give body2",
                    });
                }
                let s = check_unit("steering_axis", steering)?;
                let u = check_unit("axle", axle)?;
                check_perpendicular("axle", u, s, "must be perpendicular to steering_axis")?;
                check_positive("k", k)?;
                check_non_negative("d", d)?;
                ConstraintKind::Wheel(Box::new(CarWheel::new(ctx, s, u, k, d)))
            }
        })
    }
}

impl World {
    /// Creates an enabled joint between `body1` and `body2` (`None`: the static world) from a
    /// [`JointSpec`] at the bodies' present poses (the guide's `Mdt*Create` + setters +
    /// `Mdt*Enable`). Every value is checked first; a refused joint changes nothing.
    pub fn create_joint<J: JointKind>(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        spec: JointSpec<J>,
    ) -> KeaResult<JointHandle<J>> {
        self.check_pair(body1, body2)?;
        let kind = spec.build(&self.pair_context(body1, body2)?, body2.is_some())?;
        let raw = self.insert_constraint(kind, body1, body2)?;
        Ok(JointHandle::from_raw(raw))
    }
}
