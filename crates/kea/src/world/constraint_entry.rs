//! How the world stores a constraint: its kind, bodies, enabled flag and last results.

use crate::constraint::{
    BallJoint, CarWheel, Contact, CustomConstraint, FixedJoint, FixedPath, Hinge, Linear1, Linear2,
    Planar, Prismatic, RowContext, RowWriter, UniversalJoint,
};
use crate::handle::BodyHandle;
use crate::math::Real;
use crate::solver::Reaction;

/// The kinds of constraint a world holds.
#[derive(Debug)]
// Contacts stay inline: they are the most numerous entries and come and go every step, so
// boxing them would allocate in warm steps.
#[allow(clippy::large_enum_variant)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) enum ConstraintKind {
    Contact(Contact),
    // Boxed: with limits a ball joint is several times larger than a contact,
    // and contacts are by far the most numerous entries.
    Ball(Box<BallJoint>),
    Hinge(Hinge),
    Prismatic(Prismatic),
    Fixed(FixedJoint),
    Universal(UniversalJoint),
    Linear1(Linear1),
    Linear2(Linear2),
    // Boxed: a planar joint (three coordinates, each with its limit) is half again as large
    // as a contact, and would set the size of every slot.
    Planar(Box<Planar>),
    Path(FixedPath),
    Wheel(Box<CarWheel>),
    /// (A snapshot refuses a world holding one: user code cannot be saved.)
    #[cfg_attr(feature = "serde", serde(skip))]
    Custom(Box<dyn CustomConstraint>),
}

impl Clone for ConstraintKind {
    fn clone(&self) -> Self {
        match self {
            ConstraintKind::Contact(c) => ConstraintKind::Contact(*c),
            ConstraintKind::Ball(j) => ConstraintKind::Ball(j.clone()),
            ConstraintKind::Hinge(j) => ConstraintKind::Hinge(*j),
            ConstraintKind::Prismatic(j) => ConstraintKind::Prismatic(*j),
            ConstraintKind::Fixed(j) => ConstraintKind::Fixed(*j),
            ConstraintKind::Universal(j) => ConstraintKind::Universal(*j),
            ConstraintKind::Linear1(j) => ConstraintKind::Linear1(*j),
            ConstraintKind::Linear2(j) => ConstraintKind::Linear2(*j),
            ConstraintKind::Planar(j) => ConstraintKind::Planar(j.clone()),
            ConstraintKind::Path(j) => ConstraintKind::Path(*j),
            ConstraintKind::Wheel(j) => ConstraintKind::Wheel(j.clone()),
            ConstraintKind::Custom(c) => ConstraintKind::Custom(c.clone()),
        }
    }

    /// A boxed joint copied onto one of its kind reuses its box: copying a warm world's
    /// state into another (a batch's worker) allocates nothing.
    fn clone_from(&mut self, source: &Self) {
        match (self, source) {
            (ConstraintKind::Ball(a), ConstraintKind::Ball(b)) => a.clone_from(b),
            (ConstraintKind::Planar(a), ConstraintKind::Planar(b)) => a.clone_from(b),
            (ConstraintKind::Wheel(a), ConstraintKind::Wheel(b)) => a.clone_from(b),
            (this, source) => *this = source.clone(),
        }
    }
}

