//! How a shape was made: its constructor and arguments. A snapshot saves the recipe and makes
//! the shape again through the same validated constructor (parry derives the same geometry
//! from the same input), rather than parry's internal form (`snapshot.rs`).

use kea::{Quat, Real, Vec3};

/// A shape constructor and its arguments.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) enum Recipe {
    Sphere(Real),
    Cuboid(Vec3),
    Plane(Vec3),
    Capsule(Real, Real),
    Cylinder(Real, Real),
    Cone(Real, Real),
    ConvexHull(Vec<Vec3>),
    Trimesh(Vec<Vec3>, Vec<[u32; 3]>),
    Heightfield(Vec<Vec<Real>>, Vec3),
    Compound(Vec<(Vec3, Quat, Recipe)>),
}
