//! Keyframed paths of fixed-path joints: checked when a scene is built, sampled before each
//! step by the stepping pipeline.

use crate::error::SceneError;
use kea::{Real, Vec3};

/// A scene's fixed-path joints with keyframed paths: before each step, every path is set to its
/// position now, with the velocity that reaches its next position at the end of the step.
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
#[serde(transparent)]
pub struct ScenePaths(pub(crate) Vec<PathDriver>);

impl ScenePaths {
    /// For a step of `dt` starting at scene time `time`: each path joint, where its path is now,
    /// and the velocity that takes it to where the path is at the end of the step (the values
    /// for [`kea::JointHandle::set_path`], which the stepping pipeline writes).
    pub fn samples(
        &self,
        time: Real,
        dt: Real,
    ) -> impl Iterator<Item = (kea::JointHandle<kea::FixedPath>, Vec3, Vec3)> + '_ {
        self.0.iter().map(move |p| {
            let (position, velocity) = p.sample(time, dt);
            (p.joint, position, velocity)
        })
    }

    /// Whether the scene has no keyframed paths.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// A fixed-path joint driven along keyframes `[t, x, y, z]` (world frame).
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct PathDriver {
    /// The joint.
    pub joint: kea::JointHandle<kea::FixedPath>,
    /// Keyframes, t strictly increasing.
    pub(crate) keys: Vec<[Real; 4]>,
}

impl PathDriver {
    /// The path point at time `t`: linear between keyframes, held outside them.
    fn at(&self, t: Real) -> Vec3 {
        let p = |k: &[Real; 4]| Vec3::new(k[1], k[2], k[3]);
        let first = &self.keys[0];
        if t <= first[0] {
            return p(first);
        }
        for w in self.keys.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            if t <= b[0] {
                let s = (t - a[0]) / (b[0] - a[0]);
                return p(a).lerp(p(b), s);
            }
        }
        p(self.keys.last().expect("at least one keyframe"))
    }

    /// Where the path is at `t` and the velocity that takes it to where it is at `t + dt`.
    pub fn sample(&self, t: Real, dt: Real) -> (Vec3, Vec3) {
        let (a, b) = (self.at(t), self.at(t + dt));
        let v = if dt > 0.0 { (b - a) / dt } else { Vec3::ZERO };
        (a, v)
    }
}

/// Checks keyframes: finite, t strictly increasing.
pub(crate) fn check_path(keys: &[[Real; 4]], place: &str) -> Result<(), SceneError> {
    for (k, key) in keys.iter().enumerate() {
        if !key.iter().all(|x| x.is_finite()) {
            return Err(SceneError::at(
                format!("{place}.path[{k}]"),
                format!("must be finite, got {key:?}"),
            ));
        }
        if k > 0 && key[0] <= keys[k - 1][0] {
            return Err(SceneError::at(
                format!("{place}.path[{k}]"),
                format!(
                    "keyframe times must increase: t = {} after t = {}",
                    key[0],
                    keys[k - 1][0]
                ),
            ));
        }
    }
    Ok(())
}
