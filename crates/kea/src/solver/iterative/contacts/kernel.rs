//! The contact kernels, written once over [`FloatW`] lanes: warm start, solve (biased or
//! relax) and restitution of one batch. Box2D v3's soft step over manifolds in 3D.
//!
//! Solve, per point, in impulse units (P = λ·hs):
//!
//! ```text
//!   s    = base + n·(Δx₁ − Δx₂) + (Δq₁⁻¹ n)·r₁ − (Δq₂⁻¹ n)·r₂   current separation
//!   vₙ   = n·(v₁ + ω₁×r₁ − v₂ − ω₂×r₂)                         relative normal velocity
//!   s > 0 (speculative):  bias = s/hs, rigid: the gap may close within the substep, no more
//!   biased solve:         bias = max(β·s, −v_push), mass scale and impulse scale of the spring
//!   relax solve:          bias = 0, rigid (so correcting penetration adds no kinetic energy)
//!   ΔPₙ  = −mₙ·mass_scale·(vₙ + bias) − impulse_scale·Pₙ,   Pₙ ← max(Pₙ + ΔPₙ, P_min)
//! ```
//!
//! Friction is solved in the relax pass only (Rapier's rule: friction that reacts to the bias
//! velocities pumps the lean of tall stacks until they fall), once per manifold between two
//! passes over its points' normals: first the twist about the normal, `P_τ ← clamp(P_τ − m_τ·n·(ω₁ − ω₂),
//! ±μ·Σ Pₙ·lever)`, then the friction at the centre: with `vₜ` the tangential velocity there
//! less the conveyor slide, `Pₜ ← Pₜ − mₜ(vₜ + slip·Pₜ)`, projected on the disc `|Pₜ| ≤ μ·ΣPₙ`
//! (isotropic Coulomb) or on each direction's own bound. The restitution pass,
//! once after the substeps, drives the normal velocity of every point that pushed in this step
//! and approached faster than the threshold to `−e` times its approach velocity: the relative
//! normal velocity at the step's start plus what gravity and applied forces added up to the
//! substep in which the point first pushed. So the bounce is right whatever the phase of the
//! impact in the step (Box2D v3 uses the step's start, so a speculative point that closes
//! late bounces without the speed gravity added meanwhile), and the points of a manifold that
//! lands flat bounce alike (none sees the others' impulses). The biased and relax solves take a
//! manifold's points first to last on even substeps and last to first on odd ones (symmetric
//! Gauss–Seidel over the step), so that an impact on a face leaves no moment to tip it.

use super::super::super::wide::{FloatW, Records, V3};
use super::batch::{gather_vel, ContactBatch, PointLanes, NEVER};
use crate::math::Real;

/// Step constants of the kernels.
#[derive(Debug, Clone, Copy)]
pub(crate) struct KernelParams {
    pub(crate) inv_hs: Real,
    /// Fastest push-out speed of the biased solve, m/s.
    pub(crate) max_push: Real,
    /// Index of the current substep (0 for the first).
    pub(crate) substep: Real,
    /// The last relax pass of the step (its normals answer the friction's torque again).
    pub(crate) closing: bool,
    /// No relax pass: the biased solve also solves friction.
    pub(crate) friction_in_solve: bool,
    /// Step and substep, s.
    pub(crate) h: Real,
    pub(crate) hs: Real,
}

/// Writes velocity and spin back to the lanes' bodies that may be written.
#[inline(always)]
fn scatter_vel<F: FloatW>(vel: Records<'_>, idx: &F::Index, write: &F::Index, v: V3<F>, w: V3<F>) {
    let zero = F::zero();
    F::scatter8(vel, idx, write, [v.x, v.y, v.z, w.x, w.y, w.z, zero, zero]);
}

/// Each lane body's displacement since the step began, and the contact normal as the anchor's
/// turn moves the separation to first order (`n + 2w·(n × u)` for the turn `(u, w)`).
///
/// First order on purpose: the solver's velocities move the separation exactly as much (the
/// relative normal velocity uses the same fixed anchors), so a curved surface that rolls
/// opens no phantom gap. The rigid turn `Δq⁻¹ n` would lift a rolling ball's anchor off the
/// slope by r(1 − cos ωh) within the step (3 mm at 3.5 m/s), and the ball would sink as much
/// and slip while its point read as a gap. For a sphere or a cylinder rolling on its side the
/// anchor is along the normal, so the turn does not move the separation at all, as it should.
#[inline(always)]
fn gather_delta<F: FloatW>(delta: Records<'_>, idx: &F::Index, n: V3<F>) -> (V3<F>, V3<F>) {
    let r = F::gather8(delta, idx);
    let dp = V3::new(r[0], r[1], r[2]);
    let u = V3::new(r[4], r[5], r[6]);
    let w = r[7];
    let turned = n.sub(u.cross(n).scale(F::splat(2.0) * w));
    (dp, turned)
}

