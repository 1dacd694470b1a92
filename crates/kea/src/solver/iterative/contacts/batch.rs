//! A batch: up to `LANES` contacts of one colour side by side, one per SIMD lane, in structure
//! of arrays, and how one contact is written into its lane (the prepare stage).
//!
//! Per contact (lane): its two bodies' local indices and whether each may be written, their
//! inverse masses and world inverse inertias at the step's start, the normal and the fixed
//! tangent basis, the friction, restitution, adhesion, slide and slip parameters, and the soft
//! bias rate. Per point: the anchors `r₁ = p − x₁`, `r₂ = p − x₂` (relative to each centre of
//! mass, world orientation, fixed for the step), the separation with the anchors' part taken
//! out (`s = base + n·(Δx₁ − Δx₂) + (Δq₁⁻¹n)·r₁ − (Δq₂⁻¹n)·r₂` in the solve), the normal
//! masses, the accumulated normal impulses and their totals over the step, and the point's
//! lever about the friction centre.
//!
//! Friction is the manifold's, not each point's (Rapier's "simplified" friction model): one
//! tangential impulse at the friction centre (the mean of the points), bounded by μ times the
//! manifold's normal impulse, and one twist impulse about the normal, bounded by μ times the
//! sum of each point's normal impulse times its lever. Two friction directions and a twist per
//! manifold instead of two per point: cheaper, and no per-point friction to couple with the
//! rocking of tall stacks.
//!
//! Prepare is two passes: [`ContactBatch::load_lane`] copies each contact's raw data into its
//! lane (scalar), then [`derive`] computes everything else lane-parallel: anchors' effective
//! masses, soft coefficients, approach velocities, the warm start clamped to this step's
//! bounds.
//!
//! Effective masses. Normal: `m_n = 1/(1/m₁ + 1/m₂ + (r₁×n)·I₁⁻¹(r₁×n) + (r₂×n)·I₂⁻¹(r₂×n))`.
//! Friction at the centre uses one scalar mass for both tangent directions,
//! `m_t = 2/(K₁₁ + K₂₂)` (the mean of the two diagonal terms of the tangential block): with it
//! the projected friction impulse is parallel to the sliding velocity, so friction is
//! isotropic and a sliding box neither veers nor spins, and the Gauss-Seidel step stays below
//! twice the stiffest direction's, so it converges. Twist: `m_τ = 1/(n·I₁⁻¹n + n·I₂⁻¹n)`.
//! Slip `s` (velocity per force, per point) acts on the manifold as its points in parallel,
//! `s/k` for `k` points, and softens a direction to `1/(1/m_t + s/(k·hs))`.

use super::super::super::wide::{FloatW, Records, Sym3, Sym3A, V3, V3A};
use super::super::bodies::BodyStates;
use crate::constraint::{Contact, FrictionModel, SoftCoefficients, Spring, MAX_CONTACT_POINTS};
use crate::math::{Real, Vec3};

/// One point of every lane.
#[derive(Clone, Copy, Default, Debug)]
pub(crate) struct PointLanes<F: FloatW> {
    pub(crate) r_a: V3A<F>,
    pub(crate) r_b: V3A<F>,
    pub(crate) base_separation: F::Array,
    pub(crate) normal_mass: F::Array,
    /// Normal mass and impulse scale of the soft (biased) solve.
    pub(crate) soft_mass: F::Array,
    pub(crate) soft_impulse: F::Array,
    /// Distance from the friction centre in the tangent plane (the twist's lever), m.
    pub(crate) lever: F::Array,
    /// Accumulated normal impulse of the current substep, N·s.
    pub(crate) normal_impulse: F::Array,
    /// Relative normal velocity at the step's start, and its change per substep from gravity
    /// and applied forces (restitution: the approach velocity of a point that starts pushing in
    /// substep k is `relative_velocity + k·forcing`).
    pub(crate) relative_velocity: F::Array,
    pub(crate) forcing: F::Array,
    /// The first substep in which the point pushed this step ([`NEVER`] until it does); its
    /// approach velocity then was `relative_velocity + impact_substep·forcing` (restitution).
    pub(crate) impact_substep: F::Array,
    /// Impulses over the substeps before the last, and the restitution pass's.
    pub(crate) total_normal: F::Array,
    pub(crate) bounce: F::Array,
}

