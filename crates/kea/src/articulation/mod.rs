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
use impulses::CoordinateRow;

mod ball_charts;
mod base_frame;
mod contacts;
mod dynamics;
mod impulses;
mod integrate;
mod model;
mod soft_limits;
mod tendons;

pub use contacts::TreeContact;
pub use integrate::Integrator;
use model::TreeModel;
pub(crate) use model::{LinkDrive, SharedModels};
pub(crate) use soft_limits::{impedance, reference_gains};
use std::sync::Arc;
pub(crate) use tendons::stretch;
pub(crate) use tendons::TreeTendon;

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
    /// MuJoCo's soft model for the stops in `limits` (`None`: hard stops, as impulses).
    pub soft_limit: Option<crate::SoftLimit>,
    /// A servo: stiffness kp towards a position and gain kv towards a rate, implicit in the
    /// step (`(position, rate, kp, kv)`, gains ≥ 0).
    pub servo: Option<(f64, f64, f64, f64)>,
    /// The joint's passive spring, `(rest, stiffness ≥ 0)`: explicit in every integrator, as
    /// MuJoCo's joint `stiffness` (read at each evaluation's coordinates).
    pub spring: Option<(f64, f64)>,
    /// Fastest a stop pushes back a coordinate found beyond it, rad/s or m/s (`INFINITY`: a
    /// fifth of the overshoot per step, as the maximal-coordinate path's stops do).
    pub stop_recovery_speed: f64,
}

impl TreeLink {
    /// Its joint's motion subspace in its own coordinates: `[ω; v]` per unit rate.
    fn subspace(&self) -> [DVec3; 2] {
        match self.kind {
            TreeJointKind::Hinge => [self.axis, self.anchor.cross(self.axis)],
            TreeJointKind::Slider => [DVec3::ZERO, self.axis],
        }
    }
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
            soft_limit: None,
            servo: None,
            spring: None,
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

/// A tree of links on a fixed base, in reduced coordinates.
///
/// `repr(C)`, what a batch's worker trades with each world's tree first
/// (`swap_model`): a few cache lines of the world's tree, not its whole.
#[derive(Debug, Clone, PartialEq)]
#[repr(C)]
pub struct ArticulatedTree {
    /// The links' geometry and inertia and what follows from them, shared by the trees of
    /// the same model (`model.rs`).
    model: Arc<TreeModel>,
    /// Its step's scratch may be sized for another tree's links (after a trade,
    /// [`ArticulatedTree::swap_model`], or a copy without workspace): sized again, if it
    /// must be, before it steps ([`ArticulatedTree::ensure_workspace`]).
    scratch_stale: bool,
    /// Traded ([`ArticulatedTree::swap_model`]): what it placed, its contact and tendon sets
    /// are another tree's, forgotten before it steps.
    traded: bool,
    /// How a step integrates (default [`Integrator::Euler`] for a tree made on its own).
    integrator: Integrator,
    /// Each link's joint dynamics, stops and drives: this tree's own.
    drives: Vec<LinkDrive>,
    /// Each link's frame in its parent's at `q = 0`: this tree's own, as a world measures it
    /// where the tree's joints hold its bodies when it builds the tree (a floating root's
    /// place and chart centre, each joint's turn), so that trees built at other poses share
    /// one model.
    origins: Vec<(DVec3, DQuat)>,
    /// Gravity in the base's frame, m/s².
    gravity: DVec3,
    // Scratch, reused every call: per link its transform from the parent (E, r), spatial
    // velocity and acceleration, force (also the one frame's, `base_frame.rs`).
    rot: Vec<DMat3>,
    pos: Vec<DVec3>,
    vel: Vec<[DVec3; 2]>,
    acc: Vec<[DVec3; 2]>,
    force: Vec<[DVec3; 2]>,
    /// The links in one frame, for the joint-space inertia and the bias forces.
    base: base_frame::BaseFrame,
    /// `H'` and then its factor, packed (`solver::sparse::joint_space`).
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
    // Scratch of the integrators: a stage's coordinates and rates, the weighted sums, each
    // coordinate's mean rate less its end rate, the implicit step's matrix, the start.
    stage_q: Vec<f64>,
    stage_v: Vec<f64>,
    sum_a: Vec<f64>,
    sum_v: Vec<f64>,
    offset: Vec<f64>,
    lu: Vec<f64>,
    q_start: Vec<f64>,
    /// The soft stops engaged in the last evaluation, and the step's length they read.
    soft_rows: Vec<soft_limits::SoftRow>,
    step_length: f64,
    /// The links' contacts with the base.
    contact: contacts::ContactState,
    /// Fixed tendons over its coordinates (`tendons.rs`).
    tendon: tendons::TendonState,
    /// The applied wrenches while the reactions' pass adds the contacts' to them.
    external_kept: Vec<[DVec3; 2]>,
    /// The links and packed factor length its step's scratch was last sized for.
    workspace_shape: (usize, usize),
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
        let model = if links.is_empty() {
            TreeModel::empty()
        } else {
            let mut model = TreeModel::default();
            model.refill(&links);
            Arc::new(model)
        };
        let ancestry_len = model.ancestry.packed_len();
        Ok(Self {
            drives: links.iter().map(TreeLink::drive).collect(),
            origins: links.iter().map(|l| l.origin).collect(),
            h: vec![0.0; ancestry_len],
            model,
            gravity,
            rot: vec![DMat3::IDENTITY; n],
            pos: vec![DVec3::ZERO; n],
            vel: vec![[DVec3::ZERO; 2]; n],
            acc: vec![[DVec3::ZERO; 2]; n],
            force: vec![[DVec3::ZERO; 2]; n],
            base: {
                let mut b = base_frame::BaseFrame::default();
                b.resize(n);
                b
            },
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
            integrator: Integrator::Euler,
            stage_q: vec![0.0; n],
            stage_v: vec![0.0; n],
            sum_a: vec![0.0; n],
            sum_v: vec![0.0; n],
            offset: vec![0.0; n],
            lu: vec![0.0; n * n],
            q_start: vec![0.0; n],
            soft_rows: Vec::with_capacity(2 * n),
            step_length: 0.0,
            contact: contacts::ContactState::default(),
            tendon: tendons::TendonState::default(),
            external_kept: Vec::with_capacity(n),
            scratch_stale: false,
            traded: false,
            workspace_shape: (n, ancestry_len),
        })
    }

