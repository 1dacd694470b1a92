//! Contacts of a tree's links with its base (the ground a robot stands on), in joint space, by
//! MuJoCo's soft contact model: the tree stays in reduced coordinates while it touches.
//!
//! A contact is a point fixed on a link, a unit normal `n` (base frame, the way the base — or
//! a second link of the tree — pushes the link) and the signed distance `r` along it at the
//! step's start (negative: overlap). At the coordinates `q` of an evaluation the point is at
//! `p(q)` (less the other link's point, between links) and the distance is
//! `r + n·(p(q) − p(q₀))`. Within the model's margin the contact gives rows `J = dᵀ J_p(q)` on
//! the rates, `J_p` the point's velocity Jacobian (`Σ_j (s_j × (p − a_j)) q̇_j` over its
//! link's hinges from the root, `s_j q̇_j` for sliders) and `d` the edges of MuJoCo's pyramidal
//! friction cone, `n ± μ t₁`, `n ± μ t₂` (the normal alone without friction). Each row's force
//! `f ≥ 0` joins the soft stops' problem (`soft_limits.rs`):
//! `min ½ fᵀ (A + R) f + fᵀ (J q̈₀ − a_ref)` with `A = J H'⁻¹ Jᵀ`,
//! `a_ref = −b J q̇ − k·imp(x)·x` at `x = r − margin`, `b = 2/(d_max τ)`,
//! `k = 1/(d_max² τ² ζ²)` (τ at least two steps), `R = (1 − imp)/imp · A`, and on a pyramid
//! every edge `2μ²` times its first edge's `R` (MuJoCo's match of the elliptic cone's friction
//! impedance) — the soft stops' formulas with the contact's `solref`/`solimp`, solved together
//! with the soft stops as one small LCP by the exact dense solver (`solve_rows_exactly`), so
//! a foot on the ground and a knee on its stop hold together. It runs inside every evaluation
//! of the accelerations (the four stages of Runge–Kutta each), and the force a contact
//! passes in a step is the integrator's weighted mean of its evaluations'.

use super::soft_limits::{impedance, reference_gains};
use super::{ArticulatedTree, TreeJointKind};
use crate::error::{KeaError, KeaResult};
use crate::math::wide;
use crate::solver::sparse::dot_lanes as dot;
use crate::solver::sparse::lcp_dense::{self, Bound, LcpWorkspace, Unknowns};
use crate::SoftLimit;
use glam::{DMat3, DVec3};

/// Pivoting iterations the exact solve of an evaluation's rows may take.
const LCP_ITERATIONS: u32 = 50;

/// A contact of one of a tree's links with its base (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreeContact {
    /// The link touched.
    pub link: usize,
    /// The contact point, in the link's frame.
    pub point: DVec3,
    /// Unit normal in the base's frame: the direction the base pushes the link.
    pub normal: DVec3,
    /// Signed distance along the normal at the coordinates the next step starts from, m
    /// (negative: overlapping).
    pub distance: f64,
    /// Coulomb friction coefficient μ ≥ 0 (0: frictionless, the normal row alone).
    pub friction: f64,
    /// A contact between two of the tree's links: the other link (pushed along `−normal`)
    /// and the point on it, in its frame. `None`: the base.
    pub other: Option<(usize, DVec3)>,
    /// The contact's force on the link in the last step, base frame, N (zero for a new one):
    /// the solve's first guess of which of its rows push (a warm start, so it changes how
    /// fast the step is found, not what it is).
    pub warm: DVec3,
}

/// One row of a contact in the evaluation in flight: its contact and edge direction (base
/// frame), MuJoCo's reference acceleration and regulariser, the force,
/// and where its `J` and `L⁻ᵀJᵀ` sit in the scratch (`2n` numbers from `at`, `H' = LᵀL`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct ContactRow {
    contact: usize,
    direction: DVec3,
    reference: f64,
    regulariser: f64,
    force: f64,
    at: usize,
}

/// What a tree keeps for its contacts: the contacts, their model, where each point was at the
/// step's start, each one's mean force over the last step, and the evaluations' scratch.
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct ContactState {
    contacts: Vec<TreeContact>,
    model: SoftLimit,
    origin: Vec<DVec3>,
    /// Each contact's mean force on its link over the last step, base frame, N.
    force: Vec<DVec3>,
    /// The weight of the evaluation in flight in the step's mean (Runge–Kutta's `b_k`).
    pub(super) weight: f64,
    pub(super) rows: Vec<ContactRow>,
    jw: Vec<f64>,
    /// One point's `J` and `L⁻ᵀJᵀ` along its normal and tangents (`2n` numbers each).
    point: Vec<f64>,
    /// Each link's rotation and origin in the base's frame at the evaluation's coordinates.
    rot: Vec<DMat3>,
    pos: Vec<DVec3>,
    /// The exact solve's system (stops' rows first, then the contacts'), and its scratch.
    lcp: LcpSystem,
}