/// Up to `F::LANES` contacts of one colour (module docs).
#[derive(Clone, Copy, Default, Debug)]
pub(crate) struct ContactBatch<F: FloatW> {
    pub(crate) body_a: F::Index,
    pub(crate) body_b: F::Index,
    /// 1 where the body may be written (it can be pushed), 0 otherwise.
    pub(crate) write_a: F::Index,
    pub(crate) write_b: F::Index,
    /// Index of each lane's contact in the solver's contact slice (`u32::MAX`: empty lane).
    pub(crate) contact: F::Index,
    /// Points of each lane, and the most of any lane.
    pub(crate) count: F::Array,
    pub(crate) points: u32,
    pub(crate) inv_mass_a: F::Array,
    pub(crate) inv_mass_b: F::Array,
    pub(crate) inv_inertia_a: Sym3A<F>,
    pub(crate) inv_inertia_b: Sym3A<F>,
    pub(crate) normal: V3A<F>,
    pub(crate) tangent: [V3A<F>; 2],
    /// Coulomb coefficient per tangent direction (0 for a box or infinite model).
    pub(crate) mu: [F::Array; 2],
    /// Constant friction bound per direction, N·s per substep: the box model's bound times
    /// the points (∞ when infinite).
    pub(crate) fixed_limit: [F::Array; 2],
    /// 1 where friction is isotropic Coulomb (bounded by a disc), 0 for per-direction bounds.
    pub(crate) disc: F::Array,
    /// Surface speed of body 1 relative to body 2 along each direction (conveyor), m/s.
    pub(crate) slide: [F::Array; 2],
    /// Slip `s/hs` per direction.
    pub(crate) slip: [F::Array; 2],
    pub(crate) restitution: F::Array,
    pub(crate) restitution_threshold: F::Array,
    /// Lowest normal impulse per substep (minus the adhesive force × hs).
    pub(crate) min_normal: F::Array,
    pub(crate) bias_rate: F::Array,
    /// The spring's mass and impulse scales, or (raw softness) the extra diagonal `1/(hs(hs k + d))`.
    pub(crate) mass_scale: F::Array,
    pub(crate) impulse_scale: F::Array,
    pub(crate) raw_extra: F::Array,
    /// 1 where the contact has its own raw softness: a physical spring also in the relax solve.
    pub(crate) spring_relax: F::Array,
    /// Anchors of the friction centre.
    pub(crate) r_ca: V3A<F>,
    pub(crate) r_cb: V3A<F>,
    /// Tangent mass per direction: one isotropic mass, softened by each direction's slip.
    pub(crate) tangent_mass: [F::Array; 2],
    pub(crate) twist_mass: F::Array,
    /// Constant twist bound, N·m·s per substep (box and infinite models).
    pub(crate) twist_fixed: F::Array,
    /// Accumulated friction and twist impulses of the current substep, and over the substeps
    /// before the last.
    pub(crate) tangent_impulse: [F::Array; 2],
    pub(crate) twist_impulse: F::Array,
    pub(crate) total_tangent: [F::Array; 2],
    pub(crate) total_twist: F::Array,
    pub(crate) p: [PointLanes<F>; MAX_CONTACT_POINTS],
}

/// The impact substep of a point that has not pushed (more substeps than any step has).
pub(crate) const NEVER: Real = 1.0e6;

/// What prepare needs of the step.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PrepareParams {
    pub(crate) h: Real,
    pub(crate) hs: Real,
    pub(crate) spring: Spring,
    pub(crate) gamma: Real,
}

fn lane(a: &mut impl AsMut<[Real]>, l: usize) -> &mut Real {
    &mut a.as_mut()[l]
}

fn index_lane(a: &mut impl AsMut<[u32]>, l: usize) -> &mut u32 {
    &mut a.as_mut()[l]
}

