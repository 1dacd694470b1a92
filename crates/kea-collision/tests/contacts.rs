//! Contacts from geometry: normals and depths of known configurations, a box at rest on a
//! plane, persistent contact handles, and no tunnelling at speed.

use kea::{inertia, BodyDef, BodyHandle, Quat, Real, Vec3, World};
use kea_collision::{ColliderDef, CollisionWorld, Shape};
mod common;

fn body(world: &mut World, position: Vec3, shape: &Shape) -> BodyHandle {
    let mp = shape.mass_properties(1000.0).unwrap();
    world
        .create_body(&BodyDef {
            mass: mp.mass,
            inertia: mp.inertia,
            position,
            ..Default::default()
        })
        .unwrap()
}

/// The contact points generated between two bodies (or a body and the ground), over all
/// their manifolds: (normal, depth, position).
fn contacts(
    world: &World,
    collision: &CollisionWorld,
    a: kea_collision::ColliderHandle,
    b: kea_collision::ColliderHandle,
) -> Vec<(Vec3, Real, Vec3)> {
    collision
        .contacts_between(a, b)
        .unwrap()
        .into_iter()
        .flat_map(|h| {
            let c = world.contact(h).unwrap();
            c.points()
                .iter()
                .map(|p| (c.normal(), p.penetration, p.position))
                .collect::<Vec<_>>()
        })
        .collect()
}

#[test]
fn known_configurations_give_the_right_normal_and_depth() {
    let mut world = World::with_capacity(8, 64).unwrap();
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let mut collision = CollisionWorld::new();
    // Sphere–sphere: radii 0.5, centres 0.9 apart along x → depth 0.1, normal from body 2 to 1.
    let s = Shape::sphere(0.5).unwrap();
    let a = body(&mut world, Vec3::ZERO, &s);
    let b = body(&mut world, Vec3::new(0.9, 0.0, 0.0), &s);
    let ca = collision
        .add_collider(&world, ColliderDef::new(Some(a), s.clone()))
        .unwrap();
    let cb = collision
        .add_collider(&world, ColliderDef::new(Some(b), s.clone()))
        .unwrap();
    collision.update_contacts(&mut world, 1.0 / 60.0).unwrap();
    let got = contacts(&world, &collision, ca, cb);
    assert_eq!(got.len(), 1, "{got:?}");
    let (n, depth, p) = got[0];
    // Body 1 is a (the first collider); body 2 is b, so the normal points from b to a: −x.
    assert!(n.abs_diff_eq(-Vec3::X, 1e-5), "normal {n}");
    assert!((depth - 0.1).abs() < 1e-5, "depth {depth}");
    assert!(p.abs_diff_eq(Vec3::new(0.45, 0.0, 0.0), 1e-5), "point {p}");

    // Box on the ground plane, its face 2 cm into it: one manifold of 4 corner points, normal
    // +y, depth 0.02.
    let mut world = World::with_capacity(8, 64).unwrap();
    let mut collision = CollisionWorld::new();
    let cube = Shape::cuboid(Vec3::splat(0.5)).unwrap();
    let b = body(&mut world, Vec3::new(0.0, 0.48, 0.0), &cube);
    let ground = collision
        .add_collider(
            &world,
            ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap()),
        )
        .unwrap();
    let cb = collision
        .add_collider(&world, ColliderDef::new(Some(b), cube.clone()))
        .unwrap();
    collision.update_contacts(&mut world, 1.0 / 60.0).unwrap();
    let got = contacts(&world, &collision, ground, cb);
    assert_eq!(got.len(), 4, "{got:?}");
    for (n, depth, p) in &got {
        assert!(
            n.abs_diff_eq(Vec3::Y, 1e-5) && (depth - 0.02).abs() < 1e-5,
            "{n} {depth}"
        );
        assert!(
            (p.x.abs() - 0.5).abs() < 1e-4 && (p.z.abs() - 0.5).abs() < 1e-4,
            "{p}"
        );
    }
    // With one point per pair (the bounce strategy) only the deepest is kept.
    collision.strategy.max_points = 1;
    collision.update_contacts(&mut world, 1.0 / 60.0).unwrap();
    assert_eq!(contacts(&world, &collision, ground, cb).len(), 1);
    // Out of 1–4 the strategy is clamped: 0 keeps one point, 8 at most four.
    collision.strategy.max_points = 0;
    collision.update_contacts(&mut world, 1.0 / 60.0).unwrap();
    assert_eq!(contacts(&world, &collision, ground, cb).len(), 1);
    collision.strategy.max_points = 8;
    collision.update_contacts(&mut world, 1.0 / 60.0).unwrap();
    assert_eq!(contacts(&world, &collision, ground, cb).len(), 4);

    // Box–box, edge on face: a box turned 45° about z resting its edge on another's top face.
    let mut world = World::with_capacity(8, 64).unwrap();
    let mut collision = CollisionWorld::new();
    let lower = body(&mut world, Vec3::ZERO, &cube);
    let edge_height = 0.5 + (0.5 as Real).sqrt() * 1.0 - 0.01;
    let upper = world
        .create_body(&BodyDef {
            mass: 1.0,
            inertia: inertia::solid_box(1.0, Vec3::ONE).unwrap(),
            position: Vec3::new(0.0, edge_height, 0.0),
            orientation: Quat::from_rotation_z(std::f64::consts::FRAC_PI_4 as Real),
            ..Default::default()
        })
        .unwrap();
    let cl = collision
        .add_collider(&world, ColliderDef::new(Some(lower), cube.clone()))
        .unwrap();
    let cu = collision
        .add_collider(&world, ColliderDef::new(Some(upper), cube.clone()))
        .unwrap();
    collision.update_contacts(&mut world, 1.0 / 60.0).unwrap();
    let got = contacts(&world, &collision, cl, cu);
    assert_eq!(
        got.len(),
        2,
        "an edge on a face touches at its two ends: {got:?}"
    );
    for (n, depth, p) in &got {
        // Body 1 is the lower box, body 2 the upper: the normal points down, from upper to lower.
        assert!(n.abs_diff_eq(-Vec3::Y, 1e-4), "normal {n}");
        assert!((depth - 0.01).abs() < 1e-4, "depth {depth}");
        assert!(
            p.x.abs() < 1e-3 && (p.z.abs() - 0.5).abs() < 1e-3,
            "point {p}"
        );
    }

    // Capsule lying on a triangle mesh floor: two contacts (its two ends), normal +y.
    let mut world = World::with_capacity(8, 64).unwrap();
    let mut collision = CollisionWorld::new();
    let floor = Shape::trimesh(
        vec![
            Vec3::new(-5.0, 0.0, -5.0),
            Vec3::new(5.0, 0.0, -5.0),
            Vec3::new(5.0, 0.0, 5.0),
            Vec3::new(-5.0, 0.0, 5.0),
        ],
        vec![[0, 2, 1], [0, 3, 2]],
    )
    .unwrap();
    let capsule = Shape::capsule(0.5, 0.2).unwrap();
    let cap = world
        .create_body(&BodyDef {
            mass: 1.0,
            inertia: capsule.mass_properties(1.0).unwrap().inertia,
            position: Vec3::new(0.3, 0.19, 0.2),
            orientation: Quat::from_rotation_z(std::f64::consts::FRAC_PI_2 as Real),
            ..Default::default()
        })
        .unwrap();
    let cf = collision
        .add_collider(&world, ColliderDef::new(None, floor))
        .unwrap();
    let cc = collision
        .add_collider(&world, ColliderDef::new(Some(cap), capsule))
        .unwrap();
    collision.update_contacts(&mut world, 1.0 / 60.0).unwrap();
    let got = contacts(&world, &collision, cf, cc);
    assert!(!got.is_empty(), "capsule on mesh gave no contacts");
    for (n, depth, _) in &got {
        assert!(n.abs_diff_eq(Vec3::Y, 1e-4), "normal {n}");
        assert!((depth - 0.01).abs() < 1e-4, "depth {depth}");
    }
}

