//! Rigid bodies (the guide's `MdtBody`): mass, inertia, pose, velocities, force accumulators.
//!
//! A body's frame has its origin at the centre of mass. Its pose is the position of the centre of
//! mass and an orientation quaternion, both in world coordinates; the 4×4 transform a renderer
//! wants is kept up to date and readable by reference ([`Body::transform`]).

pub mod inertia;

use crate::error::{
    check_coordinate, check_inertia, check_mass, check_non_negative, check_quat, check_unit,
    check_vec3, KeaError, KeaResult,
};
use crate::math::{Mat3, Mat4, Quat, Real, Vec3};
use crate::solver::SolverPath;

/// Everything needed to create a body. Defaults follow the guide's `MdtBodyCreate`: mass 1,
/// identity inertia (a unit sphere's... almost: the guide's default), at the origin, at rest,
/// enabled, no damping, no fast-spin axis.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyDef {
    /// Mass in kg, within [`crate::error::MASS_RANGE`].
    pub mass: Real,
    /// Inertia tensor about the centre of mass, in the body frame (symmetric positive definite).
    pub inertia: Mat3,
    /// World position of the centre of mass.
    pub position: Vec3,
    /// World orientation (unit quaternion).
    pub orientation: Quat,
    /// Linear velocity of the centre of mass, world frame.
    pub linear_velocity: Vec3,
    /// Angular velocity, world frame (rad/s).
    pub angular_velocity: Vec3,
    /// Linear velocity damping, kg/s: a force `-d·v` applied implicitly each step. Normal 0;
    /// values up to `m/h` are harmless because the damping is integrated implicitly.
    pub linear_damping: Real,
    /// Angular velocity damping, N·m·s: a torque `-d·ω`, integrated implicitly. Normal 0.
    pub angular_damping: Real,
    /// Optional fast-spin axis in the body frame (unit), e.g. a wheel's axle: rotation about it is
    /// applied as its own exact finite rotation (the guide's `fastSpin`).
    pub fast_spin_axis: Option<Vec3>,
    /// Whether the body takes part in the simulation (the guide's `MdtBodyEnable`). A disabled
    /// body does not move and acts as fixed for constraints attached to it.
    pub enabled: bool,
    /// Free for the user (the guide's user data pointer).
    pub user_data: u64,
    /// Ask for the exact solver for this body's island whatever its size (vehicles, ragdolls),
    /// when the world routes islands in hybrid mode.
    pub prefer_exact: bool,
    /// A kinematic body moves with the velocity you set and is not pushed by anything
    /// (constraints, contacts, forces, gravity): a moving platform, a driven robot base.
    /// Constraints see it as infinitely heavy. Default false.
    pub kinematic: bool,
}

impl Default for BodyDef {
    fn default() -> Self {
        Self {
            mass: 1.0,
            inertia: Mat3::IDENTITY,
            position: Vec3::ZERO,
            orientation: Quat::IDENTITY,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            linear_damping: 0.0,
            angular_damping: 0.0,
            fast_spin_axis: None,
            enabled: true,
            user_data: 0,
            prefer_exact: false,
            kinematic: false,
        }
    }
}

/// A rigid body in a world. Read it through [`crate::World::body`], change it through
/// [`crate::World::body_mut`]; every setter validates its argument first and changes nothing on
/// error.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Body {
    pub(crate) mass: Real,
    pub(crate) inv_mass: Real,
    pub(crate) inertia: Mat3,
    pub(crate) inv_inertia: Mat3,
    pub(crate) position: Vec3,
    pub(crate) orientation: Quat,
    pub(crate) transform: Mat4,
    pub(crate) linear_velocity: Vec3,
    pub(crate) angular_velocity: Vec3,
    pub(crate) force: Vec3,
    pub(crate) torque: Vec3,
    pub(crate) linear_acceleration: Vec3,
    pub(crate) angular_acceleration: Vec3,
    pub(crate) linear_damping: Real,
    pub(crate) angular_damping: Real,
    pub(crate) fast_spin_axis: Option<Vec3>,
    pub(crate) enabled: bool,
    pub(crate) user_data: u64,
    /// Disabled automatically because its island rested (see [`crate::world::DemSettings`]).
    pub(crate) sleeping: bool,
    /// Time this body has been resting, s.
    pub(crate) rest_time: Real,
    pub(crate) prefer_exact: bool,
    pub(crate) last_path: SolverPath,
    /// Frozen by the world's quarantine (and disabled) until cleared.
    pub(crate) quarantined: bool,
    /// Moves with its set velocity, pushed by nothing (see [`BodyDef::kinematic`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub(crate) kinematic: bool,
}

