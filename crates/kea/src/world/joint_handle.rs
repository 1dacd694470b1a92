//! Typed joint handles: a `JointHandle<Hinge>` reads as a hinge, and a hinge's own calls
//! (angle, limits, motor, re-basing) live on it, not on the world. Calls that any constraint
//! takes (enable, break, destroy, reactions) stay on [`World`] with the untyped
//! [`ConstraintHandle`], which every joint handle gives with [`JointHandle::raw`].

use super::constraint_entry::ConstraintKind;
use super::constraints::wrong_kind;
use super::World;
use crate::constraint::ball::BallLimits;
use crate::constraint::{
    BallJoint, CarWheel, FixedJoint, FixedPath, Hinge, Limit, Linear1, Linear2, Planar, Prismatic,
    UniversalJoint,
};
use crate::error::{check_coordinate, check_finite, check_quat, check_unit, check_vec3};
use crate::error::{KeaError, KeaResult};
use crate::handle::ConstraintHandle;
use crate::math::{Quat, Real, Vec3};
use crate::solver::Reaction;
use std::any::Any;
use std::marker::PhantomData;

mod sealed {
    pub trait Sealed {}
}

/// A kind of joint: what a [`JointHandle`] of it reads as. Implemented by the guide's nine
/// joints and the car wheel.
pub trait JointKind: sealed::Sealed + Any + Sized {
    /// The kind's name, as errors give it.
    const NAME: &'static str;
}

macro_rules! joint_kind {
    ($($ty:ty => $name:literal),* $(,)?) => {$(
        impl sealed::Sealed for $ty {}
        impl JointKind for $ty {
            const NAME: &'static str = $name;
        }
    )*};
}

joint_kind! {
    BallJoint => "ball joint",
    Hinge => "hinge",
    Prismatic => "prismatic joint",
    FixedJoint => "fixed joint",
    UniversalJoint => "universal joint",
    Linear1 => "linear1 joint",
    Linear2 => "linear2 joint",
    Planar => "planar joint",
    FixedPath => "fixed-path joint",
    CarWheel => "car wheel joint",
}

/// The joint inside a constraint kind, as `Option<&dyn Any>` (`as_ref`) or `Option<&mut dyn
/// Any>` (`as_mut`); `None` for a contact or a custom constraint.
macro_rules! joint_inside {
    ($kind:expr, $unbox:ident) => {
        Some(match $kind {
            ConstraintKind::Ball(j) => j.$unbox(),
            ConstraintKind::Hinge(j) => j,
            ConstraintKind::Prismatic(j) => j,
            ConstraintKind::Fixed(j) => j,
            ConstraintKind::Universal(j) => j,
            ConstraintKind::Linear1(j) => j,
            ConstraintKind::Linear2(j) => j,
            ConstraintKind::Planar(j) => j.$unbox(),
            ConstraintKind::Path(j) => j,
            ConstraintKind::Wheel(j) => j.$unbox(),
            ConstraintKind::Contact(_) | ConstraintKind::Custom(_) => return None,
        })
    };
}

impl ConstraintKind {
    /// The joint inside, to be downcast to its kind; `None` for a contact or a custom one.
    fn joint_any(&self) -> Option<&dyn Any> {
        joint_inside!(self, as_ref)
    }

    /// [`ConstraintKind::joint_any`], to change.
    fn joint_any_mut(&mut self) -> Option<&mut dyn Any> {
        joint_inside!(self, as_mut)
    }
}

/// A joint's handle that knows its kind. It is `Copy`, compares and hashes as the untyped
/// [`ConstraintHandle`] it wraps, and goes stale when the joint is destroyed.
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(transparent, bound = "")
)]
pub struct JointHandle<J> {
    raw: ConstraintHandle,
    #[cfg_attr(feature = "serde", serde(skip))]
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
        let kind = std::any::type_name::<J>()
            .rsplit("::")
            .next()
            .unwrap_or("?");
        write!(f, "JointHandle<{kind}>({:?})", self.raw)
    }
}
impl<J> From<JointHandle<J>> for ConstraintHandle {
    fn from(h: JointHandle<J>) -> Self {
        h.raw
    }
}

