//! Limits and motors on a joint's free coordinate (the guide's `MdtLimit`, `MdtSingleLimit`,
//! `MdtBclLimit`): a hinge angle or a slider distance.
//!
//! Each part is its own row on the coordinate's Jacobian `J` (`J·v = ṗ`), so driving away from a
//! stop never jumps:
//!
//! * **motor**: target velocity `c = ṗ_desired`, force bounds `±F_max`, velocity-only (γ = 0)
//!   and nearly rigid; desired velocity 0 is a brake (the guide's disc brake);
//! * **lower stop** `p ≥ lo`: `J`, `xi = p − lo`, `λ ≥ 0`; **upper stop** `p ≤ hi`: `−J`,
//!   `xi = hi − p`, `λ ≥ 0`. A stop row is written once the coordinate is within one step's
//!   travel of the stop (speculatively, like a contact, so a fast joint cannot step through it).
//!
//! * **joint dynamics** ([`JointDynamics`]): armature `a` (a rotor's inertia on the
//!   coordinate), viscous damping `d`, a spring `k` towards a rest position `p₀`, and dry
//!   friction `f` (MuJoCo's `armature`, `damping`, `stiffness`/`springref`, `frictionloss`;
//!   URDF's `damping`, `friction`). Armature, damping and spring are one implicit row: its force
//!   `λ = −a·(ṗ⁺ − ṗ)/h − d·ṗ⁺ − k·(p − p₀ + h·ṗ⁺)` is the row
//!   `J·v⁺ = a·ṗ/m − (h²k/m)/h·(p − p₀) − (h/m)·λ` with `m = a + h·d + h²·k`: target
//!   `c = a·ṗ/m`, relaxation `γ = h²k/m` on the error `p − p₀`, softness `ε = 1/m`. So a joint
//!   of inertia `I` swings as one of `I + a`, decays at `d/(I + a)` and springs at
//!   `√(k/(I + a))` whatever the step. Friction is a rigid brake bounded by `±f`;
//! * **actuator** ([`Actuator`]): a set force along the coordinate (a row with `lo = hi`), or a
//!   servo — stiffness `kp` toward a target position and gain `kv` toward a target velocity,
//!   implicit (a [`crate::Softness::from_spring`] row with error `p − p_target`), force within
//!   `±max_force` (MuJoCo's `motor`, `position` and `velocity` actuators).
//!
//! A stop is **hard** when its stiffness is above its damping threshold (the guide's rule): it
//! is then rigid and bounces with its restitution. At or below the threshold it is **soft**: a
//! spring of that stiffness and damping ([`crate::Softness::from_spring`]), restitution ignored,
//! so it settles at `F/k` and oscillates at `√(k/m)` whatever the step.

use super::{Jacobian, Row, RowWriter, Softness};
use crate::error::{check_finite, check_non_negative, KeaError, KeaResult};
use crate::math::Real;

/// Softness of motor and hard-stop rows: rigid for any practical purpose, but regular when a
/// motor and a stop act on the same coordinate.
const RIGID: Real = 1.0e-10;
/// Approach speed below which a hard stop does not bounce.
const BOUNCE_MIN_SPEED: Real = 1.0e-3;
/// A hard stop's row is written at every step, however far the coordinate is from it: an
/// impact inside the step (a contact's push during the substeps) then meets the stop instead
/// of carrying the coordinate through it for a step. Written only within 0.1 rad of being
/// reached, a ragdoll dropped 3 m onto steps overran a neck's cone by 0.10–0.19 rad; always
/// written, by 0.04 at most. The row only keeps the coordinate from passing the stop (`γ = 1`
/// on the gap), so it costs a row (held at zero by the solver while the stop is open), not
/// motion.
const STOP_MARGIN: Real = Real::INFINITY;

/// The relaxation γ up to which a stop's recovery is left alone (the solver's default).
const STOP_RECOVERY_GAMMA: Real = 0.2;

