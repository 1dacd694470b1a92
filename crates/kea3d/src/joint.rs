//! Joint builders and typed joint handles: a `JointHandle<Hinge>` reads as a hinge and its
//! own calls (limits, motor, angle) live on it, not on the world.

use crate::PhysicsWorld;
use kea::constraint::{BallLimits, CarWheel, FixedPath};
use kea::{
    BallJoint, ConstraintHandle, FixedJoint, Hinge, KeaResult, Limit, Linear1, Linear2, Planar,
    Prismatic, Quat, Reaction, Real, SingleLimit, UniversalJoint, Vec3, World,
};
use std::marker::PhantomData;

mod sealed {
    pub trait Sealed {}
}

/// A kind of joint: what a [`JointHandle`] of it reads as.
pub trait JointKind: sealed::Sealed + Sized {
    /// The joint of `h` in `world`, or an error naming the kind it is instead.
    fn read(world: &World, h: ConstraintHandle) -> KeaResult<&Self>;
}

macro_rules! joint_kind {
    ($($ty:ty => $getter:ident),* $(,)?) => {$(
        impl sealed::Sealed for $ty {}
        impl JointKind for $ty {
            fn read(world: &World, h: ConstraintHandle) -> KeaResult<&Self> {
                world.$getter(h)
            }
        }
    )*};
}

joint_kind! {
    BallJoint => ball_joint,
    Hinge => hinge,
    Prismatic => prismatic,
    FixedJoint => fixed_joint,
    UniversalJoint => universal_joint,
    Linear1 => linear1_joint,
    Linear2 => linear2_joint,
    Planar => planar_joint,
    FixedPath => fixed_path,
    CarWheel => car_wheel,
}

/// A joint's handle that knows its kind.
pub struct JointHandle<J> {
    raw: ConstraintHandle,
    _kind: PhantomData<fn() -> J>,
}

impl<J> Clone for JointHandle<J> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<J> Copy for JointHandle<J> {}
impl<J> PartialEq for JointHandle<J> {
    fn eq(&self, other: &Self) -> bool {
        self.raw == other.raw
    }
}
impl<J> Eq for JointHandle<J> {}
impl<J> std::hash::Hash for JointHandle<J> {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.raw.hash(state);
    }
}
impl<J> std::fmt::Debug for JointHandle<J> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "JointHandle<{}>({:?})",
            std::any::type_name::<J>(),
            self.raw
        )
    }
}

impl<J: JointKind> JointHandle<J> {
    pub(crate) fn from_raw(raw: ConstraintHandle) -> Self {
        Self {
            raw,
            _kind: PhantomData,
        }
    }

    /// The typed handle of an untyped one (a scene's joint by name), checked: an error names
    /// the kind the joint is if it is another.
    pub fn try_from_raw(world: &PhysicsWorld, raw: ConstraintHandle) -> KeaResult<Self> {
        J::read(world.dynamics(), raw)?;
        Ok(Self::from_raw(raw))
    }

    /// The untyped handle, for the dynamics layer ([`PhysicsWorld::dynamics`]).
    #[must_use]
    pub fn raw(self) -> ConstraintHandle {
        self.raw
    }

    /// The joint, read-only.
    pub fn get(self, world: &PhysicsWorld) -> KeaResult<&J> {
        J::read(world.dynamics(), self.raw)
    }

    /// The force and torque the joint applied to its two bodies in the last step.
    pub fn reaction(self, world: &PhysicsWorld) -> KeaResult<[Reaction; 2]> {
        world.dynamics().constraint_reaction(self.raw)
    }

    /// Turns the joint off (its bodies move freely) or on again.
    pub fn set_enabled(self, world: &mut PhysicsWorld, enabled: bool) -> KeaResult<()> {
        world
            .dynamics_mut()
            .set_constraint_enabled(self.raw, enabled)
    }

    /// Makes the joint break when its force exceeds `force` N or its torque `torque` N·m
    /// (`None`: no threshold).
    pub fn set_breakable(
        self,
        world: &mut PhysicsWorld,
        force: Option<Real>,
        torque: Option<Real>,
    ) -> KeaResult<()> {
        world.dynamics_mut().set_breakable(self.raw, force, torque)
    }
}

impl JointHandle<Hinge> {
    /// The hinge angle, rad (0 at creation).
    pub fn angle(self, world: &PhysicsWorld) -> KeaResult<Real> {
        Ok(world.dynamics().hinge(self.raw)?.angle())
    }

    /// Its limits and motor, to change.
    pub fn limit_mut(self, world: &mut PhysicsWorld) -> KeaResult<&mut Limit> {
        world.dynamics_mut().hinge_limit_mut(self.raw)
    }