impl AsRef<World> for World {
    fn as_ref(&self) -> &World {
        self
    }
}
impl AsMut<World> for World {
    fn as_mut(&mut self) -> &mut World {
        self
    }
}

impl<J: JointKind> JointHandle<J> {
    /// The typed handle of an untyped one, unchecked: if the constraint is of another kind,
    /// every call on the handle returns [`KeaError::WrongConstraintKind`] and changes nothing.
    #[must_use]
    pub fn from_raw(raw: ConstraintHandle) -> Self {
        Self {
            raw,
            _kind: PhantomData,
        }
    }

    /// The typed handle of an untyped one (a scene's joint by name), checked: the error names
    /// the kind the constraint is if it is another.
    pub fn try_from_raw(world: &impl AsRef<World>, raw: ConstraintHandle) -> KeaResult<Self> {
        Self::from_raw(raw).get(world)?;
        Ok(Self::from_raw(raw))
    }

    /// The untyped handle, for the calls every constraint takes ([`World::destroy_constraint`],
    /// [`World::set_constraint_enabled`], …).
    #[must_use]
    pub fn raw(self) -> ConstraintHandle {
        self.raw
    }

    /// The joint, read-only.
    pub fn get(self, world: &impl AsRef<World>) -> KeaResult<&J> {
        let kind = &world.as_ref().constraints.get(self.raw)?.kind;
        kind.joint_any()
            .and_then(|j| j.downcast_ref::<J>())
            .ok_or_else(|| wrong_kind(self.raw, J::NAME, kind.name()))
    }

    /// The joint, to change (only through what its type lets change), with its world's
    /// other parts.
    fn get_mut(self, world: &mut World) -> KeaResult<&mut J> {
        let kind = &mut world.constraints.get_mut(self.raw)?.kind;
        let name = kind.name();
        kind.joint_any_mut()
            .and_then(|j| j.downcast_mut::<J>())
            .ok_or_else(|| wrong_kind(self.raw, J::NAME, name))
    }

    /// The force and torque the joint applied to its two bodies in the last step.
    pub fn reaction(self, world: &impl AsRef<World>) -> KeaResult<[Reaction; 2]> {
        self.get(world)?;
        world.as_ref().constraint_reaction(self.raw)
    }

    /// Turns the joint off (its bodies move freely) or on again.
    pub fn set_enabled(self, world: &mut impl AsMut<World>, enabled: bool) -> KeaResult<()> {
        self.get(world.as_mut())?;
        world.as_mut().set_constraint_enabled(self.raw, enabled)
    }

    /// Makes the joint break when its force exceeds `max_force` N or its torque `max_torque`
    /// N·m (`None`: no threshold); see [`World::set_breakable`].
    pub fn set_breakable(
        self,
        world: &mut impl AsMut<World>,
        max_force: Option<Real>,
        max_torque: Option<Real>,
    ) -> KeaResult<()> {
        self.get(world.as_mut())?;
        world
            .as_mut()
            .set_breakable(self.raw, max_force, max_torque)
    }

    /// Moves the joint to world point `anchor` for the bodies' present poses (the guide's
    /// `Mdt*SetPosition`), keeping its axes: the joint is re-initialised there, so its angle
    /// or distance reads 0 from now on and nothing jumps if the bodies already meet there.
    pub fn set_position(self, world: &mut impl AsMut<World>, anchor: Vec3) -> KeaResult<()> {
        self.get(world.as_mut())?;
        world.as_mut().set_joint_position(self.raw, anchor)
    }

