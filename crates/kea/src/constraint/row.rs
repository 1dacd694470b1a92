//! The constraint row: the one contract every contact, joint and custom constraint writes
//! (the guide's `MdtKeaConstraints`, one row at a time).
//!
//! A row `i` constrains the velocities `v` of at most two bodies through its Jacobian `J_i`
//! (per body: 3 linear and 3 angular entries, world frame). With step `h`, error `xi`, target
//! velocity `c`, softness `ε` and relaxation `γ`, the solver looks for a force `λ_i` with
//!
//! ```text
//!   J_i v⁺ = c − (γ/h)·xi − ε·h·λ_i − s·λ_i         (s: slip, velocity per unit force)
//!   lo_i ≤ λ_i ≤ hi_i,   complementary: λ_i at lo ⇒ J_i v⁺ ≥ target, at hi ⇒ ≤ target
//! ```
//!
//! where `v⁺ = v + h M⁻¹(f_ext + Jᵀλ)`. Eliminating `v⁺` gives the guide's
//! `(A + εI)λ = b` with `A = J M⁻¹ Jᵀ` (see [`crate::solver`]). Units: `λ` is a **force**
//! (N for linear rows, N·m for angular rows), so `lo`/`hi` are force bounds and `ε` has units
//! of inverse mass. A row with stiffness `k` and damping `d` is obtained with
//! [`Softness::from_spring`].

use super::softness::{Softness, Spring};
use crate::math::{Real, Vec3};

/// The Jacobian entries of one row for one body: `J·(v, ω) = linear·v + angular·ω`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Jacobian {
    /// Coefficients of the linear velocity.
    pub linear: Vec3,
    /// Coefficients of the angular velocity.
    pub angular: Vec3,
}

impl Jacobian {
    /// A Jacobian from its two parts.
    #[must_use]
    pub const fn new(linear: Vec3, angular: Vec3) -> Self {
        Self { linear, angular }
    }
    /// The zero Jacobian (no coupling to that body).
    pub const ZERO: Self = Self {
        linear: Vec3::ZERO,
        angular: Vec3::ZERO,
    };
}

/// Coulomb coupling of a friction row to its normal row: the bounds become `±μ·max(λ_n, 0)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionLink {
    /// Index of the normal row **within the same constraint** (0 for the first row written).
    pub normal_row: u16,
    /// Friction coefficient μ (≥ 0).
    pub mu: Real,
}

/// One constraint row. Build it with [`Row::new`] and the `with_*` methods, or fill the public
/// fields directly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// Jacobian for the constraint's first and second body. The entry of an absent (world)
    /// body is ignored.
    pub jacobian: [Jacobian; 2],
    /// Position-level constraint error `C(x)` (the guide's `xi`); the solver drives it to zero
    /// at rate `γ/h`.
    pub xi: Real,
    /// Target velocity of the row (the guide's `c`): motors, conveyor slide, restitution.
    pub c: Real,
    /// The row's velocity-product acceleration `J̇·v` at the present state (m/s², or rad/s²):
    /// how its velocity would drift with no force, from the bodies' rotation alone (a jointed
    /// point's centripetal acceleration). In the relax pass of the iterative path's substeps
    /// of `hs` the row's velocity aims at `c − (hs/2)·curvature`, the velocity along the chord
    /// of the substep, so that the joint's force does next to no work (a double pendulum
    /// released horizontal lost 31% of its energy in 10 s at 60 Hz on split islands without
    /// it, and keeps it to 0.2% with it). The exact path, one linearisation a step, does not
    /// use it (there it turned a slow loss into a gain). 0 where a row does not write it.
    pub curvature: Real,
    /// Lower bound on λ (force); may be `-INFINITY`.
    pub lo: Real,
    /// Upper bound on λ (force); may be `INFINITY`.
    pub hi: Real,
    /// Coulomb link to a normal row: if set, `lo`/`hi` are replaced by `∓μ·λ_normal`.
    pub friction: Option<FrictionLink>,
    /// First-order slip (the guide's `slipfactor`): velocity per unit force, ≥ 0.
    pub slip: Real,
    /// Per-row softness ε (inverse mass units); `None` uses the solver's ε.
    pub softness: Option<Real>,
    /// Per-row error reduction γ in [0, 1]; `None` uses the solver's γ. A row with γ = 0 acts
    /// on velocity only (friction, motors): its error is neither corrected nor tracked.
    pub gamma: Option<Real>,
    /// Mass-independent softness (see [`Spring`]): when set, it replaces `softness` and `gamma`
    /// with the ε and γ of this spring at the row's own effective mass.
    pub spring: Option<Spring>,
    /// `c` is a restitution (bounce) velocity. The exact path uses it as the target of its one
    /// solve; the iterative path treats the row as resting during its substeps and applies the
    /// bounce once afterwards, if the row carried impulse.
    pub bounce: bool,
}

