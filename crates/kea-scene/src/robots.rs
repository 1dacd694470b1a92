//! Robots in a scene file: `{"urdf": "robots/arm.urdf", "fixed_base": true}` or
//! `{"mjcf": "models/ant.xml"}`, placed by `position` and `rotation`. This crate only reads and
//! checks the entries and resolves their paths against the scene file's folder; the layer that
//! owns the world (`kea3d::PhysicsWorld::load_scene_robots`) reads the robot files.

use crate::error::SceneError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One robot of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotEntry {
    /// A URDF file (relative paths are against the scene file's folder).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urdf: Option<String>,
    /// An MJCF file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mjcf: Option<String>,
    /// URDF: weld the root link to the world (default false: a free base).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub fixed_base: bool,
    /// Where the robot's root (URDF) sits, m.
    #[serde(default, skip_serializing_if = "is_origin")]
    pub position: [f64; 3],
    /// How the robot's root (URDF) is turned: a unit quaternion x, y, z, w.
    #[serde(default = "identity", skip_serializing_if = "is_identity")]
    pub rotation: [f64; 4],
}

fn is_origin(p: &[f64; 3]) -> bool {
    *p == [0.0; 3]
}

fn identity() -> [f64; 4] {
    [0.0, 0.0, 0.0, 1.0]
}

fn is_identity(q: &[f64; 4]) -> bool {
    *q == identity()
}

impl RobotEntry {
    /// The robot's file, and whether it is MJCF. Errors name the entry.
    pub fn file(&self, index: usize) -> Result<(&str, bool), SceneError> {
        match (&self.urdf, &self.mjcf) {
            (Some(u), None) => Ok((u, false)),
            (None, Some(m)) => Ok((m, true)),
            _ => Err(SceneError::at(
                format!("robots[{index}]"),
                "give exactly one of `urdf` and `mjcf`",
            )),
        }
    }

    /// Checks the entry's numbers, naming the field.
    pub fn validate(&self, index: usize) -> Result<(), SceneError> {
        self.file(index)?;
        if self.position.iter().any(|x| !x.is_finite()) {
            return Err(SceneError::at(
                format!("robots[{index}].position"),
                "must be finite",
            ));
        }
        let len = self.rotation.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !len.is_finite() || (len - 1.0).abs() > 1e-3 {
            return Err(SceneError::at(
                format!("robots[{index}].rotation"),
                format!("{:?} is not a unit quaternion (x, y, z, w)", self.rotation),
            ));
        }
        if self.mjcf.is_some()
            && (self.fixed_base || !is_origin(&self.position) || !is_identity(&self.rotation))
        {
            return Err(SceneError::at(
                format!("robots[{index}]"),
                "an MJCF model places itself: `fixed_base`, `position` and `rotation` are for URDF",
            ));
        }
        Ok(())
    }

    /// The entry with its file's path made absolute against `folder` (a scene file's).
    #[must_use]
    pub fn resolved(&self, folder: &Path) -> Self {
        let fix = |p: &Option<String>| {
            p.as_ref().map(|p| {
                let path = Path::new(p);
                if path.is_absolute() {
                    p.clone()
                } else {
                    folder.join(path).to_string_lossy().into_owned()
                }
            })
        };
        Self {
            urdf: fix(&self.urdf),
            mjcf: fix(&self.mjcf),
            ..self.clone()
        }
    }
}