/// One stop of a limit.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SingleLimit {
    /// Position of the stop (rad or m).
    pub stop: Real,
    /// Stiffness, N·m/rad or N/m (`INFINITY`: perfectly hard, the default).
    #[cfg_attr(feature = "serde", serde(with = "crate::world::serde_real"))]
    pub stiffness: Real,
    /// Damping of a soft stop, N·m·s/rad or N·s/m (≥ 0).
    pub damping: Real,
    /// Restitution of a hard stop, in [0, 1] normally (rebound = e · approach speed).
    pub restitution: Real,
    /// The guide's damping threshold: a stop stiffer than this is hard (restitution used), one at
    /// or below it soft (stiffness and damping used). Default `INFINITY`: only an infinitely
    /// stiff stop is hard.
    #[cfg_attr(feature = "serde", serde(with = "crate::world::serde_real"))]
    pub damping_threshold: Real,
    /// Fastest a hard stop pushes back a coordinate found beyond it, rad/s or m/s (default
    /// `INFINITY`: the solver's γ alone). A robot file's joints start far outside their
    /// range at times (Gymnasium's ant: 30° below its ankles' range); capped, the joint comes
    /// in without being flung to the other stop. The importers set 0.5.
    #[cfg_attr(
        feature = "serde",
        serde(with = "crate::world::serde_real", default = "unbounded")
    )]
    pub recovery_speed: Real,
}

#[cfg(feature = "serde")]
fn unbounded() -> Real {
    Real::INFINITY
}

impl Default for SingleLimit {
    fn default() -> Self {
        Self {
            stop: 0.0,
            stiffness: Real::INFINITY,
            damping: 0.0,
            restitution: 0.0,
            damping_threshold: Real::INFINITY,
            recovery_speed: Real::INFINITY,
        }
    }
}

impl SingleLimit {
    /// A hard stop at `stop` with restitution `e`.
    #[must_use]
    pub fn hard(stop: Real, restitution: Real) -> Self {
        Self {
            stop,
            restitution,
            ..Self::default()
        }
    }
    /// A soft stop at `stop`: a spring of stiffness `k` and damping `d`.
    #[must_use]
    pub fn soft(stop: Real, k: Real, d: Real) -> Self {
        Self {
            stop,
            stiffness: k,
            damping: d,
            ..Self::default()
        }
    }
    /// Whether the stop is hard (stiffness above the damping threshold).
    #[must_use]
    pub fn is_hard(&self) -> bool {
        self.stiffness > self.damping_threshold || self.stiffness == Real::INFINITY
    }
    fn validate(&self, which: &'static str) -> KeaResult<()> {
        let arg = |f: &'static str| match (which, f) {
            ("lower", "stop") => "lower.stop",
            ("lower", "stiffness") => "lower.stiffness",
            ("lower", "damping") => "lower.damping",
            ("lower", "restitution") => "lower.restitution",
            ("lower", _) => "lower.damping_threshold",
            (_, "stop") => "upper.stop",
            (_, "stiffness") => "upper.stiffness",
            (_, "damping") => "upper.damping",
            (_, "restitution") => "upper.restitution",
            _ => "upper.damping_threshold",
        };
        check_finite(arg("stop"), self.stop)?;
        if self.stiffness.is_nan() || self.stiffness <= 0.0 {
            return Err(KeaError::OutOfRange {
                arg: arg("stiffness"),
                value: format!("{}", self.stiffness),
                expected: "must be > 0 (INFINITY for a hard stop)",
            });
        }
        check_non_negative(arg("damping"), self.damping)?;
        check_non_negative(arg("restitution"), self.restitution)?;
        if self.recovery_speed.is_nan() || self.recovery_speed <= 0.0 {
            return Err(KeaError::OutOfRange {
                arg: if which == "lower" {
                    "lower.recovery_speed"
                } else {
                    "upper.recovery_speed"
                },
                value: format!("{}", self.recovery_speed),
                expected: "must be > 0 (INFINITY for no cap)",
            });
        }
        if self.damping_threshold.is_nan() || self.damping_threshold < 0.0 {
            return Err(KeaError::OutOfRange {
                arg: arg("damping_threshold"),
                value: format!("{}", self.damping_threshold),
                expected: "must be >= 0",
            });
        }
        Ok(())
    }
}

/// A force-limited motor (the guide's limited-force motor).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Motor {
    /// Desired velocity of the coordinate, rad/s or m/s (0: a brake).
    pub desired_velocity: Real,
    /// Largest force or torque the motor may apply, N or N·m (≥ 0).
    pub max_force: Real,
}

