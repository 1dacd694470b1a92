//! How a shape was made: its constructor and arguments. A snapshot saves the recipe and makes
//! the shape again through the same validated constructor (parry derives the same geometry
//! from the same input), rather than parry's internal form.

#[cfg(feature = "serde")]
use crate::{error::CollisionResult, shape::Shape};
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

#[cfg(feature = "serde")]
impl Recipe {
    /// The shape, made again (and checked again).
    pub(crate) fn build(&self) -> CollisionResult<Shape> {
        match self {
            Recipe::Sphere(r) => Shape::sphere(*r),
            Recipe::Cuboid(h) => Shape::cuboid(*h),
            Recipe::Plane(n) => Shape::plane(*n),
            Recipe::Capsule(h, r) => Shape::capsule(*h, *r),
            Recipe::Cylinder(h, r) => Shape::cylinder(*h, *r),
            Recipe::Cone(h, r) => Shape::cone(*h, *r),
            Recipe::ConvexHull(points) => Shape::convex_hull(points),
            Recipe::Trimesh(v, i) => Shape::trimesh(v.clone(), i.clone()),
            Recipe::Heightfield(heights, size) => Shape::heightfield(heights, *size),
            Recipe::Compound(parts) => {
                let parts = parts
                    .iter()
                    .map(|(o, q, r)| Ok((*o, *q, r.build()?)))
                    .collect::<CollisionResult<Vec<_>>>()?;
                Shape::compound(&parts)
            }
        }
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for Shape {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.recipe.serialize(s)
    }
}

#[cfg(feature = "serde")]
impl<'de> serde::Deserialize<'de> for Shape {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let recipe = Recipe::deserialize(d)?;
        recipe.build().map_err(serde::de::Error::custom)
    }
}
