//! A joint's anchor and axis changed after it was made (the guide's `Mdt*SetPosition` and
//! `Mdt*SetAxis`). The joint is set again for the bodies where they are now, so nothing jumps:
//! a new anchor keeps the joint's axes, coordinate and limits; a new axis makes the joint
//! again about it (its angle or travel starts at 0 there) and keeps its limits and motor.

use super::constraint_entry::ConstraintKind;
use super::World;
use crate::constraint::{Hinge, Linear2, Prismatic, RowContext, UniversalJoint};
use crate::error::{check_coordinate, check_unit, KeaError, KeaResult};
use crate::handle::ConstraintHandle;
use crate::math::Vec3;

impl World {
    /// Moves a joint's anchor to world point `anchor` with the bodies where they are (the
    /// guide's `Mdt*SetPosition`): its axes, its coordinate and its limits stay as they were.
    /// Refused, changing nothing, for a contact (`Contact::set_position`), a car wheel (whose
    /// anchor is its wheel's centre), a custom constraint, or a bad point.
    pub(super) fn set_joint_position(
        &mut self,
        h: ConstraintHandle,
        anchor: Vec3,
    ) -> KeaResult<()> {
        let anchor = check_coordinate("anchor", anchor)?;
        let [b1, b2] = self.constraint_bodies(h)?;
        let ctx = self.pair_context(b1.expect("constraints have a first body"), b2)?;
        let [r1, r2] = &ctx.bodies;
        let local =
            |i: usize| ctx.bodies[i].orientation.inverse() * (anchor - ctx.bodies[i].position);
        let (a1, a2) = (local(0), local(1));
        let entry = self.constraints.get_mut(h)?;
        match &mut entry.kind {
            ConstraintKind::Ball(j) => (j.local_anchor1, j.local_anchor2) = (a1, a2),
            ConstraintKind::Hinge(j) => (j.local_anchor1, j.local_anchor2) = (a1, a2),
            ConstraintKind::Fixed(j) => (j.local_anchor1, j.local_anchor2) = (a1, a2),
            ConstraintKind::Universal(j) => (j.local_anchor1, j.local_anchor2) = (a1, a2),
            ConstraintKind::Linear1(j) => (j.local_anchor1, j.local_anchor2) = (a1, a2),
            ConstraintKind::Linear2(j) => (j.local_anchor1, j.local_anchor2) = (a1, a2),
            ConstraintKind::Planar(j) => (j.local_anchor1, j.local_anchor2) = (a1, a2),
            ConstraintKind::Prismatic(j) => {
                // Body 2's anchor set back along the axis by the travel, which stays.
                let u = r2.orientation * j.local_axis2;
                let travel = j.limit.position();
                j.local_anchor1 = a1;
                j.local_anchor2 = r2.orientation.inverse() * (anchor - u * travel - r2.position);
            }
            ConstraintKind::Path(j) => {
                j.local_anchor1 = a1;
                j.path_position = r1.position + r1.orientation * a1;
            }
            other => {
                return Err(KeaError::InvalidState {
                    operation: "set_position",
                    reason: match other {
                        ConstraintKind::Contact(_) => "a contact's points are set on the contact",
                        ConstraintKind::Wheel(_) => "a car wheel is anchored at its wheel's centre",
                        _ => "a custom constraint keeps its own anchors",
                    },
                })
            }
        }
        Ok(())
    }

    /// Turns a hinge's, prismatic joint's or linear-2 joint's axis, or a universal joint's first
    /// axis (its second kept perpendicular), to world unit `axis` with the bodies where they
    /// are (the guide's `Mdt*SetAxis`): the joint is made again about it at its anchor, its
    /// coordinate starting at 0 there, its limits and motor kept. Refused, changing nothing,
    /// for other kinds, a bad axis, or a universal axis along its second axis.
    pub(super) fn set_joint_axis(&mut self, h: ConstraintHandle, axis: Vec3) -> KeaResult<()> {
        let axis = check_unit("axis", axis)?;
        let [b1, b2] = self.constraint_bodies(h)?;
        let ctx = self.pair_context(b1.expect("constraints have a first body"), b2)?;
        let entry = self.constraints.get_mut(h)?;
        let kind = remade_about(&entry.kind, &ctx, axis)?;
        entry.kind = kind;
        Ok(())
    }
}

/// The joint made again about `axis` at its present anchor (body 1's), limits kept.
fn remade_about(kind: &ConstraintKind, ctx: &RowContext, axis: Vec3) -> KeaResult<ConstraintKind> {
    let r1 = &ctx.bodies[0];
    let anchor_of = |local: Vec3| r1.position + r1.orientation * local;
    Ok(match kind {
        ConstraintKind::Hinge(j) => {
            let mut new = Hinge::new(ctx, anchor_of(j.local_anchor1), axis);
            new.limit = j.limit;
            new.limit.record(0.0, 0.0);
            ConstraintKind::Hinge(new)
        }
        ConstraintKind::Prismatic(j) => {
            let mut new = Prismatic::new(ctx, anchor_of(j.local_anchor1), axis);
            new.limit = j.limit;
            new.limit.record(0.0, 0.0);
            ConstraintKind::Prismatic(new)
        }
        ConstraintKind::Linear2(j) => {
            ConstraintKind::Linear2(Linear2::new(ctx, anchor_of(j.local_anchor1), axis))
        }
        ConstraintKind::Universal(j) => {
            let second = ctx.bodies[1].orientation * j.local_axis2;
            let second = second - axis * second.dot(axis);
            if second.length() < 1e-3 {
                return Err(KeaError::OutOfRange {
                    arg: "axis",
                    value: format!("{axis}"),
                    expected: "not along the universal joint's second axis",
                });
            }
            ConstraintKind::Universal(UniversalJoint::new(
                ctx,
                anchor_of(j.local_anchor1),
                axis,
                second.normalize(),
            ))
        }
        _ => {
            return Err(KeaError::InvalidState {
                operation: "set_axis",
                reason:
                    "only a hinge, a prismatic, a linear-2 or a universal joint has an axis to set",
            })
        }
    })
}
