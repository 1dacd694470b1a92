//! The bridge between geometry and dynamics (the guide's Dynamics Toolkit Bridge): colliders
//! attached to Kea bodies, and the step that turns their contact manifolds into the world's
//! contacts.

use crate::broad_phase::{Entry, SweepAndPrune};
use crate::error::{check_finite, CollisionError, CollisionResult};
use crate::events::{ContactEvent, ContactEventKind};
use crate::material::{MaterialId, MaterialTable};
use crate::narrow_phase::ManifoldScratch;
use crate::parry::math::Pose;
use crate::parry::query::{ContactManifold, ContactManifoldsWorkspace};
use crate::shape::Shape;
use kea::{BodyHandle, ConstraintHandle, Contact, Quat, Real, StepStats, Vec3, World};
use std::collections::BTreeMap;

/// A collider's handle: generational, like Kea's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ColliderHandle {
    index: u32,
    generation: u32,
}

/// What to attach: a shape on a body (or on the static world), placed in the body's frame.
#[derive(Debug, Clone)]
pub struct ColliderDef {
    /// The body it moves with; `None` for static geometry.
    pub body: Option<BodyHandle>,
    /// The geometry.
    pub shape: Shape,
    /// Where the shape's origin sits in the body's frame (the body's position is its centre
    /// of mass), or in the world for static geometry.
    pub offset: Vec3,
    /// The shape's orientation in the body's frame.
    pub rotation: Quat,
    /// Its material, an id of the world's [`MaterialTable`].
    pub material: MaterialId,
    /// Collision groups this collider belongs to (bits).
    pub groups: u32,
    /// Groups it collides with (bits). Two colliders meet only if each one's groups intersect
    /// the other's mask.
    pub mask: u32,
}

impl ColliderDef {
    /// A collider of `shape` on `body` (or static), at the body's centre, material 0, in every
    /// group and colliding with every group.
    #[must_use]
    pub fn new(body: Option<BodyHandle>, shape: Shape) -> Self {
        Self {
            body,
            shape,
            offset: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            material: 0,
            groups: 1,
            mask: u32::MAX,
        }
    }
}

/// How many contact points a pair of shapes keeps (the guide's contact strategy: one point is
/// enough to bounce, three or four to rest).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ContactStrategy {
    /// Most points per manifold, 1 to 8; 4 by default.
    pub max_points: usize,
}

impl Default for ContactStrategy {
    fn default() -> Self {
        Self { max_points: 4 }
    }
}

/// One contact point of a pair, remembered across steps by its features so that its Kea
/// contact (and the solvers' warm start) persists.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PairContact {
    pub key: (u32, u32, u32, u32),
    pub handle: ConstraintHandle,
    pub seen: bool,
}

/// What the collision world remembers of a pair of colliders whose bounds overlap.
#[derive(Default)]
pub(crate) struct PairState {
    pub manifolds: Vec<ContactManifold<(), ()>>,
    pub workspace: Option<ContactManifoldsWorkspace>,
    pub contacts: Vec<PairContact>,
    /// Among this step's candidate pairs (bounds overlap and the filter lets it collide).
    pub seen: bool,
    /// Neither side can move: its contacts are kept as they are.
    pub resting: bool,
    /// Touching last step, and this step.
    pub touching: bool,
    pub touching_now: bool,
    /// Impulse on the first collider's side over the last step, N·s.
    pub impulse: Vec3,
    /// The first collider's body is body 2 of the pair's contacts.
    pub flipped: bool,
}

pub(crate) struct Collider {
    pub(crate) def: ColliderDef,
    /// Radius of the shape's bounding sphere about the body's centre, for swept bounds.
    pub(crate) reach: Real,
}

pub(crate) struct Slot {
    generation: u32,
    pub(crate) collider: Option<Collider>,
}

/// The handle of the collider in slot `i`.
pub(crate) fn handle_of(slots: &[Slot], i: u32) -> ColliderHandle {
    ColliderHandle {
        index: i,
        generation: slots[i as usize].generation,
    }
}

