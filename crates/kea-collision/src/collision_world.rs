//! The bridge between geometry and dynamics (the guide's Dynamics Toolkit Bridge): colliders
//! attached to Kea bodies, and the step that turns their contact manifolds into the world's
//! contacts.

use crate::broad_phase::{Aabb, DynamicTree};
use crate::capacity::reserve_total;
pub(crate) use crate::collider::{handle_of, local_box, Collider, Slot, WORLD_BOUND};
pub use crate::collider::{ColliderDef, ColliderHandle};
use crate::error::{check_distance, CollisionError, CollisionResult};
use crate::events::{ContactEvent, ContactEventKind};
use crate::material::MaterialTable;
use crate::narrow_phase::{NarrowWorker, PAIR_CHUNK};
use crate::pairs::Pairs;
use crate::parry::math::Pose;
use kea::timing::Stamp;
use kea::{BodyHandle, CollisionStats, ConstraintHandle, Quat, Real, StepSize, Vec3, World};

/// How many contact points a pair of shapes keeps (the guide's contact strategy: one point is
/// enough to bounce, three or four to rest).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactStrategy {
    /// Most points per manifold, 1 to 4 (other values are clamped into that range); 4 by
    /// default.
    pub max_points: usize,
}

impl Default for ContactStrategy {
    fn default() -> Self {
        Self { max_points: 4 }
    }
}

/// Colliders, materials, and the contacts they generate in a [`World`]. It produces contacts
/// and never steps the world: `kea3d::PhysicsWorld` runs the whole step (drivers, contacts,
/// solve), and a loop of one's own calls [`CollisionWorld::update_contacts`], then
/// [`World::step`].
///
/// Clone it together with its [`World`]: the two clones step on bit for bit like the
/// originals.
///
/// ```
/// use kea::{BodyDef, Vec3, World};
/// use kea_collision::{ColliderDef, CollisionWorld, Shape};
///
/// let mut world = World::with_capacity(8, 64)?;
/// world.update_settings(|s| s.gravity = Vec3::new(0.0, -9.81, 0.0))?;
/// let mut collision = CollisionWorld::new();
/// collision.add_collider(&world, ColliderDef::new(None, Shape::plane(Vec3::Y)?))?;
/// let ball = Shape::sphere(0.5)?;
/// let mass = ball.mass_properties(1000.0)?;
/// let body = world.create_body(&BodyDef {
///     mass: mass.mass,
///     inertia: mass.inertia,
///     position: Vec3::new(0.0, 2.0, 0.0),
///     ..BodyDef::default()
/// })?;
/// collision.add_collider(&world, ColliderDef::new(Some(body), ball))?;
/// let dt = kea::StepSize::new(1.0 / 60.0)?;
/// for _ in 0..120 {
///     collision.update_contacts_by(&mut world, dt)?; // contacts from geometry
///     world.step_by(dt)?; // the world's step
/// }
/// let y = world.body(body)?.position().y;
/// assert!((y - 0.5).abs() < 0.02, "resting on the plane: y = {y}");
/// # Ok::<(), kea_collision::CollisionError>(())
/// ```
#[derive(Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CollisionWorld {
    pub(crate) slots: Vec<Slot>,
    pub(crate) free: Vec<u32>,
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
    pub(crate) pairs: Pairs,
    pub(crate) tree: DynamicTree,
    /// Colliders whose fat box changed this step (they look for new pairs).
    pub(crate) moved: Vec<u32>,
    /// Per collider slot: whether it cannot move this step (static, asleep, disabled; false
    /// for an empty slot), dense so that the narrow phase passes resting pairs without
    /// reaching into their colliders.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) still: Vec<bool>,
    /// The step the contacts were last updated for, s (pair impulses are forces times it).
    pub(crate) last_dt: Real,
    /// The jointed pairs changed this step (resting pairs are filtered again).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) jointed_changed: bool,
    /// The world's joint revision the jointed pairs were read at (`None`: read them, as after
    /// a change of which joints may collide).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) jointed_revision: Option<u64>,
    pub(crate) new_pairs: Vec<(u32, u32)>,
    /// The narrow phase's chunks of pairs: what each wants this step.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) workers: Vec<NarrowWorker>,
    /// Workers in use this step (`pairs / PAIR_CHUNK`, rounded up).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) active_workers: usize,
    pub(crate) events: Vec<ContactEvent>,
    pub(crate) pending_events: Vec<ContactEvent>,
    /// Body pairs joined by an enabled joint, sorted; rebuilt each update, and last update's.
    pub(crate) jointed: Vec<(BodyHandle, BodyHandle)>,
    pub(crate) previously_jointed: Vec<(BodyHandle, BodyHandle)>,
    /// Joints whose bodies may still collide.
    pub(crate) colliding_joints: Vec<ConstraintHandle>,
    /// Body pairs that never collide, as if jointed (sorted; [`CollisionWorld::exclude_pair`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub(crate) excluded: Vec<(BodyHandle, BodyHandle)>,
    /// What the last update did.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) stats: CollisionStats,
    /// Pairs whose manifold failed in the last update (see [`CollisionWorld::failed_pairs`]).
    pub(crate) failed_pairs: Vec<(ColliderHandle, ColliderHandle)>,
    /// The strategy and margin the pairs' manifolds were generated with: a change makes every
    /// manifold be generated anew.
    pub(crate) generated_with: (ContactStrategy, Real),
    /// Each body's colliders, to find those of the bodies that changed (`body_colliders.rs`).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) by_body: crate::body_colliders::BodyColliders,
    /// The world's `completed_steps` at the last update (`None`: look at every collider).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) bodies_seen_at: Option<u64>,
    /// The colliders this update looks at, ascending (when the world can tell).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) changed: Vec<u32>,
    /// Every collider is still this update (static, asleep or disabled).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) all_still: bool,
    /// Live pairs the last narrow phase left not at rest (`None`: not known, as after a
    /// restore).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) unrest: Option<u32>,
    /// Their slots, ascending (while `unrest` is known).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) unrested: Vec<u32>,
    /// The slots of the pairs this update found, and of the pairs its narrow phase visits
    /// when it can tell which (`narrow_pass.rs`): scratch.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) found_pairs: Vec<u32>,
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) visited_pairs: Vec<u32>,
    /// The events were made by a quiet update: the next quiet one makes the same.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) events_quiet: bool,
    /// What merging the next update's events with these needs (`events.rs`).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) event_record: crate::events::EventRecord,
    /// Whether two colliders may pair under the filter (`None`: not known since colliders
    /// were added or removed or the jointed pairs changed; `pairable.rs`).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) pairable: Option<bool>,
    /// Updates passed the broad phase by (`pairable.rs`): every collider's pose and box are
    /// as they were then, a sleeping or disabled body's too, and are set again before the
    /// next update that may pair.
    #[cfg_attr(feature = "serde", serde(default))]
    pub(crate) bounds_stale: bool,
}

