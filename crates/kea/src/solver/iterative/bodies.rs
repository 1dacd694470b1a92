//! The iterative path's bodies: a compact hot array of velocities and step displacements that
//! every stage reads and writes, and the per-substep integration.
//!
//! Hot data is what the contact and joint solves touch in their inner loops: [`BodyVel`]
//! (velocity and spin, 32 bytes in `f32`) and [`BodyDelta`] (displacement and rotation since the
//! step began, 32 bytes). Constraints keep their anchors relative to each body's centre of mass
//! at the step's start, so the current separation of a contact is its initial one moved by the
//! two bodies' displacements: deltas instead of poses keep that exact far from the origin and
//! make the static world an identity. Local index 0 is that static world: zero velocity,
//! identity delta, never written.
//!
//! Bodies are numbered island by island (so an island's bodies sit together in memory); fixed
//! or kinematic bodies that contacts touch get a read-only slot as well, so that their motion
//! enters the contacts' relative velocity and separation.

use super::super::integrate::{advance_rotation, gyroscopic_step, BodyScratch, Rotation};
use super::super::wide::Records;
use super::super::{reserve, SolverBody, SolverParams};
use crate::math::{rotate_by_vector, Mat3, Quat, Real, Vec3};

/// Marks a body with no local slot.
pub(crate) const NONE: u32 = u32::MAX;

/// Velocity and spin of one body (hot).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BodyVel {
    pub(crate) v: Vec3,
    pub(crate) w: Vec3,
    _pad: [Real; 2],
}

impl BodyVel {
    pub(crate) const ZERO: Self = Self {
        v: Vec3::ZERO,
        w: Vec3::ZERO,
        _pad: [0.0; 2],
    };
    pub(crate) fn new(v: Vec3, w: Vec3) -> Self {
        Self {
            v,
            w,
            _pad: [0.0; 2],
        }
    }
}

/// Displacement and rotation of one body since the step began (hot).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BodyDelta {
    pub(crate) dp: Vec3,
    _pad: Real,
    pub(crate) dq: Quat,
}

impl BodyDelta {
    pub(crate) const IDENTITY: Self = Self {
        dp: Vec3::ZERO,
        _pad: 0.0,
        dq: Quat::IDENTITY,
    };
}

// The contact kernels read both as records of 8 reals (one 256-bit load each in `f32`).
const _: () = assert!(std::mem::size_of::<BodyVel>() == 8 * std::mem::size_of::<Real>());
const _: () = assert!(std::mem::size_of::<BodyDelta>() == 8 * std::mem::size_of::<Real>());

/// The states as records of 8 reals, `[v.x, v.y, v.z, ω.x, ω.y, ω.z, _, _]`, for the lanes of
/// one colour.
pub(crate) fn vel_records(vel: &mut [BodyVel]) -> Records<'_> {
    // SAFETY: `BodyVel` is `repr(C)`, 8 reals and nothing else (asserted above), its alignment
    // is at least that of `Real`, and every bit pattern is a valid `BodyVel`.
    Records::new(unsafe { std::slice::from_raw_parts_mut(vel.as_mut_ptr().cast(), vel.len()) })
}

/// The deltas as records of 8 reals, `[dp.x, dp.y, dp.z, _, dq.x, dq.y, dq.z, dq.w]`.
pub(crate) fn delta_records(delta: &mut [BodyDelta]) -> Records<'_> {
    // SAFETY: `BodyDelta` is `repr(C)`: a `Vec3`, one `Real` and a `Quat`, 8 reals with no
    // padding (asserted above); every bit pattern is valid.
    Records::new(unsafe { std::slice::from_raw_parts_mut(delta.as_mut_ptr().cast(), delta.len()) })
}

/// How a body's velocity is damped every substep, precomputed.
#[derive(Debug, Clone, Copy)]
struct Damping {
    /// `1/(1 + hs·d/m)`.
    linear: Real,
    /// `(I_w + hs·d_ω)⁻¹ I_w`, when the body has angular damping.
    angular: Option<Mat3>,
    /// World inertia (at the step's start, or now for a body in `following`) of a body whose
    /// inertia is not isotropic: its gyroscopic torque is taken implicitly every substep (see
    /// `local`).
    gyroscopic: Option<Mat3>,
}

