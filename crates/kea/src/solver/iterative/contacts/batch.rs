//! A batch: up to `LANES` contacts of one colour side by side, one per SIMD lane, in structure
//! of arrays, and how one contact is written into its lane (the prepare stage).
//!
//! Per contact (lane): its two bodies' local indices and whether each may be written, their
//! inverse masses and world inverse inertias at the step's start, the normal and the fixed
//! tangent basis, the friction, restitution, adhesion, slide and slip parameters, and the soft
//! bias rate. Per point: the anchors `r₁ = p − x₁`, `r₂ = p − x₂` (relative to each centre of
//! mass, world orientation, fixed for the step), the separation with the anchors' part taken
//! out (`s = base + n·(Δx₁ − Δx₂) + (Δq₁⁻¹n)·r₁ − (Δq₂⁻¹n)·r₂` in the solve), the effective
//! masses, the accumulated impulses and their totals over the step.
//!
//! Effective masses. Normal: `m_n = 1/(1/m₁ + 1/m₂ + (r₁×n)·I₁⁻¹(r₁×n) + (r₂×n)·I₂⁻¹(r₂×n))`.
//! Friction uses one scalar mass for both tangent directions, `m_t = 2/(K₁₁ + K₂₂)` (the mean
//! of the two diagonal terms of the tangential block): with it the projected friction impulse
//! is parallel to the sliding velocity, so friction is isotropic and a sliding box neither
//! veers nor spins, and the Gauss-Seidel step stays below twice the stiffest direction's, so it
//! converges. Slip `s` (velocity per force) softens a direction to `1/(1/m_t + s/hs)`.

use super::super::super::wide::{FloatW, Sym3A, V3A};
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
    /// Tangent mass per direction: one isotropic mass, softened by each direction's slip.
    pub(crate) tangent_mass: [F::Array; 2],
    /// Accumulated impulses of the current substep, N·s.
    pub(crate) normal_impulse: F::Array,
    pub(crate) tangent_impulse: [F::Array; 2],
    /// Relative normal velocity at the step's start, and its change per substep from gravity
    /// and applied forces (restitution: the approach velocity of a point that starts pushing in
    /// substep k is `relative_velocity + k·forcing`).
    pub(crate) relative_velocity: F::Array,
    pub(crate) forcing: F::Array,
    /// Approach velocity of the point when it first pushed in this step, and the substep in
    /// which it did (restitution).
    pub(crate) approach: F::Array,
    pub(crate) impact_substep: F::Array,
    /// Impulses over the whole step.
    pub(crate) total_normal: F::Array,
    pub(crate) total_tangent: [F::Array; 2],
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
    /// Most points of any lane.
    pub(crate) points: u32,
    pub(crate) inv_mass_a: F::Array,
    pub(crate) inv_mass_b: F::Array,
    pub(crate) inv_inertia_a: Sym3A<F>,
    pub(crate) inv_inertia_b: Sym3A<F>,
    pub(crate) normal: V3A<F>,
    pub(crate) tangent: [V3A<F>; 2],
    /// Coulomb coefficient per tangent direction (0 for a box or infinite model).
    pub(crate) mu: [F::Array; 2],
    /// Constant friction bound per direction, N·s per substep (box model; ∞ when infinite).
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
    /// 1 where the contact has its own raw softness: a physical spring also in the relax solve.
    pub(crate) spring_relax: F::Array,
    pub(crate) p: [PointLanes<F>; MAX_CONTACT_POINTS],
}

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

/// `m·I⁻¹` quadratic form `a·(I⁻¹ a)` for a (symmetric) inverse inertia.
fn quad(inv_inertia: &crate::math::Mat3, a: Vec3) -> Real {
    a.dot(*inv_inertia * a)
}

impl<F: FloatW> ContactBatch<F> {
    /// An empty batch: every lane a no-op on the static world.
    pub(crate) fn empty() -> Self {
        let mut b = Self::default();
        for l in 0..F::LANES {
            *index_lane(&mut b.contact, l) = u32::MAX;
        }
        b
    }

