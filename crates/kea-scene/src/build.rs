//! Building a scene: materials, static geometry, bodies with mass from their shapes, groups and
//! joints, every reference checked and every error placed.

use crate::error::SceneError;
use crate::format::{
    BodySpec, ColliderSpec, GroupSpec, JointSpec, Scene, ShapeSpec, SolverSpec, V3,
};
use kea::{
    BodyDef, BodyHandle, DemMode, DemSettings, Quat, Real, Routing, SolverMode, StepStats, Vec3,
    World, WorldDef,
};
use kea_collision::{ColliderDef, CollisionWorld, MassProperties, Shape, Surface};

/// A built scene: the world, its collision layer, and the bodies by name.
pub struct BuiltScene {
    /// The dynamics.
    pub world: World,
    /// The geometry and contacts.
    pub collision: CollisionWorld,
    /// Every body with its name, in scene order (groups name theirs `pyramid0.12`, `chain1.3`).
    pub bodies: Vec<(String, BodyHandle)>,
}

impl BuiltScene {
    /// Steps the scene by `dt` (contacts from geometry, then the world's step).
    pub fn step(&mut self, dt: Real) -> Result<StepStats, kea_collision::CollisionError> {
        self.collision.step(&mut self.world, dt)
    }

    /// The body of that name.
    #[must_use]
    pub fn body(&self, name: &str) -> Option<BodyHandle> {
        self.bodies.iter().find(|(n, _)| n == name).map(|(_, h)| *h)
    }
}

/// Builds `scene` into a new world.
pub fn build(scene: &Scene) -> Result<BuiltScene, SceneError> {
    let body_count = scene.bodies.len() + scene.groups.iter().map(group_size).sum::<usize>();
    let w = &scene.world;
    let max_bodies = if w.max_bodies > 0 {
        w.max_bodies
    } else {
        body_count.max(1)
    };
    let max_constraints = if w.max_constraints > 0 {
        w.max_constraints
    } else {
        (16 * body_count).max(256)
    };
    let def = WorldDef {
        max_bodies,
        max_constraints,
        gravity: v3(w.gravity),
        epsilon: w.epsilon,
        gamma: w.gamma,
        dem: DemSettings {
            mode: if w.sleep {
                DemMode::PartitionAutoDisable
            } else {
                DemMode::default()
            },
            ..Default::default()
        },
        routing: Routing {
            mode: match w.solver {
                SolverSpec::Hybrid => SolverMode::Hybrid,
                SolverSpec::Exact => SolverMode::Exact,
                SolverSpec::Iterative => SolverMode::Iterative,
            },
            ..Default::default()
        },
        ..Default::default()
    };
    let world = World::new(def).map_err(|e| SceneError::at("world", e))?;
    let mut built = BuiltScene {
        world,
        collision: CollisionWorld::new(),
        bodies: Vec::new(),
    };
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
            ..Default::default()
        };
        built
            .collision
            .materials
            .add(surface)
            .map_err(|e| SceneError::at(place, e))?;
        materials.push(m.name.clone());
    }
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
        add_joint(&mut built, j, &format!("joints[{i}]"))?;
    }
    Ok(built)
}

fn v3(v: V3) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

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
        ShapeSpec::HeightField { heights, size } => Shape::heightfield(heights, v3(*size)),
    };
    shape.map_err(|e| SceneError::at(place, e))
}

fn collider(
    spec: &ColliderSpec,
    body: Option<BodyHandle>,
    materials: &[String],
    place: &str,
) -> Result<ColliderDef, SceneError> {
    let mut def = ColliderDef::new(body, shape(&spec.shape, place)?);
    def.offset = v3(spec.offset);
    if let Some(name) = &spec.material {
        let id = materials.iter().position(|m| m == name).ok_or_else(|| {
            SceneError::at(
                format!("{place}.material"),
                format!("no material named \"{name}\""),
            )
        })?;
        def.material = id as u32;
    }
    Ok(def)
}

fn add_body(
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
    let mut shapes = Vec::with_capacity(spec.shapes.len());
    for (k, c) in spec.shapes.iter().enumerate() {
        let shape_place = format!("{place}.shapes[{k}]");
        shapes.push((v3(c.offset), Quat::IDENTITY, shape(&c.shape, &shape_place)?));
    }
    let density = spec.density.unwrap_or(1000.0);
    let (mut mass, mut inertia) = (1.0, kea::Mat3::IDENTITY);
    if !shapes.is_empty() {
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
        ..Default::default()
    };
    let h = built
        .world
        .create_body(&def)
        .map_err(|e| SceneError::at(place, e))?;
    for (k, c) in spec.shapes.iter().enumerate() {
        let shape_place = format!("{place}.shapes[{k}]");
        let def = collider(c, Some(h), materials, &shape_place)?;
        built
            .collision
            .add_collider(&built.world, def)
            .map_err(|e| SceneError::at(shape_place, e))?;
    }
    built.bodies.push((spec.name.clone(), h));
    Ok(())
}

fn group_size(g: &GroupSpec) -> usize {
    match g {
        GroupSpec::Pyramid { base, .. } => (*base as usize) * (*base as usize + 1) / 2,
        GroupSpec::Chain { links, .. } => *links as usize,
        GroupSpec::Grid { counts, .. } => counts.iter().map(|&c| c as usize).product(),
    }
}

