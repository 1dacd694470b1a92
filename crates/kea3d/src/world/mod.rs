//! [`PhysicsWorld`]: dynamics and collision in one object.

mod attach;
mod bodies;
mod held;
mod pipeline;
mod snapshot;
mod state_copy;
pub use held::HeldWorld;

use crate::body::BodyType;
use crate::collider::ColliderMass;
use crate::Result;
use kea::{BodyHandle, KeaError, Quat, Real, Vec3, World, WorldDef};
use kea_collision::{ColliderHandle, CollisionWorld, MaterialId, Surface};
use kea_scene::{BuiltScene, ScenePaths};

/// A world that owns dynamics and collision together: insert bodies, colliders and joints,
/// then [`PhysicsWorld::step`].
///
/// Capacities start small and grow as the world fills; [`PhysicsWorld::reserve`] sets them
/// ahead, and once warm (a step after the last growth) a step allocates nothing.
///
/// A clone is the same world at the same instant: stepping both alike gives the same bits.
///
/// ```
/// use kea3d::prelude::*;
///
/// let mut world = PhysicsWorld::new();
/// world.set_gravity([0.0, -9.81, 0.0])?;
/// let ball = world.insert_body(Body::dynamic().linear_velocity([2.0, 0.0, 0.0]))?;
/// world.insert_collider(Collider::ball(0.1), Some(ball))?;
/// for _ in 0..60 {
///     world.step(1.0 / 60.0)?; // one second of flight, nothing to hit
/// }
/// let p = world.position(ball)?;
/// assert!((p.x - 2.0).abs() < 1e-3, "{p}");
/// assert!((p.y + 0.5 * 9.81).abs() < 0.1, "free fall: y = {}", p.y);
/// # Ok::<(), kea3d::Error>(())
/// ```
#[derive(Clone)]
pub struct PhysicsWorld {
    dynamics: World,
    collision: CollisionWorld,
    /// Per body slot of `dynamics`: what the facade knows of it.
    meta: Vec<Option<BodyMeta>>,
    /// Materials made for colliders' own surfaces, by surface.
    surfaces: Vec<(Surface, MaterialId)>,
    /// Position-driven kinematic bodies, in insertion order.
    driven: Vec<BodyHandle>,
    /// A scene's keyframed paths, driven before each step.
    paths: ScenePaths,
    /// A scene's bodies and joints by name.
    names: Vec<(String, BodyHandle)>,
    joint_names: Vec<(String, kea::ConstraintHandle)>,
}

/// What a body is beyond the dynamics layer's view.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct BodyMeta {
    pub handle: BodyHandle,
    pub kind: BodyType,
    /// The builder's mass and inertia, which win over the colliders'.
    pub explicit_mass: Option<Real>,
    pub explicit_inertia: Option<kea::Mat3>,
    /// The builder's centre of mass (body frame), which wins over the colliders'.
    pub explicit_com: Option<Vec3>,
    /// Centre of mass in the body's frame (the dynamics layer's body sits there).
    pub local_com: Vec3,
    pub colliders: Vec<Attached>,
    /// The pose to reach in the coming step (position-driven kinematic bodies).
    pub target: Option<(Vec3, Quat)>,
}

/// A collider as its body holds it: placed in the body's frame (about its origin).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct Attached {
    pub handle: ColliderHandle,
    pub offset: Vec3,
    pub rotation: Quat,
    pub mass: ColliderMass,
}

impl Default for PhysicsWorld {
    fn default() -> Self {
        Self::new()
    }
}

impl PhysicsWorld {
    /// An empty world with default parameters (gravity −9.81 m/s² along y) and small
    /// capacities that grow.
    #[must_use]
    pub fn new() -> Self {
        Self::with_def(WorldDef {
            max_bodies: 16,
            max_constraints: 64,
            max_island_rows: 64,
            ..WorldDef::default()
        })
        .expect("the default parameters are valid")
    }

    /// An empty world with these parameters ([`WorldDef`]'s capacities are reserved up front).
    pub fn with_def(def: WorldDef) -> Result<Self> {
        let bodies = def.max_bodies;
        let mut collision = CollisionWorld::new();
        collision.reserve(bodies);
        Ok(Self::from_parts(World::new(def)?, collision))
    }

    /// A world of a dynamics world and its collision layer, made elsewhere. Every body in it
    /// counts as dynamic (kinematic if flagged, static if disabled), its mass as given, its
    /// origin at its centre of mass.
    #[must_use]
    pub fn from_parts(dynamics: World, collision: CollisionWorld) -> Self {
        let mut world = Self {
            dynamics,
            collision,
            meta: Vec::new(),
            surfaces: Vec::new(),
            driven: Vec::new(),
            paths: ScenePaths::default(),
            names: Vec::new(),
            joint_names: Vec::new(),
        };
        let found: Vec<(BodyHandle, BodyType, Real)> = world
            .dynamics
            .bodies()
            .map(|(h, b)| {
                let kind = if !b.is_enabled() {
                    BodyType::Static
                } else if b.is_kinematic() {
                    BodyType::KinematicVelocity
                } else {
                    BodyType::Dynamic
                };
                (h, kind, b.mass())
            })
            .collect();
        for (h, kind, mass) in found {
            world.set_meta(
                h,
                BodyMeta {
                    handle: h,
                    kind,
                    explicit_mass: Some(mass),
                    explicit_inertia: None,
                    explicit_com: None,
                    local_com: Vec3::ZERO,
                    colliders: Vec::new(),
                    target: None,
                },
            );
        }
        world
    }

