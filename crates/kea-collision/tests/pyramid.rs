//! VALIDATION #19: a pyramid with a 20-box base (210 boxes) stands for 20 s.

use kea::{BodyDef, Real, Vec3, World, WorldDef};
use kea_collision::{ColliderDef, CollisionWorld, Shape};
mod common;

#[test]
fn a_pyramid_of_210_boxes_stands_for_20_seconds() {
    let base = 20;
    let count = base * (base + 1) / 2;
    let mut world = World::new(WorldDef {
        max_bodies: count,
        max_constraints: count * 12,
        ..Default::default()
    })
    .unwrap();
    let mut collision = CollisionWorld::new();
    collision
        .add_collider(
            &world,
            ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap()),
        )
        .unwrap();
    let cube = Shape::cuboid(Vec3::splat(0.5)).unwrap();
    let mp = cube.mass_properties(1.0).unwrap();
    let mut boxes = Vec::new();
    for layer in 0..base {
        let n = base - layer;
        for i in 0..n {
            let x = (i as Real) * 1.0 - (n as Real - 1.0) * 0.5;
            let y = 0.5 + layer as Real * 1.0;
            let b = world
                .create_body(&BodyDef {
                    mass: mp.mass,
                    inertia: mp.inertia,
                    position: Vec3::new(x, y, 0.0),
                    ..Default::default()
                })
                .unwrap();
            collision
                .add_collider(&world, ColliderDef::new(Some(b), cube.clone()))
                .unwrap();
            boxes.push((b, Vec3::new(x, y, 0.0)));
        }
    }
    let mut worst: Real = 0.0;
    for _ in 0..1200 {
        common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
    }
    for (b, start) in &boxes {
        worst = worst.max((world.body(*b).unwrap().position() - *start).length());
    }
    eprintln!("pyramid of {count}: largest displacement after 20 s {worst:e} m");
    assert!(worst < 0.05, "largest displacement {worst}");
}
