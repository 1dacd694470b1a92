//! # Kea: rigid-body dynamics with an exact constraint solver
//!
//! Kea re-creates the layered engine of the MathEngine Dynamics Toolkit 2.0 in Rust:
//!
//! * [`solver`] — the Kea solver (MdtKea): bodies and constraint rows in, new states and
//!   constraint forces out, by an exact boxed-LCP solve per island. Callable without a world.
//! * [`constraint`] — constraint rows (MdtBcl): contacts, joints, and your own.
//! * [`World`] — the retained world (Mdt): bodies, constraints, the step.
//!
//! ```
//! use kea::{World, BodyDef, Vec3};
//! let mut world = World::with_capacity(16, 16).unwrap();
//! let ball = world
//!     .create_body(&BodyDef { position: Vec3::new(0.0, 10.0, 0.0), ..Default::default() })
//!     .unwrap();
//! for _ in 0..60 {
//!     world.step(1.0 / 60.0).unwrap();
//! }
//! let y = world.body(ball).unwrap().position().y;
//! assert!(y < 10.0 - 4.5 && y > 10.0 - 5.2); // about ½ g t² after 1 s
//! ```
#![warn(missing_docs)]

pub mod articulation;
pub use articulation::Integrator;
pub mod body;
pub mod cache;
pub mod constraint;
pub mod edge_lists;
pub mod error;
pub mod float_mode;
mod handle;
pub mod math;
pub mod prefetch;
pub mod solver;
pub mod threads;
pub mod timing;
mod union_find;
pub mod world;

pub use body::{inertia, Body, BodyDef};
pub use constraint::{
    Actuator, BallJoint, CarWheel, Contact, ContactParams, ContactPoint, ContactType,
    CustomConstraint, FixedJoint, FixedPath, FrictionModel, Hinge, Jacobian, JointDynamics, Limit,
    Linear1, Linear2, Motor, Planar, PointForce, Prismatic, Row, RowBody, RowContext, RowWriter,
    SingleLimit, SoftLimit, Softness, Spring, UniversalJoint, MAX_CONTACT_POINTS,
};
pub use error::{KeaError, KeaResult};
pub use handle::{BodyHandle, ConstraintHandle};
pub use math::{Mat3, Mat4, Quat, Real, Vec3, PI as PI_REAL};
pub use solver::{
    IslandReport, IterativeParams, Reaction, Routing, SimdLevel, Solver, SolverBody, SolverContact,
    SolverMode, SolverParams, SolverPath, SolverStats, DEFAULT_CONTACT_SPRING,
    DENSE_EXACT_MAX_ROWS, EXACT_CONTACT_STIFFENING,
};
pub use threads::PARALLEL_MIN_BODIES;
pub use world::{
    CollisionStats, DemMode, DemSettings, FixedTendon, HeldState, IslandList, JointHandle,
    JointKind, JointRange, JointSketch, JointSpec, OneCoordinate, QuarantineEvent,
    QuarantineReason, SpeedLimits, StepSize, StepStats, TendonHandle, TendonTerm, World, WorldDef,
    WorldSettings, MAX_CAPACITY,
};
#[cfg(feature = "serde")]
pub use world::{WorldSnapshot, SNAPSHOT_VERSION as WORLD_SNAPSHOT_VERSION};

/// The tour of this layer (`docs/tour.md`), compiled and run as a doctest so that it stays true.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/tour.md")]
pub struct TourDoctests;