impl Row {
    /// An equality row (unbounded λ) with the given Jacobian for body 0 and body 1, no error and
    /// zero target velocity.
    #[must_use]
    pub fn new(j0: Jacobian, j1: Jacobian) -> Self {
        Self {
            jacobian: [j0, j1],
            xi: 0.0,
            c: 0.0,
            curvature: 0.0,
            lo: Real::NEG_INFINITY,
            hi: Real::INFINITY,
            friction: None,
            slip: 0.0,
            softness: None,
            gamma: None,
            spring: None,
            bounce: false,
        }
    }
    /// Sets the position error.
    #[must_use]
    pub fn with_error(mut self, xi: Real) -> Self {
        self.xi = xi;
        self
    }
    /// Sets the target velocity.
    #[must_use]
    pub fn with_target_velocity(mut self, c: Real) -> Self {
        self.c = c;
        self
    }
    /// Sets the force bounds.
    #[must_use]
    pub fn with_bounds(mut self, lo: Real, hi: Real) -> Self {
        self.lo = lo;
        self.hi = hi;
        self
    }
    /// Makes this a Coulomb friction row bounded by `μ` times the λ of `normal_row`.
    #[must_use]
    pub fn with_friction_link(mut self, normal_row: u16, mu: Real) -> Self {
        self.friction = Some(FrictionLink { normal_row, mu });
        self
    }
    /// Sets the slip factor.
    #[must_use]
    pub fn with_slip(mut self, slip: Real) -> Self {
        self.slip = slip;
        self
    }
    /// Sets softness and relaxation for this row.
    #[must_use]
    pub fn with_softness(mut self, softness: Softness) -> Self {
        self.softness = Some(softness.epsilon);
        self.gamma = Some(softness.gamma);
        self
    }
    /// Makes this row a mass-independent spring (see [`Spring`]).
    #[must_use]
    pub fn with_spring(mut self, spring: Spring) -> Self {
        self.spring = Some(spring);
        self
    }
    /// Sets the per-row γ.
    #[must_use]
    pub fn with_gamma(mut self, gamma: Real) -> Self {
        self.gamma = Some(gamma);
        self
    }

    /// Checks the row's numbers: finite Jacobian, error and target, `lo ≤ hi`, no NaN bounds,
    /// non-negative slip and μ, γ in [0, 1], ε ≥ 0. Returns the name of the first bad field.
    pub fn invalid_field(&self) -> Option<&'static str> {
        // The common row first, in one pass: a sum of finite numbers times zero is zero (an
        // overflowing sum only sends a good row to the full check below).
        let sum = self
            .jacobian
            .iter()
            .map(|j| j.linear.element_sum() + j.angular.element_sum())
            .sum::<Real>()
            + self.xi
            + self.c
            + self.slip;
        if sum * 0.0 == 0.0
            && self.slip >= 0.0
            && self.lo <= self.hi
            && self.lo != Real::INFINITY
            && self.hi != Real::NEG_INFINITY
            && self.friction.is_none()
            && self.softness.is_none()
            && self.gamma.is_none()
            && self.spring.is_none()
        {
            return None;
        }
        let fin = |v: Vec3| v.is_finite();
        if !self
            .jacobian
            .iter()
            .all(|j| fin(j.linear) && fin(j.angular))
        {
            return Some("jacobian");
        }
        if !self.xi.is_finite() {
            return Some("xi");
        }
        if !self.c.is_finite() {
            return Some("c");
        }
        if self.lo.is_nan()
            || self.hi.is_nan()
            || self.lo > self.hi
            || self.lo == Real::INFINITY
            || self.hi == Real::NEG_INFINITY
        {
            return Some("lo/hi");
        }
        if !(self.slip.is_finite() && self.slip >= 0.0) {
            return Some("slip");
        }
        if let Some(f) = self.friction {
            if !(f.mu.is_finite() && f.mu >= 0.0) {
                return Some("friction.mu");
            }
        }
        if let Some(e) = self.softness {
            if !(e.is_finite() && e >= 0.0) {
                return Some("softness");
            }
        }
        if let Some(g) = self.gamma {
            if !(g.is_finite() && (0.0..=1.0).contains(&g)) {
                return Some("gamma");
            }
        }
        if let Some(sp) = self.spring {
            if sp.validate("spring").is_err() {
                return Some("spring");
            }
        }
        None
    }
}

/// Where constraints write their rows. It remembers where the current constraint's rows begin so
/// that [`FrictionLink::normal_row`] can be local.
pub struct RowWriter<'a> {
    rows: &'a mut Vec<Row>,
    start: usize,
}

impl<'a> RowWriter<'a> {
    /// A writer appending to `rows`; the current constraint's rows start at the current end.
    pub fn new(rows: &'a mut Vec<Row>) -> Self {
        let start = rows.len();
        Self { rows, start }
    }
    /// Appends a row and returns its index within the current constraint.
    pub fn push(&mut self, row: Row) -> u16 {
        self.rows.push(row);
        (self.rows.len() - 1 - self.start) as u16
    }
    /// Sets the velocity-product accelerations ([`Row::curvature`]) of three consecutive
    /// rows of the current constraint, starting at its row `first`.
    pub fn set_curvatures(&mut self, first: usize, k: [Real; 3]) {
        let base = self.start + first;
        for (j, kj) in k.into_iter().enumerate() {
            if let Some(r) = self.rows.get_mut(base + j) {
                r.curvature = kj;
            }
        }
    }
    /// Sets the target velocities (and, if given, γ) of three consecutive rows of the current
    /// constraint, starting at its row `first` (used after a shared builder wrote them).
    pub fn set_targets(&mut self, first: usize, c: [Real; 3], gamma: Option<Real>) {
        let base = self.start + first;
        for (k, ck) in c.into_iter().enumerate() {
            if let Some(r) = self.rows.get_mut(base + k) {
                r.c = ck;
                if gamma.is_some() {
                    r.gamma = gamma;
                }
            }
        }
    }

    /// Gives every row of the current constraint without its own γ the relaxation `gamma`.
    pub(crate) fn set_default_gamma(&mut self, gamma: Real) {
        for r in &mut self.rows[self.start..] {
            r.gamma.get_or_insert(gamma);
        }
    }

    /// Number of rows written for the current constraint.
    #[must_use]
    pub fn len(&self) -> usize {
        self.rows.len() - self.start
    }
    /// True when no row was written yet for the current constraint.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