/// The bodies of a batch, loaded.
struct Pair<F> {
    va: V3<F>,
    wa: V3<F>,
    vb: V3<F>,
    wb: V3<F>,
}

impl<F: FloatW> Pair<F> {
    #[inline(always)]
    fn load(c: &ContactBatch<F>, vel: Records<'_>) -> Self {
        let (va, wa) = gather_vel::<F>(vel, &c.body_a);
        let (vb, wb) = gather_vel::<F>(vel, &c.body_b);
        Self { va, wa, vb, wb }
    }

    #[inline(always)]
    fn store(self, c: &ContactBatch<F>, vel: Records<'_>) {
        scatter_vel(vel, &c.body_a, &c.write_a, self.va, self.wa);
        scatter_vel(vel, &c.body_b, &c.write_b, self.vb, self.wb);
    }

    /// Velocity of body 1 relative to body 2 at the point.
    #[inline(always)]
    fn relative(&self, ra: V3<F>, rb: V3<F>) -> V3<F> {
        self.va
            .add(self.wa.cross(ra))
            .sub(self.vb.add(self.wb.cross(rb)))
    }

    /// Applies angular impulse `l`: `+l` on body 1, `−l` on body 2.
    #[inline(always)]
    fn turn(&mut self, m: &Masses<F>, l: V3<F>) {
        self.wa = self.wa.add(m.ia.mul(l));
        self.wb = self.wb.sub(m.ib.mul(l));
    }

    /// Applies impulse `p` at the point: `+p` on body 1, `−p` on body 2.
    #[inline(always)]
    fn apply(&mut self, m: &Masses<F>, ra: V3<F>, rb: V3<F>, p: V3<F>) {
        self.va = self.va.add(p.scale(m.ma));
        self.wa = self.wa.add(m.ia.mul(ra.cross(p)));
        self.vb = self.vb.sub(p.scale(m.mb));
        self.wb = self.wb.sub(m.ib.mul(rb.cross(p)));
    }
}

/// The inverse masses of a batch, loaded.
struct Masses<F> {
    ma: F,
    mb: F,
    ia: super::super::super::wide::Sym3<F>,
    ib: super::super::super::wide::Sym3<F>,
}

impl<F: FloatW> Masses<F> {
    #[inline(always)]
    fn load(c: &ContactBatch<F>) -> Self {
        Self {
            ma: F::load(&c.inv_mass_a),
            mb: F::load(&c.inv_mass_b),
            ia: c.inv_inertia_a.load(),
            ib: c.inv_inertia_b.load(),
        }
    }
}

/// Re-applies each point's impulse of the last substep (or step), and the manifold's friction
/// and twist. From the second substep on, those impulses (the whole impulse of the substep
/// before) are added to the step's totals; the last substep's is added when the forces are
/// stored.
#[inline(always)]
pub(crate) fn warm_start<F: FloatW>(c: &mut ContactBatch<F>, vel: Records<'_>, k: &KernelParams) {
    let m = Masses::load(c);
    let mut bodies = Pair::load(c, vel);
    let n = c.normal.load();
    let t = [c.tangent[0].load(), c.tangent[1].load()];
    let accumulate = k.substep > 0.0;
    for p in c.p.iter_mut().take(c.points as usize) {
        let pn = F::load(&p.normal_impulse);
        if accumulate {
            (F::load(&p.total_normal) + pn).store(&mut p.total_normal);
        }
        bodies.apply(&m, p.r_a.load(), p.r_b.load(), n.scale(pn));
    }
    let pt = [
        F::load(&c.tangent_impulse[0]),
        F::load(&c.tangent_impulse[1]),
    ];
    let twist = F::load(&c.twist_impulse);
    if accumulate {
        for (total, p) in c.total_tangent.iter_mut().zip(pt) {
            (F::load(total) + p).store(total);
        }
        (F::load(&c.total_twist) + twist).store(&mut c.total_twist);
    }
    let friction = t[0].scale(pt[0]).add(t[1].scale(pt[1]));
    bodies.apply(&m, c.r_ca.load(), c.r_cb.load(), friction);
    bodies.turn(&m, n.scale(twist));
    bodies.store(c, vel);
}