/// The passive dynamics of a joint's coordinate: a rotor's inertia, viscous damping and dry
/// friction (all ≥ 0; all 0, the default, writes no row).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct JointDynamics {
    /// Armature: inertia added on the coordinate, kg·m² (or kg for a slider), as a geared
    /// rotor adds it (MuJoCo's `armature`).
    pub armature: Real,
    /// Viscous damping, N·m·s/rad (or N·s/m): a force `−d·ṗ`.
    pub damping: Real,
    /// Spring stiffness, N·m/rad (or N/m): a force `−k·(p − rest)`.
    pub stiffness: Real,
    /// Where the spring rests, rad or m (the coordinate as the joint measures it).
    pub rest: Real,
    /// Dry friction, N·m (or N): the coordinate holds until pushed harder than this.
    pub friction: Real,
    /// MuJoCo's soft-constraint model for the coordinate's stops (an MJCF joint's
    /// `solreflimit`, `solimplimit` and `margin`), which the reduced-coordinate path follows;
    /// `None` (the default): hard stops. The maximal-coordinate paths keep hard stops.
    #[cfg_attr(feature = "serde", serde(default))]
    pub soft_limit: Option<SoftLimit>,
}

/// MuJoCo's soft constraint for a joint's stops: within `margin` of a stop a row pulls the
/// coordinate's acceleration towards `−b v − k d(x) x` (`x` the distance past the margin,
/// `v` the rate towards the stop), `b = 2 / (d_max τ)`, `k = 1 / (d_max² τ² ζ²)` with
/// `solref = (τ, ζ)` and `τ` at least two steps; its impedance `d(x)` rises from `d_min`
/// to `d_max` over `width` (`solimp = (d_min, d_max, width, midpoint, power)`) and sets how
/// much of that the row achieves: regulariser `R = (1 − d)/d · [H⁻¹]ᵢᵢ`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SoftLimit {
    /// Time constant τ (s) and damping ratio ζ. MuJoCo's default (0.02, 1).
    pub solref: [Real; 2],
    /// `d_min`, `d_max` (in (0, 1)), `width` (> 0), midpoint (in (0, 1)), power (≥ 1).
    /// MuJoCo's default (0.9, 0.95, 0.001, 0.5, 2).
    pub solimp: [Real; 5],
    /// Distance from a stop at which its row engages (≥ 0).
    pub margin: Real,
}

impl Default for SoftLimit {
    fn default() -> Self {
        Self {
            solref: [0.02, 1.0],
            solimp: [0.9, 0.95, 0.001, 0.5, 2.0],
            margin: 0.0,
        }
    }
}

impl SoftLimit {
    /// Checks every field, naming the first out of range.
    pub fn validate(&self) -> KeaResult<()> {
        let [tau, zeta] = self.solref;
        let [dmin, dmax, width, mid, power] = self.solimp;
        let bad = |arg: &'static str, v: Real, expected: &'static str| {
            Err(KeaError::OutOfRange {
                arg,
                value: v.to_string(),
                expected,
            })
        };
        let unit = |x: Real| x > 0.0 && x < 1.0;
        if !(tau.is_finite() && tau > 0.0) {
            return bad("solref[0]", tau, "a time constant > 0");
        }
        if !(zeta.is_finite() && zeta > 0.0) {
            return bad("solref[1]", zeta, "a damping ratio > 0");
        }
        if !unit(dmin) || !unit(dmax) {
            return bad(
                "solimp[0..2]",
                if unit(dmin) { dmax } else { dmin },
                "in (0, 1)",
            );
        }
        if !(width.is_finite() && width > 0.0) {
            return bad("solimp[2]", width, "a width > 0");
        }
        if !unit(mid) {
            return bad("solimp[3]", mid, "a midpoint in (0, 1)");
        }
        if !(power.is_finite() && power >= 1.0) {
            return bad("solimp[4]", power, "a power >= 1");
        }
        if !(self.margin.is_finite() && self.margin >= 0.0) {
            return bad("margin", self.margin, "a distance >= 0");
        }
        Ok(())
    }
}

impl JointDynamics {
    /// Checks that every field is finite and ≥ 0, naming the first that is not.
    pub fn validate(&self) -> KeaResult<()> {
        check_non_negative("armature", self.armature)?;
        check_non_negative("damping", self.damping)?;
        check_non_negative("stiffness", self.stiffness)?;
        check_finite("rest", self.rest)?;
        check_non_negative("friction", self.friction)?;
        self.soft_limit.map_or(Ok(()), |s| s.validate())
    }

