//! How soft a row is: the guide's raw softness ε and relaxation γ ([`Softness`]), or a
//! mass-independent spring given as a natural frequency and a damping ratio ([`Spring`]).
//!
//! # The two forms and how they relate
//!
//! A row with softness ε and relaxation γ at step h behaves as an implicit spring of stiffness
//! `k = γ/(ε h²)` and damping `d = (1 − γ)/(ε h)` (the guide's soft mode; [`Softness`]). Its
//! stiffness does not depend on the bodies, so the same ε is soft under a heavy body and stiff
//! under a light one: a 5 t box sinks where a 1 kg box rests.
//!
//! A [`Spring`] instead gives the frequency `f` (Hz) and damping ratio `ζ` the row has *with its
//! own effective mass* `m = 1/(J M⁻¹ Jᵀ)`: `k = m ω²`, `d = 2 ζ m ω`, `ω = 2π f` (Box2D v3 and
//! Jolt do the same). A body resting on a spring row sinks `g/ω²` whatever its mass. In the
//! guide's terms, for a row of effective mass m at step h:
//!
//! ```text
//!   γ = h ω / (h ω + 2ζ)              (independent of m)
//!   ε = 1 / (m · h ω · (h ω + 2ζ))    (proportional to 1/m)
//! ```
//!
//! and back: `k = γ/(ε h²)`, `d = (1 − γ)/(ε h)`, `ω = √(k/m)`, `ζ = d/(2 m ω)`
//! ([`Spring::from_softness`]). The exact path applies these per row with the row's diagonal
//! `J M⁻¹ Jᵀ`; the iterative path uses the equivalent coefficients of Box2D v3's soft step at
//! its substep ([`Spring::coefficients`]).

use crate::math::{Real, PI};

/// A row's softness ε and relaxation γ, usually derived from a physical spring.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Softness {
    /// Softness ε (inverse mass units).
    pub epsilon: Real,
    /// Error reduction γ in [0, 1].
    pub gamma: Real,
}

impl Softness {
    /// The ε and γ that make a row behave as an implicit spring of stiffness `k` (N/m or
    /// N·m/rad) and damping `d` (N·s/m or N·m·s/rad) at step `h`:
    /// `γ = h·k / (h·k + d)`, `ε = 1 / (h·(h·k + d))`.
    ///
    /// With these, one step of the row reproduces implicit Euler on `m·ẍ = −k·x − d·ẋ`
    /// exactly for a single body of effective mass `m`, so the spring oscillates at `√(k/m)`
    /// whatever the step. Returns `None` unless `k ≥ 0`, `d ≥ 0`, `h > 0`, `h·k + d > 0`.
    #[must_use]
    pub fn from_spring(k: Real, d: Real, h: Real) -> Option<Self> {
        let ok = k.is_finite() && d.is_finite() && h.is_finite() && k >= 0.0 && d >= 0.0;
        let hkd = h * k + d;
        if !ok || h <= 0.0 || hkd <= 0.0 {
            return None;
        }
        Some(Self {
            epsilon: 1.0 / (h * hkd),
            gamma: h * k / hkd,
        })
    }
}

/// Mass-independent softness: the natural frequency and damping ratio a row has with its own
/// effective mass (see the module docs). The default softness of contacts.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Spring {
    /// Natural frequency, Hz, > 0. A body resting on a contact of this spring sinks
    /// `g/(n (2πf)²)` with `n` the iterative path's substeps (4 by default: 0.07 mm at 30 Hz,
    /// 1 µm at 240 Hz; `kea3d/tests/contact_softness.rs`). Stiffer rows let tall stacks sag less and need the solver to
    /// converge harder; a frequency above the substep rate behaves as rigid.
    pub hertz: Real,
    /// Damping ratio ζ, ≥ 0: 1 is critical; contacts use a heavily damped 10 so that they
    /// absorb impacts without ringing (restitution is separate).
    pub damping_ratio: Real,
}

/// The coefficients of a [`Spring`] at one (sub)step for a Gauss-Seidel solve, Box2D v3's soft
/// step: `ΔP = −m·mass_scale·(v + bias_rate·C) − impulse_scale·P`, with `m` the row's effective
/// mass and `P` its accumulated impulse. `mass_scale + impulse_scale = 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SoftCoefficients {
    /// Rate at which the position error C is fed back as velocity, 1/s.
    pub bias_rate: Real,
    /// Fraction of the rigid effective mass used.
    pub mass_scale: Real,
    /// Fraction of the accumulated impulse relaxed away each solve.
    pub impulse_scale: Real,
}

impl SoftCoefficients {
    /// A rigid row that corrects no error.
    pub const RIGID: Self = Self {
        bias_rate: 0.0,
        mass_scale: 1.0,
        impulse_scale: 0.0,
    };
}

impl Spring {
    /// A spring of `hertz` Hz and damping ratio `damping_ratio`.
    #[must_use]
    pub const fn new(hertz: Real, damping_ratio: Real) -> Self {
        Self {
            hertz,
            damping_ratio,
        }
    }

