//! Per-body work of a step: free velocities before the solve, the semi-implicit update after it.
//!
//! Orientation and the gyroscopic term. After the constraint solve, the step has produced the
//! world angular momentum `L = I_w(q) ω⁺`. The orientation then follows the torque-free motion
//! with that `L` for the step, integrated by the symplectic splitting of Dullweber, Leimkuhler
//! and McLachlan (1997): in the principal frame the free body's energy is
//! `Σ L_k²/(2 I_k)`, and each term's flow is an exact rotation about principal axis `k` by
//! `τ·L_k/I_k`; the Strang composition `X(h/2) Y(h/2) Z(h) Y(h/2) X(h/2)` is second order and
//! time-reversible. Every sub-step is a rotation, so world `L` and `|L|` are conserved to
//! round-off, the energy error stays bounded (no drift: an explicit `ω × Iω` torque gains
//! energy), and the intermediate-axis flip happens. The new angular velocity is
//! `ω = I_w(q⁺)⁻¹ L`. An isotropic body rotates by the exact `exp(h ω)` directly.
//!
//! Bodies in iterative islands are the exception: they turn by `exp(hs ω)` with ω kept, their
//! gyroscopic torque taken implicitly in the velocities each substep ([`gyroscopic_step`];
//! see `iterative::bodies`), because carrying `L` through the rotation hands their joints a
//! sideways spin every substep.
//!
//! Fast spin. With a fast-spin axis `a` (body frame), the component of ω along `a` is applied
//! as its own exact finite rotation first and the rest of ω after it (the guide's `fastSpin`:
//! a wheel keeps its axle exactly however fast it spins); `ω` is then re-expressed at the new
//! orientation with `L` unchanged.

use super::{reserve, SolverBody, SolverParams};
use crate::math::{
    from_f64, rotate_by_vector, symmetric_eigen, to_f64, wide, DVec3, Mat3, Quat, Real, Vec3,
};
use glam::{DMat3, DQuat};

/// Per-body scratch: world inverse inertia, free velocities, constraint force accumulators.
#[derive(Debug, Default, Clone)]
pub(crate) struct BodyScratch {
    pub(crate) inv_inertia_world: Vec<Mat3>,
    pub(crate) free_linear: Vec<Vec3>,
    pub(crate) free_angular: Vec<Vec3>,
    pub(crate) constraint_force: Vec<DVec3>,
    pub(crate) constraint_torque: Vec<DVec3>,
    /// Bodies already advanced by the iterative path this step.
    pub(crate) integrated: Vec<bool>,
    /// Each body's rotation rule this step.
    pub(crate) rotation: Vec<Rotation>,
    /// Per solver body, the last inertia seen and its principal frame and moments: inertia
    /// rarely changes, and its eigen-decomposition is a tenth of a small world's step.
    principal: Vec<(Mat3, Quat, Vec3)>,
}

impl BodyScratch {
    pub(crate) fn reserve(&mut self, n: usize) {
        reserve(&mut self.inv_inertia_world, n);
        reserve(&mut self.free_linear, n);
        reserve(&mut self.free_angular, n);
        reserve(&mut self.constraint_force, n);
        reserve(&mut self.constraint_torque, n);
        reserve(&mut self.integrated, n);
        reserve(&mut self.rotation, n);
        reserve(&mut self.principal, n);
    }

    pub(crate) fn bytes(&self) -> usize {
        self.inv_inertia_world.capacity() * std::mem::size_of::<Mat3>()
            + (self.free_linear.capacity() + self.free_angular.capacity())
                * std::mem::size_of::<Vec3>()
            + (self.constraint_force.capacity() + self.constraint_torque.capacity()) * 24
            + self.integrated.capacity()
            + self.rotation.capacity() * std::mem::size_of::<Rotation>()
            + self.principal.capacity() * std::mem::size_of::<(Mat3, Quat, Vec3)>()
    }

    pub(crate) fn bytes_for(n: usize) -> usize {
        n * (std::mem::size_of::<Mat3>()
            + 2 * std::mem::size_of::<Vec3>()
            + 49
            + std::mem::size_of::<Rotation>()
            + std::mem::size_of::<(Mat3, Quat, Vec3)>())
    }

