//! Snapshots of a built scene: the world, its collision layer and the scene's drivers, saved
//! whole so that restoring and stepping reproduces the uninterrupted run bit for bit. Two
//! forms: a binary one (a magic line, then postcard) and JSON. Both carry
//! [`SNAPSHOT_VERSION`]; another version, the other precision, or a snapshot whose parts do
//! not fit together is refused by name.

use crate::build::BuiltScene;
use crate::error::SceneError;
use kea::{BodyHandle, ConstraintHandle, Real, World, WorldSnapshot};
use kea_collision::CollisionWorld;
use serde::{Deserialize, Serialize};

/// The scene snapshot format's version.
pub const SNAPSHOT_VERSION: u32 = 1;

/// The first bytes of a binary snapshot.
const MAGIC: &[u8; 8] = b"KEASNAP\n";

/// A built scene's whole state (see the module docs).
#[derive(Clone, Serialize, Deserialize)]
pub struct SceneSnapshot {
    /// Format version ([`SNAPSHOT_VERSION`]).
    pub version: u32,
    world: WorldSnapshot,
    collision: CollisionWorld,
    bodies: Vec<(String, BodyHandle)>,
    joints: Vec<(String, ConstraintHandle)>,
    paths: crate::joints::ScenePaths,
    time: Real,
}

fn invalid(message: impl std::fmt::Display) -> SceneError {
    SceneError::Invalid {
        place: "snapshot".into(),
        message: message.to_string(),
    }
}

impl BuiltScene {
    /// The scene's state now.
    pub fn snapshot(&self) -> Result<SceneSnapshot, SceneError> {
        Ok(SceneSnapshot {
            version: SNAPSHOT_VERSION,
            world: self.world.snapshot().map_err(invalid)?,
            collision: self.collision.clone(),
            bodies: self.bodies.clone(),
            joints: self.joints.clone(),
            paths: self.paths.clone(),
            time: self.time,
        })
    }

    /// The scene a snapshot was taken of, at that instant.
    pub fn restore(snapshot: SceneSnapshot) -> Result<BuiltScene, SceneError> {
        if snapshot.version != SNAPSHOT_VERSION {
            return Err(SceneError::Version {
                found: snapshot.version,
                expected: SNAPSHOT_VERSION,
            });
        }
        let world = World::restore(snapshot.world).map_err(invalid)?;
        let collision = snapshot.collision;
        collision.check_against(&world).map_err(invalid)?;
        Ok(BuiltScene {
            body_index: index(&snapshot.bodies),
            joint_index: index(&snapshot.joints),
            world,
            collision,
            bodies: snapshot.bodies,
            joints: snapshot.joints,
            paths: snapshot.paths,
            time: snapshot.time,
        })
    }

    /// The scene's state now, in the binary form.
    pub fn snapshot_binary(&self) -> Result<Vec<u8>, SceneError> {
        let mut out = MAGIC.to_vec();
        out.extend_from_slice(&SNAPSHOT_VERSION.to_le_bytes());
        let body = postcard::to_stdvec(&self.snapshot()?).map_err(invalid)?;
        out.extend_from_slice(&body);
        Ok(out)
    }

    /// The scene saved by [`BuiltScene::snapshot_binary`].
    pub fn restore_binary(bytes: &[u8]) -> Result<BuiltScene, SceneError> {
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
        let snapshot: SceneSnapshot = postcard::from_bytes(body).map_err(invalid)?;
        Self::restore(snapshot)
    }

    /// The scene's state now, as JSON.
    pub fn snapshot_json(&self) -> Result<String, SceneError> {
        serde_json::to_string(&self.snapshot()?).map_err(invalid)
    }

    /// The scene saved by [`BuiltScene::snapshot_json`].
    pub fn restore_json(text: &str) -> Result<BuiltScene, SceneError> {
        let snapshot: SceneSnapshot = serde_json::from_str(text).map_err(invalid)?;
        Self::restore(snapshot)
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