/// Per-batch constants of the solve, loaded once.
struct Surface<F> {
    n: V3<F>,
    t: [V3<F>; 2],
    bias_rate: F,
    min_normal: F,
    spring_relax: F,
    disc: F,
    mu: [F; 2],
    fixed: [F; 2],
    slide: [F; 2],
    slip: [F; 2],
}

impl<F: FloatW> Surface<F> {
    #[inline(always)]
    fn load(c: &ContactBatch<F>) -> Self {
        Self {
            n: c.normal.load(),
            t: [c.tangent[0].load(), c.tangent[1].load()],
            bias_rate: F::load(&c.bias_rate),
            min_normal: F::load(&c.min_normal),
            spring_relax: F::load(&c.spring_relax),
            disc: F::load(&c.disc),
            mu: [F::load(&c.mu[0]), F::load(&c.mu[1])],
            fixed: [F::load(&c.fixed_limit[0]), F::load(&c.fixed_limit[1])],
            slide: [F::load(&c.slide[0]), F::load(&c.slide[1])],
            slip: [F::load(&c.slip[0]), F::load(&c.slip[1])],
        }
    }
}

/// One Gauss-Seidel pass over the batch: the biased solve of the normals (`use_bias`), or the
/// relax of the normals and then the friction.
#[inline(always)]
pub(crate) fn solve<F: FloatW>(
    c: &mut ContactBatch<F>,
    vel: Records<'_>,
    delta: Records<'_>,
    k: &KernelParams,
    use_bias: bool,
) {
    let m = Masses::load(c);
    let mut bodies = Pair::load(c, vel);
    let surface = Surface::load(c);
    // Only a batch that can bounce records when its points start pushing.
    let bouncy = F::any(F::load(&c.restitution).gt(F::zero()));
    let n = surface.n;
    let (dpa, na) = gather_delta::<F>(delta, &c.body_a, n);
    let (dpb, nb) = gather_delta::<F>(delta, &c.body_b, n);
    let moved = n.dot(dpa.sub(dpb));
    let (mut held, mut held_lever) = (F::zero(), F::zero());
    // A manifold's points in one order on even substeps and the reverse on odd ones: solved
    // always first to last, the first corners of a face landing flat took most of the impact
    // and left a moment that tipped a tall box over (`kea3d/tests/landing.rs`).
    let count = c.points as usize;
    let reverse = (k.substep as usize) % 2 == 1;
    for j in 0..count {
        let p = &mut c.p[if reverse { count - 1 - j } else { j }];
        let ra = p.r_a.load();
        let rb = p.r_b.load();
        let s = F::load(&p.base_separation) + moved + na.dot(ra) - nb.dot(rb);
        let (normal, total) = solve_normal(p, &surface, &bodies, ra, rb, s, k, use_bias, bouncy);
        bodies.apply(&m, ra, rb, n.scale(normal));
        let pushing = total.max(F::zero());
        held = held + pushing;
        held_lever = held_lever + pushing * F::load(&p.lever);
    }
    if !use_bias || k.friction_in_solve {
        solve_twist(c, &surface, &m, &mut bodies, held_lever);
        solve_friction(c, &surface, &m, &mut bodies, held);
        // Friction acts in the contact plane, below (or above) the centres of mass: the next
        // substep's normals answer its torque, and after the last one a second pass does, or
        // a box that stops sliding ends the step rocking on its leading edge.
        for p in
            c.p.iter_mut()
                .take(if k.closing { c.points as usize } else { 0 })
        {
            let ra = p.r_a.load();
            let rb = p.r_b.load();
            let s = F::load(&p.base_separation) + moved + na.dot(ra) - nb.dot(rb);
            let (normal, _) = solve_normal(p, &surface, &bodies, ra, rb, s, k, false, bouncy);
            bodies.apply(&m, ra, rb, n.scale(normal));
        }
    }
    bodies.store(c, vel);
}

