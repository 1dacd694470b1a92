//! The iterative path's per-substep integration of its bodies: velocities (damping, gravity and
//! applied forces, the implicit gyroscopic step; the synchronised islands' half kicks) and
//! positions (each body moved by `hs` at its velocity, turning by its rotation rule), and the
//! world inertia of jointed bodies turned with them.

use super::{BodyDelta, BodyStates, BodyVel, Damping, NONE};
use crate::math::{Mat3, Quat, Real, Vec3};
use crate::solver::integrate::{advance_rotation, gyroscopic_step, Rotation};
use crate::solver::SolverBody;

impl BodyStates {
    /// Adds `scale` times a substep's forcing to every synchronised body that can be pushed
    /// (−½ after the first substep's full kick, +½ at the step's end: the half kicks).
    pub(crate) fn kick_synchronised(&mut self, scale: Real) {
        for l in 0..self.vel.len() {
            if self.synchronised[l] && self.writable[l] {
                let f = self.forcing[l];
                let vel = &mut self.vel[l];
                vel.v += f.v * scale;
                vel.w += f.w * scale;
            }
        }
    }

    /// Substep stage 1: damping, gravity and applied forces on every body that can be pushed.
    pub(crate) fn integrate_velocities(&mut self, hs: Real) {
        let step = |(vel, ((forcing, damping), writable)): VelocityChunk<'_>| {
            for (vel, ((f, d), &writable)) in vel
                .iter_mut()
                .zip(forcing.iter().zip(damping).zip(writable))
            {
                if !writable {
                    continue;
                }
                let mut w = vel.w;
                if let Some(a) = d.angular {
                    w = a * w;
                }
                if let Some(iw) = &d.gyroscopic {
                    w = gyroscopic_step(iw, w, hs);
                }
                vel.v = vel.v * d.linear + f.v;
                vel.w = w + f.w;
            }
        };
        #[cfg(feature = "parallel")]
        if self.vel.len() >= 2 * BODY_CHUNK {
            use rayon::prelude::*;
            let c = BODY_CHUNK;
            self.vel
                .par_chunks_mut(c)
                .zip(
                    self.forcing
                        .par_chunks(c)
                        .zip(self.damping.par_chunks(c))
                        .zip(self.writable.par_chunks(c)),
                )
                .for_each_init(crate::float_mode::FlushSubnormals::new, |_, chunk| {
                    step(chunk)
                });
            return;
        }
        step((
            &mut self.vel,
            ((&self.forcing, &self.damping), &self.writable),
        ));
    }

    /// Substep stage 4: every body (kinematic ones included) moves by `hs` at its velocity;
    /// bodies with mass turn keeping their angular momentum.
    pub(crate) fn integrate_positions(&mut self, bodies: &[SolverBody], hs: Real) {
        // Slot 0 is the static world.
        let Some(n) = self.len().checked_sub(1) else {
            return;
        };
        let moving = Moving {
            vel: &mut self.vel[1..],
            delta: &mut self.delta[1..],
            dx_sub: &mut self.dx_sub[1..],
            dtheta: &mut self.dtheta[1..],
            dtheta_sub: &mut self.dtheta_sub[1..],
            orientation: &mut self.orientation[1..],
            global: &self.global[1..n + 1],
            rotation: &self.rotation[1..],
            orientation0: &self.orientation0[1..],
            writable: &self.writable[1..],
            inv_inertia: &mut self.inv_inertia[1..],
        };
        moving.advance(bodies, hs);
        self.turn_inertia(bodies);
    }

    /// Local body `l` is held by a joint row: its inertia follows its rotation (`following`).
    pub(crate) fn follow_rotation(&mut self, l: u32) {
        let i = l as usize;
        if l != NONE && i != 0 && self.writable[i] && !self.follows[i] {
            self.follows[i] = true;
            self.following.push(l);
        }
    }

    /// The world inertia of the bodies in `following`, inverse and gyroscopic, at their
    /// present orientation.
    fn turn_inertia(&mut self, bodies: &[SolverBody]) {
        for &l in &self.following {
            let l = l as usize;
            let b = &bodies[self.global[l] as usize];
            let r = Mat3::from_quat(self.orientation[l]);
            self.inv_inertia[l] = r * b.inv_inertia * r.transpose();
            if let Some(iw) = &mut self.damping[l].gyroscopic {
                *iw = r * b.inertia * r.transpose();
            }
        }
    }
}

