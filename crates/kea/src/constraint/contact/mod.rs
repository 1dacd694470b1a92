//! Contacts (the guide's `MdtContact`, `MdtBclContact`): a unit normal `n` pointing from body 2
//! towards body 1, shared by one to four points, each with a position and a penetration depth
//! (a contact manifold). The guide's contact is the one-point case, and the single-point
//! accessors ([`Contact::new`], [`Contact::position`], [`Contact::set_penetration`]) keep its
//! API.
//!
//! The iterative path solves contacts as contacts (`solver::iterative::contacts`): one
//! constraint per manifold, a fixed tangent basis, Coulomb friction isotropic in the tangent
//! plane, warm-started from each point's force of the last step. The exact path solves the rows
//! they write ([`Contact::write_rows`]), three per point:
//!
//! * **normal**: `J₁ = (n, r₁×n)`, `J₂ = (−n, −r₂×n)`, `xi = −penetration`, `λ ∈ [−F_adhesive, ∞)`.
//!   A negative penetration is a gap (a speculative point): the row then uses γ = 1, so the
//!   bodies may close exactly the gap in this step and no more, and land without popping.
//!   When the approach speed exceeds the restitution threshold (and the bodies touch this step),
//!   the target velocity is `c = e·v_in` and the row is made nearly rigid for that step (ε ≈ 0,
//!   no error term) so that softness does not eat into the bounce.
//! * **friction** along the primary direction `t₁` and (2D) the secondary `t₂ = n × t₁`
//!   (right-hand rule): `J = (t, r₁×t)`, `(−t, −r₂×t)`, target `c = slide` (conveyor belt
//!   speed of body 1 relative to body 2), slip factor `s` (sliding speed `s·|F|`), bounds by
//!   model: box `±F_max`, Coulomb `±μλₙ` (linked to the normal row), infinite `±∞`.
//!
//! Softness. With no softness of its own ([`ContactParams::softness`]), a contact is the
//! mass-independent spring of the solver's [`crate::SolverParams::contact_spring`]: a 1 g and a
//! 10 t box sink alike (see [`Spring`](crate::constraint::Spring)). Friction rows are [`FRICTION_STIFFNESS_FACTOR`] times
//! stiffer: just soft enough to regularise redundant points, not enough to creep.
//!
//! With no primary direction set, the exact path's `t₁` follows each point's predicted sliding
//! velocity (so its box-shaped friction bound opposes sliding exactly), or a fixed basis of the
//! normal when there is none.

pub use super::contact_params::{ContactParams, ContactType, FrictionModel};
use crate::error::{check_coordinate, check_finite, check_unit, check_vec3, KeaError, KeaResult};
use crate::math::{Real, Vec3};

mod rows;

/// Most points one contact holds (a box face on a face needs four).
pub const MAX_CONTACT_POINTS: usize = 4;

/// Softness of friction rows relative to the contact's own raw softness ε (see
/// [`Contact::write_rows`]).
pub const FRICTION_SOFTNESS_RATIO: Real = 1.0e-3;

/// How much stiffer (in frequency) a friction row is than its contact's [`Spring`](crate::constraint::Spring): about a
/// thousandth of the softness, as [`FRICTION_SOFTNESS_RATIO`] for raw softness.
pub const FRICTION_STIFFNESS_FACTOR: Real = 32.0;

/// Predicted sliding speed, m/s, above which a point with no primary direction aligns the exact
/// path's friction rows with its sliding direction. Below it the direction comes from a fixed
/// basis of the normal, so resting contacts keep the same friction rows from step to step.
pub const SLIDING_SPEED: Real = 1.0e-2;

/// Softness of a bounce row (inverse mass units): small enough that the rebound is exact to
/// ~1e-10 relative for bodies of a gram or more, large enough to keep redundant bounces regular.
pub const BOUNCE_SOFTNESS: Real = 1.0e-10;

/// One point of a contact.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactPoint {
    /// World position, between the two surfaces.
    pub position: Vec3,
    /// Penetration depth, m: positive when the shapes overlap, negative for a gap (a
    /// speculative point, which acts only if the gap closes within the step).
    pub penetration: Real,
    /// Feature id: when a contact's points are replaced, a new point with the id of an old one
    /// inherits its force as the solver's warm start (collision code passes the features that
    /// made the point; any stable numbering works).
    pub id: u32,
    /// Where body 2 holds the point, relative to `position` (where body 1 holds it): zero for
    /// a point both bodies hold at one place. Collision code that keeps each body's lever arm
    /// fixed while a manifold is reused sets it (see [`ContactPoint::held_at`]).
    pub to_second: Vec3,
}