impl<F: FloatW> ContactBatch<F> {
    /// Makes lane `l` an empty lane: a no-op on the static world.
    pub(crate) fn clear_lane(&mut self, l: usize) {
        for idx in [
            &mut self.body_a,
            &mut self.body_b,
            &mut self.write_a,
            &mut self.write_b,
        ] {
            *index_lane(idx, l) = 0;
        }
        *index_lane(&mut self.contact, l) = u32::MAX;
        *lane(&mut self.count, l) = 0.0;
        *lane(&mut self.inv_mass_a, l) = 0.0;
        *lane(&mut self.inv_mass_b, l) = 0.0;
        self.inv_inertia_a.set_lane(l, &crate::math::Mat3::ZERO);
        self.inv_inertia_b.set_lane(l, &crate::math::Mat3::ZERO);
        self.normal.set_lane(l, Vec3::ZERO);
        for v in &mut self.tangent {
            v.set_lane(l, Vec3::ZERO);
        }
        for d in 0..2 {
            *lane(&mut self.tangent_impulse[d], l) = 0.0;
            *lane(&mut self.mu[d], l) = 0.0;
            *lane(&mut self.fixed_limit[d], l) = 0.0;
            *lane(&mut self.slide[d], l) = 0.0;
            *lane(&mut self.slip[d], l) = 0.0;
        }
        for a in [
            &mut self.disc,
            &mut self.restitution,
            &mut self.restitution_threshold,
            &mut self.min_normal,
            &mut self.bias_rate,
            &mut self.mass_scale,
            &mut self.impulse_scale,
            &mut self.raw_extra,
            &mut self.spring_relax,
            &mut self.twist_mass,
            &mut self.twist_fixed,
            &mut self.twist_impulse,
        ] {
            *lane(a, l) = 0.0;
        }
        self.r_ca.set_lane(l, Vec3::ZERO);
        self.r_cb.set_lane(l, Vec3::ZERO);
        self.clear_points(l, 0);
    }

    /// Zeroes the points of lane `l` from `from` on (they do nothing then: no mass).
    pub(crate) fn clear_points(&mut self, l: usize, from: usize) {
        for p in &mut self.p[from..] {
            p.r_a.set_lane(l, Vec3::ZERO);
            p.r_b.set_lane(l, Vec3::ZERO);
            *lane(&mut p.base_separation, l) = 0.0;
            *lane(&mut p.normal_impulse, l) = 0.0;
            *lane(&mut p.lever, l) = 0.0;
        }
    }