/// The dense LCP of an evaluation's soft rows: `(A + R) f − b ≥ 0`, `f ≥ 0`, complementary.
#[derive(Debug, Clone, Default)]
struct LcpSystem {
    a: Vec<f64>,
    b: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    f: Vec<f64>,
    w: Vec<f64>,
    state: Vec<Bound>,
    /// Each row's `J` and `L⁻ᵀJᵀ` (`2n` numbers a row), regulariser, and `Jᵀ f`.
    jw: Vec<f64>,
    reg: Vec<f64>,
    push: Vec<f64>,
    ws: LcpWorkspace,
}

impl PartialEq for LcpSystem {
    fn eq(&self, _: &Self) -> bool {
        true // scratch: no part of a tree's state
    }
}

impl ContactState {
    /// Forgets the contacts (the links they named changed).
    pub(super) fn clear(&mut self) {
        self.contacts.clear();
        self.force.clear();
    }

    /// Asks for the cache lines an evaluation's contacts read (`crate::prefetch`).
    pub(super) fn prefetch(&self) {
        use crate::prefetch::slice;
        slice(&self.contacts);
        slice(&self.origin);
        slice(&self.force);
        slice(&self.rot);
        slice(&self.pos);
        slice(&self.rows);
        slice(&self.jw);
        slice(&self.point);
        let s = &self.lcp;
        for v in [&s.a, &s.b, &s.lo, &s.hi, &s.f, &s.w, &s.jw, &s.reg, &s.push] {
            slice(v);
        }
        slice(&s.state);
    }

    /// Whether the tree has no contact.
    pub(super) fn is_empty(&self) -> bool {
        self.contacts.is_empty()
    }
}

impl ArticulatedTree {
    /// Sets the contacts of the steps that follow (replacing any before) and the soft model
    /// they are solved by (its `solref`, `solimp` and `margin`). Errors name the contact and
    /// the field: a link outside the tree, a normal not of unit length, a non-finite point or
    /// distance, a negative friction.
    pub fn set_contacts(&mut self, contacts: &[TreeContact], model: SoftLimit) -> KeaResult<()> {
        model.validate()?;
        self.set_contacts_by_valid_model(contacts, model)
    }

    /// [`ArticulatedTree::set_contacts`] with a model already checked (a world's settings are
    /// checked when set, not at every substep).
    pub(crate) fn set_contacts_by_valid_model(
        &mut self,
        contacts: &[TreeContact],
        model: SoftLimit,
    ) -> KeaResult<()> {
        for (k, c) in contacts.iter().enumerate() {
            let bad = |arg: &'static str, value: String, expected: &'static str| {
                Err(KeaError::OutOfRange {
                    arg,
                    value: format!("contact {k}: {value}"),
                    expected,
                })
            };
            if c.link >= self.len() || c.other.is_some_and(|(o, _)| o >= self.len() || o == c.link)
            {
                return bad(
                    "link",
                    format!("{} / {:?}", c.link, c.other.map(|o| o.0)),
                    "links of the tree, two different ones for a contact between links",
                );
            }
            if c.other.is_some_and(|(_, p)| !p.is_finite()) {
                return bad("point", format!("{:?}", c.other), "a finite point");
            }
            if !(c.point.is_finite() && c.distance.is_finite()) {
                return bad(
                    "point",
                    format!("{} / {}", c.point, c.distance),
                    "a finite point and distance",
                );
            }
            if !c.normal.is_finite() || (c.normal.length() - 1.0).abs() >= 1e-6 {
                return bad("normal", c.normal.to_string(), "a unit vector");
            }
            if !(c.friction >= 0.0 && c.friction.is_finite()) {
                return bad("friction", c.friction.to_string(), "a finite μ >= 0");
            }
            if !c.warm.is_finite() {
                return bad("warm", c.warm.to_string(), "a finite force");
            }
        }
        let s = &mut self.contact;
        s.contacts.clear();
        s.contacts.extend_from_slice(contacts);
        s.model = model;
        s.force.clear();
        s.force.resize(contacts.len(), DVec3::ZERO);
        Ok(())
    }