#[test]
fn a_box_rests_on_a_plane_without_drift_or_rotation() {
    let mut world = World::with_capacity(4, 64).unwrap();
    let mut collision = CollisionWorld::new();
    let cube = Shape::cuboid(Vec3::new(0.5, 0.25, 0.4)).unwrap();
    let b = body(&mut world, Vec3::new(0.0, 0.25, 0.0), &cube);
    let ground = collision
        .add_collider(
            &world,
            ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap()),
        )
        .unwrap();
    let cb = collision
        .add_collider(&world, ColliderDef::new(Some(b), cube))
        .unwrap();
    // Let it settle onto its contacts for a moment, then watch it for 10 s.
    let mut first = Vec::new();
    for _ in 0..30 {
        common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
        first = collision.contacts_between(ground, cb).unwrap();
    }
    assert_eq!(first.len(), 1, "one manifold");
    assert_eq!(world.contact(first[0]).unwrap().points().len(), 4);
    let start = world.body(b).unwrap().position();
    let mut worst: Real = 0.0;
    let mut worst_turn: Real = 0.0;
    for _ in 0..600 {
        common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
        let body = world.body(b).unwrap();
        worst = worst.max((body.position() - start).length());
        worst_turn = worst_turn.max(2.0 * body.orientation().xyz().length());
    }
    eprintln!("box on plane: drift {worst:e} m, rotation {worst_turn:e} rad over 10 s");
    assert!(worst < 1e-4, "drift {worst}");
    assert!(worst_turn < 1e-4, "rotation {worst_turn}");
    // The same manifold persisted (same handle and point ids: warm starting keeps working).
    assert_eq!(collision.contacts_between(ground, cb).unwrap(), first);
    // The ground carries the weight.
    let total: Real = first
        .iter()
        .map(|&h| world.contact_force(h).unwrap().y)
        .sum();
    let weight = world.body(b).unwrap().mass() * 9.81;
    assert!(
        (total - weight).abs() < 1e-3 * weight,
        "ground force {total} vs weight {weight}"
    );
}

