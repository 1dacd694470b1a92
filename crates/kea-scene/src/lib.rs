//! Kea scene files: a documented, versioned JSON format (`docs/scene-format.md`) that describes a
//! whole world — parameters, materials and their pairs, static geometry, bodies with their
//! shapes, every joint type of the guide with limits and motors, and repeated structures — and
//! builds it into a `kea::World` with a `kea_collision::CollisionWorld`, the bodies and joints
//! by name and the keyframed paths ([`BuiltScene`]). It builds and saves; it does not step:
//! `kea3d::PhysicsWorld::from_scene` takes the built scene and its pipeline steps it.
//!
//! ```
//! let text = r#"{ "version": 1,
//!   "static": [ { "shape": { "plane": { "normal": [0, 1, 0] } } } ],
//!   "bodies": [ { "name": "ball", "position": [0, 2, 0],
//!                 "shapes": [ { "shape": { "sphere": { "radius": 0.5 } } } ] } ] }"#;
//! let scene = kea_scene::Scene::from_json(text).unwrap();
//! let built = kea_scene::build(&scene).unwrap();
//! assert!(built.body("ball").is_some());
//! ```

#![warn(missing_docs)]

mod bodies;
mod build;
mod car_wheel;
mod error;
mod format;
mod groups;
mod joint_format;
mod joint_limits;
mod joints;
mod paths;
mod robots;
mod shape_format;
mod snapshot;

pub use bodies::BuiltScene;
pub use build::{body_count, build, MAX_BODIES, MAX_CONSTRAINTS};
pub use error::SceneError;
pub use format::{
    BodySpec, ColliderSpec, InertiaSpec, IterativeSpec, MaterialPairSpec, MaterialSpec,
    RoutingSpec, Scene, ShapeSpec, SleepSpec, SolverSpec, WorldSpec, V3, VERSION,
};
pub use joint_format::{GroupSpec, JointKind, JointSpec, LimitSpec, OneCoordinateSpec, StopsSpec};
pub use paths::ScenePaths;
pub use robots::RobotEntry;
pub use snapshot::{SceneSnapshot, SNAPSHOT_VERSION};

impl Scene {
    /// Reads a scene from JSON text. Errors carry the line and column and what was expected.
    pub fn from_json(text: &str) -> Result<Self, SceneError> {
        let scene: Scene = serde_json::from_str(text)?;
        if scene.version != VERSION {
            return Err(SceneError::Version {
                found: scene.version,
                expected: VERSION,
            });
        }
        Ok(scene)
    }

    /// The scene with its robots' file paths made absolute against `folder` (the scene
    /// file's), so that it can be built from anywhere.
    #[must_use]
    pub fn with_paths_from(mut self, folder: &std::path::Path) -> Self {
        self.robots = self.robots.iter().map(|r| r.resolved(folder)).collect();
        self
    }

    /// Writes the scene as JSON (two-space indentation, fields in a fixed order, defaults
    /// omitted), ending with a newline. Reading a file written this way and writing it again gives
    /// the same text.
    #[must_use]
    pub fn to_json(&self) -> String {
        let mut text = serde_json::to_string_pretty(self).expect("a scene is always serialisable");
        text.push('\n');
        text
    }
}
