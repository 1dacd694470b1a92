//! A contact's friction geometry and its rows: the friction centre and directions, and the
//! normal, friction and bounce rows each point writes for the exact path (the iterative path
//! takes the contact whole, `solver/iterative/contacts/`).

use super::{
    Contact, ContactPoint, ContactType, FrictionFrame, FrictionModel, PointForce, BOUNCE_SOFTNESS,
    FRICTION_SOFTNESS_RATIO, FRICTION_STIFFNESS_FACTOR, MAX_CONTACT_POINTS, SLIDING_SPEED,
};
use crate::constraint::{Jacobian, Row, RowContext, RowWriter, Spring};
use crate::math::{orthonormal_basis, Real, Vec3};

impl Contact {
    /// The mean of the points: where the iterative path applies the manifold's friction.
    #[must_use]
    pub fn friction_centre(&self) -> Vec3 {
        let points = self.points();
        points.iter().map(|p| p.position).sum::<Vec3>() / points.len() as Real
    }

    /// The friction centre and each point's offset from it in the tangent plane.
    #[must_use]
    pub(crate) fn friction_frame(&self) -> FrictionFrame {
        let centre = self.friction_centre();
        let mut levers = [Vec3::ZERO; MAX_CONTACT_POINTS];
        let mut spread = 0.0;
        for (lever, p) in levers.iter_mut().zip(self.points()) {
            let d = p.position - centre;
            *lever = d - self.normal * d.dot(self.normal);
            spread += lever.length_squared();
        }
        FrictionFrame {
            centre,
            levers,
            spread,
        }
    }

    /// Point friction forces as the manifold's friction: their sum (applied at the friction
    /// centre) and their twist about the normal there.
    #[must_use]
    pub(crate) fn gather_friction(
        &self,
        frame: &FrictionFrame,
        forces: &[PointForce],
    ) -> (Vec3, Real) {
        let mut force = Vec3::ZERO;
        let mut twist = 0.0;
        for (f, lever) in forces.iter().zip(&frame.levers).take(self.count as usize) {
            force += f.friction;
            twist += lever.cross(f.friction).dot(self.normal);
        }
        (force, twist)
    }

    /// Manifold friction (a force at the friction centre and a twist about the normal)
    /// spread evenly over the points: each point's share. The shares add up to the force,
    /// and their moments about the centre to the twist.
    #[must_use]
    pub(crate) fn spread_friction(
        &self,
        frame: &FrictionFrame,
        force: Vec3,
        twist: Real,
    ) -> [Vec3; MAX_CONTACT_POINTS] {
        let k = self.count as usize;
        let turn = if frame.spread > Real::EPSILON * Real::EPSILON {
            twist / frame.spread
        } else {
            0.0
        };
        let mut out = [Vec3::ZERO; MAX_CONTACT_POINTS];
        for (o, lever) in out.iter_mut().zip(&frame.levers).take(k) {
            *o = force / k as Real + self.normal.cross(*lever) * turn;
        }
        out
    }

    /// Records the primary friction direction the exact path's rows used in a step, so that a
    /// persistent contact keeps the same friction rows at the next one.
    pub fn remember_direction(&mut self, t1: Vec3) {
        if t1.is_finite() && (t1.length() - 1.0).abs() < 1.0e-3 {
            self.last_direction = Some(t1);
        }
    }

    /// The fixed tangent basis `(t₁, t₂)` of the iterative path: the primary direction if set,
    /// else a basis that depends on the normal only (`t₂ = n × t₁`).
    #[must_use]
    pub fn tangent_basis(&self) -> (Vec3, Vec3) {
        let n = self.normal;
        let t1 = self.direction.unwrap_or_else(|| orthonormal_basis(n).0);
        (t1, n.cross(t1))
    }

