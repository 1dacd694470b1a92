//! Kept trees copied or traded between worlds (`World::copy_state_from`,
//! `World::swap_state`): what a kept tree is between steps — its plan, links, coordinates,
//! rates and marks — without its step's scratch.

use super::{CachedTree, ReducedScratch};

impl ReducedScratch {
    /// Becomes `other`'s kept trees (and the caches found by joint revision, which are
    /// unique to a world's joints), reusing this scratch's trees; `workspace`: this one steps,
    /// so each tree's step scratch is sized.
    pub(in crate::world) fn copy_kept_from(&mut self, other: &ReducedScratch, workspace: bool) {
        self.hold_trees(other.trees.len());
        for (t, o) in self.trees.iter_mut().zip(&other.trees) {
            t.copy_kept_from(o, workspace);
        }
        let (a, b) = (self, other);
        macro_rules! copy {
            ($f:ident) => {
                a.$f.clone_from(&b.$f)
            };
        }
        each_kept_cache!(copy);
    }

    /// Trades kept trees with `other` (and the caches found by joint revision), each keeping
    /// its trees' step scratch: this one's are sized for the trees it takes.
    pub(in crate::world) fn swap_kept(&mut self, other: &mut ReducedScratch) {
        let (mine, theirs) = (self.trees.len(), other.trees.len());
        self.hold_trees(mine.max(theirs));
        other.hold_trees(mine.max(theirs));
        for (t, o) in self.trees.iter_mut().zip(&mut other.trees) {
            t.swap_kept(o);
        }
        self.hold_trees(theirs);
        other.hold_trees(mine);
        let (a, b) = (self, other);
        macro_rules! trade {
            ($f:ident) => {
                std::mem::swap(&mut a.$f, &mut b.$f)
            };
        }
        each_kept_cache!(trade);
    }

    /// Holds `n` trees: more taken from the spares first (with the step scratch they keep),
    /// fewer by putting the last ones among the spares, so that a worker trading with
    /// worlds of other tree counts keeps its trees' scratch.
    pub(super) fn hold_trees(&mut self, n: usize) {
        while self.trees.len() < n {
            let spare = self.spare_trees.pop().unwrap_or_default();
            self.trees.push(spare);
        }
        while self.trees.len() > n {
            let spare = self.trees.pop().expect("more trees than held");
            self.spare_trees.push(spare);
        }
    }
}

/// Calls `$m!(field)` for the reduced path's caches that travel with the kept trees: each
/// joint's and root body's tree, and what the last step found of the world's joints.
macro_rules! each_kept_cache {
    ($m:ident) => {
        $m!(tree_of);
        $m!(floating_of);
        $m!(candidates);
        $m!(alone);
    };
}

/// Calls `$m!(field)` for every field of a kept tree that travels with it, but for its
/// articulated tree, whose links move and whose scratch stays.
macro_rules! each_kept_field {
    ($m:ident) => {
        $m!(base_joint);
        $m!(revision);
        $m!(plan);
        $m!(link_of);
        $m!(first_link);
        $m!(rebuilt_each_step);
        $m!(kick);
        $m!(q);
        $m!(qd);
        $m!(marks);
    };
}
use each_kept_cache;

impl CachedTree {
    fn swap_kept(&mut self, o: &mut CachedTree) {
        let a = &mut *self;
        macro_rules! trade {
            ($f:ident) => {
                std::mem::swap(&mut a.$f, &mut o.$f)
            };
        }
        each_kept_field!(trade);
        self.stepped = false;
        o.stepped = false;
        self.tree.swap_model(&mut o.tree);
    }

    fn copy_kept_from(&mut self, o: &CachedTree, workspace: bool) {
        let a = &mut *self;
        macro_rules! copy {
            ($f:ident) => {
                a.$f.clone_from(&o.$f)
            };
        }
        each_kept_field!(copy);
        self.stepped = false;
        // A stale tree (revision 0) is built again before use: its links need not travel.
        if o.revision != 0 {
            self.tree.copy_model_from(&o.tree, workspace);
        }
    }
}

