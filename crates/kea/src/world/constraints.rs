//! The world's constraint API (the guide's `MdtConstraint*`, `MdtContact*`, `MdtBSJoint*`).

use super::constraint_entry::{ConstraintEntry, ConstraintKind};
use super::World;
use crate::constraint::{Contact, CustomConstraint};
use crate::error::{check_finite, check_non_negative, KeaError, KeaResult};
use crate::handle::{BodyHandle, ConstraintHandle};
use crate::math::{Real, Vec3};
use crate::solver::Reaction;

impl World {
    pub(super) fn check_pair(&self, b1: BodyHandle, b2: Option<BodyHandle>) -> KeaResult<()> {
        self.bodies.check(b1)?;
        if let Some(b2) = b2 {
            self.bodies.check(b2)?;
            if b2 == b1 {
                return Err(KeaError::InvalidState {
                    operation: "constraint creation",
                    reason: "body1 and body2 are the same body",
                });
            }
        }
        Ok(())
    }

    pub(super) fn insert_constraint(
        &mut self,
        kind: ConstraintKind,
        b1: BodyHandle,
        b2: Option<BodyHandle>,
    ) -> KeaResult<ConstraintHandle> {
        self.check_pair(b1, b2)?;
        let joint = !matches!(kind, ConstraintKind::Contact(_));
        let h = self
            .constraints
            .insert(ConstraintEntry::new(kind, [Some(b1), b2]))?;
        self.index_constraint(h.index() as usize, joint);
        Ok(h)
    }

    /// Creates an enabled contact between `body1` and `body2` (`None`: the static world), as
    /// bounce.c does with `MdtContactCreate` + setters + `MdtContactEnable`.
    pub fn create_contact(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        contact: Contact,
    ) -> KeaResult<ConstraintHandle> {
        contact.params().validate()?;
        self.insert_constraint(ConstraintKind::Contact(contact), body1, body2)
    }

    /// Overrides γ for this constraint's rows (those that do not set their own), or restores the
    /// world's with `None`.
    pub fn set_constraint_gamma(
        &mut self,
        h: impl Into<ConstraintHandle>,
        gamma: Option<Real>,
    ) -> KeaResult<()> {
        let h = h.into();
        if let Some(g) = gamma {
            check_finite("gamma", g)?;
            if !(0.0..=1.0).contains(&g) {
                return Err(KeaError::OutOfRange {
                    arg: "gamma",
                    value: format!("{g}"),
                    expected: "must be in [0, 1]",
                });
            }
        }
        self.constraints.get_mut(h)?.gamma = gamma;
        Ok(())
    }

    /// Makes a constraint breakable: when the force (N) or torque (N·m) it applies to body 1
    /// passes a threshold in a step, it disables itself and the step reports it
    /// ([`crate::StepStats::broken_joints`], [`World::broken_last_step`]). `None` removes a
    /// threshold.
    pub fn set_breakable(
        &mut self,
        h: impl Into<ConstraintHandle>,
        max_force: Option<Real>,
        max_torque: Option<Real>,
    ) -> KeaResult<()> {
        let h = h.into();
        if let Some(f) = max_force {
            check_non_negative("max_force", f)?;
        }
        if let Some(t) = max_torque {
            check_non_negative("max_torque", t)?;
        }
        let e = self.constraints.get_mut(h)?;
        e.break_force = max_force;
        e.break_torque = max_torque;
        Ok(())
    }

    /// A readable dump of a constraint: kind, bodies, state, parameters, last forces (the
    /// guide's `Mdt*Log`).
    pub fn constraint_log(&self, h: impl Into<ConstraintHandle>) -> KeaResult<String> {
        let h = h.into();
        let e = self.constraints.get(h)?;
        Ok(format!(
            "{} {:?}: bodies {:?}, {}, γ override {:?}, breaks at force {:?} / torque {:?}\n  λ last step {:?}\n  reaction on body 1 {:?}, on body 2 {:?}\n  {:#?}",
            e.kind.name(),
            h,
            e.bodies,
            if e.enabled { "enabled" } else { "disabled" },
            e.gamma,
            e.break_force,
            e.break_torque,
            self.constraint_lambdas(h)?,
            e.reaction[0],
            e.reaction[1],
            e.kind
        ))
    }

    /// Adds a user-written constraint (see [`CustomConstraint`]).
    pub fn add_custom_constraint(
        &mut self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
        constraint: impl CustomConstraint,
    ) -> KeaResult<ConstraintHandle> {
        self.check_pair(body1, body2)?;
        self.insert_constraint(ConstraintKind::Custom(Box::new(constraint)), body1, body2)
    }