    fn is_zero(&self) -> bool {
        self.armature == 0.0 && self.damping == 0.0 && self.stiffness == 0.0 && self.friction == 0.0
    }
}

/// What drives a coordinate besides its motor: a set force, or an implicit servo.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Actuator {
    /// This force or torque along the coordinate, N or N·m (MuJoCo's `motor`).
    Force(Real),
    /// A servo: force `kp·(p_target − p) + kv·(ṗ_target − ṗ)`, implicit in the step, within
    /// `±max_force` (MuJoCo's `position` with `kp`, `kv`; `velocity` with `kp = 0`).
    Servo {
        /// Target position, rad or m (unused when `stiffness` is 0).
        position: Real,
        /// Target velocity, rad/s or m/s.
        velocity: Real,
        /// Stiffness kp, N·m/rad or N/m (≥ 0).
        stiffness: Real,
        /// Gain kv, N·m·s/rad or N·s/m (≥ 0; kp + kv > 0).
        damping: Real,
        /// Largest force, N or N·m (> 0, `INFINITY` for none).
        #[cfg_attr(feature = "serde", serde(with = "crate::world::serde_real"))]
        max_force: Real,
    },
}

impl Actuator {
    /// Checks the numbers, naming the first bad one.
    pub fn validate(&self) -> KeaResult<()> {
        match *self {
            Self::Force(f) => check_finite("force", f).map(|_| ()),
            Self::Servo {
                position,
                velocity,
                stiffness,
                damping,
                max_force,
            } => {
                check_finite("position", position)?;
                check_finite("velocity", velocity)?;
                check_non_negative("stiffness", stiffness)?;
                check_non_negative("damping", damping)?;
                if max_force.is_nan() || max_force <= 0.0 {
                    return Err(KeaError::OutOfRange {
                        arg: "max_force",
                        value: format!("{max_force}"),
                        expected: "must be > 0 (INFINITY for no limit)",
                    });
                }
                if stiffness + damping <= 0.0 {
                    return Err(KeaError::OutOfRange {
                        arg: "stiffness",
                        value: format!("{stiffness} with damping {damping}"),
                        expected: "a servo needs stiffness or damping > 0",
                    });
                }
                Ok(())
            }
        }
    }
}

/// Limits and motor of one coordinate, with the read-outs of the last step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Limit {
    limited: bool,
    lower: SingleLimit,
    upper: SingleLimit,
    motor: Option<Motor>,
    dynamics: JointDynamics,
    actuator: Option<Actuator>,
    position: Real,
    velocity: Real,
    /// The force its fixed tendons put on the coordinate this step (maximal paths; set by
    /// the world before each step).
    #[cfg_attr(feature = "serde", serde(skip))]
    tendon_force: Real,
}

/// What a step, or a batch's writes, change in a [`Limit`]: its motor and actuator (a
/// world's actions), the coordinate's last position and velocity, and its tendons' force.
/// The stops and the joint's dynamics are its definition, which a batch's worlds share
/// (`crate::world::held`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct LimitMotion {
    motor: Option<Motor>,
    actuator: Option<Actuator>,
    position: Real,
    velocity: Real,
    tendon_force: Real,
}

impl Limit {
    /// Its [`LimitMotion`].
    pub(crate) fn motion(&self) -> LimitMotion {
        // Every field named, so that a new one is sorted into definition or motion.
        let Limit {
            limited: _,
            lower: _,
            upper: _,
            motor,
            dynamics: _,
            actuator,
            position,
            velocity,
            tendon_force,
        } = *self;
        LimitMotion {
            motor,
            actuator,
            position,
            velocity,
            tendon_force,
        }
    }

    /// Takes `m` in place of its motion; its definition stays.
    pub(crate) fn set_motion(&mut self, m: &LimitMotion) {
        self.motor = m.motor;
        self.actuator = m.actuator;
        self.position = m.position;
        self.velocity = m.velocity;
        self.tendon_force = m.tendon_force;
    }
}