impl ReducedScratch {
    /// Asks for the cache lines of what travels with the kept trees (`crate::prefetch`): a
    /// held world's, which a worker takes in.
    pub(in crate::world) fn prefetch_kept(&self) {
        use crate::prefetch::slice;
        slice(&self.trees);
        for t in &self.trees {
            // Its head to the tree's own leading fields (`repr(C)`): what a trade touches.
            let own = std::mem::offset_of!(CachedTree, tree) + 128;
            crate::prefetch::head(&**t, own);
            slice(&t.plan);
            slice(&t.q);
            slice(&t.qd);
            slice(&t.marks);
        }
        slice(&self.tree_of);
    }

    /// Asks for the cache lines of the kept trees a step reads first (`crate::prefetch`).
    pub(in crate::world) fn prefetch(&self) {
        use crate::prefetch::slice;
        slice(&self.trees);
        for t in &self.trees {
            slice(&t.plan);
            slice(&t.link_of);
            slice(&t.first_link);
            slice(&t.q);
            slice(&t.qd);
            slice(&t.q_next);
            slice(&t.qd_next);
            slice(&t.marks);
            t.tree.prefetch();
        }
        slice(&self.tree_of);
        slice(&self.reduced);
        slice(&self.tau);
    }
}

#[cfg(test)]
mod tests {
    use crate::constraint::Hinge;
    use crate::world::joint_handle::JointHandle;
    use crate::{BodyDef, BodyHandle, JointSpec, Vec3, World};

    /// A three-link arm on hinges from a fixed base (one kept tree): its first joint and its
    /// last body.
    fn arm() -> (World, JointHandle<Hinge>, BodyHandle) {
        let mut w = World::with_capacity(8, 16).unwrap();
        w.update_settings(|s| s.gravity = Vec3::new(0.0, -9.81, 0.0))
            .unwrap();
        let (mut parent, mut first) = (None, None);
        for k in 0..3 {
            let x = 0.5 * (k + 1) as crate::Real;
            let b = w
                .create_body(&BodyDef {
                    position: Vec3::new(x, 0.0, 0.0),
                    ..BodyDef::default()
                })
                .unwrap();
            let anchor = Vec3::new(x - 0.5, 0.0, 0.0);
            let j = w
                .create_joint(b, parent, JointSpec::hinge(anchor, Vec3::Z))
                .unwrap();
            first.get_or_insert(j);
            parent = Some(b);
        }
        (w, first.unwrap(), parent.unwrap())
    }

    /// The kept trees' models, by address.
    fn models(w: &World) -> Vec<usize> {
        let trees = &w.scratch.reduced.trees;
        trees.iter().map(|t| t.tree.model_address()).collect()
    }

    #[test]
    fn worlds_stepped_by_one_worker_share_their_tree_model_and_step_as_alone() {
        let (template, first, tip) = arm();
        let mut held = Vec::new();
        let mut alone = Vec::new();
        for k in 0..3 {
            let mut w = template.clone();
            w.trim_to_state();
            // Each world its own motor on the first joint: drives differ, geometry not.
            first.set_motor(&mut w, k as crate::Real, 200.0).unwrap();
            alone.push(w.clone());
            held.push(w);
        }
        let mut worker = template.clone();
        for _ in 0..20 {
            for w in &mut held {
                worker.swap_state(w);
                worker.step(0.01).unwrap();
                worker.swap_state(w);
            }
            for w in &mut alone {
                w.step(0.01).unwrap();
            }
        }
        let shared = models(&held[0]);
        assert_eq!(shared.len(), 1, "one kept tree");
        for (w, a) in held.iter().zip(&alone) {
            assert_eq!(
                models(w),
                shared,
                "one model for every world the worker stepped"
            );
            assert_ne!(models(a), shared, "a world stepped alone built its own");
            let (b, c) = (w.body(tip).unwrap(), a.body(tip).unwrap());
            assert_eq!(b.position().to_array(), c.position().to_array());
            assert_eq!(
                b.linear_velocity().to_array(),
                c.linear_velocity().to_array()
            );
        }
        // Their drives stayed their own: the motors turned the arms apart.
        let tip_of = |w: &World| w.body(tip).unwrap().position();
        assert!((tip_of(&held[0]) - tip_of(&held[2])).length() > 1e-3);
    }

