//! Every shape the toolkit supports, resting 1 cm into each kind of ground (plane, height field,
//! triangle mesh, box): contacts have the ground's normal and the right depth.

use kea::{BodyDef, Quat, Real, Vec3, World};
use kea_collision::{ColliderDef, CollisionWorld, Shape};
mod common;

/// Each shape with the distance from its origin down to its lowest point.
fn shapes() -> Vec<(&'static str, Shape, Real)> {
    let hull: Vec<Vec3> = vec![
        Vec3::new(-0.3, -0.2, -0.3),
        Vec3::new(0.3, -0.2, -0.3),
        Vec3::new(0.3, -0.2, 0.3),
        Vec3::new(-0.3, -0.2, 0.3),
        Vec3::new(0.0, 0.4, 0.0),
    ];
    vec![
        ("sphere", Shape::sphere(0.3).unwrap(), 0.3),
        ("box", Shape::cuboid(Vec3::new(0.4, 0.2, 0.3)).unwrap(), 0.2),
        ("capsule", Shape::capsule(0.3, 0.2).unwrap(), 0.5),
        ("cylinder", Shape::cylinder(0.25, 0.3).unwrap(), 0.25),
        ("cone", Shape::cone(0.3, 0.3).unwrap(), 0.3),
        ("convex hull", Shape::convex_hull(&hull).unwrap(), 0.2),
        (
            "compound",
            Shape::compound(&[
                (
                    Vec3::new(-0.3, 0.0, 0.0),
                    Quat::IDENTITY,
                    Shape::sphere(0.2).unwrap(),
                ),
                (
                    Vec3::new(0.3, -0.1, 0.0),
                    Quat::IDENTITY,
                    Shape::cuboid(Vec3::splat(0.2)).unwrap(),
                ),
            ])
            .unwrap(),
            0.3,
        ),
    ]
}

fn grounds() -> Vec<(&'static str, Shape, Vec3)> {
    let flat = vec![vec![0.0; 5]; 5];
    let mesh = Shape::trimesh(
        vec![
            Vec3::new(-5.0, 0.0, -5.0),
            Vec3::new(5.0, 0.0, -5.0),
            Vec3::new(5.0, 0.0, 5.0),
            Vec3::new(-5.0, 0.0, 5.0),
        ],
        vec![[0, 2, 1], [0, 3, 2]],
    )
    .unwrap();
    vec![
        ("plane", Shape::plane(Vec3::Y).unwrap(), Vec3::ZERO),
        (
            "height field",
            Shape::heightfield(&flat, Vec3::new(10.0, 1.0, 10.0)).unwrap(),
            Vec3::ZERO,
        ),
        ("triangle mesh", mesh, Vec3::ZERO),
        (
            "box",
            Shape::cuboid(Vec3::new(5.0, 0.5, 5.0)).unwrap(),
            Vec3::new(0.0, -0.5, 0.0),
        ),
    ]
}

#[test]
fn every_shape_on_every_ground_gets_the_right_normal_and_depth() {
    let mut failures = Vec::new();
    for (ground_name, ground, ground_offset) in grounds() {
        for (name, shape, bottom) in shapes() {
            let mut world = World::with_capacity(4, 64).unwrap();
            let mut collision = CollisionWorld::new();
            let mut g = ColliderDef::new(None, ground.clone());
            g.offset = ground_offset;
            let gc = collision.add_collider(&world, g).unwrap();
            let b = world
                .create_body(&BodyDef {
                    position: Vec3::new(0.1, bottom - 0.01, 0.2),
                    ..Default::default()
                })
                .unwrap();
            let sc = collision
                .add_collider(&world, ColliderDef::new(Some(b), shape))
                .unwrap();
            collision.update_contacts(&mut world, 1.0 / 60.0).unwrap();
            let contacts = collision.contacts_between(gc, sc).unwrap();
            let depths: Vec<Real> = contacts
                .iter()
                .map(|&h| world.contact(h).unwrap().penetration())
                .collect();
            let normals_ok = contacts.iter().all(|&h| {
                world
                    .contact(h)
                    .unwrap()
                    .normal()
                    .abs_diff_eq(Vec3::Y, 1e-3)
            });
            let deepest = depths.iter().copied().fold(Real::NEG_INFINITY, Real::max);
            if contacts.is_empty() || !normals_ok || (deepest - 0.01).abs() > 2e-3 {
                failures.push(format!(
                    "{name} on {ground_name}: depths {depths:?}, normals ok {normals_ok}"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// A wheel (a cylinder on its side) rolling over a height field's ramp: parry can report the
/// same features in two of the field's manifolds, and each key must give one contact (this
/// used to underflow the capacity check).
#[test]
fn a_wheel_rolls_over_a_height_field_ramp() {
    let mut world = World::with_capacity(4, 256).unwrap();
    let mut collision = CollisionWorld::new();
    let heights: Vec<Vec<Real>> = (0..11)
        .map(|_| {
            (0..11)
                .map(|c| ((c as Real - 5.0) * 0.2).max(0.0))
                .collect()
        })
        .collect();
    let field = Shape::heightfield(&heights, Vec3::new(20.0, 1.0, 20.0)).unwrap();
    collision
        .add_collider(&world, ColliderDef::new(None, field))
        .unwrap();
    let wheel = Shape::cylinder(0.15, 0.4).unwrap();
    let mp = wheel.mass_properties(500.0).unwrap();
    let b = world
        .create_body(&BodyDef {
            mass: mp.mass,
            inertia: mp.inertia,
            position: Vec3::new(-2.0, 0.45, 0.0),
            orientation: Quat::from_rotation_x(kea::PI_REAL / 2.0),
            linear_velocity: Vec3::new(4.0, 0.0, 0.0),
            angular_velocity: Vec3::new(0.0, 0.0, -10.0),
            ..Default::default()
        })
        .unwrap();
    collision
        .add_collider(&world, ColliderDef::new(Some(b), wheel))
        .unwrap();
    for _ in 0..120 {
        common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
    }
    let p = world.body(b).unwrap().position();
    assert!(
        p.is_finite() && p.x > 0.5 && p.y > 0.3,
        "rolled up the ramp: {p}"
    );
}
