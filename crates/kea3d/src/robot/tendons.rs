//! A robot's fixed tendons (`mjcf_tendon.rs` reads them) put into its world as
//! [`kea::FixedTendon`]s, and read back in the file's units.
//!
//! A file's length is `Σ c·q` in its own coordinates, where Kea's coordinate is
//! `sign·(q − ref)` (0 at the file's pose, `kea_sign` −1 where a planar joint's second travel
//! runs against the file's slide): the Kea tendon takes `c·sign` and its lengths (spring
//! lengths, range) less the offset `Σ c·ref`; MuJoCo's default spring length, the length at
//! the joints' `springref`, is `Σ c·(springref − ref)` in Kea's.

use super::model::{Robot, RobotJoint, RobotTendon};
use super::spec::{kea_sign, RobotSpec};
use super::ImportError;
use crate::PhysicsWorld;
use kea::{FixedTendon, Real, TendonTerm};
use std::path::Path;

/// Adds `spec`'s tendons to `world` over the robot's `joints`.
pub(super) fn insert_tendons(
    world: &mut PhysicsWorld,
    spec: &RobotSpec,
    joints: &[RobotJoint],
    file: &Path,
) -> Result<Vec<RobotTendon>, ImportError> {
    let mut out = Vec::with_capacity(spec.tendons.len());
    for t in &spec.tendons {
        let mut terms = Vec::with_capacity(t.terms.len());
        let (mut offset, mut rest) = (0.0, 0.0);
        for (name, c) in &t.terms {
            let (joint, k) = joints
                .iter()
                .find_map(|j| {
                    let k = j.parts.iter().position(|p| p == name)?;
                    Some((j, k))
                })
                .expect("the reader checked the tendon's joints");
            let coord = &joint.coords[k];
            let sign = kea_sign(joint.kind, &joint.coords, k);
            offset += c * coord.reference;
            rest += c * coord.dynamics.rest;
            terms.push(TendonTerm {
                joint: joint.raw.expect("a hinge or slide has a Kea joint"),
                coordinate: k,
                coefficient: c * sign,
            });
        }
        let kea = FixedTendon {
            terms,
            stiffness: t.stiffness,
            damping: t.damping,
            spring_length: t
                .spring_length
                .map_or([rest; 2], |[lo, hi]| [lo - offset, hi - offset]),
            range: t.range.map(|[lo, hi]| [lo - offset, hi - offset]),
            soft: t.soft,
        };
        let handle = world
            .dynamics_mut()
            .add_tendon(kea)
            .map_err(|e| ImportError::World {
                file: file.to_path_buf(),
                line: t.line,
                element: format!("tendon \"{}\"", t.name),
                source: e.into(),
            })?;
        out.push(RobotTendon {
            name: t.name.clone(),
            handle,
            offset,
        });
    }
    Ok(out)
}

impl Robot {
    /// The robot's fixed tendons that act.
    #[must_use]
    pub fn tendons(&self) -> &[RobotTendon] {
        &self.tendons
    }

    /// Each tendon's length in the file's units (MuJoCo's `ten_length`) and its rate, after
    /// the last step.
    pub fn tendon_lengths(&self, world: &PhysicsWorld) -> crate::Result<Vec<(Real, Real)>> {
        self.tendons
            .iter()
            .map(|t| {
                let (length, rate) = world.dynamics().tendon_length(t.handle)?;
                Ok((length + t.offset, rate))
            })
            .collect()
    }
}