    /// Each contact's mean force on its link over the last step, base frame, N (in the order
    /// [`ArticulatedTree::set_contacts`] gave them).
    #[must_use]
    pub fn contact_forces(&self) -> &[DVec3] {
        &self.contact.force
    }

    /// At a step's start (coordinates `q`): where each contact point is, and no force yet.
    pub(super) fn start_contacts(&mut self, q: &[f64]) {
        if self.contact.is_empty() {
            return;
        }
        self.place(q);
        self.link_frames();
        let s = &mut self.contact;
        s.origin.clear();
        for c in &s.contacts {
            s.origin.push(separation(s, c));
        }
        s.force.iter_mut().for_each(|f| *f = DVec3::ZERO);
        s.weight = 1.0;
    }

    /// Each link's rotation and origin in the base's frame from the placements `place` left.
    fn link_frames(&mut self) {
        let n = self.len();
        let s = &mut self.contact;
        s.rot.resize(n, DMat3::IDENTITY);
        s.pos.resize(n, DVec3::ZERO);
        for i in 0..n {
            let local = self.rot[i].transpose();
            (s.rot[i], s.pos[i]) = match self.model.parents[i] {
                Some(p) => (s.rot[p] * local, s.pos[p] + s.rot[p] * self.pos[i]),
                None => (local, self.pos[i]),
            };
        }
    }

    /// The rows of the contacts within their margin at rates `qd` (module docs), with their
    /// `J` and `L⁻ᵀJᵀ`; the evaluation's `assemble` must have placed the links and left the
    /// factor of `H'` in `h`.
    pub(super) fn contact_rows(&mut self, qd: &[f64], step: f64) {
        self.contact.rows.clear();
        if self.contact.is_empty() {
            return;
        }
        self.link_frames();
        let n = self.len();
        let model = self.contact.model;
        let margin = wide(model.margin);
        let (b, k_stiff) = reference_gains(&model, step);
        let mut jw = std::mem::take(&mut self.contact.jw);
        let mut point = std::mem::take(&mut self.contact.point);
        let mut rows = std::mem::take(&mut self.contact.rows);
        jw.clear();
        for c in 0..self.contact.contacts.len() {
            let contact = self.contact.contacts[c];
            let s = &self.contact;
            let p = s.pos[contact.link] + s.rot[contact.link] * contact.point;
            let distance =
                contact.distance + contact.normal.dot(separation(s, &contact) - s.origin[c]);
            if distance >= margin {
                continue;
            }
            let x = distance - margin;
            let imp = impedance(&model, x);
            let n_dir = contact.normal;
            let (t1, t2) = n_dir.any_orthonormal_pair();
            let mu = contact.friction;
            let edges = [
                n_dir + t1 * mu,
                n_dir - t1 * mu,
                n_dir + t2 * mu,
                n_dir - t2 * mu,
            ];
            let used = if mu > 0.0 { &edges[..] } else { &edges[..1] };
            // MuJoCo's pyramid: every edge takes the regulariser `2μ²·R` of its first edge,
            // which matches the elliptic cone's friction impedance; without friction, `R`.
            let cone = if mu > 0.0 { 2.0 * mu * mu } else { 1.0 };
            let first_row = rows.len();
            // The point's velocity along n, t₁ and t₂ per coordinate (less the other link's
            // point's, between links) and their halves `L⁻ᵀJᵀ`, once: each edge is `J_n ± μ J_t`.
            let basis = [n_dir, t1, t2];
            let dirs = if mu > 0.0 { 3 } else { 1 };
            self.point_bases(&contact, p, &basis[..dirs], &mut point);
            for (k, &d) in used.iter().enumerate() {
                let at = jw.len();
                jw.resize(at + 2 * n, 0.0);
                // Edge k: the normal's halves plus or minus μ times a tangent's.
                let (t, sign) = match k {
                    0 => (1, mu),
                    1 => (1, -mu),
                    2 => (2, mu),
                    _ => (2, -mu),
                };
                for i in 0..2 * n {
                    let tangent = if dirs > 1 { point[2 * n * t + i] } else { 0.0 };
                    jw[at + i] = point[i] + sign * tangent;
                }
                let velocity = dot(&jw[at..at + n], qd);
                rows.push(ContactRow {
                    contact: c,
                    direction: d,
                    reference: -b * velocity - k_stiff * imp * x,
                    regulariser: 0.0,
                    force: 0.0,
                    at,
                });
            }
            // The first edge's `R = (1 − imp)/imp · A` (A = |L⁻ᵀJᵀ|²) for every edge.
            let at = rows[first_row].at;
            let y = &jw[at + n..at + 2 * n];
            let common = (1.0 - imp) / imp * dot(y, y) * cone;
            for row in &mut rows[first_row..] {
                row.regulariser = common;
            }
        }
        self.contact.jw = jw;
        self.contact.point = point;
        self.contact.rows = rows;
    }

