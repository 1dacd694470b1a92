//! Issue 12's reproductions in the collision layer, each under its own name: what used to panic
//! inside parry, hang in a query or stop the world for good is refused by name before parry
//! sees it, bounded, or carried on with.

use kea::{BodyDef, Quat, Real, Vec3, World};
use kea_collision::{
    ColliderDef, CollisionError, CollisionWorld, QueryFilter, Shape, ShapeCast, MAX_CAST_CELLS,
};
mod common;

fn refused(result: Result<impl std::fmt::Debug, CollisionError>, arg: &str, value: &str) {
    let text = result.expect_err("a bad value was accepted").to_string();
    assert!(text.contains(arg), "the error does not name {arg}: {text}");
    assert!(
        text.contains(value),
        "the error does not show {value}: {text}"
    );
}

fn flat(n: usize) -> Vec<Vec<Real>> {
    vec![vec![0.0; n]; n]
}

#[test]
fn a_capsule_of_half_height_min_positive_is_refused_by_name() {
    let tiny = Real::MIN_POSITIVE;
    refused(
        Shape::capsule(tiny, 0.5),
        "half_height",
        &format!("{tiny:e}"),
    );
    // A capsule far thinner than it is long (the other way round) too.
    refused(Shape::capsule(1.0e4, 1.0e-3), "half_height and radius", "");
}

#[test]
fn a_height_field_of_size_f32_max_is_refused_by_name() {
    let huge = f32::MAX as Real;
    let size = Vec3::new(huge, 1.0, 10.0);
    refused(
        Shape::heightfield(&flat(4), size),
        "size.x",
        &format!("{huge:e}"),
    );
}

#[test]
fn a_height_field_sample_of_f32_max_is_refused_by_name() {
    let mut heights = flat(4);
    let huge = f32::MAX as Real;
    heights[1][2] = huge;
    refused(
        Shape::heightfield(&heights, Vec3::splat(10.0)),
        "heights",
        &format!("{huge:e}"),
    );
}

#[test]
fn a_height_field_of_size_1e_minus_9_is_refused_by_name() {
    refused(
        Shape::heightfield(&flat(4), Vec3::splat(1.0e-9)),
        "size.x",
        "1e-9",
    );
}

#[test]
fn a_plane_on_a_dynamic_body_is_refused_by_name() {
    let mut world = World::with_capacity(4, 16).unwrap();
    let mut collision = CollisionWorld::new();
    let body = world.create_body(&BodyDef::default()).unwrap();
    let plane = Shape::plane(Vec3::Y).unwrap();
    refused(
        collision.add_collider(&world, ColliderDef::new(Some(body), plane)),
        "add_collider",
        "plane",
    );
    assert_eq!(collision.collider_count(), 0);
}

/// A world with a fine height field (the smallest accepted cells) and a sphere above it.
fn fine_field() -> (World, CollisionWorld) {
    let world = World::with_capacity(4, 16).unwrap();
    let mut collision = CollisionWorld::new();
    let field = Shape::heightfield(&flat(64), Vec3::new(1.0e-4, 1.0e-4, 1.0e-4)).unwrap();
    collision
        .add_collider(&world, ColliderDef::new(None, field))
        .unwrap();
    (world, collision)
}

#[test]
fn a_shape_cast_over_a_fine_height_field_is_bounded() {
    let (world, collision) = fine_field();
    let cast = |from: Vec3, velocity: Vec3, max_time: Real| ShapeCast {
        shape: Shape::sphere(1.0e-4).unwrap(),
        position: from,
        rotation: Quat::IDENTITY,
        velocity,
        max_time,
    };
    // Falling straight onto it: a hit, found at once.
    let hit = collision
        .cast_shape(
            &world,
            &cast(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, -1.0, 0.0), 2.0),
            QueryFilter::default(),
        )
        .unwrap()
        .expect("the sphere falls onto the field");
    assert!((hit.time - (1.0 - 1.0e-4)).abs() < 1.0e-3, "{hit:?}");
    // A long horizontal sweep from far away: clipped to the field's bounds, which it crosses
    // in at most 126 cells: an answer, not a hang.
    let sweep = cast(
        Vec3::new(-1.0e4, 2.0e-4, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        2.0e4,
    );
    let answer = collision.cast_shape(&world, &sweep, QueryFilter::default());
    assert!(answer.is_ok(), "{answer:?}");
    // A big sphere sweeping past the tiny field walks its cells across the whole sphere's
    // width (1.3e9 of them): refused by name rather than walked.
    let big = ShapeCast {
        shape: Shape::sphere(1.0e3).unwrap(),
        ..cast(
            Vec3::new(-1.0e4, 999.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            2.0e4,
        )
    };
    let answer = collision.cast_shape(&world, &big, QueryFilter::default());
    refused(answer, "cast_shape", "height-field cells");
    const { assert!(MAX_CAST_CELLS < 1.3e9) };
}

/// Ten boxes dropped on a plane in a world with room reserved for only four contacts.
fn crowded() -> (World, CollisionWorld, Vec<kea::BodyHandle>) {
    let mut world = World::with_capacity(16, 4).unwrap();
    let mut collision = CollisionWorld::new();
    collision
        .add_collider(
            &world,
            ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap()),
        )
        .unwrap();
    let shape = Shape::cuboid(Vec3::splat(0.25)).unwrap();
    let mp = shape.mass_properties(500.0).unwrap();
    let mut boxes = Vec::new();
    for i in 0..10 {
        let body = world
            .create_body(&BodyDef {
                mass: mp.mass,
                inertia: mp.inertia,
                position: Vec3::new(i as Real, 0.3, 0.0),
                ..Default::default()
            })
            .unwrap();
        collision
            .add_collider(&world, ColliderDef::new(Some(body), shape.clone()))
            .unwrap();
        boxes.push(body);
    }
    (world, collision, boxes)
}

#[test]
fn contacts_beyond_the_reserved_room_grow_the_world_and_every_box_rests() {
    let (mut world, mut collision, boxes) = crowded();
    for _ in 0..60 {
        let stats = common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
        assert_eq!(stats.collision.dropped_manifolds, 0);
    }
    assert!(
        world.constraint_count() >= 10,
        "one contact per box at least"
    );
    assert!(world.max_constraints() >= world.constraint_count());
    for &b in &boxes {
        let y = world.body(b).unwrap().position().y;
        assert!((y - 0.25).abs() < 0.02, "a box at y = {y}");
    }
}
