//! Body types and the body builder.

use kea::{Mat3, Quat, Real, Vec3};

/// How a body moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum BodyType {
    /// Moved by gravity, forces, contacts and joints.
    Dynamic,
    /// Never moves (unless you place it): the ground, walls, fixed machinery. Joints and
    /// contacts treat it as infinitely heavy.
    Static,
    /// Moves with the velocity you set, pushed by nothing.
    KinematicVelocity,
    /// Moves to the pose you set for each step ([`crate::PhysicsWorld::set_kinematic_target`]),
    /// with the velocity that gets it there, pushed by nothing.
    KinematicPosition,
}

/// A body to insert, made with a builder:
/// `Body::dynamic().position([0.0, 2.0, 0.0]).linear_velocity([1.0, 0.0, 0.0])`.
///
/// Its position is its frame's origin; colliders are placed in that frame, and its centre of
/// mass follows from them. Its mass and inertia come from its colliders' density unless set
/// here: an explicit mass wins, and without an explicit inertia the colliders' inertia is
/// scaled to that mass.
///
/// ```
/// use kea3d::prelude::*;
///
/// let mut world = PhysicsWorld::new();
/// // A 2 kg box: the explicit mass wins over the collider's density.
/// let crate_body = world.insert_body(Body::dynamic().position([0.0, 1.0, 0.0]).mass(2.0))?;
/// world.insert_collider(Collider::cuboid([0.5, 0.5, 0.5]).density(10.0), Some(crate_body))?;
/// assert_eq!(world.dynamics().body(crate_body)?.mass(), 2.0);
/// // A fixed body never moves; a kinematic one moves at its set velocity, pushed by nothing.
/// let floor = world.insert_body(Body::fixed())?;
/// world.insert_collider(Collider::halfspace([0.0, 1.0, 0.0]), Some(floor))?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[must_use]
pub struct Body {
    pub(crate) kind: BodyType,
    pub(crate) position: Vec3,
    pub(crate) rotation: Quat,
    pub(crate) linear_velocity: Vec3,
    pub(crate) angular_velocity: Vec3,
    pub(crate) mass: Option<Real>,
    pub(crate) inertia: Option<Mat3>,
    pub(crate) center_of_mass: Option<Vec3>,
    pub(crate) linear_damping: Real,
    pub(crate) angular_damping: Real,
    pub(crate) user_data: u64,
    pub(crate) prefer_exact: bool,
    pub(crate) fast_spin_axis: Option<Vec3>,
}

impl Body {
    /// A body of type `kind` at the origin, at rest.
    pub fn new(kind: BodyType) -> Self {
        Self {
            kind,
            position: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            mass: None,
            inertia: None,
            center_of_mass: None,
            linear_damping: 0.0,
            angular_damping: 0.0,
            user_data: 0,
            prefer_exact: false,
            fast_spin_axis: None,
        }
    }

    /// A dynamic body.
    pub fn dynamic() -> Self {
        Self::new(BodyType::Dynamic)
    }

    /// A static body.
    pub fn fixed() -> Self {
        Self::new(BodyType::Static)
    }

    /// A kinematic body driven by the velocity you set.
    pub fn kinematic_velocity_based() -> Self {
        Self::new(BodyType::KinematicVelocity)
    }

    /// A kinematic body driven to the pose you set for each step.
    pub fn kinematic_position_based() -> Self {
        Self::new(BodyType::KinematicPosition)
    }

    /// Where the body's frame starts, m (`[x, y, z]`, a tuple or a `Vec3`).
    pub fn position(mut self, position: impl Into<Vec3>) -> Self {
        self.position = position.into();
        self
    }

    /// The body's orientation (a unit quaternion).
    pub fn rotation(mut self, rotation: Quat) -> Self {
        self.rotation = rotation;
        self
    }

    /// Velocity of the centre of mass, m/s.
    pub fn linear_velocity(mut self, v: impl Into<Vec3>) -> Self {
        self.linear_velocity = v.into();
        self
    }

    /// Angular velocity, rad/s, world frame.
    pub fn angular_velocity(mut self, w: impl Into<Vec3>) -> Self {
        self.angular_velocity = w.into();
        self
    }

    /// An explicit mass, kg: it wins over the colliders' density.
    pub fn mass(mut self, mass: Real) -> Self {
        self.mass = Some(mass);
        self
    }

    /// An explicit inertia tensor about the centre of mass, body frame, kg·m².
    pub fn inertia(mut self, inertia: Mat3) -> Self {
        self.inertia = Some(inertia);
        self
    }

    /// An explicit centre of mass in the body's frame, m (a robot link's inertial frame): it
    /// wins over the colliders'. Without it the centre of mass follows the colliders.
    pub fn center_of_mass(mut self, com: impl Into<Vec3>) -> Self {
        self.center_of_mass = Some(com.into());
        self
    }

    /// Linear damping, kg/s (integrated implicitly).
    pub fn linear_damping(mut self, d: Real) -> Self {
        self.linear_damping = d;
        self
    }

    /// Angular damping, N·m·s (integrated implicitly).
    pub fn angular_damping(mut self, d: Real) -> Self {
        self.angular_damping = d;
        self
    }

    /// Free for the user.
    pub fn user_data(mut self, data: u64) -> Self {
        self.user_data = data;
        self
    }

    /// Ask for the exact solver for this body's island (vehicles, ragdolls, mechanisms).
    pub fn prefer_exact(mut self, prefer: bool) -> Self {
        self.prefer_exact = prefer;
        self
    }

    /// A fast-spin axis in the body frame (a wheel's axle): spin about it is integrated as
    /// its own exact rotation.
    pub fn fast_spin_axis(mut self, axis: impl Into<Vec3>) -> Self {
        self.fast_spin_axis = Some(axis.into());
        self
    }

    /// The body's type.
    pub fn body_type(&self) -> BodyType {
        self.kind
    }
}

impl From<BodyType> for Body {
    fn from(kind: BodyType) -> Self {
        Self::new(kind)
    }
}