    /// Drives the angle at `velocity` rad/s with at most `max_torque` N·m.
    pub fn set_motor(
        self,
        world: &mut PhysicsWorld,
        velocity: Real,
        max_torque: Real,
    ) -> KeaResult<()> {
        self.limit_mut(world)?.set_motor(velocity, max_torque)
    }
}

impl JointHandle<Prismatic> {
    /// The slide distance, m (0 at creation).
    pub fn distance(self, world: &PhysicsWorld) -> KeaResult<Real> {
        Ok(world.dynamics().prismatic(self.raw)?.distance())
    }

    /// Its limits and motor, to change.
    pub fn limit_mut(self, world: &mut PhysicsWorld) -> KeaResult<&mut Limit> {
        world.dynamics_mut().prismatic_limit_mut(self.raw)
    }

    /// Drives the slide at `velocity` m/s with at most `max_force` N.
    pub fn set_motor(
        self,
        world: &mut PhysicsWorld,
        velocity: Real,
        max_force: Real,
    ) -> KeaResult<()> {
        self.limit_mut(world)?.set_motor(velocity, max_force)
    }
}

impl JointHandle<BallJoint> {
    /// Gives the joint cone and twist limit axes (world unit vectors, perpendicular).
    pub fn set_limit_axes(
        self,
        world: &mut PhysicsWorld,
        primary: Vec3,
        orthogonal: Vec3,
    ) -> KeaResult<()> {
        world
            .dynamics_mut()
            .set_ball_limit_axes(self.raw, primary, orthogonal)
    }

    /// Its cone and twist limits, to change (after [`JointHandle::set_limit_axes`]).
    pub fn limits_mut(self, world: &mut PhysicsWorld) -> KeaResult<&mut BallLimits> {
        world.dynamics_mut().ball_limits_mut(self.raw)
    }
}

impl JointHandle<FixedJoint> {
    /// Sets the relative orientation `q₂⁻¹ q₁` the joint holds.
    pub fn set_relative_orientation(self, world: &mut PhysicsWorld, q: Quat) -> KeaResult<()> {
        world.dynamics_mut().set_relative_orientation(self.raw, q)
    }
}

impl JointHandle<FixedPath> {
    /// Moves the path point to `position` (world), moving at `velocity`.
    pub fn set_path(
        self,
        world: &mut PhysicsWorld,
        position: Vec3,
        velocity: Vec3,
    ) -> KeaResult<()> {
        world.dynamics_mut().set_path(self.raw, position, velocity)
    }
}

impl JointHandle<CarWheel> {
    /// The wheel joint, to change its suspension, steering and drive.
    pub fn wheel_mut(self, world: &mut PhysicsWorld) -> KeaResult<&mut CarWheel> {
        world.dynamics_mut().car_wheel_mut(self.raw)
    }
}

/// What to build, with its world-frame anchor and axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Spec {
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

/// A joint to insert, made with a builder: `Joint::hinge(anchor, axis).limits(-1.0, 1.0)`.
///
/// Anchors and axes are in the world frame at insertion, as in the guide; the joint stores
/// them in each body's frame.
///
/// ```
/// use kea3d::prelude::*;
///
/// let mut world = PhysicsWorld::new();
/// let door = world.insert_body(Body::dynamic().position([0.5, 1.0, 0.0]))?;
/// world.insert_collider(Collider::cuboid([0.5, 1.0, 0.05]), Some(door))?;
/// // Hinged to the world along its left edge, free to swing ±1 rad, driven at 1 rad/s.
/// let hinge = world.insert_joint(door, None, Joint::hinge([0.0, 1.0, 0.0], [0.0, 1.0, 0.0]).limits(-1.0, 1.0))?;
/// hinge.set_motor(&mut world, 1.0, 50.0)?;
/// for _ in 0..120 {
///     world.step(1.0 / 60.0)?;
/// }
/// let angle = hinge.angle(&world)?;
/// assert!((angle.abs() - 1.0).abs() < 0.02, "stopped at a limit: {angle}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[must_use]
pub struct Joint<J> {
    pub(crate) spec: Spec,
    pub(crate) limits: Option<(SingleLimit, SingleLimit)>,
    pub(crate) motor: Option<(Real, Real)>,
    pub(crate) collide_connected: bool,
    _kind: PhantomData<fn() -> J>,
}

impl<J> Joint<J> {
    fn of(spec: Spec) -> Self {
        Self {
            spec,
            limits: None,
            motor: None,
            collide_connected: false,
            _kind: PhantomData,
        }
    }