impl Body {
    /// Validates a definition and builds the body.
    pub(crate) fn from_def(def: &BodyDef) -> KeaResult<Self> {
        let mut body = Body {
            mass: 1.0,
            inv_mass: 1.0,
            inertia: Mat3::IDENTITY,
            inv_inertia: Mat3::IDENTITY,
            position: Vec3::ZERO,
            orientation: Quat::IDENTITY,
            transform: Mat4::IDENTITY,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            force: Vec3::ZERO,
            torque: Vec3::ZERO,
            linear_acceleration: Vec3::ZERO,
            angular_acceleration: Vec3::ZERO,
            linear_damping: 0.0,
            angular_damping: 0.0,
            fast_spin_axis: None,
            enabled: def.enabled,
            user_data: def.user_data,
            sleeping: false,
            rest_time: 0.0,
            prefer_exact: def.prefer_exact,
            last_path: SolverPath::None,
            quarantined: false,
            kinematic: def.kinematic,
        };
        // Validate everything before building, so a bad field reports its own name.
        check_mass("mass", def.mass)?;
        check_inertia("inertia", def.inertia)?;
        check_coordinate("position", def.position)?;
        check_quat("orientation", def.orientation)?;
        check_vec3("linear_velocity", def.linear_velocity)?;
        check_vec3("angular_velocity", def.angular_velocity)?;
        check_non_negative("linear_damping", def.linear_damping)?;
        check_non_negative("angular_damping", def.angular_damping)?;
        if let Some(axis) = def.fast_spin_axis {
            check_unit("fast_spin_axis", axis)?;
        }
        body.set_mass(def.mass)?;
        body.set_inertia(def.inertia)?;
        body.set_position(def.position)?;
        body.set_orientation(def.orientation)?;
        body.set_linear_velocity(def.linear_velocity)?;
        body.set_angular_velocity(def.angular_velocity)?;
        body.set_linear_damping(def.linear_damping)?;
        body.set_angular_damping(def.angular_damping)?;
        body.set_fast_spin_axis(def.fast_spin_axis)?;
        Ok(body)
    }

    /// Mass in kg.
    #[must_use]
    pub fn mass(&self) -> Real {
        self.mass
    }
    /// Inertia tensor in the body frame.
    #[must_use]
    pub fn inertia(&self) -> Mat3 {
        self.inertia
    }
    /// Inverse of the inertia tensor, body frame (computed once when the inertia is set, on
    /// the tensor scaled to a unit diagonal, so it is finite over the whole accepted range).
    #[must_use]
    pub fn inverse_inertia(&self) -> Mat3 {
        self.inv_inertia
    }
    /// Inertia tensor in the world frame, `R I Rᵀ`.
    #[must_use]
    pub fn world_inertia(&self) -> Mat3 {
        let r = Mat3::from_quat(self.orientation);
        r * self.inertia * r.transpose()
    }
    /// Position of the centre of mass.
    #[must_use]
    pub fn position(&self) -> Vec3 {
        self.position
    }
    /// Orientation quaternion.
    #[must_use]
    pub fn orientation(&self) -> Quat {
        self.orientation
    }
    /// The body-to-world 4×4 transform, by reference (the guide's `MdtBodyGetTransformPtr`):
    /// valid until the next step or pose change.
    #[must_use]
    pub fn transform(&self) -> &Mat4 {
        &self.transform
    }
    /// Linear velocity of the centre of mass.
    #[must_use]
    pub fn linear_velocity(&self) -> Vec3 {
        self.linear_velocity
    }
    /// Angular velocity (world frame).
    #[must_use]
    pub fn angular_velocity(&self) -> Vec3 {
        self.angular_velocity
    }
    /// Angular momentum about the centre of mass, `I_world ω`.
    #[must_use]
    pub fn angular_momentum(&self) -> Vec3 {
        self.world_inertia() * self.angular_velocity
    }
    /// Kinetic energy, `½ m v² + ½ ωᵀ I ω`.
    #[must_use]
    pub fn kinetic_energy(&self) -> Real {
        0.5 * self.mass * self.linear_velocity.length_squared()
            + 0.5 * self.angular_velocity.dot(self.angular_momentum())
    }
    /// Velocity of a world point moving with the body.
    #[must_use]
    pub fn velocity_at_point(&self, point: Vec3) -> Vec3 {
        self.linear_velocity + self.angular_velocity.cross(point - self.position)
    }
    /// Force accumulated for the next step (cleared by every step).
    #[must_use]
    pub fn force(&self) -> Vec3 {
        self.force
    }
    /// Torque accumulated for the next step (cleared by every step).
    #[must_use]
    pub fn torque(&self) -> Vec3 {
        self.torque
    }
    /// Linear acceleration over the last step, `(v⁺ − v)/h` (read-only, the guide's `accel`).
    #[must_use]
    pub fn linear_acceleration(&self) -> Vec3 {
        self.linear_acceleration
    }
    /// Angular acceleration over the last step (read-only, the guide's `accelrot`).
    #[must_use]
    pub fn angular_acceleration(&self) -> Vec3 {
        self.angular_acceleration
    }
    /// Linear velocity damping (kg/s).
    #[must_use]
    pub fn linear_damping(&self) -> Real {
        self.linear_damping
    }
    /// Angular velocity damping (N·m·s).
    #[must_use]
    pub fn angular_damping(&self) -> Real {
        self.angular_damping
    }
    /// Fast-spin axis in the body frame, if set.
    #[must_use]
    pub fn fast_spin_axis(&self) -> Option<Vec3> {
        self.fast_spin_axis
    }
    /// Whether the body is simulated.
    #[must_use]
    pub fn is_enabled(&self) -> bool {
        self.enabled
    }
    /// The user's data.
    #[must_use]
    pub fn user_data(&self) -> u64 {
        self.user_data
    }
    /// Whether this body asks for exact solving of its island.
    #[must_use]
    pub fn prefers_exact(&self) -> bool {
        self.prefer_exact
    }
    /// Asks for (or stops asking for) exact solving of this body's island in hybrid mode.
    pub fn set_prefer_exact(&mut self, prefer: bool) {
        self.prefer_exact = prefer;
    }
    /// Which path solved this body's island in the last step.
    #[must_use]
    pub fn last_solver_path(&self) -> SolverPath {
        self.last_path
    }
    /// Whether the body was disabled automatically because its island came to rest. It is
    /// still enabled: it wakes when touched, pushed, moved, or by [`crate::World::wake_body`].
    #[must_use]
    pub fn is_sleeping(&self) -> bool {
        self.sleeping
    }
    /// Converts a point from body to world coordinates.
    #[must_use]
    pub fn point_to_world(&self, local: Vec3) -> Vec3 {
        self.position + self.orientation * local
    }
    /// Converts a point from world to body coordinates.
    #[must_use]
    pub fn point_to_local(&self, world: Vec3) -> Vec3 {
        self.orientation.inverse() * (world - self.position)
    }