    /// An empty tree under `gravity`, to be filled by [`ArticulatedTree::refill`].
    pub(crate) fn empty(gravity: DVec3) -> Self {
        Self::new(Vec::new(), gravity).expect("an empty tree is valid")
    }

    /// Replaces the links (each one's parent before it; trusted: the world derives them from
    /// valid bodies and joints) and the gravity, reusing the scratch: no allocation once the
    /// tree has held as many links. The applied wrenches are cleared.
    /// A model of the same geometry is kept as it is (shared or not); another is written in
    /// place, or copied first if shared (`model.rs`).
    pub(crate) fn refill(&mut self, links: &[TreeLink], gravity: DVec3) {
        self.drives.clear();
        self.drives.extend(links.iter().map(TreeLink::drive));
        self.origins.clear();
        self.origins.extend(links.iter().map(|l| l.origin));
        if !self.model.has_geometry_of(links) {
            Arc::make_mut(&mut self.model).refill(links);
        }
        self.placed_valid = false;
        self.gravity = gravity;
        self.scratch_stale = true;
        self.ensure_workspace();
        self.contact.clear();
        self.tendon.tendons.clear();
    }

    /// Sizes the step's scratch for its links if new links or a trade left it sized for
    /// others (what a world that holds a batch's state does before it steps on its own), and
    /// clears the applied wrenches.
    pub(crate) fn ensure_workspace(&mut self) {
        // Sized only: a step writes every drive before it reads one (`swap_model`).
        self.drives.resize(self.len(), TreeLink::default().drive());
        if std::mem::take(&mut self.traded) {
            self.placed_valid = false;
            self.base.valid = false;
            self.contact.clear();
            self.tendon.tendons.clear();
        }
        if self.scratch_stale {
            if self.workspace_shape == (self.len(), self.model.ancestry.packed_len()) {
                self.scratch_stale = false; // sized for a tree of this shape already
            } else {
                self.size_workspace();
            }
            self.external.clear();
            self.external.resize(self.len(), [DVec3::ZERO; 2]);
        }
    }