/// The iterative path's bodies (module docs).
#[derive(Debug, Default, Clone)]
pub(crate) struct BodyStates {
    pub(crate) vel: Vec<BodyVel>,
    pub(crate) delta: Vec<BodyDelta>,
    /// Global (solver slice) index of each local body; `NONE` for the static world at 0.
    pub(crate) global: Vec<u32>,
    /// Local index of each global body, `NONE` if it has none.
    pub(crate) local_of: Vec<u32>,
    pub(crate) inv_mass: Vec<Real>,
    /// World inverse inertia: at the step's start, or where the body has turned to for the
    /// bodies that follow their rotation (`following`) and fast spinners.
    pub(crate) inv_inertia: Vec<Mat3>,
    /// The bodies held by joint rows (local slots, each once): their world inertia, inverse
    /// and gyroscopic, follows their rotation from substep to substep. Held at the step's
    /// start, impulses `Δω = I⁻¹ (r × P)` of the later substeps and the implicit gyroscopic
    /// torque act through an inertia the body no longer has, and a tumbling jointed pair's
    /// angular momentum drifted 0.5%/s at 60 Hz whatever the substeps (0.12%/s following, and
    /// halving with each doubling of the substeps). Contacts' bodies keep the step's start
    /// (a pile's cost).
    following: Vec<u32>,
    follows: Vec<bool>,
    /// The body can be pushed (not fixed or kinematic, and not the static world).
    pub(crate) writable: Vec<bool>,
    /// Accumulated rotation vector `Σ hs·ω` since the step began (the joint rows' linearised
    /// error), now and at the start of the current substep; the same for displacement.
    pub(crate) dtheta: Vec<Vec3>,
    pub(crate) dtheta_sub: Vec<Vec3>,
    pub(crate) dx_sub: Vec<Vec3>,
    /// Displacement when the joint rows were last linearised (zero: at the step's start).
    pub(crate) relin_dp: Vec<Vec3>,
    orientation0: Vec<Quat>,
    orientation: Vec<Quat>,
    rotation: Vec<Rotation>,
    /// Whether any slot turns by the fast-spin rule (kept as slots are pushed).
    fast_spin: bool,
    /// What each body gains every substep from gravity and applied forces: `hs·(g + f/m)` and
    /// `hs·I⁻¹τ` (laid out as velocities, so the contact solver gathers them alike).
    pub(crate) forcing: Vec<BodyVel>,
    damping: Vec<Damping>,
    /// Bodies whose step is synchronised (`substep` module docs): their islands have no
    /// contacts, and their forcing is split into half kicks at the step's two ends.
    synchronised: Vec<bool>,
    any_synchronised: bool,
}

impl BodyStates {
    pub(crate) fn reserve(&mut self, n: usize) {
        let n = n + 1;
        reserve(&mut self.vel, n);
        reserve(&mut self.delta, n);
        reserve(&mut self.global, n);
        reserve(&mut self.local_of, n);
        reserve(&mut self.inv_mass, n);
        reserve(&mut self.inv_inertia, n);
        reserve(&mut self.writable, n);
        reserve(&mut self.following, n);
        reserve(&mut self.follows, n);
        reserve(&mut self.dtheta, n);
        reserve(&mut self.dtheta_sub, n);
        reserve(&mut self.dx_sub, n);
        reserve(&mut self.relin_dp, n);
        reserve(&mut self.orientation0, n);
        reserve(&mut self.orientation, n);
        reserve(&mut self.rotation, n);
        reserve(&mut self.forcing, n);
        reserve(&mut self.damping, n);
        reserve(&mut self.synchronised, n);
    }