    /// Destroys a constraint (the guide's `Mdt*Destroy`); its handle becomes stale.
    pub fn destroy_constraint(&mut self, h: impl Into<ConstraintHandle>) -> KeaResult<()> {
        let h = h.into();
        let entry = self.constraints.remove(h)?;
        let joint = !matches!(entry.kind, ConstraintKind::Contact(_));
        self.index_constraint(h.index() as usize, joint);
        if joint {
            self.wake_bodies(entry.bodies);
        }
        Ok(())
    }

    fn wake_bodies(&mut self, bodies: [Option<BodyHandle>; 2]) {
        for b in bodies.into_iter().flatten() {
            if let Ok(body) = self.bodies.get_mut(b) {
                body.wake();
                self.awake.touch_body(b);
            }
        }
    }

    /// Enables or disables a constraint; a disabled one is kept but ignored by the step.
    pub fn set_constraint_enabled(
        &mut self,
        h: impl Into<ConstraintHandle>,
        enabled: bool,
    ) -> KeaResult<()> {
        let h = h.into();
        let entry = self.constraints.get_mut(h)?;
        let changed = entry.enabled != enabled;
        entry.enabled = enabled;
        let (is_contact, bodies) = (
            matches!(entry.kind, ConstraintKind::Contact(_)),
            entry.bodies,
        );
        self.index_constraint(h.index() as usize, changed && !is_contact);
        if changed && !is_contact {
            self.wake_bodies(bodies);
        }
        Ok(())
    }

    /// Whether a constraint is enabled.
    pub fn is_constraint_enabled(&self, h: impl Into<ConstraintHandle>) -> KeaResult<bool> {
        let h = h.into();
        Ok(self.constraints.get(h)?.enabled)
    }

    /// Changes a constraint's bodies; allowed only while it is disabled, as the guide requires.
    pub fn set_constraint_bodies(
        &mut self,
        h: impl Into<ConstraintHandle>,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
    ) -> KeaResult<()> {
        let h = h.into();
        self.check_pair(body1, body2)?;
        let entry = self.constraints.get_mut(h)?;
        if entry.enabled {
            return Err(KeaError::InvalidState {
                operation: "set_constraint_bodies",
                reason: "the constraint is enabled; disable it first",
            });
        }
        entry.bodies = [Some(body1), body2];
        let joint = self.is_joint_slot(h.index() as usize);
        self.index_constraint(h.index() as usize, joint);
        Ok(())
    }

    /// The bodies of a constraint (`None` is the static world).
    pub fn constraint_bodies(
        &self,
        h: impl Into<ConstraintHandle>,
    ) -> KeaResult<[Option<BodyHandle>; 2]> {
        let h = h.into();
        Ok(self.constraints.get(h)?.bodies)
    }

