//! # kea3d: Kea in one crate
//!
//! One object to step: a [`PhysicsWorld`] owns the dynamics ([`kea::World`]) and the
//! collision layer ([`kea_collision::CollisionWorld`]) together. Bodies have types (dynamic,
//! static, kinematic), get their mass and inertia from their colliders' density unless you
//! give one, and are made with builders; joints come back as typed handles whose own calls
//! live on them; capacities grow as the world fills.
//!
//! ```
//! use kea3d::prelude::*;
//!
//! let mut world = PhysicsWorld::new();
//! let ground = world.insert_body(Body::fixed()).unwrap();
//! world.insert_collider(Collider::cuboid([5.0, 0.5, 5.0]), Some(ground)).unwrap();
//! let ball = world.insert_body(Body::dynamic().position([0.0, 3.0, 0.0])).unwrap();
//! world.insert_collider(Collider::ball(0.5).density(1000.0), Some(ball)).unwrap();
//! for _ in 0..120 {
//!     world.step(1.0 / 60.0).unwrap();
//! }
//! let y = world.position(ball).unwrap().y;
//! assert!((y - 1.0).abs() < 0.05, "resting on the ground: y = {y}");
//! ```
//!
//! The guide-level layers stay underneath for those who want them: [`dynamics`] (the world,
//! constraint rows and the immediate-mode solver), [`collision`] and [`scene`]; reach a world's
//! own with [`PhysicsWorld::dynamics`] and [`PhysicsWorld::collision`]. `docs/api-map.md` says
//! which layer answers each function of the guide.
#![warn(missing_docs)]

mod body;
mod collider;
mod mass;
pub mod robot;
mod world;

pub use body::{Body, BodyType};
pub use collider::{Collider, DEFAULT_DENSITY};
/// A joint to insert, made with a builder: `Joint::hinge(anchor, axis).limits(-1.0, 1.0)` (the
/// dynamics layer's [`kea::JointSpec`]).
pub use kea::JointSpec as Joint;
pub use kea::{JointHandle, JointKind};
pub use world::{HeldWorld, PhysicsWorld};

/// The dynamics layer (the guide's Kea, Bcl and Mdt): [`kea`] re-exported.
pub use kea as dynamics;
/// The collision layer: [`kea_collision`] re-exported.
pub use kea_collision as collision;
/// Scene files: [`kea_scene`] re-exported.
pub use kea_scene as scene;

pub use kea::{BodyHandle, Mat3, Quat, Real, StepStats, Vec3};

/// The README's quick start, compiled and run as a doctest so that it stays true.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
pub use kea_collision::{ColliderHandle, CollisionError as Error, Shape};

/// What a fallible call of this crate returns: its error names the argument and the value.
pub type Result<T> = std::result::Result<T, Error>;

/// Everything a typical program uses.
pub mod prelude {
    pub use crate::{
        Body, BodyHandle, BodyType, Collider, ColliderHandle, Joint, JointHandle, PhysicsWorld,
        Quat, Real, Vec3,
    };
    pub use kea::{
        BallJoint, FixedJoint, Hinge, Linear1, Linear2, Planar, Prismatic, UniversalJoint,
    };
}
