//! Building a scene: world parameters, materials and their pairs, static geometry, bodies with
//! mass from their shapes, groups and joints, every reference checked and every error placed.

use crate::error::SceneError;
use crate::format::{
    BodySpec, ColliderSpec, InertiaSpec, MaterialPairSpec, Scene, ShapeSpec, SolverSpec, WorldSpec,
    V3,
};
use crate::groups::{add_group, group_size};
use crate::joints::{add_joint, ScenePaths};
use kea::{
    BodyDef, BodyHandle, ConstraintHandle, ContactType, DemMode, DemSettings, FrictionModel,
    IterativeParams, Mat3, Quat, Real, Routing, SolverMode, Vec3, World, WorldDef,
};
use kea_collision::{ColliderDef, CollisionWorld, MassProperties, Shape, Surface};
use std::collections::HashMap;

/// A built scene: the world, its collision layer, the bodies and joints by name, and the
/// keyframed paths. It is what a scene file builds; it does not step (`kea3d::PhysicsWorld`
/// takes it whole with `from_scene`, and its pipeline runs the step).
#[derive(Clone)]
pub struct BuiltScene {
    /// The dynamics.
    pub world: World,
    /// The geometry and contacts.
    pub collision: CollisionWorld,
    /// Every body with its name, in scene order (groups name theirs `pyramid0.12`, `chain1.3`,
    /// `ragdoll2.torso`).
    pub bodies: Vec<(String, BodyHandle)>,
    /// Every joint with its name: group joints first (`chain1.3`, `ragdoll2.left_knee`), then
    /// the scene's joints (unnamed ones are `joint<index>`).
    pub joints: Vec<(String, ConstraintHandle)>,
    /// Fixed-path joints with keyframed paths, driven before each step.
    pub(crate) paths: ScenePaths,
    /// Index into `bodies` by name (names are looked up for every joint and checked for
    /// every body: a linear scan would make big scenes quadratic).
    pub(crate) body_index: HashMap<String, usize>,
    /// Index into `joints` by name.
    pub(crate) joint_index: HashMap<String, usize>,
}

impl BuiltScene {
    /// The scene's keyframed path joints (`kea3d`'s pipeline drives them before each step).
    #[must_use]
    pub fn paths(&self) -> &ScenePaths {
        &self.paths
    }

    /// The body of that name.
    #[must_use]
    pub fn body(&self, name: &str) -> Option<BodyHandle> {
        self.body_index.get(name).map(|&i| self.bodies[i].1)
    }

    /// The joint of that name.
    #[must_use]
    pub fn joint(&self, name: &str) -> Option<ConstraintHandle> {
        self.joint_index.get(name).map(|&i| self.joints[i].1)
    }
}

/// Most bodies a scene may have, groups expanded (a typo in a group's counts must not try to
/// allocate the whole memory).
pub const MAX_BODIES: usize = 1 << 20;
/// Most constraints a scene's world may hold: the world reserves rows for all of them up front
/// (about 1 KB each), so this bounds what a scene file can make it allocate to about 0.5 GB.
pub const MAX_CONSTRAINTS: usize = 1 << 19;
/// Most island rows to reserve exact-solver memory for (its memory grows as rows²).
const MAX_ISLAND_ROWS: usize = 4096;

/// How many bodies `scene` makes, groups expanded (saturating; [`build`] refuses more than
/// [`MAX_BODIES`]).
#[must_use]
pub fn body_count(scene: &Scene) -> usize {
    scene
        .groups
        .iter()
        .fold(scene.bodies.len(), |n, g| n.saturating_add(group_size(g)))
}

/// Builds `scene` into a new world.
pub fn build(scene: &Scene) -> Result<BuiltScene, SceneError> {
    for (i, r) in scene.robots.iter().enumerate() {
        r.validate(i)?;
    }
    let mut body_count = scene.bodies.len();
    for (i, g) in scene.groups.iter().enumerate() {
        body_count = body_count.saturating_add(group_size(g));
        if body_count > MAX_BODIES {
            return Err(SceneError::at(
                format!("groups[{i}]"),
                format!("the scene would have more than {MAX_BODIES} bodies"),
            ));
        }
    }
    let world =
        World::new(world_def(&scene.world, body_count)?).map_err(|e| SceneError::at("world", e))?;
    let mut built = BuiltScene {
        world,
        collision: CollisionWorld::new(),
        bodies: Vec::new(),
        joints: Vec::new(),
        paths: ScenePaths::default(),
        body_index: HashMap::new(),
        joint_index: HashMap::new(),
    };
    let materials = add_materials(&mut built.collision, scene)?;
    for (i, c) in scene.statics.iter().enumerate() {
        let place = format!("static[{i}]");
        let def = collider(c, None, &materials, &place)?;
        built
            .collision
            .add_collider(&built.world, def)
            .map_err(|e| SceneError::at(place, e))?;
    }
    for (i, b) in scene.bodies.iter().enumerate() {
        add_body(&mut built, b, &materials, &format!("bodies[{i}]"))?;
    }
    for (i, g) in scene.groups.iter().enumerate() {
        add_group(&mut built, g, i, &format!("groups[{i}]"))?;
    }
    for (i, j) in scene.joints.iter().enumerate() {
        add_joint(&mut built, j, i, &format!("joints[{i}]"))?;
    }
    Ok(built)
}