    /// Sets the mass, kg (within [`crate::error::MASS_RANGE`]).
    pub fn set_mass(&mut self, mass: Real) -> KeaResult<()> {
        check_mass("mass", mass)?;
        self.mass = mass;
        self.inv_mass = 1.0 / mass;
        Ok(())
    }
    /// Sets the body-frame inertia tensor (symmetric positive definite, diagonal within
    /// [`crate::error::INERTIA_RANGE`]).
    pub fn set_inertia(&mut self, inertia: Mat3) -> KeaResult<()> {
        // The symmetric part is stored: the check allows round-off asymmetry.
        let (inertia, inverse) = check_inertia("inertia", inertia)?;
        self.inertia = inertia;
        self.inv_inertia = inverse;
        Ok(())
    }
    /// Sets the position of the centre of mass.
    pub fn set_position(&mut self, position: Vec3) -> KeaResult<()> {
        check_coordinate("position", position)?;
        self.position = position;
        self.update_transform();
        self.wake();
        Ok(())
    }
    /// Sets the orientation (unit quaternion; renormalised).
    pub fn set_orientation(&mut self, orientation: Quat) -> KeaResult<()> {
        self.orientation = check_quat("orientation", orientation)?;
        self.update_transform();
        self.wake();
        Ok(())
    }
    /// Sets the linear velocity.
    pub fn set_linear_velocity(&mut self, v: Vec3) -> KeaResult<()> {
        self.linear_velocity = check_vec3("linear_velocity", v)?;
        self.wake();
        Ok(())
    }
    /// Sets the angular velocity (world frame).
    pub fn set_angular_velocity(&mut self, w: Vec3) -> KeaResult<()> {
        self.angular_velocity = check_vec3("angular_velocity", w)?;
        self.wake();
        Ok(())
    }
    /// Sets linear damping (kg/s, ≥ 0).
    pub fn set_linear_damping(&mut self, d: Real) -> KeaResult<()> {
        self.linear_damping = check_non_negative("linear_damping", d)?;
        Ok(())
    }
    /// Sets angular damping (N·m·s, ≥ 0).
    pub fn set_angular_damping(&mut self, d: Real) -> KeaResult<()> {
        self.angular_damping = check_non_negative("angular_damping", d)?;
        Ok(())
    }
    /// Sets or clears the fast-spin axis (body frame, unit).
    pub fn set_fast_spin_axis(&mut self, axis: Option<Vec3>) -> KeaResult<()> {
        self.fast_spin_axis = match axis {
            Some(a) => Some(check_unit("fast_spin_axis", a)?),
            None => None,
        };
        Ok(())
    }
    /// Enables or disables the body (a disabled body is fixed in place).
    ///
    /// Enabling a quarantined body releases it from quarantine.
    pub fn set_enabled(&mut self, enabled: bool) {
        self.enabled = enabled;
        self.quarantined &= !enabled;
    }
    /// Whether the world's quarantine froze (and disabled) this body after a step that blew
    /// up its island (see [`crate::World::quarantine_report`]).
    #[must_use]
    pub fn is_quarantined(&self) -> bool {
        self.quarantined
    }
    /// Whether the body is kinematic (see [`BodyDef::kinematic`]).
    #[must_use]
    pub fn is_kinematic(&self) -> bool {
        self.kinematic
    }
    /// Makes the body kinematic (moved only by its set velocity) or dynamic again. Its mass
    /// and inertia are kept for when it is dynamic.
    pub fn set_kinematic(&mut self, kinematic: bool) {
        self.kinematic = kinematic;
        self.wake();
    }
    /// Sets the user's data.
    pub fn set_user_data(&mut self, data: u64) {
        self.user_data = data;
    }
    /// Adds a force at the centre of mass for the next step. Refused, changing nothing, when
    /// it is not finite or the step's total would overflow.
    pub fn add_force(&mut self, f: Vec3) -> KeaResult<()> {
        self.force = accumulated("force", self.force, check_vec3("force", f)?)?;
        Ok(())
    }
    /// Adds a torque for the next step (refused as [`Body::add_force`] is).
    pub fn add_torque(&mut self, t: Vec3) -> KeaResult<()> {
        self.torque = accumulated("torque", self.torque, check_vec3("torque", t)?)?;
        Ok(())
    }
    /// Adds a force applied at a world point: the force at the centre of mass plus the torque
    /// `(p − x) × f` (the guide's `MdtBodyAddForceAtPosition`; refused as
    /// [`Body::add_force`] is, the torque's total too).
    pub fn add_force_at_point(&mut self, f: Vec3, point: Vec3) -> KeaResult<()> {
        check_vec3("force", f)?;
        check_vec3("point", point)?;
        let force = accumulated("force", self.force, f)?;
        let torque = accumulated("force", self.torque, (point - self.position).cross(f))?;
        self.force = force;
        self.torque = torque;
        Ok(())
    }
    /// Clears the force and torque accumulators.
    pub fn clear_forces(&mut self) {
        self.force = Vec3::ZERO;
        self.torque = Vec3::ZERO;
    }

