//! What a learning task reads of a robot besides its coordinates: each link's mass, inertia
//! and velocity about its centre of mass, the contacts' push on it, and the joint-space forces
//! of its actuators — enough to build MuJoCo's `cinert`, `cvel`, `cfrc_ext` and
//! `qfrc_actuator` (Gymnasium's Ant and Humanoid observe them).

use super::mjcf_actuators::ActuatorKind;
use super::model::{check_vector, Robot};
use crate::{PhysicsWorld, Result};
use kea::{Mat3, Real, Vec3};
use kea_collision::ColliderHandle;

/// One link's dynamic state, world frame: its own mass properties (a link welded to others
/// in one body reports its own share) posed where its body is, the velocity of its centre of
/// mass as its body moves, and the push of the contacts on its own geometry.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LinkState {
    /// Mass, kg (0 for the world).
    pub mass: Real,
    /// Centre of mass, m.
    pub center_of_mass: Vec3,
    /// Inertia about the centre of mass, world axes, kg·m².
    pub inertia: Mat3,
    /// Angular velocity, rad/s.
    pub angular_velocity: Vec3,
    /// Velocity of the centre of mass, m/s.
    pub linear_velocity: Vec3,
    /// The contacts' total force on the link's geometry over the last step (their mean), N.
    pub contact_force: Vec3,
    /// Their torque about the link's centre of mass, N·m.
    pub contact_torque: Vec3,
}

impl Robot {
    /// Each link's [`LinkState`] in [`Robot::links`] order, into `out` (resized to the link
    /// count). An MJCF file's world link has no mass and does not move; the contacts on its
    /// geometry (a floor) are reported on it like any link's.
    pub fn link_states(&self, world: &PhysicsWorld, out: &mut Vec<LinkState>) -> Result<()> {
        out.clear();
        out.resize(self.links().len(), LinkState::default());
        let dynamics = world.dynamics();
        for (i, link) in self.links().iter().enumerate() {
            let b = dynamics.body(link.body)?;
            let frame = self.link_pose(world, i)?;
            let turn = Mat3::from_quat(frame.rotation);
            let com = frame.point(link.center_of_mass);
            let w = b.angular_velocity();
            out[i] = LinkState {
                mass: link.mass,
                center_of_mass: com,
                inertia: turn * link.inertia * turn.transpose(),
                angular_velocity: w,
                linear_velocity: b.linear_velocity() + w.cross(com - b.position()),
                ..LinkState::default()
            };
        }
        let link_of =
            |c: ColliderHandle| self.links().iter().position(|l| l.colliders.contains(&c));
        for (first, second, handle) in world.collision().contact_colliders() {
            let Ok(contact) = dynamics.contact(handle) else {
                continue;
            };
            let (on_first, on_second) = (link_of(first), link_of(second));
            if on_first.is_none() && on_second.is_none() {
                continue;
            }
            let n = contact.normal();
            for (p, f) in contact.points().iter().zip(contact.forces()) {
                // A point's force acts on the contact's first body at its point there; the
                // second feels the opposite at its own point.
                let force = n * f.normal + f.friction;
                let sides = [
                    (on_first, p.position, force),
                    (on_second, p.position + p.to_second, -force),
                ];
                for (link, at, force) in sides {
                    if let Some(s) = link.and_then(|i| out.get_mut(i)) {
                        s.contact_force += force;
                        s.contact_torque += (at - s.center_of_mass).cross(force);
                    }
                }
            }
        }
        Ok(())
    }

    /// The joint-space forces the file's actuators apply for `controls` at the world's
    /// present state, in the layout of [`Robot::joint_velocities`] (MuJoCo's
    /// `qfrc_actuator`): a motor `gear · u`, a position servo `gear · (kp (u − gear q) −
    /// kv gear q̇)`, a velocity servo `gear · kv (u − gear q̇)`, each control clamped to its
    /// range and each actuator's force to its force range. Errors on a vector whose length
    /// is not the actuator count or with a non-finite entry.
    pub fn actuator_forces(&self, world: &PhysicsWorld, controls: &[Real]) -> Result<Vec<Real>> {
        check_vector("controls", controls, self.actuators().len())?;
        let q = self.joint_positions(world)?;
        let v = self.joint_velocities(world)?;
        let mut out = vec![0.0; self.velocity_count()];
        for (a, &u) in self.actuators().iter().zip(controls) {
            let Some((j, k)) = self.actuated(a) else {
                continue;
            };
            let j = &self.joints()[j];
            let (pos, vel) = (j.first_position + k, j.first_velocity + k);
            let u = a.ctrl_range.map_or(u, |(lo, hi)| u.clamp(lo, hi));
            let g = a.gear;
            let force = match a.kind {
                ActuatorKind::Motor => u,
                ActuatorKind::Position { kp, kv } => kp * (u - g * q[pos]) - kv * g * v[vel],
                ActuatorKind::Velocity { kv } => kv * (u - g * v[vel]),
            };
            let force = a.force_range.map_or(force, |(lo, hi)| force.clamp(lo, hi));
            out[vel] += g * force;
        }
        Ok(out)
    }
}
