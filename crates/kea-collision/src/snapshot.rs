//! Snapshots of a collision world (feature `serde`): the world itself derives serde (shapes
//! as their recipes); here are parry's poses as a translation and a rotation, and the check
//! that a restored collision world fits its restored dynamics world.

use crate::collision_world::CollisionWorld;
use crate::error::{CollisionError, CollisionResult};
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