    /// Turns the joint's axis to world unit `axis` for the bodies' present poses (the guide's
    /// `Mdt*SetAxis`): for a hinge, a prismatic, a Linear2 joint or a universal joint's first
    /// axis, a Linear1 joint's normal, a ball joint's limit axis. The joint is re-initialised
    /// about it (angle or distance 0, limits and motor kept).
    pub fn set_axis(self, world: &mut impl AsMut<World>, axis: Vec3) -> KeaResult<()> {
        self.get(world.as_mut())?;
        world.as_mut().set_joint_axis(self.raw, axis)
    }
}

/// A joint with one coordinate, limited and motorised: a hinge (its angle, rad) or a
/// prismatic joint (its distance, m).
pub trait OneCoordinate: JointKind {
    /// The coordinate's limits and motor.
    fn coordinate_limit(&mut self) -> &mut Limit;
}

impl OneCoordinate for Hinge {
    fn coordinate_limit(&mut self) -> &mut Limit {
        &mut self.limit
    }
}

impl OneCoordinate for Prismatic {
    fn coordinate_limit(&mut self) -> &mut Limit {
        &mut self.limit
    }
}

impl<J: OneCoordinate> JointHandle<J> {
    /// Its limits and motor, to change.
    pub fn limit_mut(self, world: &mut impl AsMut<World>) -> KeaResult<&mut Limit> {
        Ok(self.get_mut(world.as_mut())?.coordinate_limit())
    }

    /// Drives the coordinate at `velocity` (rad/s or m/s) with at most `max_force` (N·m or N).
    pub fn set_motor(
        self,
        world: &mut impl AsMut<World>,
        velocity: Real,
        max_force: Real,
    ) -> KeaResult<()> {
        self.limit_mut(world)?.set_motor(velocity, max_force)
    }
}

impl JointHandle<Hinge> {
    /// The hinge angle, rad (0 at creation, continuous past ±π).
    pub fn angle(self, world: &impl AsRef<World>) -> KeaResult<Real> {
        Ok(self.get(world)?.angle())
    }

    /// Tells the hinge the continuous angle it has now, rad, after its bodies were re-posed
    /// by hand (a robot set to new joint positions): the next step unwraps against it, so an
    /// angle past ±π is kept, and the limit's read-outs start from it (rate 0).
    pub fn rebase_angle(self, world: &mut impl AsMut<World>, angle: Real) -> KeaResult<()> {
        check_finite("angle", angle)?;
        let j = self.get_mut(world.as_mut())?;
        j.angle = angle;
        j.limit.record(angle, 0.0);
        Ok(())
    }
}

impl JointHandle<Prismatic> {
    /// The slide distance, m (0 at creation).
    pub fn distance(self, world: &impl AsRef<World>) -> KeaResult<Real> {
        Ok(self.get(world)?.distance())
    }
}

impl JointHandle<Planar> {
    /// Coordinate `k`'s limits, motor and dynamics (0, 1: travels; 2: turn).
    pub fn limit_mut(self, world: &mut impl AsMut<World>, k: usize) -> KeaResult<&mut Limit> {
        self.get_mut(world.as_mut())?
            .limit_mut(k)
            .ok_or_else(|| KeaError::OutOfRange {
                arg: "k",
                value: format!("{k}"),
                expected: "a planar joint has coordinates 0, 1 and 2",
            })
    }

    /// Tells the joint the continuous turn it has now, rad, after its bodies were re-posed by
    /// hand (see [`JointHandle::rebase_angle`]).
    pub fn rebase_turn(self, world: &mut impl AsMut<World>, angle: Real) -> KeaResult<()> {
        check_finite("angle", angle)?;
        self.get_mut(world.as_mut())?.rebase(angle);
        Ok(())
    }
}

