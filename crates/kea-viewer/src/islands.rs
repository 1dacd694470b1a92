//! Islands for display: bodies joined by enabled joints and contacts, found by union-find
//! over body slots each frame the island view is on.

use kea::{BodyHandle, World};
use std::collections::HashMap;

/// Which island each body is in.
#[derive(Debug, Default)]
pub struct Islands {
    parent: HashMap<BodyHandle, BodyHandle>,
    number: HashMap<BodyHandle, usize>,
}

impl Islands {
    /// Recomputes the islands of `world`.
    pub fn rebuild(&mut self, world: &World) {
        self.parent.clear();
        self.number.clear();
        let pairs = world
            .enabled_joints()
            .map(|(_, b)| b)
            .chain(world.contacts().map(|(_, _, b)| b));
        for bodies in pairs {
            if let [Some(a), Some(b)] = bodies {
                let dynamic = |h| world.body(h).is_ok_and(|b| b.is_enabled());
                if dynamic(a) && dynamic(b) {
                    self.union(a, b);
                }
            }
        }
        for (h, _) in world.bodies() {
            let root = self.find(h);
            let next = self.number.len();
            self.number.entry(root).or_insert(next);
        }
    }

    /// A small number naming the island of body `h` (stable while the islands are).
    #[must_use]
    pub fn island_of(&self, h: BodyHandle) -> Option<usize> {
        let mut x = h;
        while let Some(&p) = self.parent.get(&x) {
            if p == x {
                break;
            }
            x = p;
        }
        self.number.get(&x).copied()
    }

    fn find(&mut self, h: BodyHandle) -> BodyHandle {
        let mut root = h;
        while let Some(&p) = self.parent.get(&root) {
            if p == root {
                break;
            }
            root = p;
        }
        // Path halving is not needed at display sizes; point h straight at its root.
        if root != h {
            self.parent.insert(h, root);
        }
        root
    }

    fn union(&mut self, a: BodyHandle, b: BodyHandle) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent.insert(ra, rb);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kea::{BodyDef, Vec3};

    #[test]
    fn jointed_bodies_share_an_island_and_free_ones_do_not() {
        let mut world = World::with_capacity(8, 32).unwrap();
        let mut body = |x: kea::Real| {
            let def = BodyDef {
                position: Vec3::new(x, 0.0, 0.0),
                ..BodyDef::default()
            };
            world.create_body(&def).unwrap()
        };
        let (a, b, c) = (body(0.0), body(1.0), body(5.0));
        world
            .create_joint(a, Some(b), kea::JointSpec::ball(Vec3::new(0.5, 0.0, 0.0)))
            .unwrap();
        let mut islands = Islands::default();
        islands.rebuild(&world);
        assert_eq!(islands.island_of(a), islands.island_of(b));
        assert_ne!(islands.island_of(a), islands.island_of(c));
        assert!(islands.island_of(c).is_some());
    }
}
