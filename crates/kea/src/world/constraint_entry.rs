//! How the world stores a constraint: its kind, bodies, enabled flag and last results.

use crate::constraint::{BallJoint, Contact, CustomConstraint, RowContext, RowWriter};
use crate::handle::BodyHandle;
use crate::solver::Reaction;

/// The kinds of constraint a world holds.
#[derive(Debug)]
pub(crate) enum ConstraintKind {
    Contact(Contact),
    Ball(BallJoint),
    Custom(Box<dyn CustomConstraint>),
}

impl ConstraintKind {
    pub(crate) fn name(&self) -> &'static str {
        match self {
            ConstraintKind::Contact(_) => "contact",
            ConstraintKind::Ball(_) => "ball joint",
            ConstraintKind::Custom(c) => c.name(),
        }
    }

    pub(crate) fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        match self {
            ConstraintKind::Contact(c) => c.write_rows(ctx, out),
            ConstraintKind::Ball(j) => j.write_rows(ctx, out),
            ConstraintKind::Custom(c) => c.write_rows(ctx, out),
        }
    }
}

/// A constraint slot's contents.
#[derive(Debug)]
pub(crate) struct ConstraintEntry {
    pub(crate) kind: ConstraintKind,
    pub(crate) bodies: [Option<BodyHandle>; 2],
    pub(crate) enabled: bool,
    /// Rows of the last step in the world's λ buffer: `(first, count)`; `None` if not solved.
    pub(crate) last_rows: Option<(u32, u32)>,
    /// Force and torque on each body in the last step.
    pub(crate) reaction: [Reaction; 2],
}

impl ConstraintEntry {
    pub(crate) fn new(kind: ConstraintKind, bodies: [Option<BodyHandle>; 2]) -> Self {
        Self {
            kind,
            bodies,
            enabled: true,
            last_rows: None,
            reaction: [Reaction::default(); 2],
        }
    }
}
