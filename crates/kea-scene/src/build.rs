//! Building a scene: world parameters, materials and their pairs, static geometry, bodies with
//! mass from their shapes, groups and joints, every reference checked and every error placed.

use crate::bodies::{add_body, collider, material_id, unit, v3, BuiltScene};
use crate::error::SceneError;
use crate::format::{MaterialPairSpec, Scene, SolverSpec, WorldSpec};
use crate::groups::{add_group, group_size};
use crate::joints::add_joint;
use crate::paths::ScenePaths;
use kea::{
    ContactType, DemMode, DemSettings, FrictionModel, IterativeParams, Routing, SolverMode, World,
    WorldDef,
};
use kea_collision::{CollisionWorld, Surface};
use std::collections::HashMap;

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
    Ok(WorldDef {
        max_bodies,
        max_constraints,
        max_island_rows: w.max_island_rows.unwrap_or(defaults.max_island_rows),
        settings: settings_of(w, &defaults.settings)?,
    })
}

/// The world's settings from the scene, the defaults `d` where it gives none.
fn settings_of(w: &WorldSpec, d: &kea::WorldSettings) -> Result<kea::WorldSettings, SceneError> {
    let it = w.iterative.clone().unwrap_or_default();
    Ok(kea::WorldSettings {
        gravity: v3(w.gravity),
        epsilon: w.epsilon,
        gamma: w.gamma,
        max_lcp_iterations: w.max_lcp_iterations.unwrap_or(d.max_lcp_iterations),
        max_friction_passes: w.max_friction_passes.unwrap_or(d.max_friction_passes),
        dem: dem_of(w)?,
        routing: routing_of(w),
        iterative: IterativeParams {
            substeps: it.substeps,
            iterations: it.iterations,
            relax_iterations: it.relax_iterations,
            max_correction_speed: it.max_correction_speed,
            ..IterativeParams::default()
        },
        contact_spring: w.contact_spring.map_or(d.contact_spring, |s| {
            kea::Spring::new(s.hertz, s.damping_ratio)
        }),
        projection_iterations: w.projection_iterations,
        world_substeps: w.world_substeps,
        integrator: w.integrator.into(),
        // Robots loaded from MJCF set it; a scene's own bodies take no contact model.
        reduced_contacts: d.reduced_contacts,
        reduced_free_trees: d.reduced_free_trees,
        reduced_lone_bodies: d.reduced_lone_bodies,
        speed_limits: w.speed_limits.map_or(d.speed_limits, |s| kea::SpeedLimits {
            linear: s.linear,
            angular: s.angular,
        }),
        step_timing: true,
    })
}

/// Sleeping (the guide's auto-disable) and its thresholds, checked.
fn dem_of(w: &WorldSpec) -> Result<DemSettings, SceneError> {
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
    Ok(dem)
}

/// The solver path and the routing thresholds.
fn routing_of(w: &WorldSpec) -> Routing {
    let r = w.routing.clone().unwrap_or_default();
    Routing {
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
    }
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
            static_friction: m.static_friction,
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