    /// Writes contact `index` (on local bodies `a`, `b`) into lane `l`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn set_lane(
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
        self.points = self.points.max(count as u32);
        let (ma, mb) = (states.inv_mass[la], states.inv_mass[lb]);
        let (ia, ib) = (&states.inv_inertia[la], &states.inv_inertia[lb]);
        *lane(&mut self.inv_mass_a, l) = ma;
        *lane(&mut self.inv_mass_b, l) = mb;
        self.inv_inertia_a.set_lane(l, ia);
        self.inv_inertia_b.set_lane(l, ib);
        let n = contact.normal();
        let (t1, t2) = contact.tangent_basis();
        self.normal.set_lane(l, n);
        self.tangent[0].set_lane(l, t1);
        self.tangent[1].set_lane(l, t2);

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
                FrictionModel::Coulomb { mu: m } => mu[d] = m,
                FrictionModel::Box { max_force } => fixed[d] = max_force * k.hs,
                FrictionModel::Infinite => fixed[d] = Real::INFINITY,
            }
        }
        let isotropic_coulomb = directions == 2
            && matches!(
                (prm.friction[0], prm.friction[1]),
                (FrictionModel::Coulomb { mu: m0 }, FrictionModel::Coulomb { mu: m1 }) if m0 == m1
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
        let coefficients = match raw {
            Some((rate, _)) => SoftCoefficients {
                bias_rate: rate,
                ..SoftCoefficients::RIGID
            },
            None if prm.softness == Some(0.0) => SoftCoefficients::RIGID,
            None => k.spring.coefficients(k.hs),
        };
        *lane(&mut self.bias_rate, l) = coefficients.bias_rate;
        *lane(&mut self.spring_relax, l) = if raw.is_some() { 1.0 } else { 0.0 };

        let (xa, xb) = positions;
        let (va, vb) = (states.vel[la], states.vel[lb]);
        let (fa, fb) = (states.forcing(la), states.forcing(lb));
        // The static world (slot 0) never moves: its anchor can be 0, which keeps the
        // separation exact however far from the origin the contact is.
        let anchor = |p: Vec3, x: Vec3, slot: usize| if slot == 0 { Vec3::ZERO } else { p - x };
        let warm = contact.warm_forces();
        for (j, point) in contact.points().iter().enumerate() {
            let pl = &mut self.p[j];
            let ra = anchor(point.position, xa, la);
            let rb = anchor(point.position, xb, lb);
            pl.r_a.set_lane(l, ra);
            pl.r_b.set_lane(l, rb);
            *lane(&mut pl.base_separation, l) = -point.penetration - n.dot(ra) + n.dot(rb);
            let kn = ma + mb + quad(ia, ra.cross(n)) + quad(ib, rb.cross(n));
            let k1 = ma + mb + quad(ia, ra.cross(t1)) + quad(ib, rb.cross(t1));
            let k2 = ma + mb + quad(ia, ra.cross(t2)) + quad(ib, rb.cross(t2));
            let normal_mass = if kn > 0.0 { 1.0 / kn } else { 0.0 };
            *lane(&mut pl.normal_mass, l) = normal_mass;
            let (soft_mass, soft_impulse) = match raw {
                Some((_, extra)) if kn > 0.0 => (1.0 / (kn + extra), extra / (kn + extra)),
                _ => (
                    normal_mass * coefficients.mass_scale,
                    coefficients.impulse_scale,
                ),
            };
            *lane(&mut pl.soft_mass, l) = soft_mass;
            *lane(&mut pl.soft_impulse, l) = soft_impulse;
            let kt = 0.5 * (k1 + k2);
            for d in 0..2 {
                let slip = prm.slip[d] / k.hs;
                let m = if kt > 0.0 { 1.0 / (kt + slip) } else { 0.0 };
                *lane(&mut pl.tangent_mass[d], l) = m;
            }
            // Warm start from the last step's impulses, within this step's bounds.
            let f = warm[j];
            let pn = (f.normal * k.hs).max(-prm.max_adhesive_force * k.hs);
            let mut pt = [f.friction.dot(t1) * k.hs, f.friction.dot(t2) * k.hs];
            for d in 0..2 {
                let limit = (mu[d] * pn).max(0.0) + fixed[d];
                pt[d] = pt[d].clamp(-limit, limit);
            }
            if isotropic_coulomb {
                let limit = (mu[0] * pn).max(0.0);
                let len = (pt[0] * pt[0] + pt[1] * pt[1]).sqrt();
                if len > limit {
                    let s = limit / len;
                    pt = [pt[0] * s, pt[1] * s];
                }
            }
            *lane(&mut pl.normal_impulse, l) = pn;
            *lane(&mut pl.tangent_impulse[0], l) = pt[0];
            *lane(&mut pl.tangent_impulse[1], l) = pt[1];
            let at = |v: Vec3, w: Vec3, r: Vec3| v + w.cross(r);
            let vn0 = n.dot(at(va.v, va.w, ra) - at(vb.v, vb.w, rb));
            let forcing = n.dot(at(fa.0, fa.1, ra) - at(fb.0, fb.1, rb));
            *lane(&mut pl.relative_velocity, l) = vn0;
            *lane(&mut pl.forcing, l) = forcing;
            *lane(&mut pl.approach, l) = 0.0;
            *lane(&mut pl.impact_substep, l) = 0.0;
            *lane(&mut pl.total_normal, l) = 0.0;
            *lane(&mut pl.total_tangent[0], l) = 0.0;
            *lane(&mut pl.total_tangent[1], l) = 0.0;
        }
    }
}