    /// A contact point's velocity along each of `basis` per coordinate (less the other link's
    /// point's, between links), its `J`, and its half `L⁻ᵀJᵀ`, into `point` (`2n` numbers a
    /// direction); the links' frames must be in the scratch (`link_frames`).
    fn point_bases(&self, contact: &TreeContact, p: DVec3, basis: &[DVec3], point: &mut Vec<f64>) {
        let n = self.len();
        let s = &self.contact;
        point.clear();
        point.resize(2 * basis.len() * n, 0.0);
        let mut sides = [(contact.link, p, 1.0), (contact.link, p, 0.0)];
        if let Some((o, at)) = contact.other {
            sides[1] = (o, s.pos[o] + s.rot[o] * at, -1.0);
        }
        for (start, at_point, sign) in sides {
            if sign == 0.0 {
                continue;
            }
            let mut j = Some(start);
            while let Some(l) = j {
                let link = &self.model.links[l];
                let axis = s.rot[l] * link.axis;
                let lin = match link.kind {
                    TreeJointKind::Hinge => {
                        axis.cross(at_point - (s.pos[l] + s.rot[l] * link.anchor))
                    }
                    TreeJointKind::Slider => axis,
                };
                for (e, d) in basis.iter().enumerate() {
                    point[2 * n * e + l] += sign * d.dot(lin);
                }
                j = link.parent;
            }
        }
        for e in 0..basis.len() {
            let (row, y) = point[2 * n * e..2 * n * (e + 1)].split_at_mut(n);
            y.copy_from_slice(row);
            if contact.other.is_some() {
                self.half_solve_h(y);
            } else {
                self.half_solve_h_path(contact.link, y);
            }
        }
    }

    /// The soft stops', the tendons' ranges' and the contacts' rows solved together exactly
    /// (module docs): the soft stops' rows (`J = ±e_i`) first, then the tendons'
    /// (`tendons.rs`), then the contacts'; `qdd` gets `H'⁻¹ Jᵀ f`.
    pub(super) fn solve_rows_exactly(&mut self, qdd: &mut [f64]) {
        let n = self.len();
        let stops = self.stop_rows();
        let tendons = self.tendon.rows.len();
        let singles = stops + tendons;
        let m = singles + self.contact.rows.len();
        let mut sys = std::mem::take(&mut self.contact.lcp);
        // The stops' rows (zero but on their coordinate's path), the tendons', then the
        // contacts' as `contact_rows` left them, in row order.
        sys.jw.clear();
        sys.jw.resize(2 * n * singles, 0.0);
        sys.jw.extend_from_slice(&self.contact.jw);
        sys.b.clear();
        sys.reg.clear();
        for r in 0..stops {
            let (i, sign, reference, reg) = self.stop_row(r);
            let (j, y) = sys.jw[2 * n * r..2 * n * (r + 1)].split_at_mut(n);
            j[i] = sign;
            y[i] = sign;
            self.half_solve_h_path(i, y);
            sys.b.push(reference - sign * qdd[i]);
            // MuJoCo's regulariser scales with the row's own `[H'⁻¹]ᵢᵢ = |L⁻ᵀeᵢ|²`.
            sys.reg.push(reg * dot(y, y));
        }
        for (k, row) in self.tendon.rows.iter().enumerate() {
            let r = stops + k;
            let (j, y) = sys.jw[2 * n * r..2 * n * (r + 1)].split_at_mut(n);
            for &(i, c) in self.tendon.terms(row.tendon) {
                j[i] += row.sign * c;
            }
            y.copy_from_slice(j);
            self.half_solve_h(y);
            sys.b.push(row.reference - dot(j, qdd));
            sys.reg.push(row.regulariser * dot(y, y));
        }
        for (k, row) in self.contact.rows.iter().enumerate() {
            debug_assert_eq!(row.at, 2 * n * k, "contact rows lie in order");
            let j = &self.contact.jw[row.at..row.at + n];
            sys.b.push(row.reference - dot(j, qdd));
            sys.reg.push(row.regulariser);
        }
        sys.a.clear();
        sys.a.resize(m * m, 0.0);
        // A = J H'⁻¹ Jᵀ = (L⁻ᵀJᵀ)ᵀ(L⁻ᵀJᵀ): symmetric by construction.
        for (r, reg) in sys.reg.iter().enumerate() {
            let yr = &sys.jw[2 * n * r + n..2 * n * (r + 1)];
            for c in 0..=r {
                let yc = &sys.jw[2 * n * c + n..2 * n * (c + 1)];
                let v = dot(yr, yc);
                sys.a[r * m + c] = v;
                sys.a[c * m + r] = v;
            }
            sys.a[r * m + r] += reg;
        }
        for v in [&mut sys.lo, &mut sys.f, &mut sys.w] {
            v.clear();
            v.resize(m, 0.0);
        }
        sys.hi.clear();
        sys.hi.resize(m, f64::INFINITY);
        self.guess_sets(&mut sys, singles, m);
        let mut u = Unknowns {
            lo: &mut sys.lo,
            hi: &mut sys.hi,
            x: &mut sys.f,
            w: &mut sys.w,
            state: &mut sys.state,
        };
        lcp_dense::solve(m, (&sys.a, &sys.b), &mut u, &mut sys.ws, LCP_ITERATIONS);
        // q̈ += H'⁻¹ Jᵀ f: one solve for all rows.
        sys.push.clear();
        sys.push.resize(n, 0.0);
        for r in 0..m {
            let f = if sys.f[r].is_finite() {
                sys.f[r].max(0.0)
            } else {
                0.0
            };
            if f != 0.0 {
                let j = &sys.jw[2 * n * r..2 * n * r + n];
                for (p, jk) in sys.push.iter_mut().zip(j) {
                    *p += jk * f;
                }
            }
            if r >= singles {
                self.contact.rows[r - singles].force = f;
            }
        }
        self.solve_h(&mut sys.push);
        for (acc, p) in qdd.iter_mut().zip(&sys.push) {
            *acc += p;
        }
        self.contact.lcp = sys;
    }

