//! The guide's animated hand: an animated "hand" (a path the program moves every step) holds a
//! box by a fixed-path-fixed-orientation joint that breaks above a set force. The hand swings the
//! box faster and faster until the grip's force passes the threshold; then the joint disables
//! itself, the step reports it, and the box flies off.
//!
//! Run: `cargo run --release --example animated_hand`

use kea::{inertia, BodyDef, Real, Vec3, World};

fn main() -> Result<(), kea::KeaError> {
    let mut world = World::with_capacity(2, 2)?;
    let grip = Vec3::new(0.8, 1.5, 0.0);
    let held = world.create_body(&BodyDef {
        mass: 2.0,
        position: grip,
        inertia: inertia::solid_box(2.0, Vec3::splat(0.15))?,
        ..Default::default()
    })?;
    let hand = world.create_joint(held, None, kea::JointSpec::fixed_path(grip, true))?;
    world.set_breakable(hand, Some(60.0), None)?;
    println!(
        "animated_hand: a 2 kg box held at the end of a swinging arm; the grip breaks above 60 N"
    );
    let h: Real = 1.0 / 60.0;
    let (mut angle, mut speed): (Real, Real) = (0.0, 0.0);
    for n in 1..=600 {
        // The animation: a hand circling at radius 0.8 m about (0, 1.5, 0), speeding up.
        speed += 1.5 * h; // rad/s²
        angle += speed * h;
        let pos = Vec3::new(0.8 * angle.cos(), 1.5, 0.8 * angle.sin());
        let vel = Vec3::new(-0.8 * speed * angle.sin(), 0.0, 0.8 * speed * angle.cos());
        if world.is_constraint_enabled(hand)? {
            hand.set_path(&mut world, pos, vel)?;
        }
        let stats = world.step(h)?;
        let force = world.constraint_reaction(hand)?[0].force.length();
        if n % 30 == 0 || stats.broken_joints > 0 {
            println!(
                "t = {:5.2} s  hand speed {:5.2} m/s  grip force {:6.1} N  box at ({:5.2}, {:5.2}, {:5.2})",
                n as Real * h,
                0.8 * speed,
                force,
                world.body(held)?.position().x,
                world.body(held)?.position().y,
                world.body(held)?.position().z
            );
        }
        if stats.broken_joints > 0 {
            println!(
                "the grip broke: the joint disabled itself ({} broken this step)",
                stats.broken_joints
            );
            for _ in 0..30 {
                world.step(h)?;
            }
            let b = world.body(held)?;
            println!(
                "half a second later the box is at {:.2?}, moving at {:.2} m/s",
                b.position(),
                b.linear_velocity().length()
            );
            return Ok(());
        }
    }
    println!("the grip held");
    Ok(())
}
