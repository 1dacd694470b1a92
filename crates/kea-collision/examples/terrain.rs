//! Bodies of every shape tumbling down a height-field hill onto a triangle-mesh floor.
//!
//! Run: `cargo run --release -p kea-collision --example terrain`

use kea::{BodyDef, Quat, Real, Vec3, World};
use kea_collision::{ColliderDef, CollisionResult, CollisionWorld, MassProperties, Shape};

fn main() -> CollisionResult<()> {
    let mut world = World::with_capacity(64, 2048)?;
    let mut collision = CollisionWorld::new();
    // A 20 m × 20 m hill sloping down towards +x (bumps on an 8 m fall), centred on the origin.
    let n = 21;
    let heights: Vec<Vec<Real>> = (0..n)
        .map(|row| {
            (0..n)
                .map(|col| {
                    let (u, v) = (col as Real / (n - 1) as Real, row as Real / (n - 1) as Real);
                    (1.0 - u) + 0.02 * ((u * 19.0).sin() * (v * 13.0).cos())
                })
                .collect()
        })
        .collect();
    let mut hill = ColliderDef::new(
        None,
        Shape::heightfield(&heights, Vec3::new(20.0, 8.0, 20.0))?,
    );
    hill.offset = Vec3::new(0.0, 0.0, 0.0);
    collision.add_collider(&world, hill)?;
    // A flat mesh floor under it all, 0.5 m below the foot of the hill.
    let floor = Shape::trimesh(
        vec![
            Vec3::new(-40.0, -0.5, -40.0),
            Vec3::new(80.0, -0.5, -40.0),
            Vec3::new(80.0, -0.5, 40.0),
            Vec3::new(-40.0, -0.5, 40.0),
        ],
        vec![[0, 2, 1], [0, 3, 2]],
    )?;
    collision.add_collider(&world, ColliderDef::new(None, floor))?;

    let hull_points: Vec<Vec3> = (0..12)
        .map(|i| {
            let a = i as Real * 0.9;
            Vec3::new(0.4 * a.cos(), 0.3 * ((i % 3) as Real - 1.0), 0.4 * a.sin())
        })
        .collect();
    let shapes: Vec<(&str, Shape)> = vec![
        ("sphere", Shape::sphere(0.4)?),
        ("box", Shape::cuboid(Vec3::new(0.4, 0.3, 0.3))?),
        ("capsule", Shape::capsule(0.4, 0.25)?),
        ("cylinder", Shape::cylinder(0.3, 0.35)?),
        ("cone", Shape::cone(0.4, 0.4)?),
        ("convex hull", Shape::convex_hull(&hull_points)?),
        (
            "compound",
            Shape::compound(&[
                (
                    Vec3::new(-0.4, 0.0, 0.0),
                    Quat::IDENTITY,
                    Shape::sphere(0.3)?,
                ),
                (
                    Vec3::new(0.4, 0.0, 0.0),
                    Quat::IDENTITY,
                    Shape::cuboid(Vec3::splat(0.25))?,
                ),
            ])?,
        ),
    ];
    let mut bodies = Vec::new();
    for (i, (name, shape)) in shapes.iter().enumerate() {
        // Body position = centre of mass; the collider is placed relative to it.
        let mp = MassProperties::of_shapes(&[(Vec3::ZERO, Quat::IDENTITY, shape.clone())], 500.0)?;
        let start = Vec3::new(-8.0, 9.5, -4.5 + 1.5 * i as Real);
        let b = world.create_body(&BodyDef {
            mass: mp.mass,
            inertia: mp.inertia,
            position: start + mp.center_of_mass,
            orientation: Quat::from_rotation_x(0.3 * i as Real),
            ..Default::default()
        })?;
        let mut def = ColliderDef::new(Some(b), shape.clone());
        def.offset = -mp.center_of_mass;
        collision.add_collider(&world, def)?;
        bodies.push((*name, b));
    }
    println!("terrain: 7 shapes roll down a height-field hill onto a triangle-mesh floor");
    println!(
        "{:>12} {:>8} {:>8} {:>8} {:>10}",
        "shape", "x (m)", "y (m)", "z (m)", "speed"
    );
    let dt: Real = 1.0 / 60.0;
    for second in 1..=10 {
        for _ in 0..60 {
            // Contacts from the geometry, then the world's step.
            collision.update_contacts(&mut world, dt)?;
            world.step(dt)?;
        }
        if second % 5 == 0 {
            println!("after {second} s:");
            for (name, b) in &bodies {
                let body = world.body(*b)?;
                let p = body.position();
                println!(
                    "{name:>12} {:>8.2} {:>8.2} {:>8.2} {:>10.2}",
                    p.x,
                    p.y,
                    p.z,
                    body.linear_velocity().length()
                );
            }
        }
    }
    // Nothing may end up under the ground it was over: below the floor, or under the hill.
    let below = bodies
        .iter()
        .filter(|(_, b)| world.body(*b).map_or(true, |b| b.position().y < -0.6))
        .count();
    println!("bodies under the ground: {below}");
    Ok(())
}