impl JointHandle<BallJoint> {
    /// Sets up the joint's twist, cone and segment limits about world unit `primary` with
    /// world unit `orthogonal` (⊥) for the bodies' present poses; all limits start off: set
    /// them through [`JointHandle::limits_mut`].
    pub fn set_limit_axes(
        self,
        world: &mut impl AsMut<World>,
        primary: Vec3,
        orthogonal: Vec3,
    ) -> KeaResult<()> {
        let primary = check_unit("primary", primary)?;
        let orthogonal = check_unit("orthogonal", orthogonal)?;
        crate::error::check_perpendicular(
            "orthogonal",
            orthogonal,
            primary,
            "must be perpendicular to primary",
        )?;
        let world = world.as_mut();
        self.get(world)?;
        let ctx = world.constraint_context(self.raw)?;
        self.get_mut(world)?.limits = Some(BallLimits::new(&ctx, primary, orthogonal));
        Ok(())
    }

    /// Sets one body's primary limit axis (the guide's `MdtBSJointSetPrimaryAxis`): world
    /// unit `axis` at the bodies' present poses, kept in body `body`'s frame (0: body 1, 1:
    /// body 2). The cone angle is the angle between the two bodies' primary axes, so giving
    /// them different directions tilts the cone. A joint without limit axes gets them here,
    /// about `axis` for both bodies (limits off).
    pub fn set_primary_axis(
        self,
        world: &mut impl AsMut<World>,
        body: usize,
        axis: Vec3,
    ) -> KeaResult<()> {
        let axis = check_unit("axis", axis)?;
        check_body_index(body)?;
        let world = world.as_mut();
        let ctx = world.constraint_context(self.raw)?;
        let joint = self.get_mut(world)?;
        let limits = joint
            .limits
            .get_or_insert_with(|| BallLimits::new(&ctx, axis, axis.any_orthonormal_vector()));
        let local = ctx.bodies[body].orientation.inverse() * axis;
        if body == 0 {
            // Body 1's orthogonal axis follows, kept ⊥ its new primary axis.
            let o = limits.orthogonal1();
            let o = o - local * o.dot(local);
            limits.orthogonal1 = o.try_normalize().unwrap_or(local.any_orthonormal_vector());
            limits.primary1 = local;
        } else {
            // Body 2's orthogonal axis follows, kept ⊥ its new primary axis.
            let o = limits.orthogonal2 - local * limits.orthogonal2.dot(local);
            limits.orthogonal2 = o.try_normalize().unwrap_or(local.any_orthonormal_vector());
            limits.primary2 = local;
        }
        Ok(())
    }

    /// Sets body `body`'s orthogonal limit axis (the guide's `MdtBSJointSetOrthogonalAxis`, 0:
    /// body 1, 1: body 2): world unit `axis` at the bodies' present poses, which must be
    /// perpendicular to that body's primary axis (within 1e-3); refused, changing nothing,
    /// otherwise or before the joint has limit axes. Body 2's is where the segment angle is
    /// zero; body 1's is where the twist is zero (the twist reads zero where body 1's
    /// orthogonal axis lies along body 2's as it was when the axes were set, so turning it
    /// by δ about the primary axis moves the twist's reading by δ).
    pub fn set_orthogonal_axis(
        self,
        world: &mut impl AsMut<World>,
        body: usize,
        axis: Vec3,
    ) -> KeaResult<()> {
        let axis = check_unit("axis", axis)?;
        check_body_index(body)?;
        let world = world.as_mut();
        let ctx = world.constraint_context(self.raw)?;
        let local = ctx.bodies[body].orientation.inverse() * axis;
        let limits = self.limits_mut(world)?;
        let (primary, what) = if body == 0 {
            (
                limits.primary1,
                "must be perpendicular to body 1's primary axis",
            )
        } else {
            (
                limits.primary2,
                "must be perpendicular to body 2's primary axis",
            )
        };
        crate::error::check_perpendicular("axis", local, primary, what)?;
        // Exactly ⊥, and unit again.
        let local = (local - primary * local.dot(primary)).normalize();
        if body == 0 {
            limits.turn_orthogonal1(local);
        } else {
            limits.orthogonal2 = local;
        }
        Ok(())
    }

