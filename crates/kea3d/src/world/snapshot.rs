//! Snapshots of a world: its dynamics (clock included), collision layer, names and keyframed
//! paths, in the scene snapshot format (`kea_scene::SceneSnapshot`, binary or JSON).

use super::PhysicsWorld;
use kea_scene::{SceneError, SceneSnapshot};

impl PhysicsWorld {
    /// The world's state now. Restoring it and stepping gives the same bits as stepping on.
    ///
    /// What the facade adds to its layers is not saved: a restored world sees its bodies as
    /// [`PhysicsWorld::from_parts`] does (types from their flags, masses as they are, frame
    /// origins at the centres of mass), and a kinematic target set since the last step is
    /// not kept. Worlds built from scene files lose nothing.
    pub fn snapshot(&self) -> Result<SceneSnapshot, SceneError> {
        SceneSnapshot::capture(
            &self.dynamics,
            &self.collision,
            &self.names,
            &self.joint_names,
            &self.paths,
        )
    }

    /// The world a snapshot was taken of, at that instant.
    pub fn restore(snapshot: SceneSnapshot) -> Result<Self, SceneError> {
        Ok(Self::from_scene(snapshot.into_scene()?))
    }
}
