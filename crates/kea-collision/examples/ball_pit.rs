//! 1000 spheres poured into a box: broad phase, many small islands merging into one big pile,
//! and the iterative path at work.
//!
//! Run: `cargo run --release -p kea-collision --example ball_pit`

use kea::{BodyDef, Quat, Real, Vec3, World, WorldDef};
use kea_collision::{ColliderDef, CollisionResult, CollisionWorld, Shape};
use std::time::Instant;

fn main() -> CollisionResult<()> {
    let n = 10;
    let count = n * n * n;
    let mut world = World::new(WorldDef {
        max_bodies: count,
        max_constraints: count * 8,
        ..Default::default()
    })?;
    let mut collision = CollisionWorld::new();
    // A 4 m × 4 m pit with 3 m walls.
    collision.add_collider(&world, ColliderDef::new(None, Shape::plane(Vec3::Y)?))?;
    let wall = Shape::cuboid(Vec3::new(0.1, 1.5, 2.2))?;
    for (x, z, turn) in [
        (2.1, 0.0, false),
        (-2.1, 0.0, false),
        (0.0, 2.1, true),
        (0.0, -2.1, true),
    ] {
        let mut def = ColliderDef::new(None, wall.clone());
        def.offset = Vec3::new(x, 1.5, z);
        if turn {
            def.rotation = Quat::from_rotation_y(std::f64::consts::FRAC_PI_2 as Real);
        }
        collision.add_collider(&world, def)?;
    }
    let ball = Shape::sphere(0.15)?;
    let mp = ball.mass_properties(500.0)?;
    for i in 0..count {
        let (x, y, z) = (i % n, i / (n * n), (i / n) % n);
        let jitter = ((i * 7919) % 13) as Real * 0.002;
        let p = Vec3::new(
            x as Real * 0.35 - 1.6 + jitter,
            0.5 + y as Real * 0.35,
            z as Real * 0.35 - 1.6,
        );
        let b = world.create_body(&BodyDef {
            mass: mp.mass,
            inertia: mp.inertia,
            position: p,
            ..Default::default()
        })?;
        collision.add_collider(&world, ColliderDef::new(Some(b), ball.clone()))?;
    }
    println!("ball pit: {count} spheres (r = 0.15 m) poured into a 4 m × 4 m pit, 60 Hz");
    println!(
        "{:>6} {:>10} {:>10} {:>12} {:>12}",
        "t (s)", "contacts", "ms/step", "top (m)", "KE (J)"
    );
    let dt: Real = 1.0 / 60.0;
    for second in 1..=8 {
        let start = Instant::now();
        for _ in 0..60 {
            // Contacts from the geometry, then the world's step.
            collision.update_contacts(&mut world, dt)?;
            world.step(dt)?;
        }
        let ms = start.elapsed().as_secs_f64() * 1000.0 / 60.0;
        let top = world
            .bodies()
            .map(|(_, b)| b.position().y)
            .fold(0.0, Real::max);
        let energy: Real = world.bodies().map(|(_, b)| b.kinetic_energy()).sum();
        println!(
            "{second:>6} {:>10} {ms:>10.2} {top:>12.3} {energy:>12.3}",
            world.constraint_count()
        );
    }
    let escaped = world
        .bodies()
        .filter(|(_, b)| {
            b.position().x.abs() > 2.0 || b.position().z.abs() > 2.0 || b.position().y < 0.0
        })
        .count();
    println!("spheres outside the pit: {escaped}");
    Ok(())
}