    /// A built scene file as one world: its bodies (dynamic, mass as the scene gives), static
    /// geometry, joints, materials, and keyframed paths; bodies and joints keep their names.
    #[must_use]
    pub fn from_scene(scene: BuiltScene) -> Self {
        let paths = scene.paths().clone();
        let mut world = Self::from_parts(scene.world, scene.collision);
        world.paths = paths;
        world.names = scene.bodies;
        world.joint_names = scene.joints;
        world
    }

    /// Gravity, m/s².
    #[must_use]
    pub fn gravity(&self) -> Vec3 {
        self.dynamics.settings().gravity
    }

    /// Sets gravity, m/s².
    pub fn set_gravity(&mut self, g: impl Into<Vec3>) -> Result<()> {
        Ok(self.dynamics.update_settings(|s| s.gravity = g.into())?)
    }

    /// Turns the stage times of the step statistics on (default) or off; off, no clock is
    /// read, which a small world stepped many times without reading its statistics notices
    /// (see [`kea::timing`]). The results are the same bits either way.
    pub fn set_step_timing(&mut self, on: bool) {
        self.dynamics
            .update_settings(|s| s.step_timing = on)
            .expect("the step-timing flag takes any value");
    }

    /// Reserves room for this many bodies, colliders and constraints (contacts included), so
    /// that adding up to that many and stepping allocate nothing more.
    pub fn reserve(&mut self, bodies: usize, colliders: usize, constraints: usize) {
        self.dynamics.reserve(bodies, constraints);
        self.collision.reserve(colliders);
        self.meta.reserve(bodies.saturating_sub(self.meta.len()));
    }

    /// The dynamics layer (the guide's Mdt world): rows, solver settings, reactions.
    #[must_use]
    pub fn dynamics(&self) -> &World {
        &self.dynamics
    }

    /// The dynamics layer, to change. Bodies made or destroyed here are unknown to this
    /// world's body types and mass bookkeeping.
    pub fn dynamics_mut(&mut self) -> &mut World {
        &mut self.dynamics
    }

    /// The collision layer: colliders, materials, events, queries.
    #[must_use]
    pub fn collision(&self) -> &CollisionWorld {
        &self.collision
    }

    /// The collision layer, to change (its settings, materials and queries).
    pub fn collision_mut(&mut self) -> &mut CollisionWorld {
        &mut self.collision
    }

    /// Both layers at once, for calls that take both (queries, `add_collider`).
    pub fn layers_mut(&mut self) -> (&mut World, &mut CollisionWorld) {
        (&mut self.dynamics, &mut self.collision)
    }

    /// A scene body by name.
    #[must_use]
    pub fn body_by_name(&self, name: &str) -> Option<BodyHandle> {
        self.names.iter().find(|(n, _)| n == name).map(|&(_, h)| h)
    }

    /// A scene joint by name (untyped).
    #[must_use]
    pub fn joint_by_name(&self, name: &str) -> Option<kea::ConstraintHandle> {
        self.joint_names
            .iter()
            .find(|(n, _)| n == name)
            .map(|&(_, h)| h)
    }

    /// The scene's bodies with their names, in scene order (empty for a world built in code).
    #[must_use]
    pub fn named_bodies(&self) -> &[(String, BodyHandle)] {
        &self.names
    }

    /// The scene's joints with their names, in scene order (empty for a world built in code).
    #[must_use]
    pub fn named_joints(&self) -> &[(String, kea::ConstraintHandle)] {
        &self.joint_names
    }

    /// Names more bodies and joints (a robot's links and joints, loaded from a scene file).
    pub(crate) fn add_names(
        &mut self,
        bodies: impl IntoIterator<Item = (String, BodyHandle)>,
        joints: impl IntoIterator<Item = (String, kea::ConstraintHandle)>,
    ) {
        self.names.extend(bodies);
        self.joint_names.extend(joints);
    }

    fn set_meta(&mut self, h: BodyHandle, meta: BodyMeta) {
        let i = h.index() as usize;
        if self.meta.len() <= i {
            self.meta.resize(i + 1, None);
        }
        self.meta[i] = Some(meta);
    }

    pub(crate) fn meta(&self, h: BodyHandle) -> Result<&BodyMeta> {
        self.dynamics.body(h)?;
        match self.meta.get(h.index() as usize) {
            Some(Some(m)) if m.handle == h => Ok(m),
            _ => Err(unknown_body()),
        }
    }

    pub(crate) fn meta_mut(&mut self, h: BodyHandle) -> Result<&mut BodyMeta> {
        self.dynamics.body(h)?;
        match self.meta.get_mut(h.index() as usize) {
            Some(Some(m)) if m.handle == h => Ok(m),
            _ => Err(unknown_body()),
        }
    }
}

/// A body made through [`PhysicsWorld::dynamics_mut`] has no type or collider records here.
fn unknown_body() -> crate::Error {
    KeaError::InvalidState {
        operation: "body",
        reason: "the body was made through dynamics_mut(): use the dynamics layer for it",
    }
    .into()
}

/// Joint handles read a physics world as its dynamics layer: `hinge.angle(&world)`.
impl AsRef<World> for PhysicsWorld {
    fn as_ref(&self) -> &World {
        &self.dynamics
    }
}

/// Joint handles change a physics world's joints through its dynamics layer:
/// `hinge.set_motor(&mut world, 1.0, 50.0)`.
impl AsMut<World> for PhysicsWorld {
    fn as_mut(&mut self) -> &mut World {
        &mut self.dynamics
    }
}
