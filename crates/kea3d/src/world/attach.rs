//! Colliders and joints: attaching them to bodies, and removing them.

use super::{Attached, PhysicsWorld};
use crate::body::BodyType;
use crate::collider::Collider;
use crate::Result;
use crate::{Joint, JointHandle, JointKind};
use kea::BodyHandle;
use kea_collision::{ColliderDef, ColliderHandle, MaterialId};

impl PhysicsWorld {
    /// Attaches a collider to `parent` (`None`: static world geometry, placed in the world
    /// frame), placed in the parent's frame about its origin. A dynamic parent's mass,
    /// inertia and centre of mass are brought up to date. On error nothing changes.
    pub fn insert_collider(
        &mut self,
        collider: Collider,
        parent: Option<BodyHandle>,
    ) -> Result<ColliderHandle> {
        let shape = collider.shape.clone()?;
        let material = self.material_for(&collider)?;
        let plane = shape.kind_name() == "plane";
        let (place, turn) = collider.placement();
        let (body, offset, rotation, attached) = match parent {
            None => (None, place, turn, false),
            Some(h) => {
                let meta = self.meta(h)?;
                let b = self.dynamics.body(h)?;
                if meta.kind == BodyType::Static && plane {
                    // A plane is unbounded: static geometry placed where the body is.
                    let q = b.orientation();
                    (
                        None,
                        b.position() + q * collider.offset,
                        q * collider.rotation,
                        false,
                    )
                } else {
                    (
                        Some(h),
                        collider.offset - meta.local_com,
                        collider.rotation,
                        true,
                    )
                }
            }
        };
        let def = ColliderDef {
            body,
            shape,
            offset,
            rotation,
            material,
            groups: collider.groups,
            mask: collider.mask,
        };
        let handle = self.collision.add_collider(&self.dynamics, def)?;
        if let (true, Some(h)) = (attached, parent) {
            self.meta_mut(h)?.colliders.push(Attached {
                handle,
                offset: place,
                rotation: turn,
                mass: collider.mass,
            });
            if let Err(e) = self.refresh_mass(h) {
                self.meta_mut(h)?.colliders.pop();
                self.collision.remove_collider(&mut self.dynamics, handle)?;
                return Err(e);
            }
        }
        Ok(handle)
    }

    /// Removes a collider; its body's mass is brought up to date.
    pub fn remove_collider(&mut self, h: ColliderHandle) -> Result<()> {
        let owner = self.collision.collider(h)?.body;
        self.collision.remove_collider(&mut self.dynamics, h)?;
        if let Some(b) = owner {
            if let Ok(meta) = self.meta_mut(b) {
                meta.colliders.retain(|c| c.handle != h);
                self.refresh_mass(b)?;
            }
        }
        Ok(())
    }

    /// The material a collider asks for: its id, or one made for its surface (shared by
    /// colliders with the same surface), or the table's default.
    fn material_for(&mut self, collider: &Collider) -> Result<MaterialId> {
        if let Some(id) = collider.material {
            self.collision.materials.check(id)?;
            return Ok(id);
        }
        let Some(surface) = collider.surface else {
            return Ok(0);
        };
        surface.validate()?;
        if let Some(&(_, id)) = self.surfaces.iter().find(|(s, _)| *s == surface) {
            return Ok(id);
        }
        let id = self.collision.materials.add(surface)?;
        self.surfaces.push((surface, id));
        Ok(id)
    }

    /// Joins `body1` to `body2` (`None`: the world) with a joint made by a [`Joint`] builder,
    /// at its world-frame anchor and axes. On error nothing changes.
    pub fn insert_joint<J: JointKind>(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        joint: Joint<J>,
    ) -> Result<JointHandle<J>> {
        let h = self.dynamics.create_joint(body1, body2, joint)?;
        if joint.collides_connected() {
            if let Err(e) = self
                .collision
                .set_joint_collisions(&self.dynamics, h.raw(), true)
            {
                self.dynamics.destroy_constraint(h)?;
                return Err(e);
            }
        }
        Ok(h)
    }

    /// Stops two bodies colliding with each other, as bodies joined by a joint do not (a
    /// robot's link and its parent, joined through light links between the link's joints).
    /// Refused, changing nothing, for a body not in the world or a body paired with itself.
    pub fn exclude_collisions(&mut self, a: BodyHandle, b: BodyHandle) -> Result<()> {
        self.collision.exclude_pair(&self.dynamics, a, b)
    }

    /// Removes a joint.
    pub fn remove_joint<J: JointKind>(&mut self, h: JointHandle<J>) -> Result<()> {
        self.collision
            .set_joint_collisions(&self.dynamics, h.raw(), false)?;
        Ok(self.dynamics.destroy_constraint(h.raw())?)
    }

    /// The joint of a typed handle, read-only.
    pub fn joint<J: JointKind>(&self, h: JointHandle<J>) -> Result<&J> {
        Ok(h.get(&self.dynamics)?)
    }
}
