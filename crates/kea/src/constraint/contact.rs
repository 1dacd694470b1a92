//! Contacts (the guide's `MdtContact`, `MdtBclContact`, `MdtBclContactParams`).
//!
//! A contact is a point `p`, a unit normal `n` pointing from body 2 towards body 1, and a
//! penetration depth. It writes up to three rows:
//!
//! * **normal**: `J₁ = (n, r₁×n)`, `J₂ = (−n, −r₂×n)`, `xi = −penetration`, `λ ∈ [−F_adhesive, ∞)`.
//!   A negative penetration is a gap (a speculative contact): the row then uses γ = 1, so the
//!   bodies may close exactly the gap in this step and no more, and land without popping.
//!   When the approach speed exceeds the restitution threshold (and the bodies touch this step),
//!   the target velocity is `c = e·v_in` and the row is made nearly rigid for that step (ε ≈ 0, no error
//!   term) so that softness does not eat into the bounce: rebound speed is `e·v_in` to round-off.
//! * **friction** along the primary direction `t₁` and (2D) the secondary `t₂ = n × t₁`
//!   (right-hand rule): `J = (t, r₁×t)`, `(−t, −r₂×t)`, target `c = slide` (conveyor belt
//!   speed of body 1 relative to body 2), slip factor `s` (sliding speed `s·|F|`), bounds by
//!   model: box `±F_max`, Coulomb `±μλₙ` (linked to the normal row), infinite `±∞`.
//!
//! With no primary direction set, `t₁` follows the predicted tangential sliding velocity (so
//! friction opposes sliding exactly, without the box model's anisotropy), or a fixed basis when
//! there is none.

use super::{Jacobian, Row, RowContext, RowWriter};
use crate::error::{check_finite, check_non_negative, check_unit, check_vec3, KeaError, KeaResult};
use crate::math::{orthonormal_basis, Real, Vec3};

/// Softness of friction rows relative to the contact's normal softness (see
/// [`Contact::write_rows`]).
pub const FRICTION_SOFTNESS_RATIO: Real = 1.0e-3;

/// Predicted sliding speed, m/s, above which a contact with no primary direction aligns its
/// friction with the sliding direction. Below it the direction comes from a fixed basis of the
/// normal, so resting contacts keep the same friction rows from step to step (and their warm
/// start stays meaningful) instead of following jitter.
pub const SLIDING_SPEED: Real = 1.0e-2;

/// Softness of a bounce row (inverse mass units): small enough that the rebound is exact to
/// ~1e-10 relative for bodies of a gram or more, large enough to keep redundant bounces regular.
pub const BOUNCE_SOFTNESS: Real = 1.0e-10;

/// Which tangential directions carry friction (the guide's `MdtContactType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ContactType {
    /// No friction: the bodies slide freely.
    Frictionless,
    /// Friction along the primary direction only.
    Friction1D,
    /// Friction along both tangential directions.
    #[default]
    Friction2D,
}

/// How friction is bounded along one direction (the guide's friction models).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrictionModel {
    /// No bound: the surfaces never slide (the guide's default when no model is set).
    Infinite,
    /// Constant maximum force, N (the guide's `MdtFrictionModelBox`).
    Box {
        /// Maximum friction force along this direction, ≥ 0.
        max_force: Real,
    },
    /// Coulomb: maximum force `μ` times the normal force.
    Coulomb {
        /// Friction coefficient, ≥ 0.
        mu: Real,
    },
}

/// The surface parameters of a contact (the guide's `MdtBclContactParams`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactParams {
    /// Frictionless, 1D or 2D.
    pub contact_type: ContactType,
    /// Friction model along the primary and secondary directions.
    pub friction: [FrictionModel; 2],
    /// Coefficient of restitution in [0, ∞) (normally ≤ 1; above 1 adds energy, a pinball
    /// bumper). 0 by default.
    pub restitution: Real,
    /// Minimum approach speed (m/s) for a bounce; slower impacts do not bounce. Default 0.1.
    pub restitution_threshold: Real,
    /// Contact softness ε (the guide's soft mode); `None` uses the world's ε. Around 1e-4 is
    /// barely soft; 0.1–1 is visibly springy (units of inverse mass).
    pub softness: Option<Real>,
    /// Maximum adhesive (pulling) force, N; 0 for none (the guide's adhesive mode).
    pub max_adhesive_force: Real,
    /// Slip factor along the primary and secondary directions, m/s per N (0 = none).
    pub slip: [Real; 2],
    /// Surface (conveyor) speed of body 1 relative to body 2 along each direction, m/s.
    pub slide: [Real; 2],
}

impl Default for ContactParams {
    /// 2D Coulomb friction with μ = 0.5, no restitution, world softness, nothing else.
    fn default() -> Self {
        Self {
            contact_type: ContactType::Friction2D,
            friction: [FrictionModel::Coulomb { mu: 0.5 }; 2],
            restitution: 0.0,
            restitution_threshold: 0.1,
            softness: None,
            max_adhesive_force: 0.0,
            slip: [0.0; 2],
            slide: [0.0; 2],
        }
    }
}

