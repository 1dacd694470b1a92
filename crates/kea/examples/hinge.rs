//! The guide's hinge tutorial: a motorised hinge with limits, one body hinged to the world, or
//! (`-- 2`) two bodies hinged to each other. The motor drives the hinge at a set speed with a
//! limited torque until it reaches a stop; halfway through, the motor is reversed.
//!
//! Run: `cargo run --release --example hinge [-- 2]`

use kea::{inertia, BodyDef, Real, SingleLimit, Vec3, World};

const LO_LIMIT: Real = -0.75;
const HI_LIMIT: Real = 1.2;

fn main() -> Result<(), kea::KeaError> {
    let two = std::env::args().nth(1).as_deref() == Some("2");
    let mut world = World::with_capacity(2, 2)?;
    world.update_settings(|s| s.gravity = Vec3::new(0.0, -9.81, 0.0))?;
    let door = |p: Vec3| BodyDef {
        mass: 2.0,
        position: p,
        inertia: inertia::solid_box(2.0, Vec3::new(0.5, 0.05, 0.5)).unwrap(),
        ..Default::default()
    };
    let body0 = world.create_body(&door(Vec3::new(0.0, 0.0, 0.5)))?;
    let body1 = if two {
        Some(world.create_body(&door(Vec3::new(0.0, 0.0, -0.5)))?)
    } else {
        None
    };
    // The guide: hinge at the origin, axis along x.
    let hinge = world.create_joint(body0, body1, kea::JointSpec::hinge(Vec3::ZERO, Vec3::X))?;
    let limit = hinge.limit_mut(&mut world)?;
    limit.set_limits(
        SingleLimit::hard(LO_LIMIT, 0.3),
        SingleLimit::hard(HI_LIMIT, 0.3),
    )?;
    limit.set_motor(2.0, 30.0)?;
    println!(
        "hinge: {} hinged at the origin about x, limits [{LO_LIMIT}, {HI_LIMIT}] rad, motor 2 rad/s at 30 N·m",
        if two { "two bodies" } else { "one body to the world" }
    );
    println!(
        "{:>6} {:>10} {:>10} {:>9} {:>12}",
        "t [s]", "angle", "rate", "at stop", "motor"
    );
    let h: Real = 1.0 / 60.0;
    for n in 1..=240 {
        if n == 120 {
            hinge.limit_mut(&mut world)?.set_motor(-2.0, 30.0)?;
        }
        world.step(h)?;
        if n % 12 == 0 {
            let l = hinge.get(&world)?.limit();
            println!(
                "{:>6.2} {:>10.4} {:>10.4} {:>9} {:>12}",
                n as Real * h,
                l.position(),
                l.velocity(),
                l.is_at_limit(1e-3),
                format!(
                    "{:+.1} rad/s",
                    l.motor().map_or(0.0, |m| m.desired_velocity)
                )
            );
        }
    }
    Ok(())
}
