//! The surface parameters of a contact (the guide's `MdtBclContactParams`): friction model and
//! directions, restitution, softness, adhesion, slip and conveyor slide.

use crate::error::{check_finite, check_non_negative, KeaResult};
use crate::math::Real;

/// Which tangential directions carry friction (the guide's `MdtContactType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
    /// Coulomb with separate static and kinetic coefficients: a contact whose surfaces were at
    /// rest on each other after the last step holds up to `static_mu` times the normal force;
    /// once they slide ([`crate::Contact::is_sliding`]) friction is `kinetic_mu` times the
    /// normal force, until they come to rest again.
    StaticKinetic {
        /// Static coefficient, ≥ `kinetic_mu`.
        static_mu: Real,
        /// Kinetic coefficient, ≥ 0.
        kinetic_mu: Real,
    },
}

impl FrictionModel {
    /// The Coulomb coefficient this model bounds friction with, for a contact sliding or
    /// not (`None`: no Coulomb bound).
    #[must_use]
    pub fn coulomb(&self, sliding: bool) -> Option<Real> {
        match *self {
            FrictionModel::Coulomb { mu } => Some(mu),
            FrictionModel::StaticKinetic {
                static_mu,
                kinetic_mu,
            } => Some(if sliding { kinetic_mu } else { static_mu }),
            FrictionModel::Infinite | FrictionModel::Box { .. } => None,
        }
    }
}

/// The surface parameters of a contact (the guide's `MdtBclContactParams`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
    /// Contact softness ε (the guide's soft mode), units of inverse mass: around 1e-4 is
    /// barely soft, 0.1–1 visibly springy. `None` (the default) does **not** use the world's
    /// ε: the contact is the world's mass-independent contact spring
    /// ([`crate::WorldSettings::contact_spring`], 30 Hz, damping ratio 10), so a 1 g and a
    /// 10 t box sink alike. To make every contact harder (the guide's advice to lower ε),
    /// raise that spring's frequency; to soften one contact, give it its own ε here.
    pub softness: Option<Real>,
    /// Maximum adhesive (pulling) force, N; 0 for none (the guide's adhesive mode).
    pub max_adhesive_force: Real,
    /// Slip factor along the primary and secondary directions, m/s per N (0 = none).
    pub slip: [Real; 2],
    /// Surface (conveyor) speed of body 1 relative to body 2 along each direction, m/s.
    pub slide: [Real; 2],
}

impl Default for ContactParams {
    /// 2D Coulomb friction with μ = 0.5, no restitution, the world's contact spring, nothing
    /// else.
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
                FrictionModel::StaticKinetic {
                    static_mu,
                    kinetic_mu,
                } => {
                    check_non_negative(arg, kinetic_mu)?;
                    check_non_negative(arg, static_mu)?;
                    if static_mu < kinetic_mu {
                        return Err(crate::error::KeaError::OutOfRange {
                            arg,
                            value: format!("static_mu {static_mu} < kinetic_mu {kinetic_mu}"),
                            expected: "a static coefficient at least the kinetic one",
                        });
                    }
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
