//! Bodies: inserting and removing them, their pose about their own origin, kinematic driving,
//! and mass properties kept in step with their colliders.

use super::{BodyMeta, PhysicsWorld};
use crate::body::{Body, BodyType};
use crate::mass::{combine, Part};
use crate::Result;
use kea::{BodyDef, BodyHandle, KeaError, Mat3, Quat, Real, Vec3};

/// Inertia of a body with a mass but no collider to shape it: a solid ball 1 m across.
const PLAIN_INERTIA_PER_KG: Real = 0.1;

impl PhysicsWorld {
    /// Inserts a body. Its mass comes from the colliders you attach to it unless the builder
    /// sets one. Returns a clear error, naming the field, for bad values.
    pub fn insert_body(&mut self, body: impl Into<Body>) -> Result<BodyHandle> {
        let b: Body = body.into();
        let fixed = b.kind == BodyType::Static;
        if fixed && (b.linear_velocity != Vec3::ZERO || b.angular_velocity != Vec3::ZERO) {
            return Err(KeaError::InvalidState {
                operation: "insert_body",
                reason: "a static body cannot have a velocity: make it kinematic",
            }
            .into());
        }
        let mass = b.mass.unwrap_or(1.0);
        let com = match b.center_of_mass {
            Some(c) => kea::error::check_coordinate("center_of_mass", c)?,
            None => Vec3::ZERO,
        };
        let def = BodyDef {
            mass,
            inertia: b
                .inertia
                .unwrap_or(Mat3::IDENTITY * (PLAIN_INERTIA_PER_KG * mass)),
            position: b.position + b.rotation * com,
            orientation: b.rotation,
            linear_velocity: b.linear_velocity,
            angular_velocity: b.angular_velocity,
            linear_damping: b.linear_damping,
            angular_damping: b.angular_damping,
            fast_spin_axis: b.fast_spin_axis,
            enabled: !fixed,
            user_data: b.user_data,
            prefer_exact: b.prefer_exact,
            kinematic: matches!(
                b.kind,
                BodyType::KinematicVelocity | BodyType::KinematicPosition
            ),
        };
        let h = self.dynamics.create_body(&def)?;
        self.set_meta(
            h,
            BodyMeta {
                handle: h,
                kind: b.kind,
                explicit_mass: b.mass,
                explicit_inertia: b.inertia,
                explicit_com: b.center_of_mass,
                local_com: com,
                colliders: Vec::new(),
                target: None,
            },
        );
        if b.kind == BodyType::KinematicPosition {
            self.driven.push(h);
        }
        Ok(h)
    }

    /// Removes a body with its colliders and joints.
    pub fn remove_body(&mut self, h: BodyHandle) -> Result<()> {
        self.meta(h)?;
        // Every collider on it, those its records list and any a scene attached.
        self.collision.remove_colliders_of(&mut self.dynamics, h);
        self.dynamics.destroy_body(h)?;
        self.meta[h.index() as usize] = None;
        self.driven.retain(|&d| d != h);
        Ok(())
    }

    /// The body as the dynamics layer holds it (mass, velocities, forces; its position there
    /// is the centre of mass).
    pub fn body(&self, h: BodyHandle) -> Result<&kea::Body> {
        Ok(self.dynamics.body(h)?)
    }

    /// The body to change through the dynamics layer's setters (velocities, forces, damping).
    pub fn body_mut(&mut self, h: BodyHandle) -> Result<&mut kea::Body> {
        Ok(self.dynamics.body_mut(h)?)
    }

    /// The body's type.
    pub fn body_type(&self, h: BodyHandle) -> Result<BodyType> {
        Ok(self.meta(h)?.kind)
    }

    /// Number of bodies.
    #[must_use]
    pub fn body_count(&self) -> usize {
        self.dynamics.body_count()
    }

