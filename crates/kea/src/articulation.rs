//! Reduced-coordinate dynamics of a tree of hinges and sliders hanging from a fixed base: the
//! core of the articulated path robots will be stepped by (a robot arm's 7 coordinates instead
//! of its 42 constraint rows). Callable on its own, like the guide's immediate-mode solver.
//!
//! # The math (Featherstone's spatial algebra, in `f64`)
//!
//! Each link `i` has a frame that moves with it; its joint places it in its parent's frame at
//! `origin_i ∘ J_i(q_i)`, where `J_i` turns by `q_i` about the unit axis `s_i` through the point
//! `a_i` (a hinge) or moves by `q_i` along `s_i` (a slider), both in the link's frame. Spatial
//! motion vectors are `[ω; v]` (v: the velocity of the frame's origin), force vectors `[n; f]`
//! (n: the moment about the origin), both in link coordinates. The joint's motion subspace is
//! `S_i = [s_i; a_i × s_i]` for a hinge and `[0; s_i]` for a slider.
//!
//! * **Joint-space inertia** `H(q)` by composite rigid bodies: each link's inertia summed into
//!   its parent's (composites of rigid bodies are rigid-body inertias: a mass, a centre and a
//!   rotational inertia, moved by the parallel-axis theorem), then
//!   `H_ij = S_jᵀ X*_{j←i} I^c_i S_i` along the path from `i` to the root.
//! * **Bias forces** `c(q, q̇)` (Coriolis, centrifugal and gravity) by recursive Newton–Euler
//!   with `q̈ = 0` and the base accelerating at `−g`: velocities and accelerations outwards,
//!   `f_i = I_i a_i + v_i ×* I_i v_i`, then `c_i = S_iᵀ f_i` inwards.
//! * **A step** of `h` is semi-implicit Euler with each joint's armature `a` and damping `d`
//!   taken implicitly: `(H' = H + diag(a + h d)) q̈ = τ − c − d q̇`, `q̇ ← q̇ + h q̈`; then the
//!   coordinates' servos are implicit the same way (`kp (q* − q − h q̇⁺) + kv (v* − q̇⁺)`, its
//!   `q̈` terms in `H'`); their stops, motors and dry friction act as impulses `P` on the rates,
//!   `q̇⁺ = q̇ + H'⁻¹ P`, each within its bounds (a stop pushes one way only, a motor up to its
//!   force times `h`), found by projected Gauss–Seidel on `H'⁻¹`; and `q⁺ = q + h q̇⁺` — the
//!   discretisation of MuJoCo's Euler integrator, with hard stops.

use crate::error::{KeaError, KeaResult};
use glam::{DMat3, DQuat, DVec3};

/// How a joint of the tree moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TreeJointKind {
    /// Turns about its axis through its anchor.
    Hinge,
    /// Slides along its axis.
    Slider,
}

/// One link of the tree with the joint that carries it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreeLink {
    /// The parent link (an index below this one), or `None` for a link on the fixed base.
    pub parent: Option<usize>,
    /// The joint's kind.
    pub kind: TreeJointKind,
    /// The link's frame in its parent's (or the base's) at `q = 0`: translation, rotation.
    pub origin: (DVec3, DQuat),
    /// The joint's unit axis, in the link's frame.
    pub axis: DVec3,
    /// A hinge's point, in the link's frame.
    pub anchor: DVec3,
    /// Mass, kg (> 0).
    pub mass: f64,
    /// Centre of mass, in the link's frame.
    pub com: DVec3,
    /// Rotational inertia about the centre of mass, link axes.
    pub inertia: DMat3,
    /// Armature: inertia added on the coordinate.
    pub armature: f64,
    /// Viscous damping on the coordinate.
    pub damping: f64,
    /// Hard stops on the coordinate (lower, upper), rad or m.
    pub limits: Option<(f64, f64)>,
    /// A motor: target rate and largest force or torque (≥ 0).
    pub motor: Option<(f64, f64)>,
    /// Dry friction: the coordinate holds until pushed harder than this (≥ 0).
    pub friction: f64,
    /// A servo: stiffness kp towards a position and gain kv towards a rate, implicit in the
    /// step (`(position, rate, kp, kv)`, gains ≥ 0).
    pub servo: Option<(f64, f64, f64, f64)>,
    /// Fastest a stop pushes back a coordinate found beyond it, rad/s or m/s (`INFINITY`: a
    /// fifth of the overshoot per step, as the maximal-coordinate path's stops do).
    pub stop_recovery_speed: f64,
}

