//! The guide's first tutorial (drop.c): a ball falling freely, printed as a trace, compared
//! with the closed form.
//!
//! Run: `cargo run --release --example drop`

use kea::{inertia, BodyDef, Real, Vec3, World};

fn main() -> Result<(), kea::KeaError> {
    let mut world = World::with_capacity(1, 1)?;
    world.update_settings(|s| s.gravity = Vec3::new(0.0, -9.8, 0.0))?;
    let ball = world.create_body(&BodyDef {
        position: Vec3::new(0.0, 10.0, 0.0),
        inertia: inertia::solid_sphere(1.0, 0.5)?,
        ..Default::default()
    })?;
    let step: Real = 0.03;
    println!("drop: a 1 kg ball released at y = 10 m, gravity 9.8 m/s², step {step} s");
    println!(
        "{:>6} {:>10} {:>10} {:>12}",
        "t [s]", "y [m]", "vy [m/s]", "½gt² err [m]"
    );
    for n in 1..=50 {
        world.step(step)?;
        let b = world.body(ball)?;
        let t = n as Real * step;
        let closed_form = 10.0 - 0.5 * 9.8 * t * t;
        if n % 5 == 0 {
            println!(
                "{:>6.2} {:>10.4} {:>10.4} {:>12.5}",
                t,
                b.position().y,
                b.linear_velocity().y,
                b.position().y - closed_form
            );
        }
    }
    println!("the error is −½·g·h·t: the semi-implicit first-order step, exactly");
    Ok(())
}
