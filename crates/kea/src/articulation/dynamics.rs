//! The tree's dynamics: spatial algebra, placing the links at `q`, forward kinematics,
//! Newton–Euler in link coordinates (the joint reactions), and the solve for `q̈` by Cholesky
//! (the module docs of [`super`] give the math; the joint-space inertia and the bias forces
//! are worked out in one frame, `base_frame.rs`).

use super::ArticulatedTree;
use super::TreeJointKind;
use crate::error::{KeaError, KeaResult};
use crate::solver::sparse::joint_space;
use glam::{DMat3, DQuat, DVec3};

/// A rigid-body inertia `(m, c, I_c)` applied to a motion `[ω; v]`: `[I_c ω + c × p; p]`,
/// `p = m (v + ω × c)`.
fn inertia_times(m: f64, c: DVec3, ic: &DMat3, [w, v]: [DVec3; 2]) -> [DVec3; 2] {
    let p = m * (v + w.cross(c));
    [*ic * w + c.cross(p), p]
}

/// `v ×* f` for a motion `v` and a force `f`.
pub(super) fn cross_force([w, v]: [DVec3; 2], [n, f]: [DVec3; 2]) -> [DVec3; 2] {
    [w.cross(n) + v.cross(f), w.cross(f)]
}

/// `v × m` for motions.
pub(super) fn cross_motion([w, v]: [DVec3; 2], [w2, v2]: [DVec3; 2]) -> [DVec3; 2] {
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

impl ArticulatedTree {
    /// Each link's frame in the base's and its spatial velocity `[ω; v]` in its own
    /// coordinates at `q`, `qd`, as [`ArticulatedTree::frame`] and
    /// [`ArticulatedTree::velocity`] read them (forward kinematics; arguments trusted).
    pub(crate) fn forward(&mut self, q: &[f64], qd: &[f64]) {
        self.place(q);
        for (i, &rate) in qd.iter().enumerate().take(self.len()) {
            let local = DQuat::from_mat3(&self.rot[i].transpose());
            let s = self.subspace(i);
            let (e, r) = (self.rot[i], self.pos[i]);
            let (frame, v_parent) = match self.model.parents[i] {
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

    /// Joint `i`'s motion subspace in its link's coordinates.
    #[inline]
    pub(super) fn subspace(&self, i: usize) -> [DVec3; 2] {
        self.model.motion[i]
    }

    /// Each link's transform from its parent at `q`: the parent-to-child rotation and the
    /// child's origin in the parent's coordinates.
    pub(super) fn place(&mut self, q: &[f64]) {
        // A step starts where the last one's forward kinematics placed the links.
        if self.placed_valid && self.placed.as_slice() == q {
            return;
        }
        self.placed.clear();
        self.placed.extend_from_slice(q);
        self.placed_valid = true;
        self.base.valid = false;
        for (i, ((l, &(t, r)), &qi)) in self
            .model
            .links
            .iter()
            .zip(&self.origins)
            .zip(q)
            .enumerate()
        {
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

    /// Recursive Newton–Euler at rates `qd` and accelerations `qdd` (0 when `None`), the base
    /// accelerating up at g and the applied wrenches taken off: leaves in `force[i]` the
    /// wrench joint `i` passes to its link (its subtree's included); `place` must have run.
    pub(super) fn newton_euler(&mut self, qd: &[f64], qdd: Option<&[f64]>) {
        let n = self.len();
        for (i, &rate) in qd.iter().enumerate().take(n) {
            let s = self.subspace(i);
            let joint = [s[0] * rate, s[1] * rate];
            let (e, r) = (self.rot[i], self.pos[i]);
            let (v_parent, a_parent) = match self.model.parents[i] {
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
            let l = &self.model.links[i];
            let ia = inertia_times(l.mass, l.com, &l.inertia, self.acc[i]);
            let iv = inertia_times(l.mass, l.com, &l.inertia, v);
            let g = cross_force(v, iv);
            let [tn, tf] = self.external[i];
            self.force[i] = [ia[0] + g[0] - tn, ia[1] + g[1] - tf];
        }
        for i in (0..n).rev() {
            if let Some(p) = self.model.parents[i] {
                let f = force_to_parent(&self.rot[i], self.pos[i], self.force[i]);
                self.force[p][0] += f[0];
                self.force[p][1] += f[1];
            }
        }
    }

    /// `(H + diag(h d) + servo terms) q̈ = τ − c − d q̇ + servo` into `qdd` (`h = 0`: all
    /// explicit), `H'` left factorised in `h`.
    pub(super) fn solve(
        &mut self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        h: f64,
        qdd: &mut [f64],
    ) -> KeaResult<()> {
        self.assemble(q, qd, tau, h, qdd);
        self.factor_h()?;
        self.solve_h(qdd);
        let step = self.step_length;
        self.soft_stops(q, qd, qdd, step);
        Ok(())
    }

    /// `H' = H + diag(h d) + servo terms` into `h` and the right side `τ − c − d q̇ + servo`
    /// into `rhs`, at `q`, `qd`.
    pub(super) fn assemble(&mut self, q: &[f64], qd: &[f64], tau: &[f64], h: f64, rhs: &mut [f64]) {
        self.place(q);
        self.mass_matrix();
        self.bias_into(qd, rhs);
        for (i, l) in self.drives.iter().enumerate() {
            let d = l.damping;
            rhs[i] = tau[i] - rhs[i] - d * qd[i];
            self.h[i] += h * d;
            if let Some((rest, k)) = l.spring {
                rhs[i] += k * (rest - q[i]);
            }
            // A servo's force kp (q* − q − h q̇⁺) + kv (v* − q̇⁺), with q̇⁺ = q̇ + h q̈: its
            // q̈ terms join H', the rest the right side.
            if let Some((target, rate, kp, kv)) = l.servo {
                rhs[i] += kp * (target - q[i]) - (kp * h + kv) * qd[i] + kv * rate;
                self.h[i] += h * h * kp + h * kv;
            }
        }
        if self.has_tendons() {
            self.tendon_forces(q, qd, rhs);
        }
    }
}

impl ArticulatedTree {
    /// Factorises `H'` (left in `h` by `assemble`) in place, leaf to root with no fill
    /// (`solver::sparse::joint_space`).
    pub(super) fn factor_h(&mut self) -> KeaResult<()> {
        joint_space::factor(&mut self.h, &self.model.ancestry).map_err(|k| KeaError::Inconsistent {
            arg: "links",
            reason: format!(
                "the tree's joint-space inertia is not positive definite (coordinate {k})"
            ),
        })
    }

    /// Solves `H' x = b` with the factor [`Self::factor_h`] left in `h`; `b` becomes `x`.
    pub(super) fn solve_h(&self, b: &mut [f64]) {
        joint_space::solve(&self.h, &self.model.ancestry, b);
    }

    /// `b ← L⁻ᵀ b` with `H' = Lᵀ L` (the factor in `h`): for rows `J`, `J H'⁻¹ Jᵀ` is the
    /// Gram matrix of their halves.
    pub(super) fn half_solve_h(&self, b: &mut [f64]) {
        joint_space::solve_transposed(&self.h, &self.model.ancestry, b);
    }

    /// [`Self::half_solve_h`] for a `b` that is zero off the path from link `leaf` to the
    /// root (one link's point Jacobian): only the path is visited.
    pub(super) fn half_solve_h_path(&self, leaf: usize, b: &mut [f64]) {
        joint_space::solve_transposed_path(&self.h, &self.model.ancestry, leaf, b);
    }
}

/// Solves `A x = b` for a general `A` (row-major, overwritten by its LU factors) by Gaussian
/// elimination with partial pivoting; `b` overwritten by `x`.
pub(super) fn lu_solve(a: &mut [f64], n: usize, b: &mut [f64]) -> KeaResult<()> {
    for j in 0..n {
        let p = (j..n)
            .max_by(|&x, &y| a[x * n + j].abs().total_cmp(&a[y * n + j].abs()))
            .unwrap_or(j);
        let pivot = a[p * n + j];
        if pivot.is_nan() || pivot.abs() < 1e-300 {
            return Err(KeaError::Inconsistent {
                arg: "links",
                reason: "the tree's implicit step matrix is singular".into(),
            });
        }
        if p != j {
            for k in 0..n {
                a.swap(j * n + k, p * n + k);
            }
            b.swap(j, p);
        }
        for i in j + 1..n {
            let f = a[i * n + j] / pivot;
            a[i * n + j] = f;
            for k in j + 1..n {
                a[i * n + k] -= f * a[j * n + k];
            }
            b[i] -= f * b[j];
        }
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= a[i * n + k] * b[k];
        }
        b[i] = s / a[i * n + i];
    }
    Ok(())
}
