//! The iterative path's bodies: a compact hot array of velocities and step displacements that
//! every stage reads and writes (the per-substep integration is `integrate.rs`).
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

mod integrate;

use super::super::integrate::{BodyScratch, Rotation};
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
        // Only the entries the last step set are reset: a workspace that solves a few small
        // islands of a big world costs what they hold, not what the world does.
        for &g in self.global.iter().skip(1) {
            if let Some(l) = self.local_of.get_mut(g as usize) {
                *l = NONE;
            }
        }
        self.global.clear();
        if self.local_of.len() < body_count {
            self.local_of.resize(body_count, NONE);
        }
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