/// A body of one shape at its centre, at rest: what groups are made of.
fn one_shape_body(name: String, shape: ShapeSpec, density: Real, position: V3) -> BodySpec {
    BodySpec {
        name,
        shapes: vec![ColliderSpec {
            shape,
            offset: [0.0; 3],
            material: None,
        }],
        density: Some(density),
        mass: None,
        position,
        orientation: None,
        velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        damping: [0.0; 2],
    }
}

fn add_group(
    built: &mut BuiltScene,
    g: &GroupSpec,
    index: usize,
    place: &str,
) -> Result<(), SceneError> {
    let named = |kind: &str, i: usize| format!("{kind}{index}.{i}");
    let mut made = 0;
    match *g {
        GroupSpec::Pyramid {
            base,
            half_extent,
            density,
            origin,
        } => {
            let edge = 2.0 * half_extent;
            for layer in 0..base {
                let n = base - layer;
                for i in 0..n {
                    let x = origin[0] + (i as Real - (n as Real - 1.0) * 0.5) * edge;
                    let y = origin[1] + half_extent + layer as Real * edge;
                    let cube = ShapeSpec::Box {
                        half_extents: [half_extent; 3],
                    };
                    let position = [x, y, origin[2]];
                    let spec = one_shape_body(named("pyramid", made), cube, density, position);
                    add_body(built, &spec, &[], place)?;
                    made += 1;
                }
            }
        }
        GroupSpec::Grid {
            ref shape,
            counts,
            spacing,
            density,
            origin,
        } => {
            let (nx, ny) = (counts[0] as usize, counts[1] as usize);
            for i in 0..nx * ny * counts[2] as usize {
                let cell = [i % nx, (i / nx) % ny, i / (nx * ny)];
                let spec = one_shape_body(
                    named("grid", i),
                    shape.clone(),
                    density,
                    std::array::from_fn(|k| origin[k] + cell[k] as Real * spacing[k]),
                );
                add_body(built, &spec, &[], place)?;
            }
        }
        GroupSpec::Chain {
            links,
            spacing,
            radius,
            density,
            origin,
        } => {
            let mut previous: Option<BodyHandle> = None;
            for i in 0..links as usize {
                let centre = [
                    origin[0],
                    origin[1] - spacing * (i as Real + 0.5),
                    origin[2],
                ];
                let spec = one_shape_body(
                    named("chain", i),
                    ShapeSpec::Sphere { radius },
                    density,
                    centre,
                );
                add_body(built, &spec, &[], place)?;
                let h = built.bodies.last().expect("just added").1;
                let anchor = Vec3::new(centre[0], centre[1] + 0.5 * spacing, centre[2]);
                built
                    .world
                    .create_ball_joint(h, previous, anchor)
                    .map_err(|e| SceneError::at(place, e))?;
                previous = Some(h);
            }
        }
    }
    Ok(())
}

fn add_joint(built: &mut BuiltScene, j: &JointSpec, place: &str) -> Result<(), SceneError> {
    let (body1, body2) = match j {
        JointSpec::Ball { body1, body2, .. }
        | JointSpec::Hinge { body1, body2, .. }
        | JointSpec::Prismatic { body1, body2, .. }
        | JointSpec::Fixed { body1, body2, .. } => (body1, body2),
    };
    let find = |field: &str, name: &str| {
        built.body(name).ok_or_else(|| {
            SceneError::at(
                format!("{place}.{field}"),
                format!("no body named \"{name}\""),
            )
        })
    };
    let b1 = find("body1", body1)?;
    let b2 = body2.as_deref().map(|n| find("body2", n)).transpose()?;
    let w = &mut built.world;
    let at = |e: kea::KeaError| SceneError::at(place, e);
    match j {
        JointSpec::Ball { anchor, .. } => {
            w.create_ball_joint(b1, b2, v3(*anchor)).map_err(at)?;
        }
        JointSpec::Hinge {
            anchor,
            axis,
            limits,
            motor,
            ..
        } => {
            let h = w.create_hinge(b1, b2, v3(*anchor), v3(*axis)).map_err(at)?;
            let limit = w.hinge_limit_mut(h).map_err(at)?;
            if let Some([lo, hi]) = limits {
                let (lower, upper) = (
                    kea::SingleLimit::hard(*lo, 0.0),
                    kea::SingleLimit::hard(*hi, 0.0),
                );
                limit
                    .set_limits(lower, upper)
                    .map_err(|e| SceneError::at(format!("{place}.limits"), e))?;
            }
            if let Some([speed, torque]) = motor {
                limit
                    .set_motor(*speed, *torque)
                    .map_err(|e| SceneError::at(format!("{place}.motor"), e))?;
            }
        }
        JointSpec::Prismatic { anchor, axis, .. } => {
            w.create_prismatic(b1, b2, v3(*anchor), v3(*axis))
                .map_err(at)?;
        }
        JointSpec::Fixed { anchor, .. } => {
            w.create_fixed_joint(b1, b2, v3(*anchor)).map_err(at)?;
        }
    }
    Ok(())
}