    pub(crate) fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.vel.capacity() * size_of::<BodyVel>()
            + self.delta.capacity() * size_of::<BodyDelta>()
            + (self.global.capacity() + self.local_of.capacity() + self.following.capacity()) * 4
            + self.follows.capacity()
            + self.inv_mass.capacity() * size_of::<Real>()
            + self.inv_inertia.capacity() * size_of::<Mat3>()
            + self.writable.capacity()
            + self.synchronised.capacity()
            + (self.dtheta.capacity()
                + self.dtheta_sub.capacity()
                + self.dx_sub.capacity()
                + self.relin_dp.capacity())
                * size_of::<Vec3>()
            + (self.orientation0.capacity() + self.orientation.capacity()) * size_of::<Quat>()
            + self.rotation.capacity() * size_of::<Rotation>()
            + self.forcing.capacity() * size_of::<BodyVel>()
            + self.damping.capacity() * size_of::<Damping>()
    }

    pub(crate) fn bytes_for(n: usize) -> usize {
        use std::mem::size_of;
        (n + 1)
            * (size_of::<BodyVel>()
                + size_of::<BodyDelta>()
                + 15
                + size_of::<Real>()
                + size_of::<Mat3>()
                + 4 * size_of::<Vec3>()
                + 2 * size_of::<Quat>()
                + size_of::<Rotation>()
                + size_of::<BodyVel>()
                + size_of::<Damping>())
    }

    /// Empties the set, keeping only the static world at local index 0.
    pub(crate) fn begin(&mut self, body_count: usize) {
        for v in [&mut self.global, &mut self.local_of] {
            v.clear();
        }
        self.local_of.resize(body_count, NONE);
        self.vel.clear();
        self.delta.clear();
        self.inv_mass.clear();
        self.inv_inertia.clear();
        self.writable.clear();
        self.dtheta.clear();
        self.dtheta_sub.clear();
        self.dx_sub.clear();
        self.relin_dp.clear();
        self.orientation0.clear();
        self.orientation.clear();
        self.rotation.clear();
        self.fast_spin = false;
        self.following.clear();
        self.follows.clear();
        self.forcing.clear();
        self.damping.clear();
        self.synchronised.clear();
        self.any_synchronised = false;
        self.push_slot(
            NONE,
            BodyVel::ZERO,
            0.0,
            Mat3::ZERO,
            false,
            Quat::IDENTITY,
            Rotation::Kinematic,
        );
    }

    #[allow(clippy::too_many_arguments)]
    fn push_slot(
        &mut self,
        global: u32,
        vel: BodyVel,
        inv_mass: Real,
        inv_inertia: Mat3,
        writable: bool,
        q: Quat,
        rotation: Rotation,
    ) {
        self.global.push(global);
        self.vel.push(vel);
        self.delta.push(BodyDelta::IDENTITY);
        self.inv_mass.push(inv_mass);
        self.inv_inertia.push(inv_inertia);
        self.writable.push(writable);
        self.dtheta.push(Vec3::ZERO);
        self.dtheta_sub.push(Vec3::ZERO);
        self.dx_sub.push(Vec3::ZERO);
        self.relin_dp.push(Vec3::ZERO);
        self.orientation0.push(q);
        self.orientation.push(q);
        self.fast_spin |= matches!(rotation, Rotation::FastSpin);
        self.follows.push(false);
        self.rotation.push(rotation);
        self.forcing.push(BodyVel::ZERO);
        self.damping.push(Damping {
            linear: 1.0,
            angular: None,
            gyroscopic: None,
        });
        self.synchronised.push(false);
    }

    /// Marks the slots from `first` on as synchronised (their island has no contacts).
    pub(crate) fn synchronise_from(&mut self, first: usize) {
        for s in &mut self.synchronised[first..] {
            *s = true;
        }
        self.any_synchronised |= first < self.synchronised.len();
    }

    /// Whether any slot's step is synchronised.
    pub(crate) fn any_synchronised(&self) -> bool {
        self.any_synchronised
    }

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

    /// Whether any body here turns by the fast-spin rule.
    pub(crate) fn has_fast_spin(&self) -> bool {
        self.rotation
            .iter()
            .any(|r| matches!(r, Rotation::FastSpin))
    }

    /// Records the present displacements as the joint rows' new linearisation point.
    pub(crate) fn mark_linearisation(&mut self) {
        for (r, d) in self.relin_dp.iter_mut().zip(&self.delta) {
            *r = d.dp;
        }
    }

    /// Moves local body `l` by `dx` and turns it by the rotation vector `dtheta`, leaving its
    /// velocity alone (a position correction after the substeps).
    pub(crate) fn displace(&mut self, l: usize, dx: Vec3, dtheta: Vec3) {
        if !self.writable[l] {
            return;
        }
        self.delta[l].dp += dx;
        self.dtheta[l] += dtheta;
        let q = rotate_by_vector(self.orientation[l], dtheta);
        self.orientation[l] = q;
        self.delta[l].dq = (q * self.orientation0[l].inverse()).normalize();
    }

    /// The largest distance from the origin of a body that can be pushed, now.
    pub(crate) fn extent(&self, bodies: &[SolverBody]) -> Real {
        (1..self.len())
            .filter(|&l| self.writable[l])
            .map(|l| (bodies[self.global[l] as usize].position + self.delta[l].dp).length())
            .fold(0.0, Real::max)
    }

    /// Local body `l`'s orientation now.
    pub(crate) fn orientation_now(&self, l: usize) -> Quat {
        self.orientation[l]
    }

    /// Number of local slots (the static world included).
    pub(crate) fn len(&self) -> usize {
        self.vel.len()
    }

    /// The local index of global body `g` (`None`: the static world, index 0), adding it on
    /// first sight. A fixed (kinematic) body gets a read-only slot.
    pub(crate) fn local(
        &mut self,
        g: Option<u32>,
        bodies: &[SolverBody],
        scratch: &BodyScratch,
        params: &SolverParams,
        hs: Real,
    ) -> u32 {
        let Some(g) = g else { return 0 };
        let slot = self.local_of[g as usize];
        if slot != NONE {
            return slot;
        }
        let b = &bodies[g as usize];
        let local = self.len() as u32;
        self.local_of[g as usize] = local;
        let inv_iw = scratch.inv_inertia_world[g as usize];
        let writable = !b.is_fixed();
        // A body held in an iterative island turns at its angular velocity, its gyroscopic
        // torque taken implicitly in the velocities: carrying `L` through the rotation (the
        // free body's rule) hands the joints a sideways spin every substep, which a link
        // spinning fast about its own axis (a whipped chain's) turns into a blow-up.
        let (rotation, gyroscopic) = match scratch.rotation[g as usize] {
            Rotation::Free { .. } if writable => {
                let r = Mat3::from_quat(b.orientation);
                (Rotation::Isotropic, Some(r * b.inertia * r.transpose()))
            }
            rule => (rule, None),
        };
        self.push_slot(
            g,
            BodyVel::new(b.linear_velocity, b.angular_velocity),
            b.inv_mass,
            inv_iw,
            writable,
            b.orientation,
            rotation,
        );
        if writable {
            let gravity = if b.inv_mass > 0.0 {
                params.gravity
            } else {
                Vec3::ZERO
            };
            let angular_damping = (b.angular_damping > 0.0).then(|| {
                // Implicit, with the world inertia of the step's start.
                let iw = inv_iw.inverse();
                let damped = iw + Mat3::from_diagonal(Vec3::splat(hs * b.angular_damping));
                damped.inverse() * iw
            });
            *self.forcing.last_mut().expect("just pushed") = BodyVel::new(
                hs * (gravity + b.inv_mass * b.force),
                hs * (inv_iw * b.torque),
            );
            *self.damping.last_mut().expect("just pushed") = Damping {
                linear: 1.0 / (1.0 + hs * b.linear_damping * b.inv_mass),
                angular: angular_damping,
                gyroscopic,
            };
        }
        local
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
                .for_each(step);
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

    /// Writes the new state of every body that can be pushed back to the solver's array and
    /// marks it integrated.
    pub(crate) fn write_out(
        &mut self,
        bodies: &mut [SolverBody],
        scratch: &mut BodyScratch,
        h: Real,
    ) {
        for l in 1..self.len() {
            let g = self.global[l] as usize;
            if !self.writable[l] {
                continue;
            }
            let b = &mut bodies[g];
            let vel = self.vel[l];
            b.linear_acceleration = (vel.v - b.linear_velocity) / h;
            b.angular_acceleration = (vel.w - b.angular_velocity) / h;
            b.linear_velocity = vel.v;
            b.angular_velocity = vel.w;
            b.position += self.delta[l].dp;
            b.orientation = self.orientation[l];
            scratch.integrated[g] = true;
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