    /// The exact path's friction directions `(t₁, t₂)` at point `p` (see the module docs).
    #[must_use]
    pub fn friction_directions_at(&self, ctx: &RowContext, p: Vec3) -> (Vec3, Vec3) {
        let n = self.normal;
        let t1 = match self.direction {
            Some(d) => d,
            None => {
                let [b1, b2] = &ctx.bodies;
                let v = b1.free_velocity_at(p) - b2.free_velocity_at(p);
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

    /// The exact path's friction directions at the first point.
    #[must_use]
    pub fn friction_directions(&self, ctx: &RowContext) -> (Vec3, Vec3) {
        self.friction_directions_at(ctx, self.position())
    }

    /// Writes the contact's rows, point by point: normal first, then friction (see the module
    /// docs). Each point's primary friction direction is the linear Jacobian of its second row
    /// for body 1.
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        for p in self.points() {
            self.write_point_rows(p, ctx, out);
        }
    }

    fn write_point_rows(&self, point: &ContactPoint, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        let p = point.position;
        let (r1, r2) = (p - b1.position, p + point.to_second - b2.position);
        let jac = |d: Vec3| {
            [
                Jacobian::new(d, r1.cross(d)),
                Jacobian::new(-d, -r2.cross(d)),
            ]
        };
        let normal_row = out.push(self.normal_row(point, ctx, jac(self.normal)));
        let directions = match self.params.contact_type {
            ContactType::Frictionless => 0,
            ContactType::Friction1D => 1,
            ContactType::Friction2D => 2,
        };
        if directions == 0 {
            return;
        }
        let (t1, t2) = self.friction_directions_at(ctx, p);
        for (k, t) in [t1, t2].into_iter().enumerate().take(directions) {
            out.push(self.friction_row(k, jac(t), normal_row, ctx.contact_spring));
        }
    }

    /// A point's normal row: soft (its own softness or the contact spring) while resting,
    /// rigid across a speculative gap, a bounce row when it strikes fast enough.
    fn normal_row(&self, point: &ContactPoint, ctx: &RowContext, jac: [Jacobian; 2]) -> Row {
        let [b1, b2] = &ctx.bodies;
        let (p, n, prm) = (point.position, self.normal, &self.params);
        let mut normal = Row::new(jac[0], jac[1])
            .with_error(-point.penetration)
            .with_bounds(-prm.max_adhesive_force, Real::INFINITY);
        match prm.softness {
            Some(s) => normal.softness = Some(s),
            None => normal.spring = Some(ctx.contact_spring),
        }
        let gap = -point.penetration;
        if gap > 0.0 {
            // Speculative point: the bodies may close the whole gap this step, no more.
            normal.gamma = Some(1.0);
            if prm.max_adhesive_force == 0.0 {
                // Rigid (up to the bounce rows' regularisation), so that a fast body of any
                // mass stops at the surface: a soft row lets it overshoot by v·h·ε/(1/m + ε).
                normal.softness = Some(BOUNCE_SOFTNESS);
                normal.spring = None;
            }
            // Adhesion still acts across the gap: a held adhesive contact opens slightly
            // under load (softness), and the guide's sticky contacts fail exactly there.
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
            normal.spring = None;
            normal.gamma = Some(0.0);
        }
        normal
    }

    /// A point's friction row along direction `k` (Jacobian `jac`), bounded by its model.
    fn friction_row(&self, k: usize, jac: [Jacobian; 2], normal_row: u16, spring: Spring) -> Row {
        let prm = &self.params;
        let mut row = Row::new(jac[0], jac[1])
            .with_target_velocity(prm.slide[k])
            .with_slip(prm.slip[k]);
        // A friction row has no position error to recover, so softness would make a resting
        // body creep at ε·h·F for ever; it gets about a thousandth of the normal row's
        // softness, just enough to regularise redundant contacts.
        match prm.softness {
            Some(s) => row.softness = Some(s * FRICTION_SOFTNESS_RATIO),
            None => {
                row.spring = Some(Spring::new(
                    spring.hertz * FRICTION_STIFFNESS_FACTOR,
                    spring.damping_ratio,
                ));
            }
        }
        // Friction acts on velocity only: no position error to drive (γ = 0).
        row.gamma = Some(0.0);
        match prm.friction[k] {
            FrictionModel::Infinite => row,
            FrictionModel::Box { max_force } => row.with_bounds(-max_force, max_force),
            FrictionModel::Coulomb { .. } | FrictionModel::StaticKinetic { .. } => {
                let mu = self.coulomb_mu(k).unwrap_or(0.0);
                row.with_friction_link(normal_row, mu)
            }
        }
    }
}
