//! A scene's bodies and colliders: the built scene they go into, each body with its mass
//! properties (given, or from its colliders' shapes) and colliders, errors placed on the
//! field they are about.

use crate::error::SceneError;
use crate::format::{BodySpec, ColliderSpec, InertiaSpec, ShapeSpec, V3};
use crate::paths::ScenePaths;
use kea::{BodyDef, BodyHandle, ConstraintHandle, Mat3, Quat, Real, Vec3, World};
use kea_collision::{ColliderDef, CollisionWorld, MassProperties, Shape};
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
pub(crate) fn collider(
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

/// The id of the material `name`, or an error placed at `place`.
pub(crate) fn material_id(
    materials: &[String],
    name: &str,
    place: String,
) -> Result<u32, SceneError> {
    materials
        .iter()
        .position(|m| m == name)
        .map(|i| i as u32)
        .ok_or_else(|| SceneError::at(place, format!("no material named \"{name}\"")))
}
