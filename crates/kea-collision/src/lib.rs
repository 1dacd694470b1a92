//! Kea's collision layer (the guide's Collision Toolkit and its Dynamics Toolkit Bridge).
//!
//! Shapes are [`parry3d`] geometry (`parry3d-f64` with the `f64` feature) attached to Kea bodies
//! with a local offset. Each [`CollisionWorld::update_contacts`] finds the overlapping pairs
//! (sweep and prune on the x axis), builds parry contact manifolds for them, and keeps the world's
//! contacts in step with those manifolds: a contact point that persists keeps its Kea constraint handle, so both
//! solvers warm-start it; a point that disappears has its contact destroyed.
//!
//! Also here: [`MaterialTable`] (pair entries and combine rules), group/mask filtering and
//! exclusion of jointed bodies, began/persisted/ended [`ContactEvent`]s and pair impulses, and
//! ray, shape-cast, overlap and point queries.
//!
//! Memory: once warm, a step allocates nothing for boxes and spheres (the tested case); parry
//! 0.31's manifold generators for a plane against a convex shape, and for its polygonal-feature
//! path (capsule, cylinder, cone or hull against a polyhedron), allocate once per such pair per
//! step (pinned by `tests/zero_alloc.rs`).
//!
//! This layer produces contacts and never steps the world: `kea3d::PhysicsWorld` owns the step
//! (drivers, contacts, solve). The dynamics crate stays usable without this one: everything here
//! goes through `kea::World`'s public contact API.
//!
//! Precision: enable `kea-collision/f64` (which enables `kea/f64`) for double precision; enabling
//! `kea/f64` alone is a compile error here, because the geometry must match the dynamics.

#![warn(missing_docs)]

mod body_colliders;
mod broad_phase;
mod capacity;
mod cast_window;
mod collider;
mod collision_world;
mod error;
mod events;
mod guard;
mod manifold_gen;
mod material;
mod narrow_pass;
mod narrow_phase;
mod pairable;
mod pairs;
mod proxies;
mod query;
mod readouts;
mod reduce;
mod shape;
mod shape_recipe;
#[cfg(feature = "serde")]
mod snapshot;
mod state_copy;
mod sync;
mod tessellate;

pub use cast_window::MAX_CAST_CELLS;
pub use collision_world::{
    ColliderDef, ColliderHandle, CollisionWorld, ContactStrategy, FAT_LOOKAHEAD, FAT_MARGIN,
};
pub use error::{CollisionError, CollisionResult, MAX_ASPECT, SIZE_RANGE};
pub use events::{ContactEvent, ContactEventKind};
pub use material::{MaterialId, MaterialTable, PairContact, Surface};
pub use narrow_phase::{CACHE_ANGLE, CACHE_DISTANCE};
pub use query::{PointHit, QueryFilter, RayCast, RayHit, ShapeCast, ShapeHit};
pub use shape::{MassProperties, Shape};
pub use tessellate::PLANE_HALF_SIZE;

/// The parry crate matching Kea's precision.
#[cfg(not(feature = "f64"))]
pub use parry3d as parry;
/// The parry crate matching Kea's precision.
#[cfg(feature = "f64")]
pub use parry3d_f64 as parry;

// The geometry and the dynamics must use the same real type.
const _: () = assert!(
    std::mem::size_of::<kea::Real>() == std::mem::size_of::<parry::math::Real>(),
    "kea is built with `f64` but kea-collision is not: enable `kea-collision/f64` instead of `kea/f64`"
);