    /// Sizes the step's scratch for the links it holds (no allocation once it has held a
    /// tree as big).
    fn size_workspace(&mut self) {
        self.scratch_stale = false;
        let n = self.len();
        self.workspace_shape = (n, self.model.ancestry.packed_len());
        self.rot.resize(n, DMat3::IDENTITY);
        self.pos.resize(n, DVec3::ZERO);
        self.vel.resize(n, [DVec3::ZERO; 2]);
        self.acc.resize(n, [DVec3::ZERO; 2]);
        self.force.resize(n, [DVec3::ZERO; 2]);
        self.base.resize(n);
        self.h.resize(self.model.ancestry.packed_len(), 0.0);
        self.rhs.resize(n, 0.0);
        self.inverse.resize(n * n, 0.0);
        self.column.resize(n, 0.0);
        self.impulse.resize(n, 0.0);
        self.external.resize(n, [DVec3::ZERO; 2]);
        self.rate0.resize(n, 0.0);
        self.frames.resize(n, (DVec3::ZERO, DQuat::IDENTITY));
        for v in [
            &mut self.stage_q,
            &mut self.stage_v,
            &mut self.sum_a,
            &mut self.sum_v,
            &mut self.offset,
            &mut self.q_start,
        ] {
            v.resize(n, 0.0);
        }
        self.lu.resize(n * n, 0.0);
        self.soft_rows.reserve(2 * n);
    }

    /// Becomes `other`'s links, gravity and integrator (what a kept tree is between steps),
    /// reusing this tree's buffers; with `workspace`, its step's scratch sized for them as
    /// [`ArticulatedTree::refill`] sizes it (a worker that steps), else left as it is (a copy
    /// that only holds the tree).
    pub(crate) fn copy_model_from(&mut self, other: &ArticulatedTree, workspace: bool) {
        // The model is shared, not copied.
        self.model = Arc::clone(&other.model);
        self.drives.clone_from(&other.drives);
        self.origins.clone_from(&other.origins);
        self.gravity = other.gravity;
        self.placed_valid = false;
        self.base.valid = false;
        self.contact.clear();
        self.tendon.tendons.clear();
        self.scratch_stale = true;
        if workspace {
            self.ensure_workspace();
        }
        self.integrator = other.integrator;
    }

    /// Trades links, gravity and integrator with `other` (what a kept tree is between steps),
    /// each keeping its own step scratch: a batch's worker takes a world's tree in, steps
    /// it, and gives it back, with no copy. Each keeps its scratch as it is, marked stale:
    /// the world sizes it before the tree's next step (`advance_tree`), so a worker that
    /// gives a tree back does not resize for the one it holds then. Both forget what they had
    /// placed, and the contact and tendon sets their last
    /// evaluations started from (a step finds the same sets without them: see
    /// [`ArticulatedTree::copy_model_from`]).
    pub(crate) fn swap_model(&mut self, other: &mut ArticulatedTree) {
        // Drives do not travel: they are written whole before a step reads them (a kept
        // tree's from its joints, a floating root's links as none, `advance_tree`; a tree
        // built again every step — a ball joint's — by its build), so a batch's worker
        // writes its own, in its cache, and not each world's. Each tree sizes its own before
        // it steps (`ensure_workspace`).
        std::mem::swap(&mut self.model, &mut other.model);
        std::mem::swap(&mut self.origins, &mut other.origins);
        std::mem::swap(&mut self.gravity, &mut other.gravity);
        std::mem::swap(&mut self.integrator, &mut other.integrator);
        // Each forgets the rest before its next step (nothing reads it before), so that the
        // trade writes only these lines of a batch world's tree.
        for t in [&mut *self, other] {
            (t.scratch_stale, t.traded) = (true, true);
        }
    }