/// A contact the narrow phase wants this step.
pub(crate) struct Wanted {
    pub pair: (u32, u32),
    pub key: (u32, u32, u32, u32),
    pub bodies: (BodyHandle, Option<BodyHandle>),
    pub contact: Contact,
}

/// Colliders, materials, and the contacts they generate in a [`World`].
pub struct CollisionWorld {
    pub(crate) slots: Vec<Slot>,
    free: Vec<u32>,
    /// The material table that gives each pair's contact parameters.
    pub materials: MaterialTable,
    /// Contact points kept per manifold.
    pub strategy: ContactStrategy,
    /// Distance below which separated shapes already get (speculative) contacts, m. The swept
    /// motion of the step is added to it, so fast bodies do not tunnel.
    pub margin: Real,
    /// How close to overlap a contact point must be for its pair to count as touching in the
    /// events, m (1 mm by default).
    pub touch_distance: Real,
    pub(crate) pairs: BTreeMap<(u32, u32), PairState>,
    sap: SweepAndPrune,
    pub(crate) candidates: Vec<(u32, u32)>,
    pub(crate) wanted: Vec<Wanted>,
    pub(crate) events: Vec<ContactEvent>,
    pub(crate) pending_events: Vec<ContactEvent>,
    /// Body pairs joined by an enabled joint, sorted; rebuilt each update.
    pub(crate) jointed: Vec<(BodyHandle, BodyHandle)>,
    /// Joints whose bodies may still collide.
    colliding_joints: Vec<ConstraintHandle>,
    pub(crate) scratch: ManifoldScratch,
}

impl Default for CollisionWorld {
    fn default() -> Self {
        Self::new()
    }
}

impl CollisionWorld {
    /// An empty collision world with material 0 only, 4 points per manifold and a 1 cm margin.
    #[must_use]
    pub fn new() -> Self {
        Self {
            slots: Vec::new(),
            free: Vec::new(),
            materials: MaterialTable::new(),
            strategy: ContactStrategy::default(),
            margin: 0.01,
            touch_distance: 1.0e-3,
            events: Vec::new(),
            pending_events: Vec::new(),
            jointed: Vec::new(),
            colliding_joints: Vec::new(),
            pairs: BTreeMap::new(),
            sap: SweepAndPrune::default(),
            candidates: Vec::new(),
            wanted: Vec::new(),
            scratch: ManifoldScratch::default(),
        }
    }

    /// Attaches a collider. The body must exist in `world`, the material in the table, and the
    /// placement must be finite with a unit rotation.
    pub fn add_collider(
        &mut self,
        world: &World,
        def: ColliderDef,
    ) -> CollisionResult<ColliderHandle> {
        if let Some(b) = def.body {
            world.body(b)?;
        }
        self.materials.check(def.material)?;
        crate::error::check_vec3("offset", def.offset)?;
        let len = def.rotation.length();
        if !def.rotation.is_finite() || (len - 1.0).abs() > 1.0e-3 {
            return Err(kea::KeaError::NotUnit {
                arg: "rotation",
                value: format!("{}", def.rotation),
                length: kea::math::wide(len),
            }
            .into());
        }
        let local = Pose::from_parts(def.offset, def.rotation.normalize());
        let sphere = def.shared_shape().compute_bounding_sphere(&local);
        let reach = sphere.center().length() + sphere.radius();
        let collider = Collider { def, reach };
        let index = match self.free.pop() {
            Some(i) => {
                self.slots[i as usize].collider = Some(collider);
                i
            }
            None => {
                self.slots.push(Slot {
                    generation: 0,
                    collider: Some(collider),
                });
                (self.slots.len() - 1) as u32
            }
        };
        Ok(ColliderHandle {
            index,
            generation: self.slots[index as usize].generation,
        })
    }