    /// Copies contact `index` (on local bodies `a`, `b` at `positions`) into lane `l`: its raw
    /// data only, [`derive`] computes the rest.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn load_lane(
        &mut self,
        l: usize,
        index: u32,
        contact: &Contact,
        (a, b): (u32, u32),
        positions: (Vec3, Vec3),
        states: &BodyStates,
        k: &PrepareParams,
    ) {
        let (la, lb) = (a as usize, b as usize);
        *index_lane(&mut self.body_a, l) = a;
        *index_lane(&mut self.body_b, l) = b;
        *index_lane(&mut self.write_a, l) = u32::from(states.writable[la]);
        *index_lane(&mut self.write_b, l) = u32::from(states.writable[lb]);
        *index_lane(&mut self.contact, l) = index;
        let count = contact.points().len();
        *lane(&mut self.count, l) = count as Real;
        self.points = self.points.max(count as u32);
        *lane(&mut self.inv_mass_a, l) = states.inv_mass[la];
        *lane(&mut self.inv_mass_b, l) = states.inv_mass[lb];
        self.inv_inertia_a.set_lane(l, &states.inv_inertia[la]);
        self.inv_inertia_b.set_lane(l, &states.inv_inertia[lb]);
        let n = contact.normal();
        let (t1, t2) = contact.tangent_basis();
        self.normal.set_lane(l, n);
        self.tangent[0].set_lane(l, t1);
        self.tangent[1].set_lane(l, t2);
        let fixed_side = !states.writable[la] || !states.writable[lb];
        self.load_surface(l, contact, k, fixed_side);

        let (xa, xb) = positions;
        // The static world (slot 0) never moves: its anchor can be 0, which keeps the
        // separation exact however far from the origin the contact is.
        let anchor = |p: Vec3, x: Vec3, slot: usize| if slot == 0 { Vec3::ZERO } else { p - x };
        let frame = contact.friction_frame();
        self.r_ca.set_lane(l, anchor(frame.centre, xa, la));
        self.r_cb.set_lane(l, anchor(frame.centre, xb, lb));
        let mut lever_sum = 0.0;
        for (j, (point, f)) in contact
            .points()
            .iter()
            .zip(contact.warm_forces())
            .enumerate()
        {
            let pl = &mut self.p[j];
            let ra = anchor(point.position, xa, la);
            let rb = anchor(point.position + point.to_second, xb, lb);
            pl.r_a.set_lane(l, ra);
            pl.r_b.set_lane(l, rb);
            *lane(&mut pl.base_separation, l) = -point.penetration - n.dot(ra) + n.dot(rb);
            let lever = frame.levers[j].length();
            *lane(&mut pl.lever, l) = lever;
            lever_sum += lever;
            // The warm start, clamped to this step's bounds by `derive`.
            *lane(&mut pl.normal_impulse, l) = f.normal * k.hs;
        }
        let (friction, twist) = contact.gather_friction(&frame, contact.warm_forces());
        *lane(&mut self.tangent_impulse[0], l) = friction.dot(t1) * k.hs;
        *lane(&mut self.tangent_impulse[1], l) = friction.dot(t2) * k.hs;
        *lane(&mut self.twist_impulse, l) = twist * k.hs;
        // The points act in parallel: the box model's bound is per point, and so is slip.
        let points = count as Real;
        let fixed = 0.5 * (self.fixed_limit[0].as_ref()[l] + self.fixed_limit[1].as_ref()[l]);
        // A lone point has no lever, so no twist (and 0·∞ must not make a NaN).
        *lane(&mut self.twist_fixed, l) = if lever_sum > 0.0 {
            fixed * lever_sum
        } else {
            0.0
        };
        for d in 0..2 {
            *lane(&mut self.fixed_limit[d], l) *= points;
            *lane(&mut self.slip[d], l) /= points;
        }
    }

    /// The surface parameters and softness of lane `l`.
    fn load_surface(&mut self, l: usize, contact: &Contact, k: &PrepareParams, fixed_side: bool) {
        let prm = contact.params();
        let directions = match prm.contact_type {
            crate::ContactType::Frictionless => 0,
            crate::ContactType::Friction1D => 1,
            crate::ContactType::Friction2D => 2,
        };
        let mut mu = [0.0; 2];
        let mut fixed = [0.0; 2];
        for d in 0..directions {
            match prm.friction[d] {
                FrictionModel::Coulomb { .. } | FrictionModel::StaticKinetic { .. } => {
                    mu[d] = contact.coulomb_mu(d).unwrap_or(0.0);
                }
                FrictionModel::Box { max_force } => fixed[d] = max_force * k.hs,
                FrictionModel::Infinite => fixed[d] = Real::INFINITY,
            }
        }
        let isotropic_coulomb = directions == 2
            && matches!(
                (contact.coulomb_mu(0), contact.coulomb_mu(1)),
                (Some(m0), Some(m1)) if m0 == m1
            );
        for d in 0..2 {
            *lane(&mut self.mu[d], l) = mu[d];
            *lane(&mut self.fixed_limit[d], l) = fixed[d];
            *lane(&mut self.slide[d], l) = prm.slide[d];
            *lane(&mut self.slip[d], l) = prm.slip[d] / k.hs;
        }
        *lane(&mut self.disc, l) = if isotropic_coulomb { 1.0 } else { 0.0 };
        *lane(&mut self.restitution, l) = prm.restitution;
        *lane(&mut self.restitution_threshold, l) = prm.restitution_threshold;
        *lane(&mut self.min_normal, l) = -prm.max_adhesive_force * k.hs;

        // Softness: the world's mass-independent spring, or the contact's own raw ε as the
        // spring k = γ/(ε h²), d = (1 − γ)/(ε h) re-discretised at the substep.
        let raw = prm.softness.filter(|&e| e > 0.0).map(|eps| {
            let stiffness = k.gamma / (eps * k.h * k.h);
            let damping = (1.0 - k.gamma) / (eps * k.h);
            let hkd = k.hs * stiffness + damping;
            (stiffness / hkd, 1.0 / (k.hs * hkd))
        });
        let c = match raw {
            Some((rate, _)) => SoftCoefficients {
                bias_rate: rate,
                ..SoftCoefficients::RIGID
            },
            None if prm.softness == Some(0.0) => SoftCoefficients::RIGID,
            // Against something that cannot move, the spring is twice as fast (Rapier does the
            // same): floors and walls hold piles firmly, and the step stays stable since only
            // one body answers.
            None if fixed_side => {
                Spring::new(2.0 * k.spring.hertz, k.spring.damping_ratio).coefficients(k.hs)
            }
            None => k.spring.coefficients(k.hs),
        };
        *lane(&mut self.bias_rate, l) = c.bias_rate;
        *lane(&mut self.mass_scale, l) = c.mass_scale;
        *lane(&mut self.impulse_scale, l) = c.impulse_scale;
        *lane(&mut self.raw_extra, l) = raw.map_or(0.0, |r| r.1);
        *lane(&mut self.spring_relax, l) = if raw.is_some() { 1.0 } else { 0.0 };
    }
}