impl ContactParams {
    /// Checks every field; names the first bad one.
    pub fn validate(&self) -> KeaResult<()> {
        for (i, f) in self.friction.iter().enumerate() {
            let arg = if i == 0 { "friction[0]" } else { "friction[1]" };
            match *f {
                FrictionModel::Infinite => {}
                FrictionModel::Box { max_force } => {
                    check_non_negative(arg, max_force)?;
                }
                FrictionModel::Coulomb { mu } => {
                    check_non_negative(arg, mu)?;
                }
            }
        }
        check_non_negative("restitution", self.restitution)?;
        check_non_negative("restitution_threshold", self.restitution_threshold)?;
        if let Some(s) = self.softness {
            check_non_negative("softness", s)?;
        }
        check_non_negative("max_adhesive_force", self.max_adhesive_force)?;
        check_non_negative("slip[0]", self.slip[0])?;
        check_non_negative("slip[1]", self.slip[1])?;
        check_finite("slide[0]", self.slide[0])?;
        check_finite("slide[1]", self.slide[1])?;
        Ok(())
    }

    /// Number of rows a contact with these parameters writes.
    #[must_use]
    pub fn row_count(&self) -> usize {
        match self.contact_type {
            ContactType::Frictionless => 1,
            ContactType::Friction1D => 2,
            ContactType::Friction2D => 3,
        }
    }
}

/// A contact point between body 1 and body 2 (or the static world). Defaults follow the
/// guide's reset table: position 0, normal +y, penetration 0, no primary direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    position: Vec3,
    normal: Vec3,
    penetration: Real,
    direction: Option<Vec3>,
    params: ContactParams,
    /// The primary friction direction used last step, kept so that a persistent contact keeps
    /// its friction rows (and their warm start) from step to step.
    last_direction: Option<Vec3>,
}

impl Default for Contact {
    fn default() -> Self {
        Self {
            position: Vec3::ZERO,
            normal: Vec3::Y,
            penetration: 0.0,
            direction: None,
            params: ContactParams::default(),
            last_direction: None,
        }
    }
}

impl Contact {
    /// A contact at a world point with a unit normal (from body 2 towards body 1) and a
    /// penetration depth (positive when overlapping).
    pub fn new(position: Vec3, normal: Vec3, penetration: Real) -> KeaResult<Self> {
        let mut c = Self::default();
        c.set_position(position)?;
        c.set_normal(normal)?;
        c.set_penetration(penetration)?;
        Ok(c)
    }
    /// Contact point, world frame.
    #[must_use]
    pub fn position(&self) -> Vec3 {
        self.position
    }
    /// Unit normal, world frame, from body 2 towards body 1.
    #[must_use]
    pub fn normal(&self) -> Vec3 {
        self.normal
    }
    /// Penetration depth (positive when overlapping).
    #[must_use]
    pub fn penetration(&self) -> Real {
        self.penetration
    }
    /// Primary friction direction, if set.
    #[must_use]
    pub fn direction(&self) -> Option<Vec3> {
        self.direction
    }
    /// The surface parameters.
    #[must_use]
    pub fn params(&self) -> &ContactParams {
        &self.params
    }
    /// Sets the contact point (world frame).
    pub fn set_position(&mut self, p: Vec3) -> KeaResult<()> {
        self.position = check_vec3("position", p)?;
        Ok(())
    }
    /// Sets the normal (unit; from body 2 towards body 1). If a primary direction is set and
    /// is no longer perpendicular, it is cleared.
    pub fn set_normal(&mut self, n: Vec3) -> KeaResult<()> {
        let n = check_unit("normal", n)?;
        self.normal = n;
        if let Some(d) = self.direction {
            if d.dot(n).abs() > 1.0e-3 {
                self.direction = None;
            }
        }
        Ok(())
    }
    /// Sets the penetration depth (finite; negative means a gap).
    pub fn set_penetration(&mut self, depth: Real) -> KeaResult<()> {
        self.penetration = check_finite("penetration", depth)?;
        Ok(())
    }
    /// Sets the primary friction direction (unit, perpendicular to the normal within 1e-3), or
    /// clears it with `None`. The secondary direction is `normal × primary`.
    pub fn set_direction(&mut self, d: Option<Vec3>) -> KeaResult<()> {
        let Some(d) = d else {
            self.direction = None;
            return Ok(());
        };
        let d = check_unit("direction", d)?;
        if d.dot(self.normal).abs() > 1.0e-3 {
            return Err(KeaError::OutOfRange {
                arg: "direction",
                value: format!("{d}"),
                expected: "must be perpendicular to the contact normal",
            });
        }
        // Remove the tiny normal component so the basis is exactly orthonormal.
        self.direction = Some((d - self.normal * d.dot(self.normal)).normalize());
        Ok(())
    }
    /// Replaces the surface parameters after checking them.
    pub fn set_params(&mut self, params: ContactParams) -> KeaResult<()> {
        params.validate()?;
        self.params = params;
        Ok(())
    }

