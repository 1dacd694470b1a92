//! The joint-space inertia and the bias forces worked out in one frame for every link: the
//! base's axes about a point among the links (MuJoCo's way). Motions, forces and inertias
//! then add up without being carried from link to link: a composite inertia is a sum, `H_ij`
//! one dot product per pair, and Newton–Euler's forces pass to a parent as they are. The
//! link-by-link recursion in link coordinates (`dynamics.rs`) stays for the joint reactions,
//! which are read in each link's own coordinates.
//!
//! Spatial vectors here are Plücker coordinates at the point `o`: a motion `[ω; v]` with `v`
//! the velocity of the body point at `o`, a force `[n; f]` with `n` the moment about `o`.

use super::dynamics::{cross_force, cross_motion};
use super::ArticulatedTree;
use glam::{DMat3, DVec3};

/// A rigid body's inertia about the frame's point: mass `m`, first moment `m c` and
/// rotational inertia about the point (`I_c + m (|c|² 1 − c cᵀ)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct SpatialInertia {
    mass: f64,
    moment: DVec3,
    rotational: DMat3,
}

impl Default for SpatialInertia {
    /// No body (glam's default matrix is the identity, not zero).
    fn default() -> Self {
        Self {
            mass: 0.0,
            moment: DVec3::ZERO,
            rotational: DMat3::ZERO,
        }
    }
}

impl SpatialInertia {
    /// A body of mass `m` centred at `c` (from the point) with inertia `ic` about its centre,
    /// both in the frame's axes.
    fn of_body(m: f64, c: DVec3, ic: DMat3) -> Self {
        let shift = DMat3::from_diagonal(DVec3::splat(c.length_squared()))
            - DMat3::from_cols(c * c.x, c * c.y, c * c.z);
        Self {
            mass: m,
            moment: c * m,
            rotational: ic + shift * m,
        }
    }

    /// Its momentum in the motion `[ω; v]`: `[I ω + h × v; m v + ω × h]`, `h = m c`.
    #[inline]
    fn times(&self, [w, v]: [DVec3; 2]) -> [DVec3; 2] {
        [
            self.rotational * w + self.moment.cross(v),
            v * self.mass + w.cross(self.moment),
        ]
    }

    fn add(&mut self, other: &Self) {
        self.mass += other.mass;
        self.moment += other.moment;
        self.rotational += other.rotational;
    }
}

/// Each link's frame, joint subspace and inertia in the one frame at the coordinates the tree
/// was last placed at, and the composite inertias: scratch of [`ArticulatedTree`].
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct BaseFrame {
    /// The link's axes in the base's, and its origin from the point.
    rot: Vec<DMat3>,
    pos: Vec<DVec3>,
    /// Its joint's motion subspace.
    motion: Vec<[DVec3; 2]>,
    /// Its own inertia, and its subtree's.
    inertia: Vec<SpatialInertia>,
    composite: Vec<SpatialInertia>,
    /// Whether the above are those of the tree's present placement.
    pub(super) valid: bool,
}

impl BaseFrame {
    /// Sized for `n` links, reusing its buffers; invalid until worked out.
    pub(super) fn resize(&mut self, n: usize) {
        self.rot.resize(n, DMat3::IDENTITY);
        self.pos.resize(n, DVec3::ZERO);
        self.motion.resize(n, [DVec3::ZERO; 2]);
        self.inertia.resize(n, SpatialInertia::default());
        self.composite.resize(n, SpatialInertia::default());
        self.valid = false;
    }

    /// Asks for its cache lines (`crate::prefetch`).
    pub(super) fn prefetch(&self) {
        use crate::prefetch::slice;
        slice(&self.rot);
        slice(&self.pos);
        slice(&self.motion);
        slice(&self.inertia);
        slice(&self.composite);
    }
}

fn dot([a, b]: [DVec3; 2], [c, d]: [DVec3; 2]) -> f64 {
    a.dot(c) + b.dot(d)
}