    /// A floating robot in zero gravity, as an ant's leg: a root and two links on hinges
    /// about other axes (one floating tree, kept from step to step, built again when its
    /// root's chart is centred again); its bodies.
    fn floating_robot() -> (World, [BodyHandle; 3]) {
        let mut w = World::new(crate::WorldDef {
            settings: crate::WorldSettings {
                gravity: Vec3::ZERO,
                reduced_free_trees: true,
                ..crate::WorldSettings::default()
            },
            ..crate::WorldDef::default()
        })
        .unwrap();
        let body = |w: &mut World, x: Vec3| {
            w.create_body(&BodyDef {
                position: x,
                ..BodyDef::default()
            })
            .unwrap()
        };
        let a = body(&mut w, Vec3::new(0.0, 1.0, 0.0));
        let b = body(&mut w, Vec3::new(0.6, 1.0, 0.0));
        let c = body(&mut w, Vec3::new(1.2, 1.0, 0.0));
        w.create_joint(
            b,
            Some(a),
            JointSpec::hinge(Vec3::new(0.3, 1.0, 0.0), Vec3::Z),
        )
        .unwrap();
        w.create_joint(
            c,
            Some(b),
            JointSpec::hinge(Vec3::new(0.9, 1.0, 0.0), Vec3::Y),
        )
        .unwrap();
        (w, [a, b, c])
    }

    #[test]
    fn floating_robots_at_other_poses_share_one_model_and_step_as_alone() {
        let (template, bodies) = floating_robot();
        let mut held = Vec::new();
        let mut alone = Vec::new();
        for k in 0..3 {
            let mut w = template.clone();
            w.trim_to_state();
            // Each world tumbles its own way (a rigid turn about the root: the joints allow
            // it), so each is built at its own pose, and its chart is centred again at its
            // own times.
            let spin = Vec3::new(0.4, 2.0 + k as crate::Real, 0.7 * k as crate::Real);
            let root = w.body(bodies[0]).unwrap().position();
            for &h in &bodies {
                let b = w.body_mut(h).unwrap();
                let v = spin.cross(b.position() - root);
                b.set_angular_velocity(spin).unwrap();
                b.set_linear_velocity(v).unwrap();
            }
            alone.push(w.clone());
            held.push(w);
        }
        let mut worker = template.clone();
        let mut first = None;
        for _ in 0..120 {
            for w in &mut held {
                worker.swap_state(w);
                let stats = worker.step(0.01).unwrap();
                assert_eq!(stats.reduced_trees, 1, "one floating tree");
                worker.swap_state(w);
            }
            for w in &mut alone {
                w.step(0.01).unwrap();
            }
            first.get_or_insert_with(|| models(&held[0]));
        }
        let shared = first.unwrap();
        assert_eq!(shared.len(), 1, "one kept tree");
        for (w, a) in held.iter().zip(&alone) {
            assert_eq!(
                models(w),
                shared,
                "one model for every world, through every centring of its chart"
            );
            for &h in &bodies {
                let (b, c) = (w.body(h).unwrap(), a.body(h).unwrap());
                assert_eq!(b.position().to_array(), c.position().to_array());
                assert_eq!(b.orientation().to_array(), c.orientation().to_array());
                assert_eq!(
                    b.angular_velocity().to_array(),
                    c.angular_velocity().to_array()
                );
            }
        }
        // They tumbled apart: the root turned past where its chart was centred.
        let turn = |w: &World| w.body(bodies[0]).unwrap().orientation();
        assert!(turn(&held[0]).angle_between(turn(&held[2])) > 0.5);
        assert!(
            turn(&held[0]).angle_between(template.body(bodies[0]).unwrap().orientation()) > 1.0
        );
    }
}