/// How far a fat box reaches beyond its collider's swept box, m: a collider moving less than
/// this since its box was last set costs the broad phase nothing. A moving collider's fat box
/// also reaches [`FAT_LOOKAHEAD`] steps ahead along its velocity.
pub const FAT_MARGIN: Real = 0.05;

/// Steps of motion a moving collider's fat box reaches ahead.
pub const FAT_LOOKAHEAD: Real = 2.0;

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
            previously_jointed: Vec::new(),
            colliding_joints: Vec::new(),
            excluded: Vec::new(),
            pairs: Pairs::default(),
            tree: DynamicTree::new(),
            moved: Vec::new(),
            still: Vec::new(),
            last_dt: 0.0,
            jointed_changed: true,
            jointed_revision: None,
            new_pairs: Vec::new(),
            workers: Vec::new(),
            active_workers: 0,
            stats: CollisionStats::default(),
            failed_pairs: Vec::new(),
            generated_with: (ContactStrategy::default(), 0.01),
            by_body: Default::default(),
            bodies_seen_at: None,
            changed: Vec::new(),
            all_still: false,
            unrest: None,
            unrested: Vec::new(),
            found_pairs: Vec::new(),
            visited_pairs: Vec::new(),
            events_quiet: false,
            event_record: Default::default(),
            pairable: None,
            bounds_stale: false,
        }
    }

    /// Attaches a collider. The body must exist in `world`, the material in the table, and the
    /// placement must be finite with a unit rotation.
    pub fn add_collider(
        &mut self,
        world: &World,
        def: ColliderDef,
    ) -> CollisionResult<ColliderHandle> {
        self.check_collider(world, &def)?;
        let local = Pose::from_parts(def.offset, def.rotation.normalize());
        let sphere = def.shared_shape().compute_bounding_sphere(&local);
        let reach = sphere.center().length() + sphere.radius();
        let pose = collider_pose(world, &def);
        let aabb = def.shared_shape().compute_aabb(&pose);
        // Planes have unbounded boxes: a bound keeps the tree's surface areas finite.
        let fat = Aabb {
            min: aabb.mins.max(Vec3::splat(-WORLD_BOUND)),
            max: aabb.maxs.min(Vec3::splat(WORLD_BOUND)),
        };
        let fat = if def.body.is_some() {
            fat.grown(FAT_MARGIN + self.margin)
        } else {
            fat
        };
        let index = match self.free.last() {
            Some(&i) => i,
            None => self.slots.len() as u32,
        };
        self.reserve_for(self.slots.len() + 1);
        if is_multi_manifold(&def) {
            // Its pairs may hold several manifolds each: slots with room for them, made now
            // rather than when a body first reaches it in a warm step.
            self.pairs.reserve_multi(MULTI_PAIRS_PER_COLLIDER);
        }
        let leaf = self.tree.insert(fat, index);
        let local_box = local_box(def.shared_shape());
        let collider = Collider {
            def,
            reach,
            leaf,
            fat,
            pose,
            still: true,
            motion: 0.0,
            local_box,
        };
        self.moved.push(index);
        self.by_body.invalidate();
        self.pairable = None;
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

    /// Checks a new collider: its body exists, a plane is static, its material is in the
    /// table, its offset finite and its rotation unit.
    fn check_collider(&self, world: &World, def: &ColliderDef) -> CollisionResult<()> {
        if let Some(b) = def.body {
            world.body(b)?;
            if def.shape.kind_name() == "plane" {
                return Err(kea::KeaError::InvalidState {
                    operation: "add_collider",
                    reason: "a plane is unbounded static geometry: give it body None",
                }
                .into());
            }
        }
        self.materials.check(def.material)?;
        crate::error::check_extent("offset", def.offset)?;
        let len = def.rotation.length();
        if !def.rotation.is_finite() || (len - 1.0).abs() > 1.0e-3 {
            return Err(kea::KeaError::NotUnit {
                arg: "rotation",
                value: format!("{}", def.rotation),
                length: kea::math::wide(len),
            }
            .into());
        }
        Ok(())
    }

    /// Moves a collider within its body's frame (or the world, for static geometry): a new
    /// offset and rotation, checked like [`CollisionWorld::add_collider`]'s. Its pairs'
    /// manifolds are generated afresh at the next step; the contacts keep their handles.
    pub fn set_collider_placement(
        &mut self,
        world: &World,
        h: ColliderHandle,
        offset: Vec3,
        rotation: Quat,
    ) -> CollisionResult<()> {
        self.get(h)?;
        crate::error::check_extent("offset", offset)?;
        let rotation = crate::error::check_unit_quat("rotation", rotation)?;
        let c = self.slots[h.index as usize]
            .collider
            .as_mut()
            .expect("checked above");
        c.def.offset = offset;
        c.def.rotation = rotation;
        let local = Pose::from_parts(offset, rotation);
        let sphere = c.def.shared_shape().compute_bounding_sphere(&local);
        c.reach = sphere.center().length() + sphere.radius();
        c.pose = collider_pose(world, &c.def);
        for p in &mut self.pairs.slots {
            if p.alive && (p.colliders.0 == h.index || p.colliders.1 == h.index) {
                p.generated_at = None;
            }
        }
        self.moved.push(h.index);
        Ok(())
    }

    /// Reserves room for `colliders` colliders (and a few pairs each), so that adding them
    /// and stepping do not allocate.
    pub fn reserve(&mut self, colliders: usize) {
        self.reserve_for(colliders);
    }

    fn reserve_for(&mut self, colliders: usize) {
        let pairs = 8 * colliders;
        reserve_total(&mut self.slots, colliders);
        self.tree.reserve(colliders);
        self.pairs.reserve(pairs);
        reserve_total(&mut self.jointed, colliders);
        reserve_total(&mut self.previously_jointed, colliders);
        reserve_total(&mut self.moved, colliders);
        reserve_total(&mut self.new_pairs, pairs);
        reserve_total(&mut self.found_pairs, pairs);
        reserve_total(&mut self.visited_pairs, pairs);
        reserve_total(&mut self.unrested, pairs);
        self.pairs.reserve_lists(colliders, pairs);
        let chunks = pairs.div_ceil(PAIR_CHUNK);
        if self.workers.len() < chunks {
            self.workers.resize_with(chunks, NarrowWorker::default);
        }
        for w in &mut self.workers {
            w.reserve(PAIR_CHUNK);
        }
        reserve_total(&mut self.events, pairs);
        self.event_record.reserve(pairs);
        reserve_total(&mut self.pending_events, pairs);
    }

    /// Removes a collider and destroys the contacts it had in `world`.
    pub fn remove_collider(&mut self, world: &mut World, h: ColliderHandle) -> CollisionResult<()> {
        self.get(h)?;
        self.forget_collider(world, h.index);
        Ok(())
    }

    /// Removes every collider on `body` (a body about to be destroyed), destroying their
    /// contacts in `world`, so that nothing refers to the body once it is gone (a snapshot
    /// taken before the next update included).
    pub fn remove_colliders_of(&mut self, world: &mut World, body: BodyHandle) {
        for i in 0..self.slots.len() as u32 {
            let on_body = self.slots[i as usize]
                .collider
                .as_ref()
                .is_some_and(|c| c.def.body == Some(body));
            if on_body {
                self.forget_collider(world, i);
            }
        }
    }

    /// Drops collider slot `index`: its pairs (destroying their contacts, an `Ended` event
    /// for those touching), its leaf, and the slot itself.
    fn forget_collider(&mut self, world: &mut World, index: u32) {
        for slot in 0..self.pairs.slots.len() as u32 {
            let p = &self.pairs.slots[slot as usize];
            if !p.alive || (p.colliders.0 != index && p.colliders.1 != index) {
                continue;
            }
            for m in &p.manifolds {
                let _ = world.destroy_constraint(m.handle); // already gone with its body is fine
            }
            if p.touching {
                let k = p.colliders;
                let colliders = [handle_of(&self.slots, k.0), handle_of(&self.slots, k.1)];
                self.pending_events.push(ContactEvent {
                    kind: ContactEventKind::Ended,
                    colliders,
                });
            }
            self.pairs.remove(slot);
        }
        let slot = &mut self.slots[index as usize];
        if let Some(c) = slot.collider.take() {
            self.tree.remove(c.leaf);
        }
        self.by_body.invalidate();
        self.pairable = None;
        slot.generation = slot.generation.wrapping_add(1);
        self.free.push(index);
    }

    /// Stops two bodies colliding with each other, as bodies joined by a joint do not (a
    /// robot's link and its parent joined through light links between its joints). Refused
    /// for a body that is not in `world`, or a body paired with itself.
    pub fn exclude_pair(
        &mut self,
        world: &World,
        a: BodyHandle,
        b: BodyHandle,
    ) -> CollisionResult<()> {
        world.body(a)?;
        world.body(b)?;
        if a == b {
            return Err(kea::KeaError::OutOfRange {
                arg: "b",
                value: format!("{b:?}"),
                expected: "a body other than `a`",
            }
            .into());
        }
        let pair = (a.min(b), a.max(b));
        if let Err(i) = self.excluded.binary_search(&pair) {
            self.excluded.insert(i, pair);
            self.jointed_revision = None;
        }
        Ok(())
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
        self.jointed_revision = None;
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

    /// Checks the public settings (`margin`, `touch_distance`: finite and not negative), naming
    /// the first bad one. A pipeline calls it before its first stage changes anything.
    pub fn check_settings(&self) -> CollisionResult<()> {
        check_distance("margin", self.margin)?;
        check_distance("touch_distance", self.touch_distance)
    }

    /// Finds the colliding pairs and creates, updates or destroys the world's contacts so they
    /// match this step's contact manifolds. `dt` is the coming step, used to widen the search by
    /// each body's motion (speculative contacts) and must be positive; the public settings
    /// `margin` and `touch_distance` must be finite and not negative. On error nothing in
    /// `world` or here has changed.
    pub fn update_contacts(&mut self, world: &mut World, dt: Real) -> CollisionResult<()> {
        self.update_contacts_by(world, StepSize::new(dt)?)
    }

    /// [`CollisionWorld::update_contacts`] for a step already checked.
    pub fn update_contacts_by(&mut self, world: &mut World, dt: StepSize) -> CollisionResult<()> {
        // The collision layer's step, flushed as the world's is (`kea::float_mode`): a
        // collider's pose turns its offset in SIMD lanes, the fourth its material id.
        let _flush = kea::float_mode::FlushSubnormals::new();
        let dt = dt.seconds();
        // Checked before anything moves: parry asserts on a negative loosening margin, and a
        // refused step must leave the contacts as they were.
        self.check_settings()?;
        self.last_dt = dt;
        let t0 = Stamp::now(world.settings().step_timing);
        if self.generated_with != (self.strategy, self.margin) {
            self.generated_with = (self.strategy, self.margin);
            for p in &mut self.pairs.slots {
                p.generated_at = None;
            }
        }
        // Only the colliders of bodies that changed since the last update, when the world
        // can tell which (a sleeping pile's cost nothing).
        let incremental = self.list_changed_colliders(world);
        self.drop_colliders_of_destroyed_bodies(world, incremental);
        self.collect_jointed_pairs(world);
        if self.nothing_to_pair() {
            self.pass_unpairable();
            return Ok(());
        }
        // After refitting every box, every pair is looked at.
        let refit = self.bounds_stale;
        if refit {
            self.refit_stale_bounds(world);
        }
        self.update_bounds(world, dt, incremental);
        self.bodies_seen_at = Some(world.completed_steps());
        self.find_new_pairs();
        let t1 = Stamp::now(world.settings().step_timing);
        let (quiet, listed) = self.narrow_phase(dt, incremental && !refit);
        self.apply(world, quiet, listed)?;
        self.stats.time_broad_phase = t0.until(t1);
        self.stats.time_narrow_phase = t1.elapsed();
        self.stats.pairs = self.pairs.len() as u32;
        Ok(())
    }

    pub(crate) fn get(&self, h: ColliderHandle) -> CollisionResult<&Collider> {
        self.slots
            .get(h.index as usize)
            .filter(|s| s.generation == h.generation)
            .and_then(|s| s.collider.as_ref())
            .ok_or(CollisionError::StaleCollider {
                index: h.index,
                generation: h.generation,
            })
    }

    /// Forgets the colliders whose body is gone: among the changed colliders when
    /// `incremental` (a destroyed body is a changed one), else among all.
    fn drop_colliders_of_destroyed_bodies(&mut self, world: &mut World, incremental: bool) {
        let count = if incremental {
            self.changed.len()
        } else {
            self.slots.len()
        };
        for k in 0..count {
            let i = if incremental {
                self.changed[k]
            } else {
                k as u32
            };
            let gone = self.slots[i as usize]
                .collider
                .as_ref()
                .is_some_and(|c| c.def.body.is_some_and(|b| world.body(b).is_err()));
            if gone {
                self.forget_collider(world, i);
            }
        }
    }

    /// Body pairs joined by an enabled joint that has not been allowed to collide. When the set
    /// changes, the colliders of the bodies concerned look for pairs again (a pair the filter
    /// refused was never made, and their boxes may not move).
    fn collect_jointed_pairs(&mut self, world: &World) {
        // The joints are as they were when last read: so are their pairs.
        if self.jointed_revision == Some(world.joint_revision()) {
            self.jointed_changed = false;
            return;
        }
        self.jointed_revision = Some(world.joint_revision());
        std::mem::swap(&mut self.jointed, &mut self.previously_jointed);
        self.jointed.clear();
        for (joint, [a, b]) in world.enabled_joints() {
            if let (Some(a), Some(b)) = (a, b) {
                if self.colliding_joints.binary_search(&joint).is_err() {
                    self.jointed.push((a.min(b), a.max(b)));
                }
            }
        }
        self.jointed.extend_from_slice(&self.excluded);
        self.jointed.sort_unstable();
        self.jointed.dedup();
        self.jointed_changed = self.jointed != self.previously_jointed;
        if !self.jointed_changed {
            return;
        }
        self.pairable = None;
        for (i, slot) in self.slots.iter().enumerate() {
            let Some(body) = slot.collider.as_ref().and_then(|c| c.def.body) else {
                continue;
            };
            let changed = |list: &[(BodyHandle, BodyHandle)],
                           other: &[(BodyHandle, BodyHandle)]| {
                list.iter().any(|&(a, b)| {
                    (a == body || b == body) && other.binary_search(&(a, b)).is_err()
                })
            };
            if changed(&self.jointed, &self.previously_jointed)
                || changed(&self.previously_jointed, &self.jointed)
            {
                self.moved.push(i as u32);
            }
        }
    }
}

impl ColliderDef {
    pub(crate) fn shared_shape(&self) -> &crate::parry::shape::SharedShape {
        &self.shape.shared
    }
}

/// Pair slots with room for several manifolds made ready for each compound, mesh or height
/// field collider added.
const MULTI_PAIRS_PER_COLLIDER: usize = 8;

/// Whether a collider's pairs may hold several manifolds (compounds, meshes, height fields).
pub(crate) fn is_multi_manifold(def: &ColliderDef) -> bool {
    use crate::parry::shape::ShapeType;
    matches!(
        def.shared_shape().shape_type(),
        ShapeType::Compound | ShapeType::TriMesh | ShapeType::HeightField
    )
}

/// The collider's pose in the world: its body's pose times its offset.
pub(crate) fn collider_pose(world: &World, def: &ColliderDef) -> Pose {
    let (p, q) = match def.body.and_then(|b| world.body(b).ok()) {
        Some(body) => (body.position(), body.orientation()),
        None => (Vec3::ZERO, Quat::IDENTITY),
    };
    Pose::from_parts(p + q * def.offset, q * def.rotation)
}
