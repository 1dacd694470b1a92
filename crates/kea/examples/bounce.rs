//! The guide's bounce.c: a ball dropped on a plane with restitution 0.6 and 2D friction. The
//! contact is made by hand each step, as the tutorial does, and destroyed the next.
//!
//! Run: `cargo run --release -p kea --example bounce`

use kea::{
    inertia, BodyDef, Contact, ContactParams, ContactType, FrictionModel, Real, Vec3, World,
};

const RADIUS: Real = 0.5;

fn main() -> Result<(), kea::KeaError> {
    let mut world = World::with_capacity(1, 4)?;
    world.update_settings(|s| s.gravity = Vec3::new(0.0, -9.8, 0.0))?;
    let ball = world.create_body(&BodyDef {
        position: Vec3::new(0.0, 5.0, 0.0),
        linear_velocity: Vec3::new(1.0, 0.0, 0.0),
        inertia: inertia::solid_sphere(1.0, RADIUS)?,
        ..Default::default()
    })?;
    let params = ContactParams {
        contact_type: ContactType::Friction2D,
        friction: [FrictionModel::Box { max_force: 5.0 }; 2],
        restitution: 0.6,
        restitution_threshold: 0.3,
        ..Default::default()
    };
    let step: Real = 1.0 / 240.0;
    let mut contact = None;
    let mut rising = false;
    let mut last_apex: Option<Real> = None;
    println!("bounce: ball of radius {RADIUS} m dropped from 4.5 m onto y = 0, e = 0.6");
    for n in 0..(8.0 / step) as usize {
        if let Some(c) = contact.take() {
            world.destroy_constraint(c)?;
        }
        let pos = world.body(ball)?.position();
        let penetration = RADIUS - pos.y;
        if penetration > 0.0 {
            let mut c = Contact::new(
                Vec3::new(pos.x, pos.y - RADIUS, pos.z),
                Vec3::Y,
                penetration,
            )?;
            c.set_params(params)?;
            contact = Some(world.create_contact(ball, None, c)?);
        }
        let v_in = world.body(ball)?.linear_velocity();
        world.step(step)?;
        let b = world.body(ball)?;
        let v = b.linear_velocity();
        if contact.is_some() && v_in.y < 0.0 && v.y > 0.0 {
            println!(
                "t = {:5.2} s  bounce: v_in = {:6.3} m/s, v_out = {:6.3} m/s (ratio {:.3}), spin {:6.3} rad/s",
                (n + 1) as Real * step,
                -v_in.y,
                v.y,
                v.y / -v_in.y,
                b.angular_velocity().z
            );
        }
        if rising && v.y <= 0.0 {
            let apex = b.position().y - RADIUS;
            match last_apex {
                Some(prev) => println!(
                    "            apex {apex:6.3} m  (ratio to previous {:.3}, e² = 0.36)",
                    apex / prev
                ),
                None => println!("            apex {apex:6.3} m"),
            }
            last_apex = Some(apex);
        }
        rising = v.y > 0.0;
    }
    let b = world.body(ball)?;
    let v = b.linear_velocity();
    println!(
        "settled: y = {:.4} m, vertical speed {:.1e} m/s, now rolling at {:.3} m/s (ω·r = {:.3} m/s)",
        b.position().y,
        v.y.abs(),
        v.x,
        -b.angular_velocity().z * RADIUS
    );
    Ok(())
}