impl Default for TreeLink {
    /// A 1 kg hinge about z on the base, its centre at its origin, unit inertia, nothing else.
    fn default() -> Self {
        Self {
            parent: None,
            kind: TreeJointKind::Hinge,
            origin: (DVec3::ZERO, DQuat::IDENTITY),
            axis: DVec3::Z,
            anchor: DVec3::ZERO,
            mass: 1.0,
            com: DVec3::ZERO,
            inertia: DMat3::IDENTITY,
            armature: 0.0,
            damping: 0.0,
            limits: None,
            motor: None,
            friction: 0.0,
            servo: None,
            stop_recovery_speed: f64::INFINITY,
        }
    }
}

impl Default for ArticulatedTree {
    /// A tree with no link, under no gravity.
    fn default() -> Self {
        Self::empty(DVec3::ZERO)
    }
}

/// A fraction of a stop's overshoot taken back per step (the maximal path's `γ` for stops).
const STOP_RECOVERY: f64 = 0.2;

/// A tree of links on a fixed base, in reduced coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct ArticulatedTree {
    links: Vec<TreeLink>,
    /// Gravity in the base's frame, m/s².
    gravity: DVec3,
    // Scratch, reused every call: per link its transform from the parent (E, r), spatial
    // velocity and acceleration, force, composite inertia.
    rot: Vec<DMat3>,
    pos: Vec<DVec3>,
    vel: Vec<[DVec3; 2]>,
    acc: Vec<[DVec3; 2]>,
    force: Vec<[DVec3; 2]>,
    composite: Vec<(f64, DVec3, DMat3)>,
    h: Vec<f64>,
    rhs: Vec<f64>,
    /// `H'⁻¹`, row-major, for the constraint solve.
    inverse: Vec<f64>,
    column: Vec<f64>,
    /// The coordinates' constraint rows this step, and each coordinate's impulse.
    rows: Vec<CoordinateRow>,
    impulse: Vec<f64>,
    /// Applied wrenches on the links, link coordinates: `[torque about the origin; force]`.
    external: Vec<[DVec3; 2]>,
    /// The rates at the start of the last step.
    rate0: Vec<f64>,
    /// Each link's frame in the base's after [`ArticulatedTree::forward`].
    frames: Vec<(DVec3, DQuat)>,
    /// The coordinates `rot` and `pos` were placed at, while the links' geometry is unchanged.
    placed: Vec<f64>,
    placed_valid: bool,
}

/// One constraint on one coordinate's rate after the step: the rate aimed at, and the
/// impulse's bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
struct CoordinateRow {
    coordinate: usize,
    target: f64,
    lo: f64,
    hi: f64,
    impulse: f64,
}

/// A rigid-body inertia `(m, c, I_c)` applied to a motion `[ω; v]`: `[I_c ω + c × p; p]`,
/// `p = m (v + ω × c)`.
fn inertia_times(m: f64, c: DVec3, ic: &DMat3, [w, v]: [DVec3; 2]) -> [DVec3; 2] {
    let p = m * (v + w.cross(c));
    [*ic * w + c.cross(p), p]
}

/// `v ×* f` for a motion `v` and a force `f`.
fn cross_force([w, v]: [DVec3; 2], [n, f]: [DVec3; 2]) -> [DVec3; 2] {
    [w.cross(n) + v.cross(f), w.cross(f)]
}