/// The world's definition, capacities sized for `body_count` bodies where not given.
fn world_def(w: &WorldSpec, body_count: usize) -> Result<WorldDef, SceneError> {
    let max_bodies = if w.max_bodies > 0 {
        w.max_bodies
    } else {
        body_count.max(1)
    };
    let max_constraints = if w.max_constraints > 0 {
        w.max_constraints
    } else {
        body_count.saturating_mul(16).clamp(256, MAX_CONSTRAINTS)
    };
    for (field, value, most) in [
        ("max_bodies", w.max_bodies, MAX_BODIES),
        ("max_constraints", w.max_constraints, MAX_CONSTRAINTS),
        (
            "max_island_rows",
            w.max_island_rows.unwrap_or(0),
            MAX_ISLAND_ROWS,
        ),
    ] {
        if value > most {
            return Err(SceneError::at(
                format!("world.{field}"),
                format!("must be at most {most}, got {value}"),
            ));
        }
    }
    let defaults = WorldDef::default();
    let s = w.sleep_thresholds.clone().unwrap_or_default();
    let dem = DemSettings {
        mode: if w.sleep {
            DemMode::PartitionAutoDisable
        } else {
            DemMode::default()
        },
        velocity_threshold: s.velocity,
        angular_velocity_threshold: s.angular_velocity,
        acceleration_threshold: s.acceleration,
        angular_acceleration_threshold: s.angular_acceleration,
        alive_window: s.time,
        force_threshold: s.force,
        torque_threshold: s.torque,
    };
    dem.validate()
        .map_err(|e| SceneError::at("world.sleep_thresholds", e))?;
    let r = w.routing.clone().unwrap_or_default();
    let it = w.iterative.clone().unwrap_or_default();
    Ok(WorldDef {
        max_bodies,
        max_constraints,
        max_island_rows: w.max_island_rows.unwrap_or(defaults.max_island_rows),
        gravity: v3(w.gravity),
        epsilon: w.epsilon,
        gamma: w.gamma,
        max_lcp_iterations: w.max_lcp_iterations.unwrap_or(defaults.max_lcp_iterations),
        max_friction_passes: w
            .max_friction_passes
            .unwrap_or(defaults.max_friction_passes),
        dem,
        routing: Routing {
            mode: match w.solver {
                SolverSpec::Hybrid => SolverMode::Hybrid,
                SolverSpec::Exact => SolverMode::Exact,
                SolverSpec::Iterative => SolverMode::Iterative,
                SolverSpec::Split => SolverMode::Split,
            },
            max_exact_rows: r.max_exact_rows,
            max_exact_bodies: r.max_exact_bodies,
            hysteresis: r.hysteresis,
            mass_ratio: r.mass_ratio,
            stack_bodies: r.stack_bodies,
            max_reduced_links: r.max_reduced_links,
        },
        iterative: IterativeParams {
            substeps: it.substeps,
            iterations: it.iterations,
            relax_iterations: it.relax_iterations,
            max_correction_speed: it.max_correction_speed,
            ..IterativeParams::default()
        },
        contact_spring: w.contact_spring.map_or(defaults.contact_spring, |s| {
            kea::Spring::new(s.hertz, s.damping_ratio)
        }),
        projection_iterations: w.projection_iterations,
        world_substeps: w.world_substeps,
        speed_limits: w
            .speed_limits
            .map_or(defaults.speed_limits, |s| kea::SpeedLimits {
                linear: s.linear,
                angular: s.angular,
            }),
    })
}

/// Adds the named materials and the pair table; returns the names by id.
fn add_materials(collision: &mut CollisionWorld, scene: &Scene) -> Result<Vec<String>, SceneError> {
    let mut materials = vec!["default".to_string()];
    for (i, m) in scene.materials.iter().enumerate() {
        let place = format!("materials[{i}]");
        if materials.contains(&m.name) {
            return Err(SceneError::at(
                place,
                format!("material \"{}\" is defined twice", m.name),
            ));
        }
        let surface = Surface {
            friction: m.friction,
            restitution: m.restitution,
            restitution_threshold: m.restitution_threshold,
            softness: m.softness,
            slip: m.slip,
            adhesion: m.adhesion,
        };
        collision
            .materials
            .add(surface)
            .map_err(|e| SceneError::at(place, e))?;
        materials.push(m.name.clone());
    }
    for (i, p) in scene.material_pairs.iter().enumerate() {
        add_pair(collision, p, &materials, &format!("material_pairs[{i}]"))?;
    }
    Ok(materials)
}