/// `1/k` where a lane is active and `k > 0`, else 0 (functions, not closures: a closure would
/// not inherit the SIMD caller's target features, and its intrinsics would be called out of
/// line).
#[inline(always)]
fn mass<F: FloatW>(k: F, active: F::Mask) -> F {
    F::select(
        F::and(active, k.gt(F::zero())),
        F::splat(1.0) / k,
        F::zero(),
    )
}

/// Velocity of the point at `r` of a body moving with `v`, `w`.
#[inline(always)]
fn at<F: FloatW>(v: V3<F>, w: V3<F>, r: V3<F>) -> V3<F> {
    v.add(w.cross(r))
}

/// `a·(I⁻¹ a)` per lane.
#[inline(always)]
fn quad<F: FloatW>(inv_inertia: &Sym3<F>, a: V3<F>) -> F {
    a.dot(inv_inertia.mul(a))
}

/// The derived data of a loaded batch, lane-parallel (module docs). `vel` are the bodies'
/// velocities at the step's start; `forcing` what gravity and applied forces add per substep.
#[inline(always)]
pub(crate) fn derive<F: FloatW>(c: &mut ContactBatch<F>, vel: Records<'_>, forcing: Records<'_>) {
    let zero = F::zero();
    let (ma, mb) = (F::load(&c.inv_mass_a), F::load(&c.inv_mass_b));
    let (ia, ib) = (c.inv_inertia_a.load(), c.inv_inertia_b.load());
    let n = c.normal.load();
    let t = [c.tangent[0].load(), c.tangent[1].load()];
    let (va, wa) = gather_vel::<F>(vel, &c.body_a);
    let (vb, wb) = gather_vel::<F>(vel, &c.body_b);
    let (fva, fwa) = gather_vel::<F>(forcing, &c.body_a);
    let (fvb, fwb) = gather_vel::<F>(forcing, &c.body_b);
    let count = F::load(&c.count);
    let extra = F::load(&c.raw_extra);
    let raw = extra.gt(zero);
    let (mass_scale, impulse_scale) = (F::load(&c.mass_scale), F::load(&c.impulse_scale));
    let min_normal = F::load(&c.min_normal);
    // The manifold's warm normal impulse, and its moment arm sum, bound the friction's.
    let (mut held, mut held_lever) = (zero, zero);
    for (j, p) in c.p.iter_mut().enumerate().take(c.points as usize) {
        let active = count.gt(F::splat(j as Real));
        let ra = p.r_a.load();
        let rb = p.r_b.load();
        let kn = ma + mb + quad(&ia, ra.cross(n)) + quad(&ib, rb.cross(n));
        let normal_mass = mass(kn, active);
        normal_mass.store(&mut p.normal_mass);
        let soft_kn = kn + extra;
        F::select(raw, mass(soft_kn, active), normal_mass * mass_scale).store(&mut p.soft_mass);
        F::select(raw, extra * mass(soft_kn, active), impulse_scale).store(&mut p.soft_impulse);
        n.dot(at(va, wa, ra).sub(at(vb, wb, rb)))
            .store(&mut p.relative_velocity);
        n.dot(at(fva, fwa, ra).sub(at(fvb, fwb, rb)))
            .store(&mut p.forcing);
        // The warm start, within this step's bounds.
        let pn = F::load(&p.normal_impulse).max(min_normal);
        pn.store(&mut p.normal_impulse);
        let pos = F::select(active, pn.max(zero), zero);
        held = held + pos;
        held_lever = held_lever + pos * F::load(&p.lever);
        F::splat(NEVER).store(&mut p.impact_substep);
        zero.store(&mut p.total_normal);
        zero.store(&mut p.bounce);
    }
    derive_friction(c, (ma, mb), (&ia, &ib), (n, t), (held, held_lever));
}

