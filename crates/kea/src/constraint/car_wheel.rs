//! Car wheel joint (the guide's `MdtCarWheel`, `MdtBclCarWheel`): body 1 is the chassis, body 2
//! the wheel, attached at the wheel's centre.
//!
//! Rows, with `s` the steering axis (fixed in the chassis) and `u` the wheel's axle (fixed in the
//! wheel):
//! * the wheel centre stays on the steering line through the attachment point (2 rows, for the
//!   two directions ⊥ s fixed in the chassis);
//! * the axle stays perpendicular to the steering axis (1 row, `C = u·s`);
//! * **suspension** along `s`: a spring of stiffness `k` and damping `d` about the rest
//!   position (a soft row, [`crate::Softness::from_spring`], so the static deflection is
//!   `m g/k` and it rings at `√(k/m)` whatever the step), and travel limits as stops whose
//!   softness is the guide's `slsoft` ([`Limit`]);
//! * **steering** about `s`: locked at 0 (a rigid row), or a [`Limit`] with motor and stops;
//! * **drive** about the axle: a [`Limit`] motor (and brake).

use super::joint::{perpendiculars, rate, relative_point_jacobian};
use super::{Jacobian, Limit, Row, RowContext, RowWriter, Softness};
use crate::math::{Real, Vec3};

/// A car wheel: chassis (body 1) to wheel (body 2).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CarWheel {
    /// Attachment point (the wheel centre at rest) in the chassis frame.
    pub local_anchor1: Vec3,
    /// Steering axis in the chassis frame (the suspension also slides along it).
    pub local_steering1: Vec3,
    /// Axle direction in the chassis frame at zero steering (the steering reference).
    pub local_axle1: Vec3,
    /// Axle direction in the wheel frame.
    pub local_axle2: Vec3,
    /// Suspension stiffness, N/m (> 0).
    pub suspension_stiffness: Real,
    /// Suspension damping, N·s/m (≥ 0).
    pub suspension_damping: Real,
    /// Steering locked at zero (the guide's `slock`).
    pub steering_locked: bool,
    pub(crate) suspension: Limit,
    pub(crate) steering: Limit,
    pub(crate) drive: Limit,
}

impl CarWheel {
    /// A wheel attached at its centre, with world `steering_axis` and world `axle` (⊥), a
    /// suspension of stiffness `k` and damping `d`, steering locked.
    #[must_use]
    pub fn new(ctx: &RowContext, steering_axis: Vec3, axle: Vec3, k: Real, d: Real) -> Self {
        let [b1, b2] = &ctx.bodies;
        let q1 = b1.orientation.inverse();
        Self {
            local_anchor1: q1 * (b2.position - b1.position),
            local_steering1: q1 * steering_axis,
            local_axle1: q1 * axle,
            local_axle2: b2.orientation.inverse() * axle,
            suspension_stiffness: k,
            suspension_damping: d,
            steering_locked: true,
            suspension: Limit::default(),
            steering: Limit::default(),
            drive: Limit::default(),
        }
    }
    /// Suspension travel limits (stops on the suspension coordinate, m; positive along the
    /// steering axis).
    pub fn suspension_limit_mut(&mut self) -> &mut Limit {
        &mut self.suspension
    }
    /// Steering limits and motor (unlock the steering first).
    pub fn steering_limit_mut(&mut self) -> &mut Limit {
        &mut self.steering
    }
    /// Drive motor and brake about the axle.
    pub fn drive_mut(&mut self) -> &mut Limit {
        &mut self.drive
    }
    /// Suspension coordinate after the last step: how far the wheel centre sits from its rest
    /// point along the steering axis, m (positive: compressed, for an axis pointing up).
    #[must_use]
    pub fn suspension_position(&self) -> Real {
        self.suspension.position()
    }
    /// Steering angle after the last step (rad).
    #[must_use]
    pub fn steering_angle(&self) -> Real {
        self.steering.position()
    }
    /// Wheel spin rate relative to the chassis after the last step (rad/s).
    #[must_use]
    pub fn spin_rate(&self) -> Real {
        self.drive.velocity()
    }

    /// Coordinates: (suspension, steering angle, spin) values, rates and Jacobians.
    fn coordinates(&self, ctx: &RowContext) -> [(Real, Real, [Jacobian; 2]); 3] {
        let [b1, b2] = &ctx.bodies;
        let s = b1.vector_to_world(self.local_steering1);
        let a1 = b1.point_to_world(self.local_anchor1);
        // Suspension d = (x₂ − a₁)·s, s fixed in the chassis.
        let [jw, jc] = relative_point_jacobian(b2, b1, b2.position, s);
        let j_s = [jc, jw];
        let d = (b2.position - a1).dot(s);
        // Steering: the axle's direction about s, from the chassis's zero-steering axle.
        let u = b2.vector_to_world(self.local_axle2);
        let r = b1.vector_to_world(self.local_axle1);
        let up = (u - s * u.dot(s)).normalize_or_zero();
        let steer = r.cross(up).dot(s).atan2(r.dot(up));
        let j_st = [Jacobian::new(Vec3::ZERO, -s), Jacobian::new(Vec3::ZERO, s)];
        // Spin about the axle (relative to the chassis).
        let j_sp = [Jacobian::new(Vec3::ZERO, -u), Jacobian::new(Vec3::ZERO, u)];
        [
            (d, rate(&j_s, b1, b2), j_s),
            (steer, rate(&j_st, b1, b2), j_st),
            (0.0, rate(&j_sp, b1, b2), j_sp),
        ]
    }

    /// Writes the wheel's rows.
    pub fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let [b1, b2] = &ctx.bodies;
        let s = b1.vector_to_world(self.local_steering1);
        let a1 = b1.point_to_world(self.local_anchor1);
        // Wheel centre on the steering line: rows for (x₂ − a₁)·p, p ⊥ s fixed in the chassis.
        for p in perpendiculars(s) {
            let [jw, jc] = relative_point_jacobian(b2, b1, b2.position, p);
            out.push(Row::new(jc, jw).with_error((b2.position - a1).dot(p)));
        }
        // Axle ⊥ steering axis: C = u·s.
        let u = b2.vector_to_world(self.local_axle2);
        let c = u.cross(s); // d(u·s)/dt = (ω₂ × u)·s + u·(ω₁ × s) = ω₂·(u × s) − ω₁·(u × s)
        out.push(
            Row::new(Jacobian::new(Vec3::ZERO, -c), Jacobian::new(Vec3::ZERO, c))
                .with_error(u.dot(s)),
        );
        let [(d, dv, js), (steer, steer_v, jst), (_, spin_v, jsp)] = self.coordinates(ctx);
        // Suspension spring about its rest position (d = 0).
        if let Some(soft) =
            Softness::from_spring(self.suspension_stiffness, self.suspension_damping, ctx.dt)
        {
            out.push(Row::new(js[0], js[1]).with_error(d).with_softness(soft));
        }
        self.suspension.write_rows(d, dv, js, ctx.dt, out);
        if self.steering_locked {
            out.push(Row::new(jst[0], jst[1]).with_error(steer));
        } else {
            self.steering.write_rows(steer, steer_v, jst, ctx.dt, out);
        }
        self.drive.write_rows(0.0, spin_v, jsp, ctx.dt, out);
    }

    pub(crate) fn commit(&mut self, ctx: &RowContext) {
        let [(d, dv, _), (steer, sv, _), (_, spin, _)] = self.coordinates(ctx);
        self.suspension.record(d, dv);
        self.steering.record(steer, sv);
        let p = self.drive.position();
        self.drive.record(p + spin * ctx.dt, spin);
    }
}