/// `v × m` for motions.
fn cross_motion([w, v]: [DVec3; 2], [w2, v2]: [DVec3; 2]) -> [DVec3; 2] {
    [w.cross(w2), w.cross(v2) + v.cross(w2)]
}

/// A motion in the parent's coordinates seen in the child's (`e`: parent-to-child rotation,
/// `r`: the child's origin in the parent's coordinates).
fn motion_to_child(e: &DMat3, r: DVec3, [w, v]: [DVec3; 2]) -> [DVec3; 2] {
    [*e * w, *e * (v - r.cross(w))]
}

/// A force in the child's coordinates seen in the parent's.
fn force_to_parent(e: &DMat3, r: DVec3, [n, f]: [DVec3; 2]) -> [DVec3; 2] {
    let (n, f) = (e.transpose() * n, e.transpose() * f);
    [n + r.cross(f), f]
}

fn dot([a, b]: [DVec3; 2], [c, d]: [DVec3; 2]) -> f64 {
    a.dot(c) + b.dot(d)
}

impl ArticulatedTree {
    /// A tree of `links` (each one's parent before it) under `gravity` (base frame). Errors
    /// name the link and the field that is wrong.
    pub fn new(links: Vec<TreeLink>, gravity: DVec3) -> KeaResult<Self> {
        for (i, l) in links.iter().enumerate() {
            let bad = |field: &'static str, value: String, expected: &'static str| {
                Err(KeaError::OutOfRange {
                    arg: field,
                    value: format!("link {i}: {value}"),
                    expected,
                })
            };
            if l.parent.is_some_and(|p| p >= i) {
                return bad(
                    "parent",
                    format!("{:?}", l.parent),
                    "a link listed before it",
                );
            }
            if !(l.mass.is_finite() && l.mass > 0.0) {
                return bad("mass", format!("{}", l.mass), "a positive finite mass");
            }
            if (l.axis.length() - 1.0).abs().is_nan() || (l.axis.length() - 1.0).abs() >= 1e-6 {
                return bad("axis", format!("{}", l.axis), "a unit vector");
            }
            if let Some((lo, hi)) = l.limits {
                if lo.is_nan() || hi.is_nan() || lo > hi {
                    return bad("limits", format!("{lo} {hi}"), "lower <= upper");
                }
            }
            if l.motor
                .is_some_and(|(v, f)| !v.is_finite() || f.is_nan() || f < 0.0)
                || l.friction.is_nan()
                || l.friction < 0.0
            {
                return bad(
                    "motor",
                    format!("{:?} / {}", l.motor, l.friction),
                    "a finite rate, forces >= 0",
                );
            }
            if !(l.armature >= 0.0 && l.damping >= 0.0) {
                return bad(
                    "armature",
                    format!("{} / {}", l.armature, l.damping),
                    "armature and damping >= 0",
                );
            }
        }
        let n = links.len();
        Ok(Self {
            links,
            gravity,
            rot: vec![DMat3::IDENTITY; n],
            pos: vec![DVec3::ZERO; n],
            vel: vec![[DVec3::ZERO; 2]; n],
            acc: vec![[DVec3::ZERO; 2]; n],
            force: vec![[DVec3::ZERO; 2]; n],
            composite: vec![(0.0, DVec3::ZERO, DMat3::ZERO); n],
            h: vec![0.0; n * n],
            rhs: vec![0.0; n],
            inverse: vec![0.0; n * n],
            column: vec![0.0; n],
            rows: Vec::with_capacity(3 * n),
            impulse: vec![0.0; n],
            external: vec![[DVec3::ZERO; 2]; n],
            rate0: vec![0.0; n],
            frames: vec![(DVec3::ZERO, DQuat::IDENTITY); n],
            placed: Vec::with_capacity(n),
            placed_valid: false,
        })
    }

    /// An empty tree under `gravity`, to be filled by [`ArticulatedTree::refill`].
    pub(crate) fn empty(gravity: DVec3) -> Self {
        Self::new(Vec::new(), gravity).expect("an empty tree is valid")
    }