/// The friction part of [`derive`]: the tangent and twist masses at the manifold's centre and
/// the friction warm start within this step's bounds (`held`: the manifold's warm normal
/// impulse, `held_lever` its moment about the centre).
#[inline(always)]
fn derive_friction<F: FloatW>(
    c: &mut ContactBatch<F>,
    (ma, mb): (F, F),
    (ia, ib): (&Sym3<F>, &Sym3<F>),
    (n, t): (V3<F>, [V3<F>; 2]),
    (held, held_lever): (F, F),
) {
    let (zero, one) = (F::zero(), F::splat(1.0));
    let count = F::load(&c.count);
    let mu = [F::load(&c.mu[0]), F::load(&c.mu[1])];
    let fixed = [F::load(&c.fixed_limit[0]), F::load(&c.fixed_limit[1])];
    let slip = [F::load(&c.slip[0]), F::load(&c.slip[1])];
    let disc = F::load(&c.disc).gt(F::splat(0.5));
    // Friction at the centre: one isotropic mass, each direction softened by its slip.
    let (rca, rcb) = (c.r_ca.load(), c.r_cb.load());
    let some = count.gt(zero);
    let k1 = ma + mb + quad(ia, rca.cross(t[0])) + quad(ib, rcb.cross(t[0]));
    let k2 = ma + mb + quad(ia, rca.cross(t[1])) + quad(ib, rcb.cross(t[1]));
    let kt = F::splat(0.5) * (k1 + k2);
    for (m, s) in c.tangent_mass.iter_mut().zip(slip) {
        mass(kt + s, some).store(m);
    }
    let twisting = count.gt(one);
    mass(quad(ia, n) + quad(ib, n), twisting).store(&mut c.twist_mass);
    // The friction warm start, within this step's bounds.
    let limit = [mu[0] * held + fixed[0], mu[1] * held + fixed[1]];
    let pt = [
        F::load(&c.tangent_impulse[0]).min(limit[0]).max(-limit[0]),
        F::load(&c.tangent_impulse[1]).min(limit[1]).max(-limit[1]),
    ];
    let limit = mu[0] * held;
    let len = (pt[0] * pt[0] + pt[1] * pt[1]).sqrt();
    let shrink = F::select(F::and(disc, len.gt(limit)), limit / len, one);
    for (d, p) in pt.iter().enumerate() {
        (*p * shrink).store(&mut c.tangent_impulse[d]);
        zero.store(&mut c.total_tangent[d]);
    }
    let twist_limit = F::select(
        twisting,
        F::splat(0.5) * (mu[0] + mu[1]) * held_lever + F::load(&c.twist_fixed),
        zero,
    );
    F::load(&c.twist_impulse)
        .min(twist_limit)
        .max(-twist_limit)
        .store(&mut c.twist_impulse);
    zero.store(&mut c.total_twist);
}

/// Velocity and spin of each lane's body.
#[inline(always)]
pub(crate) fn gather_vel<F: FloatW>(vel: Records<'_>, idx: &F::Index) -> (V3<F>, V3<F>) {
    let r = F::gather8(vel, idx);
    (V3::new(r[0], r[1], r[2]), V3::new(r[3], r[4], r[5]))
}
