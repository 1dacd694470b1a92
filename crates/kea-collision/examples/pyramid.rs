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
        "{:>6} {:>9} {:>8} {:>10} {:>9} {:>14}",
        "t (s)", "contacts", "ms/step", "collision", "dynamics", "max moved (m)"
    );
    let dt: Real = 1.0 / 60.0;
    let (mut total, mut in_collision) = (0.0, 0.0);
    for second in 1..=20 {
        let (mut geometry, mut dynamics) = (0.0, 0.0);
        for _ in 0..60 {
            let start = Instant::now();
            collision.update_contacts(&mut world, dt)?;
            let mid = Instant::now();
            world.step(dt)?;
            geometry += (mid - start).as_secs_f64() * 1000.0 / 60.0;
            dynamics += mid.elapsed().as_secs_f64() * 1000.0 / 60.0;
        }
        total += geometry + dynamics;
        in_collision += geometry;
        let moved = boxes
            .iter()
            .map(|(b, p)| {
                world
                    .body(*b)
                    .map_or(Real::NAN, |b| (b.position() - *p).length())
            })
            .fold(0.0, Real::max);
        if second % 4 == 0 || second == 1 {
            let contacts = world.constraint_count();
            let ms = geometry + dynamics;
            println!(
                "{second:>6} {contacts:>9} {ms:>8.2} {geometry:>10.2} {dynamics:>9.2} {moved:>14.4}"
            );
        }
    }
    println!(
        "mean {:.2} ms per step, of which collision {:.2} ms",
        total / 20.0,
        in_collision / 20.0
    );
    Ok(())
}
