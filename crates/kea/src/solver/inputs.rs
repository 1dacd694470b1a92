//! What the solver is given: bodies, constraint blocks, contacts; and the reactions it gives
//! back per constraint.

use super::SolverPath;
use crate::constraint::{Contact, RowContext, RowWriter};
use crate::math::{Mat3, Quat, Real, Vec3};

/// One body as the solver sees it (the guide's `MdtKeaBody` and `MdtKeaTransformation`).
///
/// A body with `inv_mass == 0` and a zero `inv_inertia` is fixed (or kinematic: it moves with its
/// set velocity and is not pushed by constraints); it never joins an island.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverBody {
    /// Centre of mass, world frame.
    pub position: Vec3,
    /// Orientation.
    pub orientation: Quat,
    /// Linear velocity.
    pub linear_velocity: Vec3,
    /// Angular velocity, world frame.
    pub angular_velocity: Vec3,
    /// 1/mass (0 for a fixed body).
    pub inv_mass: Real,
    /// Inertia tensor, body frame.
    pub inertia: Mat3,
    /// Inverse inertia tensor, body frame (zero for a fixed body).
    pub inv_inertia: Mat3,
    /// Applied force at the centre of mass for this step (gravity comes from the parameters).
    pub force: Vec3,
    /// Applied torque for this step.
    pub torque: Vec3,
    /// Linear damping, kg/s.
    pub linear_damping: Real,
    /// Angular damping, N·m·s.
    pub angular_damping: Real,
    /// Fast-spin axis in the body frame (unit), if any.
    pub fast_spin_axis: Option<Vec3>,
    /// Output: linear acceleration over the step.
    pub linear_acceleration: Vec3,
    /// Output: angular acceleration over the step.
    pub angular_acceleration: Vec3,
    /// Output: total constraint force on the body (Σ Jᵀλ, linear part).
    pub constraint_force: Vec3,
    /// Output: total constraint torque on the body about its centre of mass.
    pub constraint_torque: Vec3,
    /// Ask for the exact path for this body's island (vehicles, ragdolls), in hybrid mode.
    pub prefer_exact: bool,
    /// In/out: which path solved this body's island last step (for hysteresis).
    pub last_path: SolverPath,
}

impl SolverBody {
    /// A body at rest at a pose with a mass and body-frame inertia (both must be valid; the
    /// world validates them for you, immediate-mode users are trusted here and checked by
    /// [`super::Solver::step`]).
    #[must_use]
    pub fn new(mass: Real, inertia: Mat3, position: Vec3, orientation: Quat) -> Self {
        Self {
            position,
            orientation,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            inv_mass: 1.0 / mass,
            inertia,
            inv_inertia: inertia.inverse(),
            force: Vec3::ZERO,
            torque: Vec3::ZERO,
            linear_damping: 0.0,
            angular_damping: 0.0,
            fast_spin_axis: None,
            linear_acceleration: Vec3::ZERO,
            angular_acceleration: Vec3::ZERO,
            constraint_force: Vec3::ZERO,
            constraint_torque: Vec3::ZERO,
            prefer_exact: false,
            last_path: SolverPath::None,
        }
    }

    /// True for a fixed (infinite-mass) body.
    #[must_use]
    pub fn is_fixed(&self) -> bool {
        self.inv_mass == 0.0 && self.inv_inertia == Mat3::ZERO
    }
}

/// A constraint as the solver sees it: which bodies (indices into the body slice, `None` for the
/// static world) and which rows (a contiguous range of the row slice).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConstraintBlock {
    /// Body 0 and body 1 of the constraint's rows.
    pub bodies: [Option<u32>; 2],
    /// Index of the first row.
    pub first_row: u32,
    /// Number of rows.
    pub row_count: u32,
}

/// A contact as the solver sees it: which bodies (indices into the body slice, `None` for the
/// static world) and the contact itself (normal, points, parameters, and as warm start each
/// point's force of the last step). On return the contact holds this step's forces
/// ([`Contact::forces`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverContact {
    /// Body 1 and body 2 of the contact; the normal points from body 2 to body 1.
    pub bodies: [Option<u32>; 2],
    /// The contact.
    pub contact: Contact,
}

/// The force and torque a constraint applies to one of its bodies (torque about that body's
/// centre of mass).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Reaction {
    /// Force, N.
    pub force: Vec3,
    /// Torque about the body's centre of mass, N·m.
    pub torque: Vec3,
}

/// Writes a constraint block's rows again at the bodies' present states: what lets the
/// iterative path re-linearise joints inside its substeps (the world's joints answer it). A
/// block whose rows change in number or kind since the step began keeps its step-start rows.
pub trait RowSource: Sync {
    /// Writes block `block`'s rows for the bodies in `ctx` (the block's two bodies, in order).
    /// A slot the block gave no body (`None`) arrives as [`RowBody::STATIC`](crate::constraint::RowBody::STATIC),
    /// the world's frame: a source whose constraint holds a body there that the solver was
    /// not given (a disabled body) must write it at that body's own pose, as the world does.
    fn rewrite(&self, block: usize, ctx: &RowContext, out: &mut RowWriter<'_>);
}
