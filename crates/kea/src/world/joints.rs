//! The world's joint API: creating each joint of the guide from world-frame anchors and axes
//! (stored in each body's frame), and reaching their limits and motors.

use super::constraint_entry::ConstraintKind;
use super::World;
use crate::constraint::{
    CarWheel, FixedJoint, FixedPath, Hinge, Linear1, Linear2, Planar, Prismatic, RowBody,
    RowContext, UniversalJoint,
};
use crate::error::{KeaError, KeaResult};
use crate::handle::{BodyHandle, ConstraintHandle};
use crate::math::Vec3;

impl World {
    /// The row-writing view of two bodies at their current poses (for building joint frames).
    pub(super) fn pair_context(
        &self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
    ) -> KeaResult<RowContext> {
        let view = |h: BodyHandle| -> KeaResult<RowBody> {
            let b = self.bodies.get(h)?;
            Ok(RowBody::fixed(b.position(), b.orientation()))
        };
        Ok(RowContext {
            bodies: [view(body1)?, body2.map_or(Ok(RowBody::STATIC), view)?],
            dt: 1.0,
            epsilon: self.settings.epsilon,
            gamma: self.settings.gamma,
            contact_spring: self.settings.contact_spring,
        })
    }

    /// [`World::pair_context`] for a constraint's bodies.
    pub(super) fn constraint_context(&self, h: ConstraintHandle) -> KeaResult<RowContext> {
        let [b1, b2] = self.constraint_bodies(h)?;
        self.pair_context(b1.expect("constraints have a first body"), b2)
    }

    /// Resets a constraint to the guide's default table (`Mdt*Reset`), for its bodies' current
    /// poses: position at the world origin; hinge, prismatic and linear directions along +y;
    /// universal axes +x and +y; car wheel steering +y, axle +x; path at rest; relative
    /// orientations as they are now; limits and motors off; contacts to position 0, normal +y,
    /// no penetration, default parameters. Its γ override and breaking thresholds are cleared.
    /// Custom constraints have no table: an error, nothing changed.
    pub fn reset_constraint(&mut self, h: impl Into<ConstraintHandle>) -> KeaResult<()> {
        let h = h.into();
        let [b1, b2] = self.constraint_bodies(h)?;
        let b1 = b1.expect("constraints have a first body");
        let ctx = self.pair_context(b1, b2)?;
        let o = Vec3::ZERO;
        let entry = self.constraints.get_mut(h)?;
        let kind = match &entry.kind {
            ConstraintKind::Contact(_) => {
                ConstraintKind::Contact(crate::constraint::Contact::default())
            }
            ConstraintKind::Ball(_) => {
                ConstraintKind::Ball(Box::new(crate::constraint::BallJoint {
                    local_anchor1: ctx.bodies[0].orientation.inverse()
                        * (o - ctx.bodies[0].position),
                    local_anchor2: ctx.bodies[1].orientation.inverse()
                        * (o - ctx.bodies[1].position),
                    limits: None,
                }))
            }
            ConstraintKind::Hinge(_) => ConstraintKind::Hinge(Hinge::new(&ctx, o, Vec3::Y)),
            ConstraintKind::Prismatic(_) => {
                ConstraintKind::Prismatic(Prismatic::new(&ctx, o, Vec3::Y))
            }
            ConstraintKind::Fixed(_) => ConstraintKind::Fixed(FixedJoint::new(&ctx, o)),
            ConstraintKind::Universal(_) => {
                ConstraintKind::Universal(UniversalJoint::new(&ctx, o, Vec3::X, Vec3::Y))
            }
            ConstraintKind::Linear1(_) => ConstraintKind::Linear1(Linear1::new(&ctx, o, Vec3::Y)),
            ConstraintKind::Planar(j) => {
                ConstraintKind::Planar(Box::new(Planar::new(&ctx, o, Vec3::Y, Vec3::X, j.rotates)))
            }
            ConstraintKind::Linear2(_) => ConstraintKind::Linear2(Linear2::new(&ctx, o, Vec3::Y)),
            ConstraintKind::Path(j) => {
                ConstraintKind::Path(FixedPath::new(&ctx, o, j.orientation.is_some()))
            }
            ConstraintKind::Wheel(w) => ConstraintKind::Wheel(Box::new(CarWheel::new(
                &ctx,
                Vec3::Y,
                Vec3::X,
                w.suspension_stiffness,
                w.suspension_damping,
            ))),
            ConstraintKind::Custom(_) => {
                return Err(KeaError::InvalidState {
                    operation: "reset_constraint",
                    reason: "a custom constraint has no default table",
                })
            }
        };
        entry.kind = kind;
        entry.gamma = None;
        entry.break_force = None;
        entry.break_torque = None;
        Ok(())
    }
}