impl ArticulatedTree {
    /// Works out [`BaseFrame`] from the links' transforms `place` left (once per placement).
    fn place_in_base_frame(&mut self) {
        if self.base.valid {
            return;
        }
        let n = self.len();
        let b = &mut self.base;
        let mut centre = DVec3::ZERO;
        for i in 0..n {
            let local = self.rot[i].transpose();
            let (r, p) = match self.model.parents[i] {
                Some(a) => (b.rot[a] * local, b.pos[a] + b.rot[a] * self.pos[i]),
                None => (local, self.pos[i]),
            };
            b.rot[i] = r;
            b.pos[i] = p;
            centre += p;
        }
        // About a point among the links, not the base's origin: a robot far from it would
        // otherwise carry large, cancelling moments.
        centre /= n.max(1) as f64;
        for (i, l) in self.model.links.iter().enumerate() {
            let r = b.rot[i];
            let d = b.pos[i] - centre;
            b.pos[i] = d;
            let [w, v] = self.model.motion[i];
            let w = r * w;
            b.motion[i] = [w, r * v + d.cross(w)];
            b.inertia[i] = if l.mass > 0.0 {
                SpatialInertia::of_body(l.mass, d + r * l.com, r * l.inertia * r.transpose())
            } else {
                SpatialInertia::default()
            };
        }
        b.valid = true;
    }

    /// The joint-space inertia `H(q)` (packed, `solver::sparse::joint_space`) by composite rigid bodies,
    /// armature included: `H_ij = S_jᵀ I^c_i S_i` for `j` on the path from `i` to the root;
    /// `place` must have run.
    pub(super) fn mass_matrix(&mut self) {
        self.place_in_base_frame();
        let n = self.len();
        let b = &mut self.base;
        b.composite.copy_from_slice(&b.inertia);
        for i in (0..n).rev() {
            if let Some(p) = self.model.parents[i] {
                let child = b.composite[i];
                b.composite[p].add(&child);
            }
        }
        for i in 0..n {
            let s = b.motion[i];
            let f = b.composite[i].times(s);
            self.h[i] = dot(f, s) + self.drives[i].armature;
            let row = self.model.ancestry.packed_row(i);
            for (&j, h) in self.model.ancestry.of(i).iter().zip(&mut self.h[row]) {
                *h = dot(f, b.motion[j as usize]);
            }
        }
    }