impl ConstraintKind {
    pub(crate) fn name(&self) -> &'static str {
        match self {
            ConstraintKind::Contact(_) => "contact",
            ConstraintKind::Ball(_) => "ball joint",
            ConstraintKind::Hinge(_) => "hinge",
            ConstraintKind::Prismatic(_) => "prismatic joint",
            ConstraintKind::Fixed(_) => "fixed joint",
            ConstraintKind::Universal(_) => "universal joint",
            ConstraintKind::Linear1(_) => "linear1 joint",
            ConstraintKind::Linear2(_) => "linear2 joint",
            ConstraintKind::Planar(_) => "planar joint",
            ConstraintKind::Path(j) if j.orientation.is_some() => {
                "fixed-path-fixed-orientation joint"
            }
            ConstraintKind::Path(_) => "fixed-path joint",
            ConstraintKind::Wheel(_) => "car wheel joint",
            ConstraintKind::Custom(c) => c.name(),
        }
    }

    pub(crate) fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        match self {
            ConstraintKind::Contact(c) => c.write_rows(ctx, out),
            ConstraintKind::Ball(j) => j.write_rows(ctx, out),
            ConstraintKind::Hinge(j) => j.write_rows(ctx, out),
            ConstraintKind::Prismatic(j) => j.write_rows(ctx, out),
            ConstraintKind::Fixed(j) => j.write_rows(ctx, out),
            ConstraintKind::Universal(j) => j.write_rows(ctx, out),
            ConstraintKind::Linear1(j) => j.write_rows(ctx, out),
            ConstraintKind::Linear2(j) => j.write_rows(ctx, out),
            ConstraintKind::Planar(j) => j.write_rows(ctx, out),
            ConstraintKind::Path(j) => j.write_rows(ctx, out),
            ConstraintKind::Wheel(j) => j.write_rows(ctx, out),
            ConstraintKind::Custom(c) => c.write_rows(ctx, out),
        }
    }

    /// Whether the constraint keeps state that a step must update (a tracked coordinate).
    pub(crate) fn tracks_state(&self) -> bool {
        matches!(
            self,
            ConstraintKind::Hinge(_)
                | ConstraintKind::Prismatic(_)
                | ConstraintKind::Planar(_)
                | ConstraintKind::Wheel(_)
        ) || matches!(self, ConstraintKind::Ball(j) if j.limits.is_some())
    }

    /// Records what a successful step did, at the state after it.
    pub(crate) fn commit(&mut self, ctx: &RowContext) {
        match self {
            ConstraintKind::Hinge(j) => j.commit(ctx),
            ConstraintKind::Prismatic(j) => j.commit(ctx),
            ConstraintKind::Ball(j) => j.commit(ctx),
            ConstraintKind::Wheel(j) => j.commit(ctx),
            ConstraintKind::Planar(j) => j.commit(ctx),
            _ => {}
        }
    }
}

/// A constraint slot's contents.
#[derive(Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct ConstraintEntry {
    pub(crate) kind: ConstraintKind,
    pub(crate) bodies: [Option<BodyHandle>; 2],
    pub(crate) enabled: bool,
    /// Rows of the last step in the world's λ buffer: `(first, count)`; `None` if not solved.
    pub(crate) last_rows: Option<(u32, u32)>,
    /// Force and torque on each body in the last step.
    pub(crate) reaction: [Reaction; 2],
    /// Per-constraint γ, used by its rows that do not set their own.
    pub(crate) gamma: Option<Real>,
    /// Breaking thresholds on the reaction force and torque on body 1 (N, N·m).
    pub(crate) break_force: Option<Real>,
    pub(crate) break_torque: Option<Real>,
}

impl Clone for ConstraintEntry {
    fn clone(&self) -> Self {
        Self {
            kind: self.kind.clone(),
            ..*self
        }
    }

    /// Copies the kind in place ([`ConstraintKind::clone_from`]): no allocation.
    fn clone_from(&mut self, source: &Self) {
        // Every field named, so that a new one cannot be missed.
        let Self {
            kind,
            bodies,
            enabled,
            last_rows,
            reaction,
            gamma,
            break_force,
            break_torque,
        } = source;
        self.kind.clone_from(kind);
        (self.bodies, self.enabled, self.last_rows) = (*bodies, *enabled, *last_rows);
        (self.reaction, self.gamma) = (*reaction, *gamma);
        (self.break_force, self.break_torque) = (*break_force, *break_torque);
    }
}

impl ConstraintEntry {
    pub(crate) fn new(kind: ConstraintKind, bodies: [Option<BodyHandle>; 2]) -> Self {
        Self {
            kind,
            bodies,
            enabled: true,
            last_rows: None,
            reaction: [Reaction::default(); 2],
            gamma: None,
            break_force: None,
            break_torque: None,
        }
    }
}