/// The normal impulse of one point: updates the point and returns the change to apply and
/// the new accumulated impulse.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn solve_normal<F: FloatW>(
    p: &mut PointLanes<F>,
    sf: &Surface<F>,
    bodies: &Pair<F>,
    ra: V3<F>,
    rb: V3<F>,
    s: F,
    k: &KernelParams,
    use_bias: bool,
    bouncy: bool,
) -> (F, F) {
    let zero = F::zero();
    let vn = bodies.relative(ra, rb).dot(sf.n);
    let pn = F::load(&p.normal_impulse);
    let speculative = s.gt(zero);
    // Where the spring acts: the biased solve of every touching point, and the relax solve of
    // a contact with its own raw softness (a physical spring that keeps pushing); every other
    // solve is rigid, so correcting penetration adds no kinetic energy.
    let touching = s.le(zero);
    let spring_relax = sf.spring_relax.gt(F::splat(0.5));
    let soft = if use_bias {
        touching
    } else {
        F::and(spring_relax, touching)
    };
    let spring_bias = sf.bias_rate * s;
    let soft_bias = if use_bias {
        F::select(
            spring_relax,
            spring_bias,
            spring_bias.max(F::splat(-k.max_push)),
        )
    } else {
        spring_bias
    };
    let bias = F::select(
        speculative,
        s * F::splat(k.inv_hs),
        F::select(soft, soft_bias, zero),
    );
    let mass = F::select(soft, F::load(&p.soft_mass), F::load(&p.normal_mass));
    let scale = F::select(soft, F::load(&p.soft_impulse), zero);
    let new = (pn - mass * (vn + bias) - scale * pn).max(sf.min_normal);
    if bouncy {
        // The first substep in which the point pushes (a minimum, so the store is
        // unconditional: a masked store would be microcoded on some processors).
        let pushing = F::select(new.gt(zero), F::splat(k.substep), F::splat(NEVER));
        F::load(&p.impact_substep)
            .min(pushing)
            .store(&mut p.impact_substep);
    }
    new.store(&mut p.normal_impulse);
    (new - pn, new)
}

/// The twist about the normal, bounded by μ·Σ Pₙ·lever.
#[inline(always)]
fn solve_twist<F: FloatW>(
    c: &mut ContactBatch<F>,
    sf: &Surface<F>,
    m: &Masses<F>,
    bodies: &mut Pair<F>,
    held_lever: F,
) {
    let spin = sf.n.dot(bodies.wa.sub(bodies.wb));
    let old = F::load(&c.twist_impulse);
    let limit = F::splat(0.5) * (sf.mu[0] + sf.mu[1]) * held_lever + F::load(&c.twist_fixed);
    let new = (old - F::load(&c.twist_mass) * spin).min(limit).max(-limit);
    new.store(&mut c.twist_impulse);
    bodies.turn(m, sf.n.scale(new - old));
}

/// The friction at the centre, bounded by the manifold's normal impulse `held`.
#[inline(always)]
fn solve_friction<F: FloatW>(
    c: &mut ContactBatch<F>,
    sf: &Surface<F>,
    m: &Masses<F>,
    bodies: &mut Pair<F>,
    held: F,
) {
    let zero = F::zero();
    let one = F::splat(1.0);
    let (ra, rb) = (c.r_ca.load(), c.r_cb.load());
    let dv = bodies.relative(ra, rb);
    let pt = [
        F::load(&c.tangent_impulse[0]),
        F::load(&c.tangent_impulse[1]),
    ];
    let r = [
        dv.dot(sf.t[0]) - sf.slide[0] + sf.slip[0] * pt[0],
        dv.dot(sf.t[1]) - sf.slide[1] + sf.slip[1] * pt[1],
    ];
    let trial = [
        pt[0] - F::load(&c.tangent_mass[0]) * r[0],
        pt[1] - F::load(&c.tangent_mass[1]) * r[1],
    ];
    let limit = [sf.mu[0] * held + sf.fixed[0], sf.mu[1] * held + sf.fixed[1]];
    let len = (trial[0] * trial[0] + trial[1] * trial[1]).sqrt();
    let shrink = F::select(len.gt(limit[0]), limit[0] / len, one);
    let disc = sf.disc.gt(F::splat(0.5));
    let mut dt = [zero; 2];
    for d in 0..2 {
        let boxed = trial[d].min(limit[d]).max(-limit[d]);
        let clamped = F::select(disc, trial[d] * shrink, boxed);
        dt[d] = clamped - pt[d];
        clamped.store(&mut c.tangent_impulse[d]);
    }
    let impulse = sf.t[0].scale(dt[0]).add(sf.t[1].scale(dt[1]));
    bodies.apply(m, ra, rb, impulse);
}