    /// The bias forces `c(q, q̇)` into `out` by recursive Newton–Euler in the one frame (the
    /// base accelerating up at g, the applied wrenches taken off); `place` must have run.
    /// Uses `vel`, `acc` and `force` as scratch.
    pub(super) fn bias_into(&mut self, qd: &[f64], out: &mut [f64]) {
        self.place_in_base_frame();
        let n = self.len();
        let b = &self.base;
        for (i, &rate) in qd.iter().enumerate().take(n) {
            let s = b.motion[i];
            let joint = [s[0] * rate, s[1] * rate];
            let (v_parent, a_parent) = match self.model.parents[i] {
                Some(p) => (self.vel[p], self.acc[p]),
                // The base accelerates up at g: gravity on every link, for free.
                None => ([DVec3::ZERO; 2], [DVec3::ZERO, -self.gravity]),
            };
            let v = [v_parent[0] + joint[0], v_parent[1] + joint[1]];
            // The subspace turns with its link: d/dt (S q̇) = v × S q̇ at constant q̇.
            let turning = cross_motion(v, joint);
            let a = [a_parent[0] + turning[0], a_parent[1] + turning[1]];
            self.vel[i] = v;
            self.acc[i] = a;
            let mut f = [DVec3::ZERO; 2];
            if self.model.links[i].mass > 0.0 {
                let inertia = &b.inertia[i];
                let ia = inertia.times(a);
                let g = cross_force(v, inertia.times(v));
                f = [ia[0] + g[0], ia[1] + g[1]];
            }
            let [tn, tf] = self.external[i];
            if tn != DVec3::ZERO || tf != DVec3::ZERO {
                let r = b.rot[i];
                let tf = r * tf;
                f[0] -= r * tn + b.pos[i].cross(tf);
                f[1] -= tf;
            }
            self.force[i] = f;
        }
        for i in (0..n).rev() {
            if let Some(p) = self.model.parents[i] {
                let f = self.force[i];
                self.force[p][0] += f[0];
                self.force[p][1] += f[1];
            }
            out[i] = dot(self.force[i], b.motion[i]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{ArticulatedTree, TreeJointKind, TreeLink};
    use crate::solver::sparse::factor::tests::rnd;
    use crate::solver::sparse::joint_space;
    use glam::{DMat3, DQuat, DVec3};

    fn vec3(seed: &mut u64) -> DVec3 {
        DVec3::new(rnd(seed), rnd(seed), rnd(seed))
    }

    /// A random branched tree of hinges and sliders, some links massless, off-centre masses.
    fn random_tree(seed: &mut u64, n: usize) -> ArticulatedTree {
        let links: Vec<TreeLink> = (0..n)
            .map(|i| {
                let parent =
                    (i > 0 && rnd(seed) > -0.8).then(|| (rnd(seed).abs() * i as f64) as usize);
                let massless = rnd(seed) > 0.5;
                let a = vec3(seed);
                TreeLink {
                    parent: parent.map(|p| p.min(i - 1)),
                    kind: if rnd(seed) > -0.5 {
                        TreeJointKind::Hinge
                    } else {
                        TreeJointKind::Slider
                    },
                    origin: (vec3(seed), DQuat::from_scaled_axis(vec3(seed))),
                    axis: vec3(seed).normalize(),
                    anchor: vec3(seed),
                    mass: if massless { 0.0 } else { 1.0 + rnd(seed).abs() },
                    com: vec3(seed),
                    inertia: if massless {
                        DMat3::ZERO
                    } else {
                        let r = DMat3::from_quat(DQuat::from_scaled_axis(a));
                        r * DMat3::from_diagonal(DVec3::new(0.3, 0.4, 0.5)) * r.transpose()
                    },
                    armature: 0.01,
                    ..TreeLink::default()
                }
            })
            .collect();
        // Massless links as the world builds them (`new` asks a user for masses).
        let gravity = DVec3::new(0.3, -9.8, 1.0);
        let mut tree = ArticulatedTree::empty(gravity);
        tree.refill(&links, gravity);
        tree
    }

    /// Each joint's force from link-coordinate Newton–Euler (`dynamics.rs`).
    fn link_newton_euler(t: &mut ArticulatedTree, qd: &[f64], qdd: Option<&[f64]>) -> Vec<f64> {
        t.newton_euler(qd, qdd);
        (0..t.len())
            .map(|i| {
                let ([a, b], [c, d]) = (t.force[i], t.subspace(i));
                a.dot(c) + b.dot(d)
            })
            .collect()
    }

    #[test]
    fn the_one_frame_inertia_and_bias_are_link_coordinate_newton_eulers() {
        let mut seed = 7;
        for n in [1, 2, 5, 12, 30] {
            let mut t = random_tree(&mut seed, n);
            let q: Vec<f64> = (0..n).map(|_| 2.0 * rnd(&mut seed)).collect();
            let qd: Vec<f64> = (0..n).map(|_| 3.0 * rnd(&mut seed)).collect();
            t.set_external(n - 1, vec3(&mut seed), vec3(&mut seed))
                .unwrap();
            t.place(&q);
            let mut bias = vec![0.0; n];
            t.bias_into(&qd, &mut bias);
            let expected = link_newton_euler(&mut t, &qd, None);
            let scale = expected.iter().fold(1.0f64, |m, x| m.max(x.abs()));
            for (a, b) in bias.iter().zip(&expected) {
                assert!((a - b).abs() < 1e-10 * scale, "bias {n}: {a} vs {b}");
            }
            t.mass_matrix();
            // The kinetic energy of the links' own motions, ½ q̇ᵀ (H − armature) q̇.
            let mut dense = vec![0.0; n * n];
            joint_space::add_to_dense(&t.h, &t.model.ancestry, &mut dense);
            let quadratic: f64 = (0..n)
                .flat_map(|i| (0..n).map(move |j| (i, j)))
                .map(|(i, j)| qd[i] * qd[j] * (dense[i * n + j] - if i == j { 0.01 } else { 0.0 }))
                .sum();
            t.forward(&q, &qd);
            let energy: f64 = (0..n)
                .map(|i| {
                    let (l, [w, v]) = (&t.model.links[i], t.velocity(i));
                    let vc = v + w.cross(l.com);
                    0.5 * (l.mass * vc.length_squared() + w.dot(l.inertia * w))
                })
                .sum();
            assert!(
                (0.5 * quadratic - energy).abs() < 1e-10 * energy,
                "{n}: ½ q̇ᵀ H q̇ = {} vs {energy}",
                0.5 * quadratic
            );
            let rest = vec![0.0; n];
            let at_rest = link_newton_euler(&mut t, &rest, None);
            for j in 0..n {
                let mut unit = vec![0.0; n];
                unit[j] = 1.0;
                let column = link_newton_euler(&mut t, &rest, Some(&unit));
                let mut dense = vec![0.0; n * n];
                joint_space::add_to_dense(&t.h, &t.model.ancestry, &mut dense);
                for i in 0..n {
                    let expected = column[i] - at_rest[i] + if i == j { 0.01 } else { 0.0 };
                    let got = dense[i * n + j];
                    assert!(
                        (got - expected).abs() < 1e-10 * scale.max(1.0),
                        "H {n} ({i}, {j}): {got} vs {expected}"
                    );
                }
            }
        }
    }
}
