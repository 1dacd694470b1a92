//! Driving a loaded robot: the file's actuators fed one control each (MuJoCo's `ctrl`), or a
//! force per joint coordinate.

use super::build::coordinate_limit;
use super::mjcf_actuators::{ActuatorKind, ActuatorSpec};
use super::model::{check_vector, Robot};
use super::spec::{kea_sign, JointType};
use crate::{PhysicsWorld, Result};
use kea::{Actuator, KeaError, Real};

/// The force or torque a motor asked for "no cap" gets, N or N·m (motors need a finite one).
pub const UNCAPPED_MOTOR_FORCE: Real = 1.0e6;

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
    pub(super) fn actuated(&self, a: &ActuatorSpec) -> Option<(usize, usize)> {
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
        // Everything checked first, then applied: a refusal changes nothing, and nothing is
        // allocated (a learning loop calls this every step).
        self.check_controls(controls)?;
        for a in &self.actuators {
            let (j, _) = self.actuated(a).ok_or(KeaError::InvalidState {
                operation: "set_controls",
                reason: "an actuator's joint is not in the robot",
            })?;
            self.check_joint(world, j)?;
        }
        for (a, &u) in self.actuators.iter().zip(controls) {
            let (j, k, actuator) = self.actuator_for(a, u)?;
            self.drive(world, j, k, Some(actuator))?;
        }
        Ok(())
    }

    /// Checks a control vector as [`Robot::set_controls`] does, without a world: its
    /// length, and each actuator's force or servo it makes (finite, within range). A
    /// vector it accepts, `set_controls` applies to any world that holds the robot.
    pub fn check_controls(&self, controls: &[Real]) -> Result<()> {
        check_vector("controls", controls, self.actuators.len())?;
        for (a, &u) in self.actuators.iter().zip(controls) {
            self.actuator_for(a, u)?.2.validate()?;
        }
        Ok(())
    }

    /// The Kea actuator control `u` makes of the file's actuator `a`, on coordinate `k` of
    /// joint `j`.
    fn actuator_for(&self, a: &ActuatorSpec, u: Real) -> Result<(usize, usize, Actuator)> {
        let u = match a.ctrl_range {
            Some((lo, hi)) => u.clamp(lo, hi),
            None => u,
        };
        let (lo, hi) = a
            .force_range
            .unwrap_or((Real::NEG_INFINITY, Real::INFINITY));
        let g = a.gear;
        let (j, k) = self.actuated(a).ok_or(KeaError::InvalidState {
            operation: "set_controls",
            reason: "an actuator's joint is not in the robot",
        })?;
        // Kea's coordinate is 0 at the file's pose, where the file's reads `ref`.
        let reference = self.joints()[j].coords[k].reference;
        let cap = (lo.abs().max(hi.abs()) * g.abs()).max(Real::MIN_POSITIVE);
        // MuJoCo: the actuator's force is its gain times the control (clamped to the force
        // range), and the joint feels `gear` times it.
        let actuator = match a.kind {
            ActuatorKind::Motor => Actuator::Force(g * u.clamp(lo, hi)),
            ActuatorKind::Position { kp, kv } => Actuator::Servo {
                position: u / g - reference,
                velocity: 0.0,
                stiffness: kp * g * g,
                damping: kv * g * g,
                max_force: cap,
            },
            ActuatorKind::Velocity { kv } => Actuator::Servo {
                position: 0.0,
                velocity: u / g,
                stiffness: 0.0,
                damping: kv * g * g,
                max_force: cap,
            },
        };
        Ok((j, k, actuator))
    }

    /// Refuses a robot joint that `world` does not hold (the robot was loaded elsewhere).
    fn check_joint(&self, world: &PhysicsWorld, joint: usize) -> Result<()> {
        if let Some(raw) = self.joints()[joint].raw {
            world.dynamics().constraint_kind(raw)?;
        }
        Ok(())
    }

    /// Applies a force (N) or torque (N·m) along each joint coordinate, in the layout of
    /// [`Robot::joint_velocities`], until changed; entries of free and ball joints must be 0.
    /// Errors, changing nothing, on a bad length, a non-finite entry or a force on a free or
    /// ball joint.
    pub fn set_joint_forces(&self, world: &mut PhysicsWorld, forces: &[Real]) -> Result<()> {
        check_vector("forces", forces, self.velocity_count())?;
        self.check_free_and_ball("forces", forces)?;
        for j in 0..self.joints().len() {
            self.check_joint(world, j)?;
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

    /// Drives each joint coordinate at `velocities` (the layout of
    /// [`Robot::joint_velocities`]) with a motor of at most `max_forces` (one per coordinate;
    /// an infinite cap stands for [`UNCAPPED_MOTOR_FORCE`]), until changed; entries of free and
    /// ball joints must be 0. Errors, changing nothing, on bad lengths or values.
    pub fn set_joint_motors(
        &self,
        world: &mut PhysicsWorld,
        velocities: &[Real],
        max_forces: &[Real],
    ) -> Result<()> {
        check_vector("velocities", velocities, self.velocity_count())?;
        if max_forces.len() != self.velocity_count()
            || max_forces.iter().any(|f| f.is_nan() || *f < 0.0)
        {
            return Err(KeaError::OutOfRange {
                arg: "max_forces",
                value: format!("{} entries", max_forces.len()),
                expected: "one force >= 0 per joint velocity",
            }
            .into());
        }
        self.check_free_and_ball("velocities", velocities)?;
        for j in 0..self.joints().len() {
            self.check_joint(world, j)?;
        }
        // Checked: now applied in place, allocating nothing.
        for j in self.joints() {
            let Some(raw) = j.raw else { continue };
            for k in 0..j.kind.velocity_count() {
                let at = j.first_velocity + k;
                let sign = kea_sign(j.kind, &j.coords, k);
                if let Some(limit) = coordinate_limit(world, raw, j.kind, k)? {
                    let cap = max_forces[at].min(UNCAPPED_MOTOR_FORCE);
                    limit.set_motor(sign * velocities[at], cap)?;
                }
            }
        }
        Ok(())
    }

    /// Refuses a non-zero entry of a free or ball joint in a velocity-layout vector.
    fn check_free_and_ball(&self, arg: &'static str, x: &[Real]) -> Result<()> {
        for j in self.joints() {
            if matches!(j.kind, JointType::Free | JointType::Ball) {
                let part = &x[j.first_velocity..j.first_velocity + j.kind.velocity_count()];
                if let Some(v) = part.iter().find(|v| **v != 0.0) {
                    return Err(KeaError::OutOfRange {
                        arg,
                        value: format!("{v} on joint \"{}\"", j.name),
                        expected: "0: free and ball joints have no driven coordinate",
                    }
                    .into());
                }
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
        // In Kea's sense of the coordinate (see `kea_sign`).
        let sign = kea_sign(j.kind, &j.coords, k);
        let a = a.map(|a| match a {
            Actuator::Force(f) => Actuator::Force(sign * f),
            Actuator::Servo {
                position,
                velocity,
                stiffness,
                damping,
                max_force,
            } => Actuator::Servo {
                position: sign * position,
                velocity: sign * velocity,
                stiffness,
                damping,
                max_force,
            },
        });
        if let Some(limit) = coordinate_limit(world, raw, j.kind, k)? {
            limit.set_actuator(a)?;
        }
        Ok(())
    }
}