    /// Removes a collider and destroys the contacts it had in `world`.
    pub fn remove_collider(&mut self, world: &mut World, h: ColliderHandle) -> CollisionResult<()> {
        self.get(h)?;
        let gone: Vec<(u32, u32)> = self
            .pairs
            .keys()
            .filter(|k| k.0 == h.index || k.1 == h.index)
            .copied()
            .collect();
        for k in gone {
            let Some(state) = self.pairs.remove(&k) else {
                continue;
            };
            for c in &state.contacts {
                let _ = world.destroy_constraint(c.handle); // already gone with its body is fine
            }
            if state.touching {
                let colliders = [handle_of(&self.slots, k.0), handle_of(&self.slots, k.1)];
                self.pending_events.push(ContactEvent {
                    kind: ContactEventKind::Ended,
                    colliders,
                });
            }
        }
        let slot = &mut self.slots[h.index as usize];
        slot.collider = None;
        slot.generation = slot.generation.wrapping_add(1);
        self.free.push(h.index);
        Ok(())
    }

    /// The contact events of the last update (began, persisted, ended), in pair order.
    #[must_use]
    pub fn events(&self) -> &[ContactEvent] {
        &self.events
    }

    /// The total contact impulse on collider `a`'s body from collider `b` over the last step,
    /// N·s (zero if they did not touch).
    pub fn pair_impulse(&self, a: ColliderHandle, b: ColliderHandle) -> CollisionResult<Vec3> {
        self.get(a)?;
        self.get(b)?;
        let key = (a.index.min(b.index), a.index.max(b.index));
        let on_first = self.pairs.get(&key).map_or(Vec3::ZERO, |p| p.impulse);
        Ok(if a.index <= b.index {
            on_first
        } else {
            -on_first
        })
    }

    /// The total contact impulse on `body` from `other` (`None`: the static world) over the
    /// last step, summed over all their colliders' pairs, N·s.
    #[must_use]
    pub fn body_pair_impulse(&self, body: BodyHandle, other: Option<BodyHandle>) -> Vec3 {
        let mut total = Vec3::ZERO;
        for (&(ia, ib), state) in &self.pairs {
            let (Some(a), Some(b)) = (
                &self.slots[ia as usize].collider,
                &self.slots[ib as usize].collider,
            ) else {
                continue;
            };
            if a.def.body == Some(body) && b.def.body == other {
                total += state.impulse;
            } else if b.def.body == Some(body) && a.def.body == other {
                total -= state.impulse;
            }
        }
        total
    }

    /// The deepest penetration among the contacts this collision world made, m (0 if none
    /// overlap): the contact constraints' largest error.
    #[must_use]
    pub fn deepest_penetration(&self, world: &World) -> Real {
        self.pairs
            .values()
            .flat_map(|p| p.contacts.iter())
            .filter_map(|c| world.contact(c.handle).ok())
            .map(Contact::penetration)
            .fold(0.0, Real::max)
    }

    /// Lets (or stops) the two bodies of a joint collide with each other. By default bodies
    /// joined by an enabled joint do not collide.
    pub fn set_joint_collisions(
        &mut self,
        world: &World,
        joint: ConstraintHandle,
        collide: bool,
    ) -> CollisionResult<()> {
        world.constraint_bodies(joint)?;
        match (self.colliding_joints.binary_search(&joint), collide) {
            (Err(i), true) => self.colliding_joints.insert(i, joint),
            (Ok(i), false) => {
                self.colliding_joints.remove(i);
            }
            _ => {}
        }
        Ok(())
    }

    /// A collider's definition.
    pub fn collider(&self, h: ColliderHandle) -> CollisionResult<&ColliderDef> {
        self.get(h).map(|c| &c.def)
    }

    /// Number of colliders.
    #[must_use]
    pub fn collider_count(&self) -> usize {
        self.slots.iter().filter(|s| s.collider.is_some()).count()
    }

    /// The Kea contacts currently generated between two colliders.
    pub fn contacts_between(
        &self,
        a: ColliderHandle,
        b: ColliderHandle,
    ) -> CollisionResult<Vec<ConstraintHandle>> {
        self.get(a)?;
        self.get(b)?;
        let key = (a.index.min(b.index), a.index.max(b.index));
        Ok(self
            .pairs
            .get(&key)
            .map(|p| p.contacts.iter().map(|c| c.handle).collect())
            .unwrap_or_default())
    }

