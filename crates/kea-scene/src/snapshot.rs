//! Snapshots of a scene's world: the dynamics (its clock included), the collision layer and the
//! scene's names and keyframed paths, saved whole so that restoring and stepping reproduces the
//! uninterrupted run bit for bit. Two forms: a binary one (a magic line, then postcard) and
//! JSON. Both carry [`SNAPSHOT_VERSION`]; another version, the other precision, or a snapshot
//! whose parts do not fit together is refused by name.

use crate::bodies::BuiltScene;
use crate::error::SceneError;
use crate::paths::ScenePaths;
use kea::{BodyHandle, ConstraintHandle, World, WorldSnapshot};
use kea_collision::CollisionWorld;
use serde::{Deserialize, Serialize};

/// The scene snapshot format's version (2: the scene's clock is the world's; 3: the layer
/// above's own state rides along, [`SceneSnapshot::facade`]).
pub const SNAPSHOT_VERSION: u32 = 4;

/// The first bytes of a binary snapshot.
const MAGIC: &[u8; 8] = b"KEASNAP\n";

/// A scene world's whole state (see the module docs).
#[derive(Clone, Serialize, Deserialize)]
pub struct SceneSnapshot {
    /// Format version ([`SNAPSHOT_VERSION`]).
    pub version: u32,
    world: WorldSnapshot,
    collision: CollisionWorld,
    bodies: Vec<(String, BodyHandle)>,
    joints: Vec<(String, ConstraintHandle)>,
    paths: ScenePaths,
    /// What the layer that owns the world adds to it (`kea3d`'s body types, centres of mass
    /// and collider placements), in its own encoding; empty when it adds nothing.
    pub facade: Vec<u8>,
}

fn invalid(message: impl std::fmt::Display) -> SceneError {
    SceneError::Invalid {
        place: "snapshot".into(),
        message: message.to_string(),
    }
}

impl SceneSnapshot {
    /// The state of a scene's world now: its dynamics and collision layers, and the scene's
    /// named bodies and joints and keyframed paths.
    pub fn capture(
        world: &World,
        collision: &CollisionWorld,
        bodies: &[(String, BodyHandle)],
        joints: &[(String, ConstraintHandle)],
        paths: &ScenePaths,
    ) -> Result<Self, SceneError> {
        Ok(Self {
            version: SNAPSHOT_VERSION,
            world: world.snapshot().map_err(invalid)?,
            collision: collision.clone(),
            bodies: bodies.to_vec(),
            joints: joints.to_vec(),
            paths: paths.clone(),
            facade: Vec::new(),
        })
    }

    /// The scene the snapshot was taken of, at that instant; the parts checked against each
    /// other.
    pub fn into_scene(self) -> Result<BuiltScene, SceneError> {
        if self.version != SNAPSHOT_VERSION {
            return Err(SceneError::Version {
                found: self.version,
                expected: SNAPSHOT_VERSION,
            });
        }
        let world = World::restore(self.world).map_err(invalid)?;
        let collision = self.collision;
        collision.check_against(&world).map_err(invalid)?;
        Ok(BuiltScene {
            body_index: index(&self.bodies),
            joint_index: index(&self.joints),
            world,
            collision,
            bodies: self.bodies,
            joints: self.joints,
            paths: self.paths,
        })
    }

    /// The binary form.
    pub fn to_binary(&self) -> Result<Vec<u8>, SceneError> {
        let mut out = MAGIC.to_vec();
        out.extend_from_slice(&SNAPSHOT_VERSION.to_le_bytes());
        let body = postcard::to_stdvec(self).map_err(invalid)?;
        out.extend_from_slice(&body);
        Ok(out)
    }

    /// A snapshot from its binary form ([`SceneSnapshot::to_binary`]).
    pub fn from_binary(bytes: &[u8]) -> Result<Self, SceneError> {
        let rest = bytes
            .strip_prefix(MAGIC.as_slice())
            .ok_or_else(|| invalid("not a Kea snapshot (its first bytes are not `KEASNAP`)"))?;
        let (version, body) = rest
            .split_first_chunk::<4>()
            .ok_or_else(|| invalid("the snapshot is cut short"))?;
        let found = u32::from_le_bytes(*version);
        if found != SNAPSHOT_VERSION {
            return Err(SceneError::Version {
                found,
                expected: SNAPSHOT_VERSION,
            });
        }
        postcard::from_bytes(body).map_err(invalid)
    }

    /// The JSON form.
    pub fn to_json(&self) -> Result<String, SceneError> {
        serde_json::to_string(self).map_err(invalid)
    }

    /// A snapshot from its JSON form ([`SceneSnapshot::to_json`]).
    pub fn from_json(text: &str) -> Result<Self, SceneError> {
        serde_json::from_str(text).map_err(invalid)
    }
}

impl BuiltScene {
    /// The scene's state now.
    pub fn snapshot(&self) -> Result<SceneSnapshot, SceneError> {
        SceneSnapshot::capture(
            &self.world,
            &self.collision,
            &self.bodies,
            &self.joints,
            &self.paths,
        )
    }
}

/// Names to their positions in a list.
fn index<H>(names: &[(String, H)]) -> std::collections::HashMap<String, usize> {
    names
        .iter()
        .enumerate()
        .map(|(i, (n, _))| (n.clone(), i))
        .collect()
}
