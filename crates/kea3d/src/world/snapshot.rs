//! Snapshots of a world: its dynamics (clock included), collision layer, names and keyframed
//! paths, in the scene snapshot format (`kea_scene::SceneSnapshot`, binary or JSON), with what
//! this facade adds to them — body types, centres of mass, the colliders' placements and mass
//! rules, kinematic targets — so that a restored world reads and steps as the original.

use super::{BodyMeta, PhysicsWorld};
use kea::BodyHandle;
use kea_collision::{MaterialId, Surface};
use kea_scene::{SceneError, SceneSnapshot};
use serde::{Deserialize, Serialize};

/// The facade's own state, as it rides in [`SceneSnapshot::facade`].
#[derive(Serialize, Deserialize)]
struct FacadeState {
    meta: Vec<Option<BodyMeta>>,
    surfaces: Vec<(Surface, MaterialId)>,
    driven: Vec<BodyHandle>,
}

fn invalid(message: impl std::fmt::Display) -> SceneError {
    SceneError::Invalid {
        place: "snapshot".into(),
        message: message.to_string(),
    }
}

impl PhysicsWorld {
    /// The world's state now. Restoring it and stepping gives the same bits as stepping on,
    /// and the restored world reads the same: body types, frame origins (centres of mass off
    /// them), colliders' placements and kinematic targets are kept.
    pub fn snapshot(&self) -> Result<SceneSnapshot, SceneError> {
        let mut snapshot = SceneSnapshot::capture(
            &self.dynamics,
            &self.collision,
            &self.names,
            &self.joint_names,
            &self.paths,
        )?;
        let facade = FacadeState {
            meta: self.meta.clone(),
            surfaces: self.surfaces.clone(),
            driven: self.driven.clone(),
        };
        snapshot.facade = postcard::to_stdvec(&facade).map_err(invalid)?;
        Ok(snapshot)
    }

    /// The world a snapshot was taken of, at that instant. A snapshot of a scene's world made
    /// without this facade restores as [`PhysicsWorld::from_scene`] does.
    pub fn restore(snapshot: SceneSnapshot) -> Result<Self, SceneError> {
        let facade = snapshot.facade.clone();
        let mut world = Self::from_scene(snapshot.into_scene()?);
        if !facade.is_empty() {
            let state: FacadeState = postcard::from_bytes(&facade).map_err(invalid)?;
            for (i, m) in state.meta.iter().enumerate() {
                if let Some(m) = m {
                    if world.dynamics.body(m.handle).is_err() || m.handle.index() as usize != i {
                        return Err(invalid("the facade's bodies do not match the world's"));
                    }
                }
            }
            world.meta = state.meta;
            world.surfaces = state.surfaces;
            world.driven = state.driven;
        }
        Ok(world)
    }
}
