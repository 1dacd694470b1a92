//! The guide's bounce, on real geometry: a sphere dropped on a ground plane. The contacts come
//! from the collision layer; the bounce comes from the material pair (restitution 0.6).
//!
//! Run: `cargo run --release -p kea-collision --example bounce_on_geometry`

use kea::{BodyDef, Real, Vec3, World};
use kea_collision::{ColliderDef, CollisionResult, CollisionWorld, Shape, Surface};

fn main() -> CollisionResult<()> {
    let mut world = World::with_capacity(4, 16)?;
    let mut collision = CollisionWorld::new();
    let rubber = collision.materials.add(Surface {
        restitution: 0.6,
        restitution_threshold: 0.3,
        ..Default::default()
    })?;
    let mut ground = ColliderDef::new(None, Shape::plane(Vec3::Y)?);
    ground.material = rubber;
    collision.add_collider(&world, ground)?;
    let ball_shape = Shape::sphere(0.5)?;
    let mp = ball_shape.mass_properties(100.0)?;
    let ball = world.create_body(&BodyDef {
        mass: mp.mass,
        inertia: mp.inertia,
        position: Vec3::new(0.0, 5.0, 0.0),
        linear_velocity: Vec3::new(1.0, 0.0, 0.0),
        ..Default::default()
    })?;
    let mut def = ColliderDef::new(Some(ball), ball_shape);
    def.material = rubber;
    collision.add_collider(&world, def)?;
    println!("bounce on geometry: sphere r = 0.5 m dropped from 4.5 m, e = 0.6 (material pair)");
    let dt: Real = 1.0 / 240.0;
    let (mut rising, mut last_apex) = (false, None::<Real>);
    for n in 0..(6.0 / dt) as usize {
        let v_in = world.body(ball)?.linear_velocity().y;
        // Contacts from the geometry, then the world's step.
        collision.update_contacts(&mut world, dt)?;
        world.step(dt)?;
        let b = world.body(ball)?;
        let v = b.linear_velocity().y;
        if v_in < 0.0 && v > 0.0 {
            let t = (n + 1) as Real * dt;
            println!(
                "t = {t:5.2} s  bounce: v_in {:6.3} m/s, v_out {v:6.3} m/s, ratio {:.3}",
                -v_in,
                v / -v_in
            );
        }
        if rising && v <= 0.0 {
            let apex = b.position().y - 0.5;
            match last_apex {
                Some(prev) => println!(
                    "            apex {apex:6.3} m (ratio {:.3}, e² = 0.36)",
                    apex / prev
                ),
                None => println!("            apex {apex:6.3} m"),
            }
            last_apex = Some(apex);
        }
        rising = v > 0.0;
    }
    let b = world.body(ball)?;
    println!(
        "settled: y = {:.4} m, rolling at {:.3} m/s",
        b.position().y,
        b.linear_velocity().x
    );
    Ok(())
}