    /// Brings the world's contacts up to date with the geometry, then steps the world by `dt`.
    pub fn step(&mut self, world: &mut World, dt: Real) -> CollisionResult<StepStats> {
        self.update_contacts(world, dt)?;
        let stats = world.step(dt)?;
        for state in self.pairs.values_mut() {
            let force: Vec3 = state
                .contacts
                .iter()
                .filter_map(|c| world.contact_force(c.handle).ok())
                .sum();
            // Contact forces act on the contacts' body 1: the first collider's, unless flipped.
            state.impulse = if state.flipped {
                -force * dt
            } else {
                force * dt
            };
        }
        Ok(stats)
    }

    /// Finds the colliding pairs and creates, updates or destroys the world's contacts so they
    /// match this step's contact manifolds. `dt` is the coming step, used to widen the search by
    /// each body's motion (speculative contacts). On error nothing in `world` has changed.
    pub fn update_contacts(&mut self, world: &mut World, dt: Real) -> CollisionResult<()> {
        check_finite("dt", dt)?;
        self.drop_colliders_of_destroyed_bodies(world);
        self.collect_jointed_pairs(world);
        self.broad_phase(world, dt);
        self.narrow_phase(world, dt);
        self.apply(world)
    }

    fn get(&self, h: ColliderHandle) -> CollisionResult<&Collider> {
        self.slots
            .get(h.index as usize)
            .filter(|s| s.generation == h.generation)
            .and_then(|s| s.collider.as_ref())
            .ok_or(CollisionError::StaleCollider {
                index: h.index,
                generation: h.generation,
            })
    }

    fn drop_colliders_of_destroyed_bodies(&mut self, world: &World) {
        for slot in &mut self.slots {
            if let Some(c) = &slot.collider {
                if c.def.body.is_some_and(|b| world.body(b).is_err()) {
                    slot.collider = None;
                    slot.generation = slot.generation.wrapping_add(1);
                }
            }
        }
        self.free.clear();
        self.free.extend(
            (0..self.slots.len() as u32)
                .rev()
                .filter(|&i| self.slots[i as usize].collider.is_none()),
        );
    }

    /// Body pairs joined by an enabled joint that has not been allowed to collide.
    fn collect_jointed_pairs(&mut self, world: &World) {
        self.jointed.clear();
        for (joint, [a, b]) in world.enabled_joints() {
            if let (Some(a), Some(b)) = (a, b) {
                if self.colliding_joints.binary_search(&joint).is_err() {
                    self.jointed.push((a.min(b), a.max(b)));
                }
            }
        }
        self.jointed.sort_unstable();
    }

    fn broad_phase(&mut self, world: &World, dt: Real) {
        let margin = self.margin;
        let entries = self.slots.iter().enumerate().filter_map(|(i, s)| {
            let c = s.collider.as_ref()?;
            let pose = collider_pose(world, &c.def);
            let aabb = c.def.shared_shape().compute_aabb(&pose);
            let (mut min, mut max) = (
                aabb.mins - Vec3::splat(margin),
                aabb.maxs + Vec3::splat(margin),
            );
            if let Some(body) = c.def.body.and_then(|b| world.body(b).ok()) {
                let sweep = body.linear_velocity() * dt;
                min += sweep.min(Vec3::ZERO);
                max += sweep.max(Vec3::ZERO);
                let turn = Vec3::splat(body.angular_velocity().length() * dt * c.reach);
                min -= turn;
                max += turn;
            }
            Some(Entry {
                slot: i as u32,
                min,
                max,
            })
        });
        self.sap.pairs(entries, &mut self.candidates);
    }
}

impl ColliderDef {
    pub(crate) fn shared_shape(&self) -> &crate::parry::shape::SharedShape {
        &self.shape.shared
    }
}

/// The collider's pose in the world: its body's pose times its offset.
pub(crate) fn collider_pose(world: &World, def: &ColliderDef) -> Pose {
    let (p, q) = match def.body.and_then(|b| world.body(b).ok()) {
        Some(body) => (body.position(), body.orientation()),
        None => (Vec3::ZERO, Quat::IDENTITY),
    };
    Pose::from_parts(p + q * def.offset, q * def.rotation)
}