    /// Checks that the frequency is finite and positive and the damping ratio finite and ≥ 0.
    pub fn validate(&self, arg: &'static str) -> crate::KeaResult<()> {
        if !(self.hertz.is_finite() && self.hertz > 0.0) {
            return Err(crate::KeaError::OutOfRange {
                arg,
                value: format!("hertz {}", self.hertz),
                expected: "the frequency must be finite and > 0",
            });
        }
        if !(self.damping_ratio.is_finite() && self.damping_ratio >= 0.0) {
            return Err(crate::KeaError::OutOfRange {
                arg,
                value: format!("damping ratio {}", self.damping_ratio),
                expected: "the damping ratio must be finite and >= 0",
            });
        }
        Ok(())
    }

    /// Angular frequency ω = 2πf, rad/s.
    #[must_use]
    pub fn omega(&self) -> Real {
        2.0 * PI * self.hertz
    }

    /// The guide's ε and γ of a row of effective mass `effective_mass` at step `h`
    /// (module docs). `None` when the mass or step is not finite and positive.
    #[must_use]
    pub fn softness(&self, effective_mass: Real, h: Real) -> Option<Softness> {
        let (relative, gamma) = self.relative_softness(h)?;
        if !(effective_mass.is_finite() && effective_mass > 0.0) {
            return None;
        }
        Some(Softness {
            epsilon: relative / effective_mass,
            gamma,
        })
    }

    /// `(ε·m, γ)`: the softness relative to the row's inverse effective mass, and γ, at step
    /// `h`. The exact solver adds `ε·m · (J M⁻¹ Jᵀ)ᵢᵢ` to a row's diagonal.
    #[must_use]
    pub fn relative_softness(&self, h: Real) -> Option<(Real, Real)> {
        if !(h.is_finite() && h > 0.0) {
            return None;
        }
        let hw = h * self.omega();
        let a1 = hw + 2.0 * self.damping_ratio;
        if !(hw > 0.0 && a1.is_finite()) {
            return None;
        }
        Some((1.0 / (hw * a1), hw / a1))
    }

    /// The spring that a row of effective mass `effective_mass` with softness `s` has at step
    /// `h` (the inverse of [`Spring::softness`]). `None` for a rigid (ε = 0) or non-restoring
    /// (γ = 0) row; γ = 1 gives ζ = 0.
    #[must_use]
    pub fn from_softness(s: Softness, effective_mass: Real, h: Real) -> Option<Self> {
        let ok = s.epsilon > 0.0 && s.gamma > 0.0 && s.gamma <= 1.0 && effective_mass > 0.0;
        if !ok || h.is_nan() || h <= 0.0 {
            return None;
        }
        // k = γ/(ε h²) = m ω², d = (1 − γ)/(ε h) = 2 ζ m ω.
        let k = s.gamma / (s.epsilon * h * h);
        let d = (1.0 - s.gamma) / (s.epsilon * h);
        let omega = (k / effective_mass).sqrt();
        Some(Self {
            hertz: omega / (2.0 * PI),
            damping_ratio: d / (2.0 * effective_mass * omega),
        })
    }

    /// The soft-step coefficients at substep `h` (Catto's "Solver2D" soft step):
    /// `a₁ = 2ζ + hω`, `a₂ = hω·a₁`, `bias_rate = ω/a₁`, `mass_scale = a₂/(1 + a₂)`,
    /// `impulse_scale = 1/(1 + a₂)`.
    #[must_use]
    pub fn coefficients(&self, h: Real) -> SoftCoefficients {
        let omega = self.omega();
        let a1 = 2.0 * self.damping_ratio + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        SoftCoefficients {
            bias_rate: omega / a1,
            mass_scale: a2 * a3,
            impulse_scale: a3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spring_mapping_round_trips() {
        let h = 0.01;
        let s = Softness::from_spring(1000.0, 10.0, h).unwrap();
        // k = γ/(ε h²), d = (1 − γ)/(ε h)
        let k = s.gamma / (s.epsilon * h * h);
        let d = (1.0 - s.gamma) / (s.epsilon * h);
        assert!((k - 1000.0).abs() < 1e-2 && (d - 10.0).abs() < 1e-3);
        assert!(Softness::from_spring(-1.0, 0.0, h).is_none());
    }

    #[test]
    fn frequency_form_is_the_same_spring_for_every_mass() {
        let spring = Spring::new(30.0, 0.7);
        let h = 1.0 / 60.0;
        for m in [1.0e-3, 1.0, 1.0e4] {
            let s = spring.softness(m, h).unwrap();
            let k = s.gamma / (s.epsilon * h * h);
            let d = (1.0 - s.gamma) / (s.epsilon * h);
            let omega = spring.omega();
            assert!(
                (k / (m * omega * omega) - 1.0).abs() < 1e-4,
                "stiffness at m = {m}"
            );
            assert!(
                (d / (2.0 * 0.7 * m * omega) - 1.0).abs() < 1e-4,
                "damping at m = {m}"
            );
            let back = Spring::from_softness(s, m, h).unwrap();
            assert!((back.hertz - 30.0).abs() < 1e-3 && (back.damping_ratio - 0.7).abs() < 1e-4);
        }
    }

    #[test]
    fn soft_step_coefficients_sum_to_one() {
        let c = Spring::new(30.0, 10.0).coefficients(1.0 / 240.0);
        assert!((c.mass_scale + c.impulse_scale - 1.0).abs() < 1e-6);
        // Box2D v3's worked value: 30 Hz, ζ = 10 at 240 Hz substeps gives ≈ 9.07 /s.
        assert!((c.bias_rate - 9.07).abs() < 0.01, "{}", c.bias_rate);
    }
}
