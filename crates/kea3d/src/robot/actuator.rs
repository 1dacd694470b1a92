//! Driving a loaded robot: the file's actuators fed one control each (MuJoCo's `ctrl`), or a
//! force per joint coordinate.

use super::build::coordinate_limit;
use super::mjcf::{ActuatorKind, ActuatorSpec};
use super::model::Robot;
use super::spec::JointType;
use crate::{PhysicsWorld, Result};
use kea::{Actuator, KeaError, Real};

impl Robot {
    /// The file's actuators, in its order.
    #[must_use]
    pub fn actuators(&self) -> &[ActuatorSpec] {
        &self.actuators
    }

    pub(crate) fn set_actuators(&mut self, actuators: Vec<ActuatorSpec>) {
        self.actuators = actuators;
    }

    /// The joint and coordinate an actuator drives.
    fn actuated(&self, a: &ActuatorSpec) -> Option<(usize, usize)> {
        self.joints()
            .iter()
            .enumerate()
            .find_map(|(i, j)| j.parts.iter().position(|p| *p == a.joint).map(|k| (i, k)))
    }

    /// Feeds each actuator its control (clamped to its control range), as MuJoCo's `ctrl`:
    /// a motor applies `gear · u` (within its force range), a position servo drives its
    /// coordinate to `u / gear`, a velocity servo its rate to `u / gear`. Errors, changing
    /// nothing, on a vector whose length is not the actuator count or with a non-finite entry.
    pub fn set_controls(&self, world: &mut PhysicsWorld, controls: &[Real]) -> Result<()> {
        check_len("controls", controls, self.actuators.len())?;
        let mut staged = Vec::with_capacity(self.actuators.len());
        for (a, &u) in self.actuators.iter().zip(controls) {
            let u = match a.ctrl_range {
                Some((lo, hi)) => u.clamp(lo, hi),
                None => u,
            };
            let (lo, hi) = a
                .force_range
                .unwrap_or((Real::NEG_INFINITY, Real::INFINITY));
            let g = a.gear;
            let actuator = match a.kind {
                ActuatorKind::Motor => {
                    Actuator::Force((g * u).clamp(lo, hi) * g.signum() * g.signum())
                }
                ActuatorKind::Position { kp, kv } => Actuator::Servo {
                    position: u / g,
                    velocity: 0.0,
                    stiffness: kp * g * g,
                    damping: kv * g * g,
                    max_force: (lo.abs().max(hi.abs()) * g.abs()).max(Real::MIN_POSITIVE),
                },
                ActuatorKind::Velocity { kv } => Actuator::Servo {
                    position: 0.0,
                    velocity: u / g,
                    stiffness: 0.0,
                    damping: kv * g * g,
                    max_force: (lo.abs().max(hi.abs()) * g.abs()).max(Real::MIN_POSITIVE),
                },
            };
            let (j, k) = self.actuated(a).ok_or(KeaError::InvalidState {
                operation: "set_controls",
                reason: "an actuator's joint is not in the robot",
            })?;
            staged.push((j, k, actuator));
        }
        for (j, k, actuator) in staged {
            self.drive(world, j, k, Some(actuator))?;
        }
        Ok(())
    }

    /// Applies a force (N) or torque (N·m) along each joint coordinate, in the layout of
    /// [`Robot::joint_velocities`], until changed; entries of free and ball joints must be 0.
    /// Errors, changing nothing, on a bad length, a non-finite entry or a force on a free or
    /// ball joint.
    pub fn set_joint_forces(&self, world: &mut PhysicsWorld, forces: &[Real]) -> Result<()> {
        check_len("forces", forces, self.velocity_count())?;
        for j in self.joints() {
            if matches!(j.kind, JointType::Free | JointType::Ball) {
                let f = &forces[j.first_velocity..j.first_velocity + j.kind.velocity_count()];
                if let Some(x) = f.iter().find(|x| **x != 0.0) {
                    return Err(KeaError::OutOfRange {
                        arg: "forces",
                        value: format!(
                            "{x} on {} joint \"{}\"",
                            if j.kind == JointType::Free {
                                "free"
                            } else {
                                "ball"
                            },
                            j.name
                        ),
                        expected: "0: free and ball joints have no actuated coordinate",
                    }
                    .into());
                }
            }
        }
        for (i, j) in self.joints().iter().enumerate() {
            if matches!(j.kind, JointType::Free | JointType::Ball | JointType::Fixed) {
                continue;
            }
            for k in 0..j.kind.velocity_count() {
                let f = forces[j.first_velocity + k];
                self.drive(world, i, k, (f != 0.0).then_some(Actuator::Force(f)))?;
            }
        }
        Ok(())
    }

    fn drive(
        &self,
        world: &mut PhysicsWorld,
        joint: usize,
        k: usize,
        a: Option<Actuator>,
    ) -> Result<()> {
        let j = &self.joints()[joint];
        let Some(raw) = j.raw else {
            return Ok(());
        };
        if let Some(limit) = coordinate_limit(world, raw, j.kind, k)? {
            limit.set_actuator(a)?;
        }
        Ok(())
    }
}

fn check_len(arg: &'static str, x: &[Real], len: usize) -> Result<()> {
    if x.len() != len {
        return Err(KeaError::OutOfRange {
            arg,
            value: format!("{} entries", x.len()),
            expected: "one entry per actuator (controls) or per joint velocity (forces)",
        }
        .into());
    }
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(KeaError::OutOfRange {
            arg,
            value: format!("entry {i} = {}", x[i]),
            expected: "finite numbers",
        }
        .into());
    }
    Ok(())
}