impl ContactPoint {
    /// A point at a world position with a penetration depth and a feature id.
    #[must_use]
    pub const fn new(position: Vec3, penetration: Real, id: u32) -> Self {
        Self {
            position,
            penetration,
            id,
            to_second: Vec3::ZERO,
        }
    }

    /// A point that body 1 holds at `first` and body 2 at `second` (world positions a
    /// fraction of a millimetre to centimetres apart), with a penetration depth along the
    /// normal and a feature id.
    #[must_use]
    pub fn held_at(first: Vec3, second: Vec3, penetration: Real, id: u32) -> Self {
        Self {
            position: first,
            penetration,
            id,
            to_second: second - first,
        }
    }
}

/// A manifold's friction centre and its points' levers about it (see
/// [`Contact::friction_centre`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrictionFrame {
    pub(crate) centre: Vec3,
    /// Each point's offset from the centre in the tangent plane.
    pub(crate) levers: [Vec3; MAX_CONTACT_POINTS],
    /// The sum of the levers' squared lengths.
    pub(crate) spread: Real,
}

/// The force a contact applied at one point in the last step, on body 1 (body 2 gets the
/// opposite).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PointForce {
    /// Normal force, N, along the contact normal (negative only for an adhesive contact).
    pub normal: Real,
    /// Friction force, N, world frame, in the tangent plane.
    pub friction: Vec3,
}

/// A contact between body 1 and body 2 (or the static world): a normal shared by one to four
/// points (see the module docs). Defaults follow the guide's reset table: one point at the
/// origin, normal +y, penetration 0, no primary direction.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Contact {
    normal: Vec3,
    direction: Option<Vec3>,
    params: ContactParams,
    count: u8,
    points: [ContactPoint; MAX_CONTACT_POINTS],
    /// Each point's mean force over the last step (the read-out).
    forces: [PointForce; MAX_CONTACT_POINTS],
    /// Each point's force at the end of the last step (the iterative path's warm start: the
    /// last substep's, without the restitution pass).
    warm: [PointForce; MAX_CONTACT_POINTS],
    /// The primary friction direction of the exact path's rows last step, kept so that a
    /// persistent contact keeps its friction rows from step to step.
    last_direction: Option<Vec3>,
    /// Whether its friction gave way in the last step (static or kinetic coefficient next).
    #[cfg_attr(feature = "serde", serde(default))]
    sliding: bool,
}

impl Default for Contact {
    fn default() -> Self {
        Self {
            normal: Vec3::Y,
            direction: None,
            params: ContactParams::default(),
            count: 1,
            points: [ContactPoint::default(); MAX_CONTACT_POINTS],
            forces: [PointForce::default(); MAX_CONTACT_POINTS],
            warm: [PointForce::default(); MAX_CONTACT_POINTS],
            last_direction: None,
            sliding: false,
        }
    }
}

impl Contact {
    /// A one-point contact at a world point with a unit normal (from body 2 towards body 1)
    /// and a penetration depth (positive when overlapping).
    pub fn new(position: Vec3, normal: Vec3, penetration: Real) -> KeaResult<Self> {
        let mut c = Self::default();
        c.set_position(position)?;
        c.set_normal(normal)?;
        c.set_penetration(penetration)?;
        Ok(c)
    }

    /// A contact of one to [`MAX_CONTACT_POINTS`] points sharing a unit normal (from body 2
    /// towards body 1).
    pub fn with_points(normal: Vec3, points: &[ContactPoint]) -> KeaResult<Self> {
        let mut c = Self::default();
        c.set_normal(normal)?;
        c.set_points(points)?;
        Ok(c)
    }