    /// Computes world inverse inertia and free (unconstrained) end-of-step velocities.
    pub(crate) fn prepare(&mut self, bodies: &[SolverBody], params: &SolverParams) {
        let h = params.dt;
        self.inv_inertia_world.clear();
        self.free_linear.clear();
        self.free_angular.clear();
        self.constraint_force.clear();
        self.constraint_torque.clear();
        self.integrated.clear();
        self.integrated.resize(bodies.len(), false);
        self.rotation.clear();
        for (i, b) in bodies.iter().enumerate() {
            let rule = Rotation::of(b, |inertia| self.principal_frame(i, inertia));
            self.rotation.push(rule);
            let r = Mat3::from_quat(b.orientation);
            let inv_iw = r * b.inv_inertia * r.transpose();
            let mut v = b.linear_velocity;
            let mut w = b.angular_velocity;
            if b.linear_damping > 0.0 {
                v /= 1.0 + h * b.linear_damping * b.inv_mass;
            }
            if b.angular_damping > 0.0 && b.inv_inertia != Mat3::ZERO {
                // (I_w + h d)⁻¹ I_w ω: implicit, unconditionally stable.
                let iw = r * b.inertia * r.transpose();
                let damped = iw + Mat3::from_diagonal(Vec3::splat(h * b.angular_damping));
                w = damped.inverse() * (iw * w);
            }
            let g = if b.inv_mass > 0.0 {
                params.gravity
            } else {
                Vec3::ZERO
            };
            self.free_linear.push(v + h * (g + b.inv_mass * b.force));
            self.free_angular.push(w + h * (inv_iw * b.torque));
            self.inv_inertia_world.push(inv_iw);
            self.constraint_force.push(DVec3::ZERO);
            self.constraint_torque.push(DVec3::ZERO);
        }
    }

    /// Body `i`'s principal frame and moments for `inertia`: remembered from the last step
    /// while the inertia is the same bits, so the answer is the one computed afresh.
    fn principal_frame(&mut self, i: usize, inertia: Mat3) -> (Quat, Vec3) {
        if let Some(&(seen, p, d)) = self.principal.get(i) {
            if seen.to_cols_array().map(Real::to_bits) == inertia.to_cols_array().map(Real::to_bits)
            {
                return (p, d);
            }
        }
        let (p, d) = symmetric_eigen(inertia);
        if i < self.principal.len() {
            self.principal[i] = (inertia, p, d);
        } else if i == self.principal.len() {
            self.principal.push((inertia, p, d));
        }
        (p, d)
    }

    /// Applies constraint forces and advances every body by `h`.
    pub(crate) fn integrate(&self, bodies: &mut [SolverBody], h: Real) {
        for (i, b) in bodies.iter_mut().enumerate() {
            if self.integrated[i] {
                continue;
            }
            let f = from_f64(self.constraint_force[i]);
            let t = from_f64(self.constraint_torque[i]);
            let v_new = self.free_linear[i] + h * b.inv_mass * f;
            let w_step = self.free_angular[i] + h * (self.inv_inertia_world[i] * t);

            let (q1, w_new) = advance_rotation(b, self.rotation[i], b.orientation, w_step, h);

            b.linear_acceleration = (v_new - b.linear_velocity) / h;
            b.angular_acceleration = (w_new - b.angular_velocity) / h;
            b.position += h * v_new;
            b.orientation = q1;
            b.linear_velocity = v_new;
            b.angular_velocity = w_new;
            b.constraint_force = f;
            b.constraint_torque = t;
        }
    }
}

/// How a body's orientation advances, decided once per step (the inertia's principal frame is
/// found then, not at every substep).
#[derive(Debug, Clone, Copy)]
pub(crate) enum Rotation {
    /// A fixed or kinematic body: it just turns at its angular velocity.
    Kinematic,
    /// Isotropic inertia: the exact rotation `exp(h ω)`, ω unchanged (no gyroscopic term).
    Isotropic,
    /// General inertia: torque-free motion keeping `L` (module docs), principal frame and
    /// moments in `f64`.
    Free { principal: DQuat, moments: DVec3 },
    /// A fast-spin axis: the spin as its own exact rotation, then the rest.
    FastSpin,
}

impl Rotation {
    /// The rotation rule of body `b`, with `principal` giving its inertia's principal frame
    /// and moments (as [`symmetric_eigen`] does).
    fn of(b: &SolverBody, principal: impl FnOnce(Mat3) -> (Quat, Vec3)) -> Self {
        if b.is_fixed() {
            return Rotation::Kinematic;
        }
        if b.fast_spin_axis.is_some() {
            return Rotation::FastSpin;
        }
        let (p, d) = principal(b.inertia);
        let d = to_f64(d);
        let isotropic = (d.x - d.y).abs() <= 1e-6 * d.x && (d.x - d.z).abs() <= 1e-6 * d.x;
        if isotropic {
            Rotation::Isotropic
        } else {
            Rotation::Free {
                principal: to_dquat(p),
                moments: d,
            }
        }
    }
}

/// New orientation and angular velocity of body `b` (for its inertia and fast-spin axis), now
/// at orientation `q` turning at `w_step`, after `h`: a fixed (kinematic) body just rotates; a
/// body with mass keeps its angular momentum (module docs).
pub(crate) fn advance_rotation(
    b: &SolverBody,
    rule: Rotation,
    q: Quat,
    w_step: Vec3,
    h: Real,
) -> (Quat, Vec3) {
    match rule {
        Rotation::Kinematic | Rotation::Isotropic => (rotate_by_vector(q, w_step * h), w_step),
        Rotation::FastSpin | Rotation::Free { .. } => rotate_free(b, rule, q, w_step, h),
    }
}