    /// Asks for the cache lines its step reads first (`crate::prefetch`).
    pub(crate) fn prefetch(&self) {
        use crate::prefetch::slice;
        slice(&self.model.links);
        slice(&self.model.parents);
        slice(&self.model.motion);
        slice(&self.drives);
        slice(&self.origins);
        slice(&self.rot);
        slice(&self.pos);
        slice(&self.vel);
        slice(&self.acc);
        slice(&self.force);
        self.base.prefetch();
        slice(&self.h);
        slice(&self.rhs);
        slice(&self.external);
        slice(&self.frames);
        slice(&self.placed);
        slice(&self.rate0);
        slice(&self.q_start);
        slice(&self.stage_q);
        slice(&self.stage_v);
        slice(&self.offset);
        slice(&self.impulse);
        slice(&self.inverse);
        slice(&self.column);
        slice(&self.sum_a);
        slice(&self.sum_v);
        slice(&self.soft_rows);
        self.contact.prefetch();
    }

    /// The integrator the steps use.
    #[must_use]
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }

    /// Sets the integrator the steps use.
    pub fn set_integrator(&mut self, integrator: Integrator) {
        self.integrator = integrator;
    }

    /// Link `i`'s geometry and inertia, its origin included (its drives are not).
    #[cfg(feature = "serde")]
    pub(crate) fn link_geometry(&self, i: usize) -> TreeLink {
        TreeLink {
            origin: self.origins[i],
            ..self.model.links[i]
        }
    }

    /// Sets the gravity, base frame.
    pub(crate) fn set_gravity(&mut self, gravity: DVec3) {
        self.gravity = gravity;
    }

    /// Where its model lives: trees that share one give the same address.
    #[cfg(test)]
    pub(crate) fn model_address(&self) -> usize {
        Arc::as_ptr(&self.model) as usize
    }

    /// Link `i` driven by nothing (a floating root's links).
    pub(crate) fn clear_drive(&mut self, i: usize) {
        self.drives[i] = TreeLink::default().drive();
    }

    /// Link `i`'s drives, to change (trusted: the world keeps them valid).
    pub(crate) fn drive_mut(&mut self, i: usize) -> &mut LinkDrive {
        &mut self.drives[i]
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
        self.origins.len()
    }

    /// Whether the tree has no link.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.origins.is_empty()
    }

    /// Every link's frame in the base's at `q`: position and rotation (forward kinematics).
    pub fn link_poses(&mut self, q: &[f64]) -> KeaResult<Vec<(DVec3, DQuat)>> {
        let zeros = vec![0.0; self.len()];
        self.check(q, &zeros, &zeros)?;
        self.place(q);
        let mut out: Vec<(DVec3, DQuat)> = Vec::with_capacity(self.len());
        for i in 0..self.len() {
            let local = DQuat::from_mat3(&self.rot[i].transpose());
            let pose = match self.model.parents[i] {
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
        self.q_start.copy_from_slice(q);
        self.step_length = h;
        self.start_contacts(q);
        let mut qdd = std::mem::take(&mut self.rhs);
        qdd.resize(self.len(), 0.0);
        let solved = self.smooth_step(q, qd, tau, h, &mut qdd).and_then(|()| {
            // The coordinates at the step's end before the stops: q + h q̇⁺ (Euler), or the
            // stages' (Runge–Kutta); an impulse moves them by h times its change of rate.
            for i in 0..self.len() {
                self.stage_v[i] = qd[i];
                self.stage_q[i] = q[i] + h * (qd[i] + self.offset[i]);
            }
            self.constrain(q, qd, tau, h)
        });
        if solved.is_ok() {
            for i in 0..self.len() {
                q[i] = self.stage_q[i] + h * (qd[i] - self.stage_v[i]);
            }
            if self.integrator == Integrator::RungeKutta4 {
                self.settle_rows(qd);
            }
            if reactions {
                // The accelerations the step took, stops and motors included, through
                // Newton–Euler at the step's start.
                for i in 0..self.len() {
                    qdd[i] = (qd[i] - self.rate0[i]) / h;
                }
                let rate0 = std::mem::take(&mut self.rate0);
                let q_start = std::mem::take(&mut self.q_start);
                // The contacts' forces act on the links like applied ones.
                self.external_kept.clone_from(&self.external);
                self.add_contact_wrenches(&q_start);
                self.place(&q_start);
                self.newton_euler(&rate0, Some(&qdd));
                std::mem::swap(&mut self.external, &mut self.external_kept);
                self.rate0 = rate0;
                self.q_start = q_start;
            }
            if self.integrator == Integrator::Euler {
                self.turn_charts_as_mujoco(q, qd, h);
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
