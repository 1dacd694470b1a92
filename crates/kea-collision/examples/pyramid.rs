//! A pyramid with a 20-box base (210 boxes) on a ground plane: how long a step takes and how
//! still it stands (VALIDATION #19).
//!
//! Run: `cargo run --release -p kea-collision --example pyramid`

use kea::{BodyDef, Real, Vec3, World, WorldDef};
use kea_collision::{ColliderDef, CollisionResult, CollisionWorld, Shape};
use std::time::Instant;

fn main() -> CollisionResult<()> {
    let base = 20;
    let count = base * (base + 1) / 2;
    let mut world = World::new(WorldDef {
        max_bodies: count,
        max_constraints: count * 12,
        ..Default::default()
    })?;
    let mut collision = CollisionWorld::new();
    collision.add_collider(&world, ColliderDef::new(None, Shape::plane(Vec3::Y)?))?;
    let cube = Shape::cuboid(Vec3::splat(0.5))?;
    let mp = cube.mass_properties(1.0)?;
    let mut boxes = Vec::new();
    for layer in 0..base {
        let n = base - layer;
        for i in 0..n {
            let p = Vec3::new(
                i as Real - (n as Real - 1.0) * 0.5,
                0.5 + layer as Real,
                0.0,
            );
            let b = world.create_body(&BodyDef {
                mass: mp.mass,
                inertia: mp.inertia,
                position: p,
                ..Default::default()
            })?;
            collision.add_collider(&world, ColliderDef::new(Some(b), cube.clone()))?;
            boxes.push((b, p));
        }
    }
    println!("pyramid: {count} unit boxes, 20-box base, 60 Hz");
    println!(
        "{:>6} {:>10} {:>10} {:>14}",
        "t (s)", "contacts", "ms/step", "max moved (m)"
    );
    let dt: Real = 1.0 / 60.0;
    let mut elapsed = 0.0;
    for second in 1..=20 {
        let start = Instant::now();
        for _ in 0..60 {
            collision.step(&mut world, dt)?;
        }
        let ms = start.elapsed().as_secs_f64() * 1000.0 / 60.0;
        elapsed += ms * 60.0;
        let moved = boxes
            .iter()
            .map(|(b, p)| {
                world
                    .body(*b)
                    .map(|b| (b.position() - *p).length())
                    .unwrap_or(Real::NAN)
            })
            .fold(0.0, Real::max);
        if second % 4 == 0 || second == 1 {
            println!(
                "{second:>6} {:>10} {ms:>10.2} {moved:>14.4}",
                world.constraint_count()
            );
        }
    }
    println!(
        "mean {:.2} ms per step (collision + solve)",
        elapsed / 1200.0
    );
    Ok(())
}