    /// Replaces the links (each one's parent before it; trusted: the world derives them from
    /// valid bodies and joints) and the gravity, reusing the scratch: no allocation once the
    /// tree has held as many links. The applied wrenches are cleared.
    pub(crate) fn refill(&mut self, links: impl Iterator<Item = TreeLink>, gravity: DVec3) {
        self.links.clear();
        self.links.extend(links);
        self.placed_valid = false;
        self.gravity = gravity;
        let n = self.links.len();
        self.rot.resize(n, DMat3::IDENTITY);
        self.pos.resize(n, DVec3::ZERO);
        self.vel.resize(n, [DVec3::ZERO; 2]);
        self.acc.resize(n, [DVec3::ZERO; 2]);
        self.force.resize(n, [DVec3::ZERO; 2]);
        self.composite.resize(n, (0.0, DVec3::ZERO, DMat3::ZERO));
        self.h.resize(n * n, 0.0);
        self.rhs.resize(n, 0.0);
        self.inverse.resize(n * n, 0.0);
        self.column.resize(n, 0.0);
        self.impulse.resize(n, 0.0);
        self.external.clear();
        self.external.resize(n, [DVec3::ZERO; 2]);
        self.rate0.resize(n, 0.0);
        self.frames.resize(n, (DVec3::ZERO, DQuat::IDENTITY));
    }

    /// The links.
    #[cfg(feature = "serde")]
    pub(crate) fn links(&self) -> &[TreeLink] {
        &self.links
    }

    /// Sets the gravity, base frame.
    pub(crate) fn set_gravity(&mut self, gravity: DVec3) {
        self.gravity = gravity;
    }

    /// Link `i`, to change its drives (trusted: the world keeps them valid; its geometry —
    /// parent, kind, origin, axis, anchor — must not change, or placements would be stale).
    pub(crate) fn link_mut(&mut self, i: usize) -> &mut TreeLink {
        &mut self.links[i]
    }

    /// Sets the wrench applied to `link` (its coordinates: torque about its origin, force),
    /// kept for the steps that follow until set again.
    pub fn set_external(&mut self, link: usize, torque: DVec3, force: DVec3) -> KeaResult<()> {
        if link >= self.len() || !(torque.is_finite() && force.is_finite()) {
            return Err(KeaError::OutOfRange {
                arg: "link",
                value: format!("{link}: {torque} {force}"),
                expected: "a link of the tree and a finite wrench",
            });
        }
        self.external[link] = [torque, force];
        Ok(())
    }

    /// Each link's frame in the base's and its spatial velocity `[ω; v]` in its own
    /// coordinates at `q`, `qd`, as [`ArticulatedTree::frame`] and
    /// [`ArticulatedTree::velocity`] read them (forward kinematics; arguments trusted).
    pub(crate) fn forward(&mut self, q: &[f64], qd: &[f64]) {
        self.place(q);
        for (i, &rate) in qd.iter().enumerate().take(self.len()) {
            let local = DQuat::from_mat3(&self.rot[i].transpose());
            let s = self.subspace(i);
            let (e, r) = (self.rot[i], self.pos[i]);
            let (frame, v_parent) = match self.links[i].parent {
                Some(p) => {
                    let (t, rp) = self.frames[p];
                    ((t + rp * r, (rp * local).normalize()), self.vel[p])
                }
                None => ((r, local), [DVec3::ZERO; 2]),
            };
            let v = motion_to_child(&e, r, v_parent);
            self.frames[i] = frame;
            self.vel[i] = [v[0] + s[0] * rate, v[1] + s[1] * rate];
        }
    }

    /// Link `i`'s frame in the base's after [`ArticulatedTree::forward`].
    pub(crate) fn frame(&self, i: usize) -> (DVec3, DQuat) {
        self.frames[i]
    }