impl Limit {
    /// Sets both stops and turns the limits on. Errors if `lower.stop > upper.stop` or a field
    /// is out of range; nothing changes then.
    pub fn set_limits(&mut self, lower: SingleLimit, upper: SingleLimit) -> KeaResult<()> {
        lower.validate("lower")?;
        upper.validate("upper")?;
        if lower.stop > upper.stop {
            return Err(KeaError::OutOfRange {
                arg: "lower.stop",
                value: format!("{} > upper.stop {}", lower.stop, upper.stop),
                expected: "lower.stop must be <= upper.stop",
            });
        }
        self.lower = lower;
        self.upper = upper;
        self.limited = true;
        Ok(())
    }
    /// Turns the limits off (the stops are kept).
    pub fn clear_limits(&mut self) {
        self.limited = false;
    }
    /// Sets a force-limited motor (the guide's `MdtLimitSetLimitedForceMotor`).
    pub fn set_motor(&mut self, desired_velocity: Real, max_force: Real) -> KeaResult<()> {
        check_finite("desired_velocity", desired_velocity)?;
        check_non_negative("max_force", max_force)?;
        self.motor = Some(Motor {
            desired_velocity,
            max_force,
        });
        Ok(())
    }
    /// Turns the motor off.
    pub fn clear_motor(&mut self) {
        self.motor = None;
    }
    /// Sets the coordinate's armature, damping and friction. Errors, changing nothing, if a
    /// field is negative or not finite.
    pub fn set_dynamics(&mut self, dynamics: JointDynamics) -> KeaResult<()> {
        dynamics.validate()?;
        self.dynamics = dynamics;
        Ok(())
    }
    /// The coordinate's armature, damping and friction.
    #[must_use]
    pub fn dynamics(&self) -> JointDynamics {
        self.dynamics
    }
    /// Sets (or with `None` removes) the actuator. Errors, changing nothing, on a bad number.
    pub fn set_actuator(&mut self, actuator: Option<Actuator>) -> KeaResult<()> {
        if let Some(a) = &actuator {
            a.validate()?;
        }
        self.actuator = actuator;
        Ok(())
    }
    /// The actuator, if any.
    #[must_use]
    pub fn actuator(&self) -> Option<Actuator> {
        self.actuator
    }
    /// Whether the stops are active.
    #[must_use]
    pub fn is_limited(&self) -> bool {
        self.limited
    }
    /// The lower stop.
    #[must_use]
    pub fn lower(&self) -> &SingleLimit {
        &self.lower
    }
    /// The upper stop.
    #[must_use]
    pub fn upper(&self) -> &SingleLimit {
        &self.upper
    }
    /// The motor, if on.
    #[must_use]
    pub fn motor(&self) -> Option<Motor> {
        self.motor
    }
    /// The coordinate after the last step (rad or m).
    #[must_use]
    pub fn position(&self) -> Real {
        self.position
    }
    /// Its rate after the last step (rad/s or m/s).
    #[must_use]
    pub fn velocity(&self) -> Real {
        self.velocity
    }
    /// How far beyond a stop the coordinate is: positive beyond the upper stop, negative beyond
    /// the lower, 0 between them or with limits off.
    #[must_use]
    pub fn overshoot(&self) -> Real {
        if !self.limited {
            0.0
        } else if self.position > self.upper.stop {
            self.position - self.upper.stop
        } else if self.position < self.lower.stop {
            self.position - self.lower.stop
        } else {
            0.0
        }
    }
    /// Whether the coordinate is at (or beyond) a stop, within `tolerance`.
    #[must_use]
    pub fn is_at_limit(&self, tolerance: Real) -> bool {
        self.limited
            && (self.position >= self.upper.stop - tolerance
                || self.position <= self.lower.stop + tolerance)
    }