    /// Lets the two bodies collide with each other (by default jointed bodies do not).
    pub fn collide_connected(mut self, collide: bool) -> Self {
        self.collide_connected = collide;
        self
    }
}

impl Joint<BallJoint> {
    /// A ball-and-socket joint at a world point.
    pub fn ball(anchor: impl Into<Vec3>) -> Self {
        Self::of(Spec::Ball(anchor.into()))
    }
}

impl Joint<Hinge> {
    /// A hinge at a world point about a world unit axis.
    pub fn hinge(anchor: impl Into<Vec3>, axis: impl Into<Vec3>) -> Self {
        Self::of(Spec::Hinge(anchor.into(), axis.into()))
    }
}

impl Joint<Prismatic> {
    /// A slider at a world point along a world unit axis.
    pub fn prismatic(anchor: impl Into<Vec3>, axis: impl Into<Vec3>) -> Self {
        Self::of(Spec::Prismatic(anchor.into(), axis.into()))
    }
}

impl Joint<FixedJoint> {
    /// A weld at a world point.
    pub fn fixed(anchor: impl Into<Vec3>) -> Self {
        Self::of(Spec::Fixed(anchor.into()))
    }
}

impl Joint<UniversalJoint> {
    /// A universal joint at a world point about two perpendicular world unit axes.
    pub fn universal(
        anchor: impl Into<Vec3>,
        axis1: impl Into<Vec3>,
        axis2: impl Into<Vec3>,
    ) -> Self {
        Self::of(Spec::Universal(anchor.into(), axis1.into(), axis2.into()))
    }
}

impl Joint<Linear1> {
    /// Keeps a point of body 1 on a plane of body 2 (world point and unit normal).
    pub fn linear1(anchor: impl Into<Vec3>, normal: impl Into<Vec3>) -> Self {
        Self::of(Spec::Linear1(anchor.into(), normal.into()))
    }
}

impl Joint<Linear2> {
    /// Keeps a point of body 1 on a line of body 2 (world point and unit direction).
    pub fn linear2(anchor: impl Into<Vec3>, direction: impl Into<Vec3>) -> Self {
        Self::of(Spec::Linear2(anchor.into(), direction.into()))
    }
}

impl Joint<Planar> {
    /// Keeps a point of body 1 (world `anchor`) in the plane of body 2 with world unit
    /// `normal`; body 1 turns about the normal when `rotates`, else keeps its orientation.
    /// Its coordinates: travel along world unit `axis` (in the plane), along `normal × axis`,
    /// and the turn.
    pub fn planar(
        anchor: impl Into<Vec3>,
        normal: impl Into<Vec3>,
        axis: impl Into<Vec3>,
        rotates: bool,
    ) -> Self {
        Self::of(Spec::Planar {
            anchor: anchor.into(),
            normal: normal.into(),
            axis: axis.into(),
            rotates,
        })
    }
}

impl Joint<FixedPath> {
    /// Keeps a point of body 1 on a path point you move, optionally holding its orientation.
    pub fn fixed_path(anchor: impl Into<Vec3>, fixed_orientation: bool) -> Self {
        Self::of(Spec::FixedPath(anchor.into(), fixed_orientation))
    }
}

impl Joint<CarWheel> {
    /// A car wheel (body 2) on a chassis (body 1): suspension along the world unit
    /// `steering_axis` with stiffness `k` N/m and damping `d` N·s/m, spinning about the
    /// perpendicular world unit `axle`.
    pub fn car_wheel(
        steering_axis: impl Into<Vec3>,
        axle: impl Into<Vec3>,
        k: Real,
        d: Real,
    ) -> Self {
        Self::of(Spec::CarWheel {
            steering: steering_axis.into(),
            axle: axle.into(),
            k,
            d,
        })
    }
}

/// Joints with one limited, motorised degree of freedom.
macro_rules! limited {
    ($($ty:ty),*) => {$(
        impl Joint<$ty> {
            /// Hard stops at `lower` and `upper` (rad or m), no bounce.
            pub fn limits(mut self, lower: Real, upper: Real) -> Self {
                self.limits = Some((SingleLimit::hard(lower, 0.0), SingleLimit::hard(upper, 0.0)));
                self
            }

            /// A motor driving it at `velocity` (rad/s or m/s) with at most `max_force`
            /// (N·m or N).
            pub fn motor(mut self, velocity: Real, max_force: Real) -> Self {
                self.motor = Some((velocity, max_force));
                self
            }
        }
    )*};
}

limited!(Hinge, Prismatic);
