//! Per-body work of a step: free velocities before the solve, the semi-implicit update after it.
//!
//! Orientation. `q⁺ = exp(h ω⁺/2) ⊗ q` is the exact rotation for a constant ω over the step
//! (no first-order quaternion drift). With a fast-spin axis `a` (body frame), the component of ω
//! along `a` is applied as its own exact rotation first, then the rest: a wheel spinning fast on
//! a slowly steering axle keeps its axle exactly (the guide's `fastSpin`).
//!
//! Gyroscopic term. After rotating, ω is re-expressed at the new orientation so that the world
//! angular momentum is what the step produced: `ω ← I_w(q⁺)⁻¹ I_w(q) ω⁺`. For a torque-free body
//! `L = I_w ω` is then constant to round-off (|L| conserved exactly), and the body-frame angular
//! velocity evolves as Euler's equations say, which makes the intermediate-axis flip happen.

use super::{SolverBody, SolverParams};
use crate::math::{from_f64, rotate_by_vector, DVec3, Mat3, Real, Vec3};

/// Per-body scratch: world inverse inertia, free velocities, constraint force accumulators.
#[derive(Debug, Default)]
pub(crate) struct BodyScratch {
    pub(crate) inv_inertia_world: Vec<Mat3>,
    pub(crate) free_linear: Vec<Vec3>,
    pub(crate) free_angular: Vec<Vec3>,
    pub(crate) constraint_force: Vec<DVec3>,
    pub(crate) constraint_torque: Vec<DVec3>,
}

impl BodyScratch {
    pub(crate) fn reserve(&mut self, n: usize) {
        fn r<T>(v: &mut Vec<T>, n: usize) {
            if v.capacity() < n {
                v.reserve(n - v.len());
            }
        }
        r(&mut self.inv_inertia_world, n);
        r(&mut self.free_linear, n);
        r(&mut self.free_angular, n);
        r(&mut self.constraint_force, n);
        r(&mut self.constraint_torque, n);
    }

    pub(crate) fn bytes(&self) -> usize {
        self.inv_inertia_world.capacity() * std::mem::size_of::<Mat3>()
            + (self.free_linear.capacity() + self.free_angular.capacity())
                * std::mem::size_of::<Vec3>()
            + (self.constraint_force.capacity() + self.constraint_torque.capacity()) * 24
    }

    pub(crate) fn bytes_for(n: usize) -> usize {
        n * (std::mem::size_of::<Mat3>() + 2 * std::mem::size_of::<Vec3>() + 48)
    }

    /// Computes world inverse inertia and free (unconstrained) end-of-step velocities.
    pub(crate) fn prepare(&mut self, bodies: &[SolverBody], params: &SolverParams) {
        let h = params.dt;
        self.inv_inertia_world.clear();
        self.free_linear.clear();
        self.free_angular.clear();
        self.constraint_force.clear();
        self.constraint_torque.clear();
        for b in bodies {
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

    /// Applies constraint forces and advances every body by `h`.
    pub(crate) fn integrate(&self, bodies: &mut [SolverBody], h: Real) {
        for (i, b) in bodies.iter_mut().enumerate() {
            let f = from_f64(self.constraint_force[i]);
            let t = from_f64(self.constraint_torque[i]);
            let v_new = self.free_linear[i] + h * b.inv_mass * f;
            let w_step = self.free_angular[i] + h * (self.inv_inertia_world[i] * t);

            let q0 = b.orientation;
            let q1 = match b.fast_spin_axis {
                Some(axis) => {
                    let a = q0 * axis;
                    let spin = a * w_step.dot(a);
                    rotate_by_vector(rotate_by_vector(q0, spin * h), (w_step - spin) * h)
                }
                None => rotate_by_vector(q0, w_step * h),
            };
            let w_new = if b.is_fixed() {
                w_step
            } else {
                // Keep L = I_w ω across the rotation (see module docs).
                let r0 = Mat3::from_quat(q0);
                let r1 = Mat3::from_quat(q1);
                let l = r0 * (b.inertia * (r0.transpose() * w_step));
                r1 * (b.inv_inertia * (r1.transpose() * l))
            };

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