    /// The joint dynamics' and the actuator's rows (see the module docs) for the coordinate
    /// `(p, v, j)`: position, rate and Jacobian.
    fn write_drive_rows(
        &self,
        (p, v, j): (Real, Real, [Jacobian; 2]),
        dt: Real,
        out: &mut RowWriter<'_>,
    ) {
        let JointDynamics {
            armature: a,
            damping: d,
            stiffness: k,
            rest,
            friction,
            ..
        } = self.dynamics;
        if !self.dynamics.is_zero() {
            let m = a + dt * d + dt * dt * k;
            if m > 0.0 {
                let mut row = Row::new(j[0], j[1])
                    .with_target_velocity(a * v / m)
                    .with_error(p - rest)
                    .with_gamma(dt * dt * k / m);
                row.softness = Some(1.0 / m);
                out.push(row);
            }
            if friction > 0.0 {
                let mut row = Row::new(j[0], j[1])
                    .with_bounds(-friction, friction)
                    .with_gamma(0.0);
                row.softness = Some(RIGID);
                out.push(row);
            }
        }
        if self.tendon_force != 0.0 {
            let f = self.tendon_force;
            let mut row = Row::new(j[0], j[1]).with_bounds(f, f).with_gamma(0.0);
            row.softness = Some(RIGID);
            out.push(row);
        }
        match self.actuator {
            None => {}
            Some(Actuator::Force(f)) => {
                let mut row = Row::new(j[0], j[1]).with_bounds(f, f).with_gamma(0.0);
                row.softness = Some(RIGID);
                out.push(row);
            }
            Some(Actuator::Servo {
                position,
                velocity,
                stiffness,
                damping,
                max_force,
            }) => {
                if let Some(soft) = Softness::from_spring(stiffness, damping, dt) {
                    let error = if stiffness > 0.0 { p - position } else { 0.0 };
                    out.push(
                        Row::new(j[0], j[1])
                            .with_error(error)
                            .with_target_velocity(velocity)
                            .with_bounds(-max_force, max_force)
                            .with_softness(soft),
                    );
                }
            }
        }
    }

    /// The force the coordinate's fixed tendons put on it this step (maximal paths).
    #[must_use]
    pub fn tendon_force(&self) -> Real {
        self.tendon_force
    }

    pub(crate) fn set_tendon_force(&mut self, force: Real) {
        self.tendon_force = force;
    }

    pub(crate) fn record(&mut self, position: Real, velocity: Real) {
        self.position = position;
        self.velocity = velocity;
    }

    /// Writes the motor and stop rows for coordinate `p` with rate `v` and Jacobian `j`.
    pub fn write_rows(
        &self,
        p: Real,
        v: Real,
        j: [Jacobian; 2],
        dt: Real,
        out: &mut RowWriter<'_>,
    ) {
        self.write_drive_rows((p, v, j), dt, out);
        if let Some(m) = self.motor {
            let mut row = Row::new(j[0], j[1])
                .with_target_velocity(m.desired_velocity)
                .with_bounds(-m.max_force, m.max_force)
                .with_gamma(0.0);
            row.softness = Some(RIGID);
            out.push(row);
        }
        if !self.limited {
            return;
        }
        let neg = |j: Jacobian| Jacobian::new(-j.linear, -j.angular);
        // Lower stop: the gap p − lo closes at −v; upper: hi − p closes at v.
        for (stop, gap, closing, jac) in [
            (&self.lower, p - self.lower.stop, -v, j),
            (&self.upper, self.upper.stop - p, v, [neg(j[0]), neg(j[1])]),
        ] {
            let margin = if stop.is_hard() { STOP_MARGIN } else { 1.0e-6 };
            if gap > closing.max(0.0) * dt * 1.5 + margin {
                continue; // not reachable this step, with a margin for impacts within it
            }
            if !stop.is_hard() && gap > 0.0 {
                continue; // a spring stop pushes only once compressed
            }
            let mut row = Row::new(jac[0], jac[1])
                .with_error(gap)
                .with_bounds(0.0, Real::INFINITY);
            if stop.is_hard() {
                row.softness = Some(RIGID);
                if gap > 0.0 {
                    row.gamma = Some(1.0); // close the gap exactly, no more
                } else if gap < 0.0 && stop.recovery_speed.is_finite() {
                    let cap = stop.recovery_speed * dt / -gap;
                    if cap < STOP_RECOVERY_GAMMA {
                        row.gamma = Some(cap);
                    }
                }
                if stop.restitution > 0.0 && closing > BOUNCE_MIN_SPEED && closing * dt >= gap {
                    row.c = stop.restitution * closing;
                    row.bounce = true;
                    row.xi = 0.0;
                    row.gamma = Some(0.0);
                }
            } else if let Some(s) = Softness::from_spring(stop.stiffness, stop.damping, dt) {
                row = row.with_softness(s);
            }
            out.push(row);
        }
    }
}