/// Bodies one thread integrates at a time with the `parallel` feature. Each body's result is
/// its own, so every thread count gives the same bits.
#[cfg(feature = "parallel")]
const BODY_CHUNK: usize = 512;

/// Velocities, forcing, damping and writability of a run of bodies.
type VelocityChunk<'a> = (
    &'a mut [BodyVel],
    ((&'a [BodyVel], &'a [Damping]), &'a [bool]),
);

/// The states a run of bodies changes when they move (the fields of [`BodyStates`]).
struct Moving<'a> {
    vel: &'a mut [BodyVel],
    delta: &'a mut [BodyDelta],
    dx_sub: &'a mut [Vec3],
    dtheta: &'a mut [Vec3],
    dtheta_sub: &'a mut [Vec3],
    orientation: &'a mut [Quat],
    global: &'a [u32],
    rotation: &'a [Rotation],
    orientation0: &'a [Quat],
    writable: &'a [bool],
    inv_inertia: &'a mut [Mat3],
}

impl<'a> Moving<'a> {
    /// Moves every body by `hs` (see [`BodyStates::integrate_positions`]), on all cores with
    /// the `parallel` feature.
    fn advance(self, bodies: &[SolverBody], hs: Real) {
        // Each half of the split below may run on another thread (`crate::float_mode`).
        #[cfg(feature = "parallel")]
        let _flush = crate::float_mode::FlushSubnormals::new();
        #[cfg(feature = "parallel")]
        if self.global.len() >= 2 * BODY_CHUNK {
            let mid = self.global.len() / 2;
            let (a, b) = self.split(mid);
            rayon::join(|| a.advance(bodies, hs), || b.advance(bodies, hs));
            return;
        }
        for l in 0..self.global.len() {
            let g = self.global[l] as usize;
            let vel = &mut self.vel[l];
            let delta = &mut self.delta[l];
            self.dx_sub[l] = delta.dp;
            self.dtheta_sub[l] = self.dtheta[l];
            delta.dp += hs * vel.v;
            self.dtheta[l] += hs * vel.w;
            let (q, w) =
                advance_rotation(&bodies[g], self.rotation[l], self.orientation[l], vel.w, hs);
            self.orientation[l] = q;
            delta.dq = (q * self.orientation0[l].inverse()).normalize();
            if self.writable[l] {
                vel.w = w;
                if let Rotation::FastSpin = self.rotation[l] {
                    // A fast-spinning body's axle turns within the step: the rows see its
                    // inertia where the axle is now, or their torques, square to the old
                    // axle, would feed the spin (a gyroscope gained 14% in 4 s).
                    let r = Mat3::from_quat(q);
                    self.inv_inertia[l] = r * bodies[g].inv_inertia * r.transpose();
                }
            }
        }
    }

    /// The bodies before `mid` and those from it on.
    #[cfg(feature = "parallel")]
    fn split(self, mid: usize) -> (Self, Self) {
        let (vel, vel2) = self.vel.split_at_mut(mid);
        let (delta, delta2) = self.delta.split_at_mut(mid);
        let (dx_sub, dx_sub2) = self.dx_sub.split_at_mut(mid);
        let (dtheta, dtheta2) = self.dtheta.split_at_mut(mid);
        let (dtheta_sub, dtheta_sub2) = self.dtheta_sub.split_at_mut(mid);
        let (orientation, orientation2) = self.orientation.split_at_mut(mid);
        let (global, global2) = self.global.split_at(mid);
        let (rotation, rotation2) = self.rotation.split_at(mid);
        let (orientation0, orientation02) = self.orientation0.split_at(mid);
        let (writable, writable2) = self.writable.split_at(mid);
        let (inv_inertia, inv_inertia2) = self.inv_inertia.split_at_mut(mid);
        (
            Moving {
                vel,
                delta,
                dx_sub,
                dtheta,
                dtheta_sub,
                orientation,
                global,
                rotation,
                orientation0,
                writable,
                inv_inertia,
            },
            Moving {
                vel: vel2,
                delta: delta2,
                dx_sub: dx_sub2,
                dtheta: dtheta2,
                dtheta_sub: dtheta_sub2,
                orientation: orientation2,
                global: global2,
                rotation: rotation2,
                orientation0: orientation02,
                writable: writable2,
                inv_inertia: inv_inertia2,
            },
        )
    }
}