/// The id of the material `name`, or an error placed at `place`.
fn material_id(materials: &[String], name: &str, place: String) -> Result<u32, SceneError> {
    materials
        .iter()
        .position(|m| m == name)
        .map(|i| i as u32)
        .ok_or_else(|| SceneError::at(place, format!("no material named \"{name}\"")))
}

/// Sets one pair-table entry: the combine rules' parameters with the fields given replaced.
fn add_pair(
    collision: &mut CollisionWorld,
    p: &MaterialPairSpec,
    materials: &[String],
    place: &str,
) -> Result<(), SceneError> {
    let a = material_id(materials, &p.a, format!("{place}.a"))?;
    let b = material_id(materials, &p.b, format!("{place}.b"))?;
    let at = |field: &str| {
        let place = format!("{place}.{field}");
        move |e: kea_collision::CollisionError| SceneError::at(place, e)
    };
    let mut params = collision.materials.params(a, b).map_err(at(""))?;
    if let Some(mu) = p.friction {
        if !(mu.is_finite() && mu >= 0.0) {
            return Err(SceneError::at(
                format!("{place}.friction"),
                format!("must be finite and ≥ 0, got {mu}"),
            ));
        }
        params.friction = [FrictionModel::Coulomb { mu }; 2];
        params.contact_type = if mu > 0.0 {
            ContactType::Friction2D
        } else {
            ContactType::Frictionless
        };
    }
    params.restitution = p.restitution.unwrap_or(params.restitution);
    params.restitution_threshold = p
        .restitution_threshold
        .unwrap_or(params.restitution_threshold);
    params.softness = p.softness.or(params.softness);
    params.slip = p.slip.unwrap_or(params.slip);
    params.max_adhesive_force = p.adhesion.unwrap_or(params.max_adhesive_force);
    params.slide = p.slide.unwrap_or(params.slide);
    let direction = match p.slide_direction {
        Some(d) => Some(unit(d, &format!("{place}.slide_direction"))?),
        None => None,
    };
    collision
        .materials
        .set_pair_with_direction(a, b, params, direction)
        .map_err(|e| SceneError::at(place, e))
}

/// `v` normalised, or an error at `place` if it is zero or not finite.
pub(crate) fn unit(v: V3, place: &str) -> Result<Vec3, SceneError> {
    let w = v3(v);
    let len = w.length();
    if !(w.is_finite() && len > 1.0e-6) {
        return Err(SceneError::at(
            place,
            format!("must be a non-zero direction, got {v:?}"),
        ));
    }
    Ok(w / len)
}

/// A scene vector as a kea vector.
pub(crate) fn v3(v: V3) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

/// The collision shape of a spec, errors placed at `place.shape`.
fn shape(spec: &ShapeSpec, place: &str) -> Result<Shape, SceneError> {
    let place = format!("{place}.shape");
    let shape = match spec {
        ShapeSpec::Sphere { radius } => Shape::sphere(*radius),
        ShapeSpec::Box { half_extents } => Shape::cuboid(v3(*half_extents)),
        ShapeSpec::Plane { normal } => Shape::plane(v3(*normal)),
        ShapeSpec::Capsule {
            half_height,
            radius,
        } => Shape::capsule(*half_height, *radius),
        ShapeSpec::Cylinder {
            half_height,
            radius,
        } => Shape::cylinder(*half_height, *radius),
        ShapeSpec::Cone {
            half_height,
            radius,
        } => Shape::cone(*half_height, *radius),
        ShapeSpec::ConvexHull { points } => {
            Shape::convex_hull(&points.iter().map(|p| v3(*p)).collect::<Vec<_>>())
        }
        ShapeSpec::Mesh {
            vertices,
            triangles,
        } => Shape::trimesh(vertices.iter().map(|p| v3(*p)).collect(), triangles.clone()),
        ShapeSpec::HeightField { heights, size } => Shape::heightfield(heights, v3(*size)),
    };
    shape.map_err(|e| SceneError::at(place, e))
}

/// A collider definition on `body` (none: static), its material looked up by name.
fn collider(
    spec: &ColliderSpec,
    body: Option<BodyHandle>,
    materials: &[String],
    place: &str,
) -> Result<ColliderDef, SceneError> {
    let mut def = ColliderDef::new(body, shape(&spec.shape, place)?);
    def.offset = v3(spec.offset);
    def.rotation = collider_rotation(spec, place)?;
    if let Some(name) = &spec.material {
        def.material = material_id(materials, name, format!("{place}.material"))?;
    }
    Ok(def)
}