    /// Body `body`'s primary limit axis (0: body 1, 1: body 2), or its orthogonal axis with
    /// `orthogonal`, in the world frame at the bodies' present poses (the guide's
    /// `MdtBSJointGetPrimaryAxis`, `GetOrthogonalAxis`). An error before the joint has limit
    /// axes.
    pub fn limit_axis(
        self,
        world: &impl AsRef<World>,
        body: usize,
        orthogonal: bool,
    ) -> KeaResult<Vec3> {
        check_body_index(body)?;
        let world = world.as_ref();
        let limits = self.get(world)?.limits.ok_or(KeaError::InvalidState {
            operation: "limit_axis",
            reason: "the joint has no limit axes; call set_limit_axes first",
        })?;
        let local = match (body, orthogonal) {
            (0, false) => limits.primary1,
            (_, false) => limits.primary2,
            (0, true) => limits.orthogonal1(),
            _ => limits.orthogonal2,
        };
        let ctx = world.constraint_context(self.raw)?;
        Ok(ctx.bodies[body].orientation * local)
    }

    /// Its cone and twist limits, to change (after [`JointHandle::set_limit_axes`]).
    pub fn limits_mut(self, world: &mut impl AsMut<World>) -> KeaResult<&mut BallLimits> {
        self.get_mut(world.as_mut())?
            .limits
            .as_mut()
            .ok_or(KeaError::InvalidState {
                operation: "limits_mut",
                reason: "the joint has no limit axes; call set_limit_axes first",
            })
    }
}

impl JointHandle<FixedJoint> {
    /// Sets the relative orientation `q₂⁻¹ q₁` the joint holds; `q` must be a unit quaternion.
    pub fn set_relative_orientation(self, world: &mut impl AsMut<World>, q: Quat) -> KeaResult<()> {
        let q = check_quat("q", q)?;
        self.get_mut(world.as_mut())?.relative_orientation = q;
        Ok(())
    }
}

impl JointHandle<FixedPath> {
    /// Moves the path point to world `position`, moving at world `velocity` (the guide's
    /// `MdtFixedPathSetPosition`/`SetVelocity`; give the velocity, or the point lags a step
    /// behind a moving path).
    pub fn set_path(
        self,
        world: &mut impl AsMut<World>,
        position: Vec3,
        velocity: Vec3,
    ) -> KeaResult<()> {
        check_coordinate("position", position)?;
        check_vec3("velocity", velocity)?;
        let world = world.as_mut();
        self.get(world)?;
        let ctx = world.constraint_context(self.raw)?;
        let q2 = ctx.bodies[1].orientation.inverse();
        let j = self.get_mut(world)?;
        j.path_position = q2 * (position - ctx.bodies[1].position);
        j.path_velocity = q2 * velocity;
        Ok(())
    }

    /// Sets the relative orientation `q₂⁻¹ q₁` a fixed-path-fixed-orientation joint holds (the
    /// guide's `MdtFPFOJointSetQuaternion`); `q` must be a unit quaternion. An error for a
    /// joint made without a fixed orientation.
    pub fn set_relative_orientation(self, world: &mut impl AsMut<World>, q: Quat) -> KeaResult<()> {
        let q = check_quat("q", q)?;
        let raw = self.raw;
        match &mut self.get_mut(world.as_mut())?.orientation {
            Some(held) => *held = q,
            None => {
                return Err(wrong_kind(
                    raw,
                    "fixed-path-fixed-orientation joint",
                    "fixed-path joint",
                ))
            }
        }
        Ok(())
    }
}

impl JointHandle<CarWheel> {
    /// The wheel joint, to change its suspension, steering and drive.
    pub fn wheel_mut(self, world: &mut impl AsMut<World>) -> KeaResult<&mut CarWheel> {
        self.get_mut(world.as_mut())
    }
}

/// Checks a joint's body index (0: body 1, 1: body 2).
fn check_body_index(body: usize) -> KeaResult<()> {
    if body > 1 {
        return Err(KeaError::OutOfRange {
            arg: "body",
            value: body.to_string(),
            expected: "0 (body 1) or 1 (body 2)",
        });
    }
    Ok(())
}
