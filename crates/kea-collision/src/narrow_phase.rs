//! The narrow phase: parry contact manifolds for every candidate pair the filter lets through,
//! reduced by the contact strategy and turned into the Kea contacts the world should hold.

use crate::collision_world::{collider_pose, ColliderDef, CollisionWorld, Wanted};
use crate::parry::math::Pose;
use crate::parry::query::{ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher};
use crate::reduce::reduce;
use kea::{BodyHandle, Contact, ContactParams, Real, Vec3, World};

/// What every contact of one pair shares this step.
struct PairFrame {
    pair: (u32, u32),
    bodies: (BodyHandle, Option<BodyHandle>),
    /// The first collider is static, so it is body 2 and the normal keeps parry's direction.
    flip: bool,
    params: ContactParams,
    /// A fixed world primary friction direction (conveyor pairs).
    direction: Option<Vec3>,
    poses: (Pose, Pose),
    prediction: Real,
}

/// Buffers reused from manifold to manifold.
#[derive(Debug, Default)]
pub(crate) struct ManifoldScratch {
    points: Vec<(Vec3, Real)>,
    features: Vec<(u32, u32)>,
    keep: Vec<usize>,
}

impl ManifoldScratch {
    /// Reduces one manifold to at most `max_points` and appends its contacts to `wanted`,
    /// skipping a key that the pair's contacts from `wanted[pair_start..]` already have (parry
    /// can report the same features in two manifolds of a height field; one contact per key).
    fn push_contacts(
        &mut self,
        manifold: &ContactManifold<(), ()>,
        frame: &PairFrame,
        max_points: usize,
        wanted: &mut Vec<Wanted>,
        pair_start: usize,
    ) {
        let (pose_a, pose_b) = frame.poses;
        let sub_a = manifold.subshape_pos1().map_or(pose_a, |p| pose_a * *p);
        let sub_b = manifold.subshape_pos2().map_or(pose_b, |p| pose_b * *p);
        let n_ab = sub_a.rotation * manifold.local_n1;
        // Kea's normal points from body 2 to body 1; parry's n1 points from shape 1 to shape 2.
        let normal = if frame.flip { n_ab } else { -n_ab };
        self.points.clear();
        self.features.clear();
        for p in manifold
            .points
            .iter()
            .filter(|p| p.dist <= frame.prediction)
        {
            let wa = sub_a.transform_point(p.local_p1);
            let wb = sub_b.transform_point(p.local_p2);
            self.points.push(((wa + wb) * 0.5, -p.dist));
            self.features.push((p.fid1.0, p.fid2.0));
        }
        reduce(&self.points, max_points.clamp(1, 8), &mut self.keep);
        for &k in &self.keep {
            let (position, depth) = self.points[k];
            let Ok(mut contact) = Contact::new(position, normal, depth) else {
                continue;
            };
            if contact.set_params(frame.params).is_err() {
                continue;
            }
            if let Some(d) = frame.direction {
                // Its projection on the tangent plane; none when it is (nearly) the normal.
                let t = d - normal * d.dot(normal);
                if t.length() > 1.0e-2 {
                    let _ = contact.set_direction(Some(t.normalize()));
                }
            }
            let (f1, f2) = self.features[k];
            let key = (manifold.subshape1, manifold.subshape2, f1, f2);
            if wanted[pair_start..].iter().any(|w| w.key == key) {
                continue;
            }
            wanted.push(Wanted {
                pair: frame.pair,
                key,
                bodies: frame.bodies,
                contact,
            });
        }
    }
}

impl CollisionWorld {
    pub(crate) fn narrow_phase(&mut self, world: &World, dt: Real) {
        let dispatcher = DefaultQueryDispatcher;
        self.wanted.clear();
        for state in self.pairs.values_mut() {
            state.seen = false;
        }
        for &(ia, ib) in &self.candidates {
            let (Some(a), Some(b)) = (
                &self.slots[ia as usize].collider,
                &self.slots[ib as usize].collider,
            ) else {
                continue;
            };
            if !should_collide(&self.jointed, &a.def, &b.def) {
                continue;
            }
            let state = self.pairs.entry((ia, ib)).or_default();
            state.seen = true;
            state.resting = pair_is_resting(world, &a.def, &b.def);
            if state.resting {
                continue; // asleep or static: its contacts stay as they are
            }
            let (pose_a, pose_b) = (collider_pose(world, &a.def), collider_pose(world, &b.def));
            let prediction = self.margin
                + dt * (motion(world, &a.def, a.reach) + motion(world, &b.def, b.reach));
            let pos_ab = pose_a.inv_mul(&pose_b);
            if dispatcher
                .contact_manifolds(
                    &pos_ab,
                    a.def.shared_shape().as_ref(),
                    b.def.shared_shape().as_ref(),
                    prediction,
                    &mut state.manifolds,
                    &mut state.workspace,
                )
                .is_err()
            {
                continue; // a pair parry cannot collide (two meshes, say) gets no contacts
            }
            // Body 1 of a Kea contact must be a body; the normal points from body 2 to body 1.
            let (body1, body2, flip) = match (a.def.body, b.def.body) {
                (Some(x), y) => (x, y, false),
                (None, Some(y)) => (y, None, true),
                (None, None) => continue,
            };
            state.flipped = flip;
            let (m1, m2) = if flip {
                (b.def.material, a.def.material)
            } else {
                (a.def.material, b.def.material)
            };
            let Ok(pair) = self.materials.pair_contact(m1, m2) else {
                continue;
            };
            let frame = PairFrame {
                pair: (ia, ib),
                bodies: (body1, body2),
                flip,
                params: pair.params,
                direction: pair.friction_direction,
                poses: (pose_a, pose_b),
                prediction,
            };
            let pair_start = self.wanted.len();
            for manifold in &state.manifolds {
                self.scratch.push_contacts(
                    manifold,
                    &frame,
                    self.strategy.max_points,
                    &mut self.wanted,
                    pair_start,
                );
            }
        }
    }
}

/// An upper bound of how fast any point of the collider moves, m/s.
fn motion(world: &World, def: &ColliderDef, reach: Real) -> Real {
    def.body.and_then(|b| world.body(b).ok()).map_or(0.0, |b| {
        b.linear_velocity().length() + b.angular_velocity().length() * reach
    })
}

/// The filter: not the same body (or both static), groups and masks agree, and not joined.
fn should_collide(jointed: &[(BodyHandle, BodyHandle)], a: &ColliderDef, b: &ColliderDef) -> bool {
    if a.body == b.body || a.groups & b.mask == 0 || b.groups & a.mask == 0 {
        return false;
    }
    match (a.body, b.body) {
        (Some(x), Some(y)) => jointed.binary_search(&(x.min(y), x.max(y))).is_err(),
        _ => true,
    }
}

/// Whether neither collider can move this step (static, disabled or asleep).
fn pair_is_resting(world: &World, a: &ColliderDef, b: &ColliderDef) -> bool {
    let still = |d: &ColliderDef| {
        d.body
            .and_then(|h| world.body(h).ok())
            .is_none_or(|b| !b.is_enabled() || b.is_sleeping())
    };
    still(a) && still(b)
}