/// The restitution pass of one batch (module docs). A bounce belongs to the moment of impact:
/// the bodies also travel with their change of velocity for what remains of the step after
/// the substep in which the point first pushed (for an impact at the step's start, the whole
/// step, as in the exact path).
#[inline(always)]
pub(crate) fn restitution<F: FloatW>(
    c: &mut ContactBatch<F>,
    vel: Records<'_>,
    delta: Records<'_>,
    k: &KernelParams,
) {
    let e = F::load(&c.restitution);
    let threshold = -F::load(&c.restitution_threshold);
    let zero = F::zero();
    if !F::any(e.gt(zero)) {
        return;
    }
    let m = Masses::load(c);
    let mut bodies = Pair::load(c, vel);
    let n = c.normal.load();
    let min_normal = F::load(&c.min_normal);
    let mut travel_a = V3::new(zero, zero, zero);
    let mut travel_b = travel_a;
    for p in c.p.iter_mut().take(c.points as usize) {
        let impact = F::load(&p.impact_substep);
        let approach = F::load(&p.relative_velocity) + F::load(&p.forcing) * impact;
        let pushed = impact.lt(F::splat(NEVER));
        let bounce = F::and(F::and(e.gt(zero), approach.lt(threshold)), pushed);
        if !F::any(bounce) {
            continue;
        }
        let ra = p.r_a.load();
        let rb = p.r_b.load();
        let vn = bodies.relative(ra, rb).dot(n);
        let pn = F::load(&p.normal_impulse);
        let mass = F::select(bounce, F::load(&p.normal_mass), zero);
        // The bounce is kept apart from the substep's impulse, which warm-starts the next step.
        let new = (pn - mass * (vn + e * approach)).max(min_normal);
        let dn = new - pn;
        dn.store(&mut p.bounce);
        bodies.apply(&m, ra, rb, n.scale(dn));
        let remaining = F::splat(k.h) - impact * F::splat(k.hs);
        travel_a = travel_a.add(n.scale(m.ma * dn * remaining));
        travel_b = travel_b.sub(n.scale(m.mb * dn * remaining));
    }
    bodies.store(c, vel);
    displace(delta, &c.body_a, &c.write_a, travel_a);
    displace(delta, &c.body_b, &c.write_b, travel_b);
}

/// Adds a displacement to the lanes' bodies that may be written.
#[inline(always)]
fn displace<F: FloatW>(delta: Records<'_>, idx: &F::Index, write: &F::Index, d: V3<F>) {
    let mut a: [F::Array; 3] = Default::default();
    d.x.store(&mut a[0]);
    d.y.store(&mut a[1]);
    d.z.store(&mut a[2]);
    for (l, (&i, &ok)) in idx.as_ref().iter().zip(write.as_ref()).enumerate() {
        if ok != 0 {
            let mut s = delta.get(i);
            for k in 0..3 {
                s[k] += a[k].as_ref()[l];
            }
            delta.set(i, s);
        }
    }
}

/// Reads a lane's point back as normal impulses: the last substep's (the next step's warm
/// start) and the whole step's (every substep's and the bounce).
pub(crate) fn lane_normal<F: FloatW>(p: &PointLanes<F>, l: usize) -> (Real, Real) {
    let now = p.normal_impulse.as_ref()[l];
    (now, p.total_normal.as_ref()[l] + now + p.bounce.as_ref()[l])
}

/// Reads a lane's manifold friction back as impulses (tangent 1, tangent 2, twist): the last
/// substep's and the whole step's.
pub(crate) fn lane_friction<F: FloatW>(c: &ContactBatch<F>, l: usize) -> ([Real; 3], [Real; 3]) {
    let now = [
        c.tangent_impulse[0].as_ref()[l],
        c.tangent_impulse[1].as_ref()[l],
        c.twist_impulse.as_ref()[l],
    ];
    (
        now,
        [
            c.total_tangent[0].as_ref()[l] + now[0],
            c.total_tangent[1].as_ref()[l] + now[1],
            c.total_twist.as_ref()[l] + now[2],
        ],
    )
}