    /// Every body's handle, in slot order.
    pub fn body_handles(&self) -> impl Iterator<Item = BodyHandle> + '_ {
        self.dynamics.bodies().map(|(h, _)| h)
    }

    /// The centre of mass in the body's frame.
    pub fn local_center_of_mass(&self, h: BodyHandle) -> Result<Vec3> {
        Ok(self.meta(h)?.local_com)
    }

    /// Where the body's frame origin is, m (what [`Body::position`] set).
    pub fn position(&self, h: BodyHandle) -> Result<Vec3> {
        let com = self.meta(h)?.local_com;
        let b = self.dynamics.body(h)?;
        Ok(b.position() - b.orientation() * com)
    }

    /// The body's orientation.
    pub fn rotation(&self, h: BodyHandle) -> Result<Quat> {
        Ok(self.dynamics.body(h)?.orientation())
    }

    /// Velocity of the centre of mass, m/s.
    pub fn linear_velocity(&self, h: BodyHandle) -> Result<Vec3> {
        Ok(self.dynamics.body(h)?.linear_velocity())
    }

    /// Angular velocity, rad/s, world frame.
    pub fn angular_velocity(&self, h: BodyHandle) -> Result<Vec3> {
        Ok(self.dynamics.body(h)?.angular_velocity())
    }

    /// Moves the body's frame origin to `position` (a teleport: velocities are kept).
    pub fn set_position(&mut self, h: BodyHandle, position: impl Into<Vec3>) -> Result<()> {
        let com = self.meta(h)?.local_com;
        let b = self.dynamics.body_mut(h)?;
        let target = position.into() + b.orientation() * com;
        Ok(b.set_position(target)?)
    }

    /// Turns the body to `rotation` about its frame origin.
    pub fn set_rotation(&mut self, h: BodyHandle, rotation: Quat) -> Result<()> {
        let origin = self.position(h)?;
        let com = self.meta(h)?.local_com;
        let mut b = self.dynamics.body(h)?.clone();
        b.set_orientation(rotation)?;
        b.set_position(origin + b.orientation() * com)?;
        *self.dynamics.body_mut(h)? = b;
        Ok(())
    }

    /// Sets the velocity of the centre of mass, m/s (a kinematic body's drive).
    pub fn set_linear_velocity(&mut self, h: BodyHandle, v: impl Into<Vec3>) -> Result<()> {
        let b = self.dynamics.body_mut(h)?;
        b.set_linear_velocity(v.into())?;
        self.dynamics.wake_body(h)?;
        Ok(())
    }

    /// Sets the angular velocity, rad/s, world frame.
    pub fn set_angular_velocity(&mut self, h: BodyHandle, w: impl Into<Vec3>) -> Result<()> {
        let b = self.dynamics.body_mut(h)?;
        b.set_angular_velocity(w.into())?;
        self.dynamics.wake_body(h)?;
        Ok(())
    }

    /// Adds a force at the centre of mass for the next step, N.
    pub fn add_force(&mut self, h: BodyHandle, f: impl Into<Vec3>) -> Result<()> {
        self.dynamics.body_mut(h)?.add_force(f.into())?;
        Ok(())
    }

    /// Adds a torque for the next step, N·m.
    pub fn add_torque(&mut self, h: BodyHandle, t: impl Into<Vec3>) -> Result<()> {
        self.dynamics.body_mut(h)?.add_torque(t.into())?;
        Ok(())
    }

    /// Sets the pose a position-driven kinematic body reaches at the end of the next step
    /// (its frame origin and orientation). Without a new target it stands still.
    pub fn set_kinematic_target(
        &mut self,
        h: BodyHandle,
        position: impl Into<Vec3>,
        rotation: Quat,
    ) -> Result<()> {
        let position = kea::error::check_coordinate("position", position.into())?;
        let len = rotation.length();
        if !rotation.is_finite() || (len - 1.0).abs() > 1e-3 {
            return Err(KeaError::NotUnit {
                arg: "rotation",
                value: format!("{rotation}"),
                length: kea::math::wide(len),
            }
            .into());
        }
        let meta = self.meta_mut(h)?;
        if meta.kind != BodyType::KinematicPosition {
            return Err(KeaError::InvalidState {
                operation: "set_kinematic_target",
                reason: "the body is not a position-driven kinematic body",
            }
            .into());
        }
        meta.target = Some((position, rotation.normalize()));
        Ok(())
    }

    /// Brings a body's mass, inertia and centre of mass in step with its colliders (the
    /// builder's mass and inertia win). Moving the centre of mass keeps the frame origin and
    /// moves the colliders to match; a body that already has joints refuses that, because
    /// the joints' anchors are held about the centre of mass.
    pub(super) fn refresh_mass(&mut self, h: BodyHandle) -> Result<()> {
        let meta = self.meta(h)?.clone();
        if meta.kind == BodyType::Static {
            return Ok(());
        }
        let mut shapes = Vec::with_capacity(meta.colliders.len());
        for c in &meta.colliders {
            shapes.push(self.collision.collider(c.handle)?.shape.clone());
        }
        let parts: Vec<Part<'_>> = meta
            .colliders
            .iter()
            .zip(&shapes)
            .map(|(c, shape)| Part {
                offset: c.offset,
                rotation: c.rotation,
                shape,
                mass: c.mass,
            })
            .collect();
        let derived = combine(&parts)?;
        let mut body = self.dynamics.body(h)?.clone();
        let (mass, inertia, com) = match (derived, meta.explicit_mass) {
            (Some(d), Some(m)) => (m, d.inertia * (m / d.mass), d.center_of_mass),
            (Some(d), None) => (d.mass, d.inertia, d.center_of_mass),
            (None, Some(m)) => (m, Mat3::IDENTITY * (PLAIN_INERTIA_PER_KG * m), Vec3::ZERO),
            (None, None) => (body.mass(), body.inertia(), Vec3::ZERO),
        };
        let inertia = meta.explicit_inertia.unwrap_or(inertia);
        let com = meta.explicit_com.unwrap_or(com);
        body.set_mass(mass)?;
        body.set_inertia(inertia)?;
        if com != meta.local_com {
            if self
                .dynamics
                .enabled_joints()
                .any(|(_, b)| b.contains(&Some(h)))
            {
                return Err(KeaError::InvalidState {
                    operation: "insert_collider",
                    reason: "it would move the centre of mass of a body that has joints: \
                             attach colliders before joints",
                }
                .into());
            }
            let q = body.orientation();
            let shift = q * (com - meta.local_com);
            body.set_position(body.position() + shift)?;
            body.set_linear_velocity(
                body.linear_velocity() + body.angular_velocity().cross(shift),
            )?;
        }
        *self.dynamics.body_mut(h)? = body;
        if com != meta.local_com {
            for c in &meta.colliders {
                self.collision.set_collider_placement(
                    &self.dynamics,
                    c.handle,
                    c.offset - com,
                    c.rotation,
                )?;
            }
        }
        self.meta_mut(h)?.local_com = com;
        Ok(())
    }
}