#[test]
fn a_fast_small_sphere_does_not_pass_a_thin_wall() {
    let mut world = World::with_capacity(4, 64).unwrap();
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let mut collision = CollisionWorld::new();
    let wall = Shape::cuboid(Vec3::new(0.05, 2.0, 2.0)).unwrap();
    collision
        .add_collider(&world, ColliderDef::new(None, wall))
        .unwrap();
    let ball = Shape::sphere(0.05).unwrap();
    let b = body(&mut world, Vec3::new(-5.0, 0.0, 0.0), &ball);
    world
        .body_mut(b)
        .unwrap()
        .set_linear_velocity(Vec3::new(200.0, 0.0, 0.0))
        .unwrap();
    collision
        .add_collider(&world, ColliderDef::new(Some(b), ball))
        .unwrap();
    // 200 m/s is 3.3 m per step: without speculative contacts it would jump the 0.1 m wall.
    let mut furthest = Real::NEG_INFINITY;
    for _ in 0..60 {
        common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
        let x = world.body(b).unwrap().position().x;
        furthest = furthest.max(x);
        assert!(x < 0.0, "the ball passed the wall: x = {x}");
    }
    let speed = world.body(b).unwrap().linear_velocity().length();
    eprintln!("fast sphere: furthest x = {furthest} (touching at -0.1), final speed {speed} m/s");
    // It reached the wall (within the soft contact's give) and stopped: no bounce (e = 0),
    // only the slow push-out of the penetration correction.
    assert!((furthest + 0.1).abs() < 0.03, "furthest {furthest}");
    assert!(speed < 0.5, "speed {speed}");
}

#[test]
fn each_pair_of_materials_keeps_its_own_contact_strategy() {
    // Two boxes resting on the ground: a "ball-like" material whose pair with the ground
    // keeps one point (enough to bounce), and a plain one with the world's four.
    let mut world = World::with_capacity(8, 64).unwrap();
    let mut collision = CollisionWorld::new();
    let ground_material = collision.materials.add(Default::default()).unwrap();
    let bouncy = collision.materials.add(Default::default()).unwrap();
    let cube = Shape::cuboid(Vec3::splat(0.5)).unwrap();
    let one = body(&mut world, Vec3::new(-2.0, 0.48, 0.0), &cube);
    let four = body(&mut world, Vec3::new(2.0, 0.48, 0.0), &cube);
    let mut ground_def = ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap());
    ground_def.material = ground_material;
    let ground = collision.add_collider(&world, ground_def).unwrap();
    let mut one_def = ColliderDef::new(Some(one), cube.clone());
    one_def.material = bouncy;
    let c_one = collision.add_collider(&world, one_def).unwrap();
    let c_four = collision
        .add_collider(&world, ColliderDef::new(Some(four), cube.clone()))
        .unwrap();
    collision
        .materials
        .set_pair_strategy(
            bouncy,
            ground_material,
            Some(kea_collision::ContactStrategy { max_points: 1 }),
        )
        .unwrap();
    collision.update_contacts(&mut world, 1.0 / 60.0).unwrap();
    assert_eq!(contacts(&world, &collision, ground, c_one).len(), 1);
    assert_eq!(contacts(&world, &collision, ground, c_four).len(), 4);
    // The pair's parameters are the combined surfaces' still (friction, no bounce).
    let params = collision.materials.params(bouncy, ground_material).unwrap();
    assert_eq!(
        params,
        collision.materials.params(0, ground_material).unwrap()
    );
    // Back to the world's strategy: four again. An unknown material is refused by name.
    collision
        .materials
        .set_pair_strategy(ground_material, bouncy, None)
        .unwrap();
    collision.update_contacts(&mut world, 1.0 / 60.0).unwrap();
    assert_eq!(contacts(&world, &collision, ground, c_one).len(), 4);
    let e = collision
        .materials
        .set_pair_strategy(
            bouncy,
            99,
            Some(kea_collision::ContactStrategy { max_points: 1 }),
        )
        .unwrap_err();
    assert!(e.to_string().contains("99"), "{e}");
}
