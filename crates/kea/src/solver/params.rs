//! The solver's parameters.

use super::{IterativeParams, Routing};
use crate::constraint::Spring;
use crate::error::{check_non_negative, check_positive, check_vec3, KeaError, KeaResult};
use crate::math::{Real, Vec3};

/// The default softness of contacts: 30 Hz with a damping ratio of 10 (see [`Spring`]; the
/// choice of Box2D v3 and Rapier, and what the soft step keeps stable at four substeps). A
/// contact yields `g/(2πf)²` per unit of its own weight, whatever the masses: a box resting on
/// the ground sinks 0.07 mm (contacts with a body that cannot move spring at `2f`), and each
/// contact of a column of unit boxes 0.55 mm per box it carries, so a column of 40 sags about
/// 44 cm in the iterative path (Rapier's sags 43 cm).
pub const DEFAULT_CONTACT_SPRING: Spring = Spring::new(30.0, 10.0);

/// How much stiffer the exact path's contacts are than the iterative path's in an island of
/// contacts only (beside joints, contacts keep the world's spring: a ragdoll's limits, soft
/// by the guide's ε, would yield to stiffer ground contacts): a direct solve stays stable
/// however stiff its springs, so it runs them at eight times the frequency (240
/// Hz by default), and eight times the damping ratio so that a step still removes the same
/// fraction of a penetration (`hω/(hω + 2ζ)`, the step's γ, stays as it was) rather than
/// kicking bodies out. Resting, such a contact yields 64 times less: a column of 40 unit boxes
/// sags under 1 cm, and a 1 kg box under a 100 kg one sinks a millimetre or two, where the
/// soft step's 30 Hz gives 44 cm and 13 cm.
pub const EXACT_CONTACT_STIFFENING: Real = 8.0;

/// Solver parameters (the guide's `MdtKeaParameters`). Every field is documented with its unit,
/// normal value and safe range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverParams {
    /// Step size h, s. Normal 1/60; any positive value. Results change slightly with h (first
    /// order): tune at the rate you ship.
    pub dt: Real,
    /// Softness ε added to the diagonal (inverse mass units). Default 0.01. Larger makes
    /// constraints springier but lets redundant systems solve; 0 makes rows rigid (redundant
    /// rows are then regularised and reported). Heavy bodies (≫ 1 kg) may need smaller ε.
    pub epsilon: Real,
    /// Error reduction γ in [0, 1]: the fraction of constraint error removed per step. Default
    /// 0.2; 0.1–0.8 works; 0 lets joints drift, 1 overshoots.
    pub gamma: Real,
    /// Gravity, m/s², applied to bodies with mass.
    pub gravity: Vec3,
    /// Softness of contacts without their own ([`crate::ContactParams::softness`]): a
    /// mass-independent spring ([`Spring`]), so that a 1 g and a 10 t body rest alike.
    /// Default [`DEFAULT_CONTACT_SPRING`].
    pub contact_spring: Spring,
    /// Cap on pivoting iterations per LCP solve. Default 100; reaching it is reported.
    pub max_lcp_iterations: u32,
    /// Cap on Coulomb re-solves per island. Default 16; reaching it is reported.
    pub max_friction_passes: u32,
    /// Split the problem into independent islands (default true). False solves every coupled
    /// body as one problem (the guide's `MdtDEMModeNoPartition`): same answer, more work.
    pub partition: bool,
    /// Which path solves each island (default: hybrid, small islands exact).
    pub routing: Routing,
    /// Settings of the iterative path.
    pub iterative: IterativeParams,
    /// Read the clock for the stage times of [`SolverStats`](super::SolverStats) (default
    /// true). Off, the times are zero and a tiny island's step is about a tenth faster.
    pub timing: bool,
    /// Report each body's total constraint force and torque in
    /// [`SolverBody::constraint_force`](super::SolverBody::constraint_force) (default true).
    /// A caller that does not read them turns this off, and the iterative path then skips
    /// summing its contacts' forces per body (about 3% of a pile's step). The retained world
    /// does: it keeps each constraint's own forces.
    pub body_forces: bool,
}

impl Default for SolverParams {
    fn default() -> Self {
        Self {
            dt: 1.0 / 60.0,
            epsilon: 0.01,
            gamma: 0.2,
            gravity: Vec3::ZERO,
            contact_spring: DEFAULT_CONTACT_SPRING,
            max_lcp_iterations: 100,
            max_friction_passes: 16,
            partition: true,
            routing: Routing::default(),
            iterative: IterativeParams::default(),
            timing: true,
            body_forces: true,
        }
    }
}

impl SolverParams {
    /// Checks every field, naming the first bad one.
    pub fn validate(&self) -> KeaResult<()> {
        check_positive("dt", self.dt)?;
        check_non_negative("epsilon", self.epsilon)?;
        check_non_negative("gamma", self.gamma)?;
        if self.gamma > 1.0 {
            return Err(KeaError::OutOfRange {
                arg: "gamma",
                value: format!("{}", self.gamma),
                expected: "must be in [0, 1]",
            });
        }
        check_vec3("gravity", self.gravity)?;
        self.contact_spring.validate("contact_spring")?;
        if self.max_lcp_iterations == 0 {
            return Err(KeaError::OutOfRange {
                arg: "max_lcp_iterations",
                value: "0".into(),
                expected: "must be >= 1",
            });
        }
        if self.max_friction_passes == 0 {
            return Err(KeaError::OutOfRange {
                arg: "max_friction_passes",
                value: "0".into(),
                expected: "must be >= 1",
            });
        }
        self.routing.validate()?;
        self.iterative.validate()?;
        Ok(())
    }
}