/// A collider's orientation, checked to be a unit quaternion.
fn collider_rotation(spec: &ColliderSpec, place: &str) -> Result<Quat, SceneError> {
    let Some([x, y, z, w]) = spec.orientation else {
        return Ok(Quat::IDENTITY);
    };
    let q = Quat::from_xyzw(x, y, z, w);
    if !(q.is_finite() && (q.length() - 1.0).abs() < 1.0e-3) {
        return Err(SceneError::at(
            format!("{place}.orientation"),
            format!("must be a unit quaternion [x, y, z, w], got [{x}, {y}, {z}, {w}]"),
        ));
    }
    Ok(q.normalize())
}

/// Adds a body with its colliders under a name not yet taken.
pub(crate) fn add_body(
    built: &mut BuiltScene,
    spec: &BodySpec,
    materials: &[String],
    place: &str,
) -> Result<(), SceneError> {
    if built.body(&spec.name).is_some() {
        return Err(SceneError::at(
            format!("{place}.name"),
            format!("a body named \"{}\" already exists", spec.name),
        ));
    }
    let (mass, inertia) = mass_properties(spec, place)?;
    let q = spec.orientation.unwrap_or([0.0, 0.0, 0.0, 1.0]);
    let def = BodyDef {
        mass,
        inertia,
        position: v3(spec.position),
        orientation: Quat::from_xyzw(q[0], q[1], q[2], q[3]),
        linear_velocity: v3(spec.velocity),
        angular_velocity: v3(spec.angular_velocity),
        linear_damping: spec.damping[0],
        angular_damping: spec.damping[1],
        fast_spin_axis: match spec.fast_spin_axis {
            Some(a) => Some(unit(a, &format!("{place}.fast_spin_axis"))?),
            None => None,
        },
        enabled: spec.enabled,
        prefer_exact: spec.prefer_exact,
        ..Default::default()
    };
    let h = built.world.create_body(&def).map_err(|e| {
        let field = match &e {
            kea::KeaError::BadInertia { .. } => ".inertia",
            kea::KeaError::NotUnit { .. } => ".orientation",
            _ => "",
        };
        SceneError::at(format!("{place}{field}"), e)
    })?;
    for (k, c) in spec.shapes.iter().enumerate() {
        let shape_place = format!("{place}.shapes[{k}]");
        let def = collider(c, Some(h), materials, &shape_place)?;
        built
            .collision
            .add_collider(&built.world, def)
            .map_err(|e| SceneError::at(shape_place, e))?;
    }
    built
        .body_index
        .insert(spec.name.clone(), built.bodies.len());
    built.bodies.push((spec.name.clone(), h));
    Ok(())
}

/// Mass and inertia: from the shapes at the density, then the mass and inertia given.
fn mass_properties(spec: &BodySpec, place: &str) -> Result<(Real, Mat3), SceneError> {
    let mut shapes = Vec::with_capacity(spec.shapes.len());
    for (k, c) in spec.shapes.iter().enumerate() {
        let shape_place = format!("{place}.shapes[{k}]");
        let rotation = collider_rotation(c, &shape_place)?;
        shapes.push((v3(c.offset), rotation, shape(&c.shape, &shape_place)?));
    }
    let density = spec.density.unwrap_or(1000.0);
    let (mut mass, mut inertia) = (1.0, Mat3::IDENTITY);
    // Given both mass and inertia, the shapes need not weigh anything (meshes cannot).
    let given = spec.mass.is_some() && spec.inertia.is_some();
    if !shapes.is_empty() && !given {
        let mp = MassProperties::of_shapes(&shapes, density)
            .map_err(|e| SceneError::at(format!("{place}.shapes"), e))?;
        (mass, inertia) = (mp.mass, mp.inertia);
    }
    if let Some(m) = spec.mass {
        if !(m.is_finite() && m > 0.0) {
            return Err(SceneError::at(
                format!("{place}.mass"),
                format!("must be > 0, got {m}"),
            ));
        }
        inertia *= m / mass;
        mass = m;
    } else if shapes.is_empty() {
        return Err(SceneError::at(place, "a body needs shapes or a mass"));
    }
    match &spec.inertia {
        Some(InertiaSpec::Diagonal(d)) => inertia = Mat3::from_diagonal(v3(*d)),
        Some(InertiaSpec::Full(rows)) => {
            // glam matrices are built from columns; a symmetric matrix reads the same.
            inertia = Mat3::from_cols(v3(rows[0]), v3(rows[1]), v3(rows[2])).transpose();
        }
        None => {}
    }
    Ok((mass, inertia))
}
