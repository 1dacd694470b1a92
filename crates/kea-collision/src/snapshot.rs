//! Snapshots of a collision world (feature `serde`): the world itself derives serde; here are
//! shapes saved as their recipes and made again from them, parry's poses as a translation and
//! a rotation, and the check that a restored collision world fits its restored dynamics world.

use crate::collision_world::CollisionWorld;
use crate::error::{CollisionError, CollisionResult};
use crate::shape::Shape;
use crate::shape_recipe::Recipe;
use kea::World;

impl CollisionWorld {
    /// Checks that every collider's body and every manifold's contact is alive in `world`
    /// (a collision world restored beside the wrong world is refused).
    pub fn check_against(&self, world: &World) -> CollisionResult<()> {
        let bad = |what: String| CollisionError::DegenerateShape(format!("snapshot: {what}"));
        for slot in &self.slots {
            if let Some(body) = slot.collider.as_ref().and_then(|c| c.def.body) {
                if world.body(body).is_err() {
                    return Err(bad(format!(
                        "a collider's body {body:?} is not in the world"
                    )));
                }
            }
        }
        for pair in self.pairs.slots.iter().filter(|p| p.alive) {
            for m in &pair.manifolds {
                if world.contact(m.handle).is_err() {
                    return Err(bad(format!("contact {:?} is not in the world", m.handle)));
                }
            }
        }
        Ok(())
    }
}

/// `#[serde(with = "crate::snapshot::pose")]` for a parry pose.
pub(crate) mod pose {
    use crate::parry::math::Pose;
    use kea::{Quat, Vec3};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub(crate) fn serialize<S: Serializer>(p: &Pose, s: S) -> Result<S::Ok, S::Error> {
        (p.translation, p.rotation).serialize(s)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Pose, D::Error> {
        let (t, r) = <(Vec3, Quat)>::deserialize(d)?;
        Ok(Pose::from_parts(t, r))
    }
}

/// `#[serde(with = "crate::snapshot::pair_map")]`: the pair map as a list sorted by key (JSON
/// keys must be strings, and a sorted list makes the bytes the same every time).
pub(crate) mod pair_map {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};
    use std::collections::HashMap;

    type Map = HashMap<(u32, u32), u32>;

    pub(crate) fn serialize<S: Serializer>(map: &Map, s: S) -> Result<S::Ok, S::Error> {
        let mut list: Vec<((u32, u32), u32)> = map.iter().map(|(k, v)| (*k, *v)).collect();
        list.sort_unstable();
        list.serialize(s)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Map, D::Error> {
        let list = Vec::<((u32, u32), u32)>::deserialize(d)?;
        Ok(list.into_iter().collect())
    }
}

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

impl serde::Serialize for Shape {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.recipe.serialize(s)
    }
}

impl<'de> serde::Deserialize<'de> for Shape {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let recipe = Recipe::deserialize(d)?;
        recipe.build().map_err(serde::de::Error::custom)
    }
}