    /// Link `i`'s spatial velocity `[ω; v of its origin]`, its coordinates, after
    /// [`ArticulatedTree::forward`].
    pub(crate) fn velocity(&self, i: usize) -> [DVec3; 2] {
        self.vel[i]
    }

    /// The wrench the joint of link `i` passed to it in the last step (stops, motors and
    /// drives included): `[torque about the link's origin; force]`, in the link's coordinates
    /// at the step's start. Valid after [`ArticulatedTree::step_with_reactions`].
    pub(crate) fn reaction(&self, i: usize) -> [DVec3; 2] {
        self.force[i]
    }

    /// Number of coordinates.
    #[must_use]
    pub fn len(&self) -> usize {
        self.links.len()
    }

    /// Whether the tree has no link.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.links.is_empty()
    }

    /// Joint `i`'s motion subspace in its link's coordinates.
    fn subspace(&self, i: usize) -> [DVec3; 2] {
        let l = &self.links[i];
        match l.kind {
            TreeJointKind::Hinge => [l.axis, l.anchor.cross(l.axis)],
            TreeJointKind::Slider => [DVec3::ZERO, l.axis],
        }
    }

    /// Each link's transform from its parent at `q`: the parent-to-child rotation and the
    /// child's origin in the parent's coordinates.
    fn place(&mut self, q: &[f64]) {
        // A step starts where the last one's forward kinematics placed the links.
        if self.placed_valid && self.placed.as_slice() == q {
            return;
        }
        self.placed.clear();
        self.placed.extend_from_slice(q);
        self.placed_valid = true;
        for (i, (l, &qi)) in self.links.iter().zip(q).enumerate() {
            let (t, r) = l.origin;
            let (joint_t, joint_r) = match l.kind {
                TreeJointKind::Hinge => {
                    let turn = DQuat::from_axis_angle(l.axis, qi);
                    (l.anchor - turn * l.anchor, turn)
                }
                TreeJointKind::Slider => (l.axis * qi, DQuat::IDENTITY),
            };
            let rotation = r * joint_r;
            self.pos[i] = t + r * joint_t;
            self.rot[i] = DMat3::from_quat(rotation).transpose();
        }
    }

    /// The joint-space inertia `H(q)` (row-major, `len × len`) by composite rigid bodies,
    /// armature included; `place` must have run.
    fn mass_matrix(&mut self) {
        let n = self.len();
        // Links on different branches couple through nothing: their entries stay 0 (the
        // factor of the last step sits here).
        self.h.iter_mut().for_each(|x| *x = 0.0);
        for (i, l) in self.links.iter().enumerate() {
            self.composite[i] = (l.mass, l.com, l.inertia);
        }
        for i in (0..n).rev() {
            if let Some(p) = self.links[i].parent {
                let (m, c, ic) = self.composite[i];
                let e = self.rot[i];
                // Into the parent's coordinates, then summed about the common centre.
                let c_p = self.pos[i] + e.transpose() * c;
                let ic_p = e.transpose() * ic * e;
                let (mp, cp, icp) = self.composite[p];
                let total = mp + m;
                let centre = (cp * mp + c_p * m) / total;
                let shift = |mass: f64, d: DVec3| {
                    (DMat3::IDENTITY * d.length_squared()
                        - DMat3::from_cols(d * d.x, d * d.y, d * d.z))
                        * mass
                };
                let inertia = icp + shift(mp, cp - centre) + ic_p + shift(m, c_p - centre);
                self.composite[p] = (total, centre, inertia);
            }
        }
        for i in 0..n {
            let (m, c, ic) = self.composite[i];
            let si = self.subspace(i);
            let mut f = inertia_times(m, c, &ic, si);
            self.h[i * n + i] = dot(f, si) + self.links[i].armature;
            let mut j = i;
            while let Some(p) = self.links[j].parent {
                f = force_to_parent(&self.rot[j], self.pos[j], f);
                j = p;
                let v = dot(f, self.subspace(j));
                self.h[i * n + j] = v;
                self.h[j * n + i] = v;
            }
        }
    }

    /// The bias forces `c(q, q̇)` into `out` by recursive Newton–Euler; `place` must have run.
    fn bias(&mut self, qd: &[f64], out: &mut [f64]) {
        self.newton_euler(qd, None);
        for (i, o) in out.iter_mut().enumerate().take(self.len()) {
            *o = dot(self.force[i], self.subspace(i));
        }
    }

    /// Recursive Newton–Euler at rates `qd` and accelerations `qdd` (0 when `None`), the base
    /// accelerating up at g and the applied wrenches taken off: leaves in `force[i]` the
    /// wrench joint `i` passes to its link (its subtree's included); `place` must have run.
    fn newton_euler(&mut self, qd: &[f64], qdd: Option<&[f64]>) {
        let n = self.len();
        for (i, &rate) in qd.iter().enumerate().take(n) {
            let s = self.subspace(i);
            let joint = [s[0] * rate, s[1] * rate];
            let (e, r) = (self.rot[i], self.pos[i]);
            let (v_parent, a_parent) = match self.links[i].parent {
                Some(p) => (self.vel[p], self.acc[p]),
                // The base accelerates up at g: gravity on every link, for free.
                None => ([DVec3::ZERO; 2], [DVec3::ZERO, -self.gravity]),
            };
            let v_p = motion_to_child(&e, r, v_parent);
            let v = [v_p[0] + joint[0], v_p[1] + joint[1]];
            let a_p = motion_to_child(&e, r, a_parent);
            let c = cross_motion(v, joint);
            let own = qdd.map_or(0.0, |a| a[i]);
            self.vel[i] = v;
            self.acc[i] = [a_p[0] + c[0] + s[0] * own, a_p[1] + c[1] + s[1] * own];
            let l = &self.links[i];
            let ia = inertia_times(l.mass, l.com, &l.inertia, self.acc[i]);
            let iv = inertia_times(l.mass, l.com, &l.inertia, v);
            let g = cross_force(v, iv);
            let [tn, tf] = self.external[i];
            self.force[i] = [ia[0] + g[0] - tn, ia[1] + g[1] - tf];
        }
        for i in (0..n).rev() {
            if let Some(p) = self.links[i].parent {
                let f = force_to_parent(&self.rot[i], self.pos[i], self.force[i]);
                self.force[p][0] += f[0];
                self.force[p][1] += f[1];
            }
        }
    }

    /// Every link's frame in the base's at `q`: position and rotation (forward kinematics).
    pub fn link_poses(&mut self, q: &[f64]) -> KeaResult<Vec<(DVec3, DQuat)>> {
        let zeros = vec![0.0; self.len()];
        self.check(q, &zeros, &zeros)?;
        self.place(q);
        let mut out: Vec<(DVec3, DQuat)> = Vec::with_capacity(self.len());
        for i in 0..self.len() {
            let local = DQuat::from_mat3(&self.rot[i].transpose());
            let pose = match self.links[i].parent {
                Some(p) => {
                    let (t, r) = out[p];
                    (t + r * self.pos[i], (r * local).normalize())
                }
                None => (self.pos[i], local),
            };
            out.push(pose);
        }
        Ok(out)
    }

    /// The accelerations `q̈` under joint forces `tau` (no damping): `H q̈ = τ − c`.
    pub fn accelerations(&mut self, q: &[f64], qd: &[f64], tau: &[f64]) -> KeaResult<Vec<f64>> {
        self.check(q, qd, tau)?;
        let mut qdd = vec![0.0; self.len()];
        self.solve(q, qd, tau, 0.0, &mut qdd)?;
        Ok(qdd)
    }

    /// One semi-implicit Euler step of `h` under joint forces `tau`, damping and armature
    /// implicit (module docs): `q` and `qd` are advanced in place.
    pub fn step(&mut self, q: &mut [f64], qd: &mut [f64], tau: &[f64], h: f64) -> KeaResult<()> {
        self.step_with_reactions(q, qd, tau, h, false)
    }

    /// [`ArticulatedTree::step`], and with `reactions` each joint's wrench on its link
    /// ([`ArticulatedTree::reaction`]) from the accelerations the step took.
    pub(crate) fn step_with_reactions(
        &mut self,
        q: &mut [f64],
        qd: &mut [f64],
        tau: &[f64],
        h: f64,
        reactions: bool,
    ) -> KeaResult<()> {
        self.check(q, qd, tau)?;
        if !(h.is_finite() && h > 0.0) {
            return Err(KeaError::OutOfRange {
                arg: "h",
                value: format!("{h}"),
                expected: "a positive finite step",
            });
        }
        self.rate0.copy_from_slice(qd);
        let mut qdd = std::mem::take(&mut self.rhs);
        qdd.resize(self.len(), 0.0);
        let solved = self.solve(q, qd, tau, h, &mut qdd);
        if solved.is_ok() {
            for i in 0..self.len() {
                qd[i] += h * qdd[i];
            }
            self.constrain(q, qd, h);
            if reactions {
                // The accelerations the step took, stops and motors included, through
                // Newton–Euler at the step's start (`place` still holds q).
                for i in 0..self.len() {
                    qdd[i] = (qd[i] - self.rate0[i]) / h;
                }
                let rate0 = std::mem::take(&mut self.rate0);
                self.newton_euler(&rate0, Some(&qdd));
                self.rate0 = rate0;
            }
            for i in 0..self.len() {
                q[i] += h * qd[i];
            }
        }
        self.rhs = qdd;
        solved
    }

    /// Each coordinate's constraint force in the last step (stops, motor, friction), N·m or N.
    #[must_use]
    pub fn constraint_forces(&self, h: f64) -> Vec<f64> {
        self.impulse.iter().map(|p| p / h).collect()
    }

    /// Stops, motors and dry friction on the rates `qd` (free, in place): impulses `P` with
    /// `q̇⁺ = q̇ + H'⁻¹ P`, each row's within its bounds, by projected Gauss–Seidel on `H'⁻¹`
    /// (the factor `solve` left). A stop's row aims the rate at what reaches the stop by the
    /// step's end, and only pushes away from it.
    fn constrain(&mut self, q: &[f64], qd: &mut [f64], h: f64) {
        let n = self.len();
        self.rows.clear();
        for (i, l) in self.links.iter().enumerate() {
            if let Some((v, f)) = l.motor {
                self.rows.push(CoordinateRow {
                    coordinate: i,
                    target: v,
                    lo: -h * f,
                    hi: h * f,
                    impulse: 0.0,
                });
            }
            if l.friction > 0.0 {
                let f = h * l.friction;
                self.rows.push(CoordinateRow {
                    coordinate: i,
                    target: 0.0,
                    lo: -f,
                    hi: f,
                    impulse: 0.0,
                });
            }
            if let Some((lo, hi)) = l.limits {
                // The rate that reaches a stop by the step's end; beyond one, the rate that
                // takes back a fifth of the overshoot, no faster than the stop's recovery.
                let recover =
                    |overshoot: f64| (STOP_RECOVERY * overshoot / h).min(l.stop_recovery_speed);
                let min = if q[i] >= lo {
                    (lo - q[i]) / h
                } else {
                    recover(lo - q[i])
                };
                let max = if q[i] <= hi {
                    (hi - q[i]) / h
                } else {
                    -recover(q[i] - hi)
                };
                if qd[i] < min + 1e-9 || q[i] < lo + 1e-9 {
                    self.rows.push(CoordinateRow {
                        coordinate: i,
                        target: min,
                        lo: 0.0,
                        hi: f64::INFINITY,
                        impulse: 0.0,
                    });
                }
                if qd[i] > max - 1e-9 || q[i] > hi - 1e-9 {
                    self.rows.push(CoordinateRow {
                        coordinate: i,
                        target: max,
                        lo: f64::NEG_INFINITY,
                        hi: 0.0,
                        impulse: 0.0,
                    });
                }
            }
        }
        self.impulse.iter_mut().for_each(|p| *p = 0.0);
        if self.rows.is_empty() {
            return;
        }
        // The columns of H'⁻¹ the rows act through (one per constrained coordinate, each a
        // solve with the factor): a coordinate's impulse moves every rate along its column.
        for r in 0..self.rows.len() {
            let j = self.rows[r].coordinate;
            if self.rows[..r].iter().any(|x| x.coordinate == j) {
                continue; // solved for an earlier row of the same coordinate
            }
            self.column.iter_mut().for_each(|c| *c = 0.0);
            self.column[j] = 1.0;
            let mut col = std::mem::take(&mut self.column);
            cholesky_back_solve(&self.h, n, &mut col);
            for (i, &c) in col.iter().enumerate() {
                self.inverse[i * n + j] = c;
            }
            self.column = col;
        }
        for _sweep in 0..200 {
            let mut largest: f64 = 0.0;
            for r in 0..self.rows.len() {
                let row = self.rows[r];
                let i = row.coordinate;
                let w = self.inverse[i * n + i];
                // The impulse that brings the rate to the row's target, kept in its bounds (a
                // stop's bounds let it push one way only).
                let p = (row.impulse + (row.target - qd[i]) / w).clamp(row.lo, row.hi);
                let delta = p - row.impulse;
                if delta != 0.0 {
                    self.rows[r].impulse = p;
                    self.impulse[i] += delta;
                    for (k, rate) in qd.iter_mut().enumerate() {
                        *rate += self.inverse[k * n + i] * delta;
                    }
                    largest = largest.max((delta * w).abs());
                }
            }
            // Converged when no row moves any rate by more than round-off.
            if largest < 1e-12 {
                break;
            }
        }
    }

    /// `(H + diag(h d)) q̈ = τ − c − d q̇` into `qdd`.
    fn solve(
        &mut self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        h: f64,
        qdd: &mut [f64],
    ) -> KeaResult<()> {
        let n = self.len();
        self.place(q);
        self.mass_matrix();
        self.bias(qd, qdd);
        for (i, l) in self.links.iter().enumerate() {
            let d = l.damping;
            qdd[i] = tau[i] - qdd[i] - d * qd[i];
            self.h[i * n + i] += h * d;
            // A servo's force kp (q* − q − h q̇⁺) + kv (v* − q̇⁺), with q̇⁺ = q̇ + h q̈: its
            // q̈ terms join H', the rest the right side.
            if let Some((target, rate, kp, kv)) = l.servo {
                qdd[i] += kp * (target - q[i]) - (kp * h + kv) * qd[i] + kv * rate;
                self.h[i * n + i] += h * h * kp + h * kv;
            }
        }
        cholesky_solve(&mut self.h, n, qdd)
    }

    fn check(&self, q: &[f64], qd: &[f64], tau: &[f64]) -> KeaResult<()> {
        for (arg, x) in [("q", q), ("qd", qd), ("tau", tau)] {
            if x.len() != self.len() || x.iter().any(|v| !v.is_finite()) {
                return Err(KeaError::OutOfRange {
                    arg,
                    value: format!("{} entries", x.len()),
                    expected: "one finite number per link",
                });
            }
        }
        Ok(())
    }
}

/// Solves `L Lᵀ x = b` with the factor `cholesky_solve` left in `l`, `b` overwritten by `x`.
fn cholesky_back_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

/// Solves `A x = b` for symmetric positive definite `A` (row-major, overwritten by its
/// Cholesky factor), `b` overwritten by `x`.
fn cholesky_solve(a: &mut [f64], n: usize, b: &mut [f64]) -> KeaResult<()> {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if d.is_nan() || d <= 0.0 {
            return Err(KeaError::Inconsistent {
                arg: "links",
                reason: "the tree's joint-space inertia is not positive definite".into(),
            });
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    cholesky_back_solve(a, n, b);
    Ok(())
}