/// New orientation and angular velocity of a body with mass, keeping `L = I_w ω_step`.
/// Computed in `f64` whatever `Real` is, so that `f32` bodies keep `|L|` to ~1e-6 over
/// thousands of steps.
fn rotate_free(b: &SolverBody, rule: Rotation, q: Quat, w_step: Vec3, h: Real) -> (Quat, Vec3) {
    let h = wide(h);
    let q0 = to_dquat(q);
    let w = to_f64(w_step);
    let inertia = to_dmat3(&b.inertia);
    // World angular momentum the step produced.
    let l_world = q0 * (inertia * (q0.inverse() * w));
    let q1 = match (rule, b.fast_spin_axis) {
        (Rotation::Free { principal, moments }, _) => {
            split_rotation(q0 * principal, l_world, moments, h) * principal.inverse()
        }
        (_, Some(axis)) => {
            let a = q0 * to_f64(axis);
            let spin = a * w.dot(a);
            rotate_by_dvector(rotate_by_dvector(q0, spin * h), (w - spin) * h)
        }
        _ => rotate_by_dvector(q0, w * h),
    }
    .normalize();
    let inv_inertia = to_dmat3(&b.inv_inertia);
    let mut w_new = q1 * (inv_inertia * (q1.inverse() * l_world));
    if let Some(axis) = b.fast_spin_axis {
        // The spin rate is carried over exactly: no torque acts about the axle while the body
        // turns, and read from `L` at the new pose it would take up the rotation's
        // second-order error about the slow axes (a gyroscope's spin drifted by percents).
        let (a0, a1) = (q0 * to_f64(axis), q1 * to_f64(axis));
        w_new += a1 * (w.dot(a0) - w_new.dot(a1));
    }
    (from_dquat(q1), from_f64(w_new))
}

/// Angular velocity after `h` of a body of world inertia `iw` turning at `w` under its
/// gyroscopic torque alone: one Newton step of `I(ω⁺ − ω) + h ω⁺ × I ω⁺ = 0` from `ω⁺ = ω`
/// (implicit, so it cannot feed energy into a fast spin; Catto 2015), in `f64`.
pub(crate) fn gyroscopic_step(iw: &Mat3, w: Vec3, h: Real) -> Vec3 {
    let (i, w0, h) = (to_dmat3(iw), to_f64(w), wide(h));
    let l = i * w0;
    let skew = |v: DVec3| {
        DMat3::from_cols(
            DVec3::new(0.0, v.z, -v.y),
            DVec3::new(-v.z, 0.0, v.x),
            DVec3::new(v.y, -v.x, 0.0),
        )
    };
    let jacobian = i + h * (skew(w0) * i - skew(l));
    let det = jacobian.determinant();
    if !det.is_finite() || det.abs() <= 1.0e-300 {
        return w;
    }
    from_f64(w0 - jacobian.inverse() * (h * w0.cross(l)))
}

/// Torque-free rotation over `h` of a body whose principal frame is at `qp` with principal
/// moments `d`, carrying world angular momentum `l` (see the module docs).
fn split_rotation(mut qp: DQuat, l: DVec3, d: DVec3, h: f64) -> DQuat {
    let mut lb = qp.inverse() * l;
    let axes = [DVec3::X, DVec3::Y, DVec3::Z];
    for (k, tau) in [
        (0usize, 0.5 * h),
        (1, 0.5 * h),
        (2, h),
        (1, 0.5 * h),
        (0, 0.5 * h),
    ] {
        let theta = tau * lb[k] / d[k];
        let r = DQuat::from_axis_angle(axes[k], theta);
        qp *= r;
        lb = r.inverse() * lb;
    }
    qp
}

fn rotate_by_dvector(q: DQuat, phi: DVec3) -> DQuat {
    let angle = phi.length();
    if angle < 1.0e-14 {
        return (DQuat::from_xyzw(0.5 * phi.x, 0.5 * phi.y, 0.5 * phi.z, 1.0) * q).normalize();
    }
    (DQuat::from_axis_angle(phi / angle, angle) * q).normalize()
}

#[allow(clippy::unnecessary_cast)]
fn to_dquat(q: Quat) -> DQuat {
    DQuat::from_xyzw(q.x as f64, q.y as f64, q.z as f64, q.w as f64)
}

#[allow(clippy::unnecessary_cast)]
fn from_dquat(q: DQuat) -> Quat {
    Quat::from_xyzw(q.x as Real, q.y as Real, q.z as Real, q.w as Real)
}

fn to_dmat3(m: &Mat3) -> DMat3 {
    DMat3::from_cols(to_f64(m.x_axis), to_f64(m.y_axis), to_f64(m.z_axis))
}