    /// The exact solve's starting sets (`singles`: the stops' and tendons' rows, before the
    /// contacts').
    fn guess_sets(&self, sys: &mut LcpSystem, singles: usize, m: usize) {
        // The last evaluation's sets are the guess while the rows are as many (the stages of
        // Runge-Kutta, and the steps of a robot at rest: one pivot an evaluation); otherwise
        // a stop pushes where the motion without it breaks its reference and a contact's edge
        // where its last step's force leaned on it. The guess changes how fast the solution
        // is found, not which: with every row regularised the problem is strictly convex, its
        // solution and so its final sets unique (the free rows' values come from those sets
        // alone), so a world restored from a snapshot, whose scratch starts empty, steps on
        // the same bits.
        if sys.state.len() == m {
            return;
        }
        sys.state.clear();
        for r in 0..singles {
            // A stop pushes if the motion without it would break its reference.
            let pushing = sys.b[r] > 0.0;
            sys.state
                .push(if pushing { Bound::Free } else { Bound::Lower });
        }
        for row in &self.contact.rows {
            let warm = self.contact.contacts[row.contact].warm;
            let pushing = warm.dot(row.direction) > 0.0;
            sys.state
                .push(if pushing { Bound::Free } else { Bound::Lower });
        }
    }

    /// Adds the evaluation's contact forces, at its weight, to the step's mean.
    pub(super) fn record_contact_forces(&mut self) {
        let s = &mut self.contact;
        for row in &s.rows {
            s.force[row.contact] += row.direction * (row.force * s.weight);
        }
    }

    /// The contacts' mean forces as wrenches on their links (link coordinates at the step's
    /// start: torque about the origin, force) added to `external`, for the reactions; the
    /// links' base frames at the step's start must be in the scratch (`start_contacts`).
    pub(super) fn add_contact_wrenches(&mut self, q_start: &[f64]) {
        if self.contact.is_empty() {
            return;
        }
        self.place(q_start);
        self.link_frames();
        let s = &self.contact;
        for (c, f) in s.contacts.iter().zip(&s.force) {
            let mut sides = [(c.link, c.point, *f), (c.link, c.point, DVec3::ZERO)];
            if let Some((o, point)) = c.other {
                sides[1] = (o, point, -*f);
            }
            for (l, point, f) in sides {
                let local = s.rot[l].transpose() * f;
                let [n, force] = &mut self.external[l];
                *n += point.cross(local);
                *force += local;
            }
        }
    }
}

/// Where a contact's point on its link is from its point on the other side (the base's: the
/// origin), base frame, at the frames in the scratch.
fn separation(s: &ContactState, c: &TreeContact) -> DVec3 {
    let p = s.pos[c.link] + s.rot[c.link] * c.point;
    match c.other {
        Some((o, point)) => p - (s.pos[o] + s.rot[o] * point),
        None => p,
    }
}