    /// Records the primary friction direction used in a step, so that a persistent contact
    /// keeps the same friction rows (and their warm start) at the next one.
    pub fn remember_direction(&mut self, t1: Vec3) {
        if t1.is_finite() && (t1.length() - 1.0).abs() < 1.0e-3 {
            self.last_direction = Some(t1);
        }
    }

    /// The friction directions `(t₁, t₂)` this contact would use now.
    #[must_use]
    pub fn friction_directions(&self, ctx: &RowContext) -> (Vec3, Vec3) {
        let n = self.normal;
        let t1 = match self.direction {
            Some(d) => d,
            None => {
                let [b1, b2] = &ctx.bodies;
                let v = b1.free_velocity_at(self.position) - b2.free_velocity_at(self.position);
                let vt = v - n * v.dot(n);
                let speed = vt.length();
                // A conveyor's slide is along t₁: it needs a direction that does not follow
                // the motion it causes.
                let conveyor = self.params.slide != [0.0; 2];
                if speed > SLIDING_SPEED && !conveyor {
                    -vt / speed
                } else {
                    // Keep last step's direction, re-projected on the new tangent plane: a
                    // fixed basis of the normal jumps when the normal crosses its seam.
                    self.last_direction
                        .map(|d| d - n * d.dot(n))
                        .filter(|d| d.length_squared() > 0.25)
                        .map_or_else(|| orthonormal_basis(n).0, Vec3::normalize)
                }
            }
        };
        (t1, n.cross(t1))
    }

    /// Writes the contact's rows: normal first, then friction (see the module docs). The
    /// primary friction direction is the linear Jacobian of the second row for body 1; the
    /// world remembers it after a successful step ([`Contact::remember_direction`]).
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        let p = self.position;
        let n = self.normal;
        let r1 = p - b1.position;
        let r2 = p - b2.position;
        let prm = &self.params;
        let jac = |d: Vec3| {
            [
                Jacobian::new(d, r1.cross(d)),
                Jacobian::new(-d, -r2.cross(d)),
            ]
        };

        let mut normal = Row::new(jac(n)[0], jac(n)[1])
            .with_error(-self.penetration)
            .with_bounds(-prm.max_adhesive_force, Real::INFINITY);
        if let Some(s) = prm.softness {
            normal.softness = Some(s);
        }
        let gap = -self.penetration;
        if gap > 0.0 {
            // Speculative contact: the bodies may close the whole gap this step, no more.
            // Adhesion still acts across the gap: a held adhesive contact opens slightly
            // under load (softness), and the guide's sticky contacts fail exactly there.
            normal.gamma = Some(1.0);
        }
        let approach = -(b1.velocity_at(p) - b2.velocity_at(p)).dot(n);
        let hits_this_step = gap <= 0.0 || approach * ctx.dt > gap;
        if prm.restitution > 0.0 && approach > prm.restitution_threshold && hits_this_step {
            normal.c = prm.restitution * approach;
            normal.bounce = true;
            normal.xi = 0.0;
            // Nearly rigid, so the rebound is e·v_in to ~1e-10, yet regular when several
            // bounce rows on one body are redundant (a box landing flat).
            normal.softness = Some(BOUNCE_SOFTNESS);
            normal.gamma = Some(0.0);
        }
        let normal_row = out.push(normal);

        let directions = match prm.contact_type {
            ContactType::Frictionless => 0,
            ContactType::Friction1D => 1,
            ContactType::Friction2D => 2,
        };
        if directions == 0 {
            return;
        }
        let (t1, t2) = self.friction_directions(ctx);
        // A friction row has no position error to recover, so softness would make a resting
        // body creep at ε·h·F for ever; it gets a thousandth of the normal row's softness, just
        // enough to regularise redundant contacts.
        let friction_softness = prm.softness.unwrap_or(ctx.epsilon) * FRICTION_SOFTNESS_RATIO;
        for (k, t) in [t1, t2].into_iter().enumerate().take(directions) {
            let j = jac(t);
            let mut row = Row::new(j[0], j[1])
                .with_target_velocity(prm.slide[k])
                .with_slip(prm.slip[k]);
            row.softness = Some(friction_softness);
            // Friction acts on velocity only: no position error to drive (γ = 0).
            row.gamma = Some(0.0);
            match prm.friction[k] {
                FrictionModel::Infinite => {}
                FrictionModel::Box { max_force } => row = row.with_bounds(-max_force, max_force),
                FrictionModel::Coulomb { mu } => row = row.with_friction_link(normal_row, mu),
            }
            out.push(row);
        }
    }
}