    /// The kind of a constraint, as a name ("contact", "ball joint", or a custom name).
    pub fn constraint_kind(&self, h: impl Into<ConstraintHandle>) -> KeaResult<&'static str> {
        let h = h.into();
        Ok(self.constraints.get(h)?.kind.name())
    }

    /// Number of constraints.
    #[must_use]
    pub fn constraint_count(&self) -> usize {
        self.constraints.len()
    }

    /// Every enabled joint (any constraint that is not a contact) with its two bodies, in handle
    /// order. Collision layers use it to keep jointed bodies from colliding.
    pub fn enabled_joints(
        &self,
    ) -> impl Iterator<Item = (ConstraintHandle, [Option<BodyHandle>; 2])> + '_ {
        self.constraints
            .iter()
            .filter(|(_, e)| e.enabled && !matches!(e.kind, ConstraintKind::Contact(_)))
            .map(|(h, e)| (h, e.bodies))
    }

    /// The force and torque the constraint applied to body 1 and body 2 in the last step
    /// (zero before its first step or while disabled).
    pub fn constraint_reaction(&self, h: impl Into<ConstraintHandle>) -> KeaResult<[Reaction; 2]> {
        let h = h.into();
        Ok(self.constraints.get(h)?.reaction)
    }

    /// The total force and torque (about its centre of mass) that the constraints on a body —
    /// joints and contacts — applied to it in the last step (the guide's per-body constraint
    /// force): after a step, `m·a − (m·g + applied force)` for the force.
    pub fn body_constraint_force(&self, h: BodyHandle) -> KeaResult<Reaction> {
        self.bodies.get(h)?;
        let slot = h.index();
        let mut total = Reaction::default();
        for (i, pair) in self.constraint_bodies.iter().enumerate() {
            for side in (0..2).filter(|&side| pair[side] == slot) {
                if let Some(e) = self.constraints.at(i) {
                    total.force += e.reaction[side].force;
                    total.torque += e.reaction[side].torque;
                }
            }
        }
        Ok(total)
    }

    /// The λ (force) of each of the constraint's rows in the last step (empty before its first
    /// step or while disabled). For a contact, point by point: the normal force, then the
    /// friction force along each direction of [`Contact::tangent_basis`].
    pub fn constraint_lambdas(&self, h: impl Into<ConstraintHandle>) -> KeaResult<&[Real]> {
        let h = h.into();
        let entry = self.constraints.get(h)?;
        let all = match entry.kind {
            ConstraintKind::Contact(_) => &self.scratch.contact_lambda,
            _ => &self.scratch.lambda,
        };
        Ok(match entry.last_rows {
            Some((first, count)) => &all[first as usize..(first + count) as usize],
            None => &[],
        })
    }

    /// Every enabled contact with its two bodies, in handle order (viewers draw them).
    pub fn contacts(
        &self,
    ) -> impl Iterator<Item = (ConstraintHandle, &Contact, [Option<BodyHandle>; 2])> + '_ {
        self.constraints.iter().filter_map(|(h, e)| match &e.kind {
            ConstraintKind::Contact(c) if e.enabled => Some((h, c, e.bodies)),
            _ => None,
        })
    }

    /// A contact, read-only.
    pub fn contact(&self, h: ConstraintHandle) -> KeaResult<&Contact> {
        match &self.constraints.get(h)?.kind {
            ConstraintKind::Contact(c) => Ok(c),
            other => Err(wrong_kind(h, "contact", other.name())),
        }
    }

    /// A contact, to change through its validating setters.
    pub fn contact_mut(&mut self, h: ConstraintHandle) -> KeaResult<&mut Contact> {
        match &mut self.constraints.get_mut(h)?.kind {
            ConstraintKind::Contact(c) => Ok(c),
            other => Err(wrong_kind(h, "contact", other.name())),
        }
    }

    /// The total force a contact applied to its first body in the last step (normal plus
    /// friction, all its points), N.
    pub fn contact_force(&self, h: ConstraintHandle) -> KeaResult<Vec3> {
        let entry = self.constraints.get(h)?;
        match &entry.kind {
            ConstraintKind::Contact(_) => Ok(entry.reaction[0].force),
            other => Err(wrong_kind(h, "contact", other.name())),
        }
    }

    /// A custom constraint, to update its parameters between steps.
    pub fn custom_constraint_mut(
        &mut self,
        h: ConstraintHandle,
    ) -> KeaResult<&mut dyn CustomConstraint> {
        match &mut self.constraints.get_mut(h)?.kind {
            ConstraintKind::Custom(c) => Ok(c.as_mut()),
            other => Err(wrong_kind(h, "custom constraint", other.name())),
        }
    }

    /// The contacts between two bodies (either order; `None` is the world), in slot order: the
    /// guide's contact group walked with `MdtContactGetNext`.
    pub fn contacts_between(
        &self,
        body1: BodyHandle,
        body2: Option<BodyHandle>,
    ) -> impl Iterator<Item = ConstraintHandle> + '_ {
        self.constraints.iter().filter_map(move |(h, e)| {
            let is_contact = matches!(e.kind, ConstraintKind::Contact(_));
            let same = e.bodies == [Some(body1), body2]
                || (body2.is_some() && e.bodies == [body2, Some(body1)]);
            (is_contact && same).then_some(h)
        })
    }

    /// The next contact of the same body pair after `h` (the guide's `MdtContactGetNext`), or
    /// `None` at the end of the group.
    pub fn contact_next(&self, h: ConstraintHandle) -> KeaResult<Option<ConstraintHandle>> {
        self.contact(h)?;
        let [b1, b2] = self.constraints.get(h)?.bodies;
        let b1 = b1.expect("constraints always have a first body");
        Ok(self
            .contacts_between(b1, b2)
            .find(|c| c.index() > h.index()))
    }
}

pub(super) fn wrong_kind(
    h: ConstraintHandle,
    expected: &'static str,
    actual: &'static str,
) -> KeaError {
    KeaError::WrongConstraintKind {
        index: h.index(),
        generation: h.generation(),
        expected,
        actual,
    }
}
