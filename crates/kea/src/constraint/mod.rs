//! Constraints as rows (the guide's MdtBcl): contacts, joints, and the user's own.
//!
//! Every constraint writes [`Row`]s through a [`RowWriter`], given a [`RowContext`] that shows the
//! current state of its (up to) two bodies. Neither the constraint nor the user knows which solver
//! will use the rows.

pub mod ball;
pub mod car_wheel;
pub mod contact;
mod contact_params;
pub mod fixed;
pub mod fixed_path;
pub mod hinge;
pub mod joint;
pub mod limit;
pub mod linear1;
pub mod linear2;
pub mod planar;
pub mod prismatic;
pub mod row;
pub mod softness;
pub mod universal;

pub use ball::{BallJoint, BallLimits};
pub use car_wheel::CarWheel;
pub use contact::{
    Contact, ContactParams, ContactPoint, ContactType, FrictionModel, PointForce,
    MAX_CONTACT_POINTS,
};
pub use fixed::FixedJoint;
pub use fixed_path::FixedPath;
pub use hinge::Hinge;
pub use limit::{Actuator, JointDynamics, Limit, Motor, SingleLimit, SoftLimit};
pub use linear1::Linear1;
pub use linear2::Linear2;
pub use planar::Planar;
pub use prismatic::Prismatic;
pub use row::{FrictionLink, Jacobian, Row, RowWriter};
pub use softness::{SoftCoefficients, Softness, Spring};
pub use universal::UniversalJoint;

use crate::math::{Quat, Real, Vec3};

/// The state of one body of a constraint, as the constraint sees it while writing rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RowBody {
    /// Centre of mass, world frame (zero for the static world).
    pub position: Vec3,
    /// Orientation (identity for the static world).
    pub orientation: Quat,
    /// Linear velocity at the start of the step.
    pub linear_velocity: Vec3,
    /// Angular velocity at the start of the step.
    pub angular_velocity: Vec3,
    /// Linear velocity the body would have at the end of the step with no constraints
    /// (gravity and applied forces included, damping not).
    pub free_linear_velocity: Vec3,
    /// Angular velocity the body would have at the end of the step with no constraints.
    pub free_angular_velocity: Vec3,
    /// False for the static world or a disabled body: it does not move.
    pub dynamic: bool,
    /// The body's fast-spin axis in the world frame, if it has one: joints that leave it free
    /// (a wheel's hinge) take their free axis from it, so the spin never leaks into sideways
    /// rotation.
    pub fast_spin_axis: Option<Vec3>,
}

impl RowBody {
    /// The static world: fixed at the origin.
    pub const STATIC: Self = Self {
        position: Vec3::ZERO,
        orientation: Quat::IDENTITY,
        linear_velocity: Vec3::ZERO,
        angular_velocity: Vec3::ZERO,
        free_linear_velocity: Vec3::ZERO,
        free_angular_velocity: Vec3::ZERO,
        dynamic: false,
        fast_spin_axis: None,
    };

    /// A fixed body at a pose (a disabled body).
    #[must_use]
    pub fn fixed(position: Vec3, orientation: Quat) -> Self {
        Self {
            position,
            orientation,
            ..Self::STATIC
        }
    }

    /// World position of a point given in this body's frame.
    #[must_use]
    pub fn point_to_world(&self, local: Vec3) -> Vec3 {
        self.position + self.orientation * local
    }

    /// World direction of a vector given in this body's frame.
    #[must_use]
    pub fn vector_to_world(&self, local: Vec3) -> Vec3 {
        self.orientation * local
    }

    /// Velocity at the start of the step of a world point moving with the body.
    #[must_use]
    pub fn velocity_at(&self, point: Vec3) -> Vec3 {
        self.linear_velocity + self.angular_velocity.cross(point - self.position)
    }

    /// Unconstrained end-of-step velocity of a world point moving with the body.
    #[must_use]
    pub fn free_velocity_at(&self, point: Vec3) -> Vec3 {
        self.free_linear_velocity + self.free_angular_velocity.cross(point - self.position)
    }
}

/// What a constraint sees while writing its rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RowContext {
    /// The constraint's first and second body (the second is [`RowBody::STATIC`] for the world).
    pub bodies: [RowBody; 2],
    /// The step size h.
    pub dt: Real,
    /// The solver's default softness ε.
    pub epsilon: Real,
    /// The solver's default relaxation γ.
    pub gamma: Real,
    /// The default softness of contacts (mass-independent).
    pub contact_spring: Spring,
}

impl RowContext {
    /// World point `p` in each body's frame (a joint's anchors as it is made).
    #[must_use]
    pub fn local_points(&self, p: Vec3) -> [Vec3; 2] {
        self.bodies
            .map(|b| b.orientation.inverse() * (p - b.position))
    }

    /// World direction `v` in each body's frame (a joint's axes as it is made).
    #[must_use]
    pub fn local_vectors(&self, v: Vec3) -> [Vec3; 2] {
        self.bodies.map(|b| b.orientation.inverse() * v)
    }
}

/// A user-written constraint (the guide: "You Can Add Your Own Joint Types"): it only has to
/// write rows. Add it with [`crate::World::add_custom_constraint`]. It must be `Clone` (derive
/// it), so that a world holding it can be cloned.
pub trait CustomConstraint: std::fmt::Debug + Send + Sync + 'static + CloneCustom {
    /// A short name for logs and errors.
    fn name(&self) -> &'static str {
        "custom constraint"
    }
    /// Writes this step's rows. Friction links refer to row indices within this constraint.
    ///
    /// It must depend only on its inputs: the world may call it more than once per step (the
    /// position projection writes rows again at the new state), and discards the rows of a
    /// step that fails. Change the constraint's parameters between steps through
    /// [`crate::World::custom_constraint_mut`].
    fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>);
}

/// Cloning a boxed [`CustomConstraint`]; implemented for every custom constraint that is
/// `Clone`.
pub trait CloneCustom {
    /// A boxed copy.
    fn clone_box(&self) -> Box<dyn CustomConstraint>;
}

impl<T: CustomConstraint + Clone> CloneCustom for T {
    fn clone_box(&self) -> Box<dyn CustomConstraint> {
        Box::new(self.clone())
    }
}

impl Clone for Box<dyn CustomConstraint> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}