    pub(crate) fn wake(&mut self) {
        self.sleeping = false;
        self.rest_time = 0.0;
    }

    pub(crate) fn sleep(&mut self) {
        self.sleeping = true;
        self.linear_velocity = Vec3::ZERO;
        self.angular_velocity = Vec3::ZERO;
        self.linear_acceleration = Vec3::ZERO;
        self.angular_acceleration = Vec3::ZERO;
    }

    pub(crate) fn update_transform(&mut self) {
        self.transform = Mat4::from_rotation_translation(self.orientation, self.position);
    }

    /// Takes a step's result: pose, velocities and accelerations (a solver's, or the reduced
    /// path's), the transform following.
    pub(crate) fn take_motion(&mut self, m: &Motion) {
        self.position = m.position;
        self.orientation = m.orientation;
        self.linear_velocity = m.linear_velocity;
        self.angular_velocity = m.angular_velocity;
        self.linear_acceleration = m.linear_acceleration;
        self.angular_acceleration = m.angular_acceleration;
        self.update_transform();
    }
}

/// A body's state after a step, as a solver leaves it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Motion {
    pub(crate) position: Vec3,
    pub(crate) orientation: Quat,
    pub(crate) linear_velocity: Vec3,
    pub(crate) angular_velocity: Vec3,
    pub(crate) linear_acceleration: Vec3,
    pub(crate) angular_acceleration: Vec3,
}

/// `total + added`, or an error naming `arg` when the sum is not finite (forces a step keeps
/// adding up must reach the solver finite: a refused step would keep its collision update).
fn accumulated(arg: &'static str, total: Vec3, added: Vec3) -> KeaResult<Vec3> {
    let sum = total + added;
    if sum.is_finite() {
        Ok(sum)
    } else {
        Err(KeaError::OutOfRange {
            arg,
            value: format!("{added} on top of {total}"),
            expected: "a total for the step that stays finite",
        })
    }
}