    /// The position of the first point, world frame.
    #[must_use]
    pub fn position(&self) -> Vec3 {
        self.points[0].position
    }
    /// Unit normal, world frame, from body 2 towards body 1.
    #[must_use]
    pub fn normal(&self) -> Vec3 {
        self.normal
    }
    /// The deepest penetration among the points (the first point's for a one-point contact).
    #[must_use]
    pub fn penetration(&self) -> Real {
        self.points()
            .iter()
            .map(|p| p.penetration)
            .fold(Real::NEG_INFINITY, Real::max)
    }
    /// The points.
    #[must_use]
    pub fn points(&self) -> &[ContactPoint] {
        &self.points[..self.count as usize]
    }
    /// The force at each point in the last step (zero before the first), in point order.
    #[must_use]
    pub fn forces(&self) -> &[PointForce] {
        &self.forces[..self.count as usize]
    }
    /// The total force on body 1 in the last step (normal plus friction, every point), N.
    #[must_use]
    pub fn total_force(&self) -> Vec3 {
        self.forces()
            .iter()
            .map(|f| self.normal * f.normal + f.friction)
            .sum()
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
    /// Sets the position of the first point (world frame).
    pub fn set_position(&mut self, p: Vec3) -> KeaResult<()> {
        self.points[0].position = check_coordinate("position", p)?;
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
    /// Sets the penetration depth of the first point (finite; negative means a gap).
    pub fn set_penetration(&mut self, depth: Real) -> KeaResult<()> {
        self.points[0].penetration = check_finite("penetration", depth)?;
        Ok(())
    }
    /// Replaces the points (one to [`MAX_CONTACT_POINTS`], finite). A new point whose id an
    /// old point had keeps that point's force as its warm start; the others start from zero.
    /// On error nothing changes.
    pub fn set_points(&mut self, points: &[ContactPoint]) -> KeaResult<()> {
        check_points(points)?;
        let same_ids = points.len() == self.count as usize
            && points.iter().zip(self.points()).all(|(p, q)| p.id == q.id);
        if same_ids {
            // The same points moved (a kept manifold): the forces stay where they are.
            self.points[..points.len()].copy_from_slice(points);
            return Ok(());
        }
        let mut forces = [PointForce::default(); MAX_CONTACT_POINTS];
        let mut warm = [PointForce::default(); MAX_CONTACT_POINTS];
        for (i, p) in points.iter().enumerate() {
            if let Some(k) = self.points().iter().position(|old| old.id == p.id) {
                forces[i] = self.forces[k];
                warm[i] = self.warm[k];
            }
        }
        self.points[..points.len()].copy_from_slice(points);
        self.count = points.len() as u8;
        self.forces = forces;
        self.warm = warm;
        Ok(())
    }
    /// Moves a contact: a new normal (unit; from body 2 towards body 1) and new points (as
    /// [`Contact::set_points`]) together. Every argument is checked before either is written:
    /// on error nothing changes. A primary direction no longer perpendicular is cleared.
    pub fn update(&mut self, normal: Vec3, points: &[ContactPoint]) -> KeaResult<()> {
        let normal = check_unit("normal", normal)?;
        check_points(points)?;
        self.set_points(points)?;
        self.set_normal(normal)
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

    /// Records each point's force of a step (solvers call it): the read-out of
    /// [`Contact::forces`], also used as the next step's warm start.
    pub fn set_forces(&mut self, forces: &[PointForce]) {
        let n = forces.len().min(self.count as usize);
        self.forces[..n].copy_from_slice(&forces[..n]);
        self.warm[..n].copy_from_slice(&forces[..n]);
    }

    /// Takes the forces a solver recorded on `solved`, a copy of this contact.
    /// Whether every point's mean and end-of-step force is finite.
    pub(crate) fn forces_finite(&self) -> bool {
        let finite = |f: &PointForce| f.normal.is_finite() && f.friction.is_finite();
        self.forces.iter().chain(&self.warm).all(finite)
    }

    pub(crate) fn take_forces(&mut self, solved: &Contact) {
        self.forces = solved.forces;
        self.warm = solved.warm;
        self.last_direction = solved.last_direction;
        self.sliding = solved.sliding;
    }

    /// Whether the contact's surfaces slid over each other at the end of its last step (their
    /// relative speed in the tangent plane past [`SLIDING_SPEED`]). A sliding contact is
    /// bounded by its kinetic coefficient ([`FrictionModel::StaticKinetic`]), a holding one by
    /// its static coefficient. Tracked for contacts with static and kinetic friction only
    /// (false for the others, which have one coefficient either way).
    #[must_use]
    pub fn is_sliding(&self) -> bool {
        self.sliding
    }

    /// The Coulomb coefficient bounding friction along direction `d` (0 or 1) in the coming
    /// step, `None` when that direction has no Coulomb bound.
    #[must_use]
    pub fn coulomb_mu(&self, d: usize) -> Option<Real> {
        self.params.friction[d.min(1)].coulomb(self.sliding)
    }

    /// After a solve (the solver calls it): whether the surfaces slide, from the relative
    /// velocity of the bodies' points at the friction centre in the tangent plane (`velocity`
    /// gives a world point's velocity on body 1 minus on body 2), past [`SLIDING_SPEED`].
    pub(crate) fn record_sliding(&mut self, velocity: impl Fn(Vec3) -> Vec3) {
        let two_coefficients = |m: &FrictionModel| matches!(m, FrictionModel::StaticKinetic { .. });
        if !self.params.friction.iter().any(two_coefficients) {
            // One coefficient either way: nothing to track (the step's hot path).
            self.sliding = false;
            return;
        }
        let v = velocity(self.friction_centre());
        let tangential = v - self.normal * v.dot(self.normal);
        self.sliding = self.params.contact_type != ContactType::Frictionless
            && tangential.length() > SLIDING_SPEED;
    }

    /// Records one point's mean force over a step and its force at the step's end (the warm
    /// start of the next step; the two differ by a bounce, for instance).
    pub fn set_point_force(&mut self, point: usize, mean: PointForce, end: PointForce) {
        if point < self.count as usize {
            self.forces[point] = mean;
            self.warm[point] = end;
        }
    }

    /// Each point's force at the end of the last step: the warm start of the next one.
    #[must_use]
    pub fn warm_forces(&self) -> &[PointForce] {
        &self.warm[..self.count as usize]
    }
}

/// Refuses an empty or overlong point list, or a point with a non-finite field, naming it.
fn check_points(points: &[ContactPoint]) -> KeaResult<()> {
    if points.is_empty() || points.len() > MAX_CONTACT_POINTS {
        return Err(KeaError::OutOfRange {
            arg: "points",
            value: points.len().to_string(),
            expected: "a contact has 1 to 4 points",
        });
    }
    for p in points {
        check_coordinate("points[].position", p.position)?;
        check_vec3("points[].to_second", p.to_second)?;
        check_finite("points[].penetration", p.penetration)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_refused_update_changes_nothing_and_an_accepted_one_moves_both() {
        let pts = [ContactPoint::new(Vec3::ZERO, 0.01, 1)];
        let mut c = Contact::with_points(Vec3::Y, &pts).unwrap();
        c.set_direction(Some(Vec3::X)).unwrap();
        let before = c;
        let moved = [ContactPoint::new(Vec3::new(1.0, 2.0, 3.0), 0.02, 2)];
        // A normal off unit length, with good points: refused, naming it, nothing moved.
        let e = c.update(Vec3::new(0.0, 1.5, 0.0), &moved).unwrap_err();
        assert!(e.to_string().contains("normal"), "{e}");
        assert_eq!(format!("{c:?}"), format!("{before:?}"));
        // A good normal with a bad point: the same.
        let bad = [ContactPoint::new(Vec3::splat(Real::NAN), 0.0, 3)];
        let e = c.update(Vec3::Z, &bad).unwrap_err();
        assert!(e.to_string().contains("points"), "{e}");
        assert_eq!(format!("{c:?}"), format!("{before:?}"));
        // Both good: both written; the direction, no longer perpendicular, is cleared.
        c.update(Vec3::X, &moved).unwrap();
        assert_eq!(c.normal(), Vec3::X);
        assert_eq!(c.points(), &moved);
        assert_eq!(c.direction(), None);
    }

    #[test]
    fn replacing_points_keeps_the_force_of_each_surviving_id() {
        let pts = [
            ContactPoint::new(Vec3::ZERO, 0.01, 7),
            ContactPoint::new(Vec3::X, 0.02, 9),
        ];
        let mut c = Contact::with_points(Vec3::Y, &pts).unwrap();
        c.set_forces(&[
            PointForce {
                normal: 3.0,
                friction: Vec3::X,
            },
            PointForce {
                normal: 5.0,
                friction: Vec3::Z,
            },
        ]);
        c.set_points(&[
            ContactPoint::new(Vec3::Z, 0.0, 9),
            ContactPoint::new(Vec3::Z, 0.0, 4),
        ])
        .unwrap();
        assert_eq!(c.forces()[0].normal, 5.0);
        assert_eq!(c.forces()[1], PointForce::default());
        assert_eq!(c.penetration(), 0.0);
        // Five points, or a NaN, are refused and change nothing.
        let five = [ContactPoint::default(); 5];
        assert!(c.set_points(&five).is_err());
        let bad = [ContactPoint::new(Vec3::NAN, 0.0, 1)];
        assert!(c.set_points(&bad).is_err());
        assert_eq!(c.points().len(), 2);
    }
}
