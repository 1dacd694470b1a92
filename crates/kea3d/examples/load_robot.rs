//! Loads a URDF or MJCF robot, prints its links and joints, lets it swing for a second under
//! gravity along −z and prints where its joints went.
//!
//! `cargo run --release -p kea3d --example load_robot -- path/to/robot.urdf [--fixed-base]`

use kea3d::prelude::*;
use kea3d::robot::{MjcfOptions, UrdfOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.iter().find(|a| !a.starts_with("--")) else {
        eprintln!("usage: load_robot FILE.urdf|FILE.xml [--fixed-base]");
        std::process::exit(2);
    };
    let mut world = PhysicsWorld::new();
    world.set_gravity([0.0, 0.0, -9.81])?;
    let robot = if path.ends_with(".urdf") {
        let options = UrdfOptions {
            fixed_base: args.iter().any(|a| a == "--fixed-base"),
            ..UrdfOptions::default()
        };
        world.load_urdf(path, &options)?
    } else {
        world.load_mjcf(path, &MjcfOptions::default())?
    };
    println!(
        "{}: {} links, {} joints, {} positions, {} velocities, {} actuators, {} bodies, {} colliders",
        robot.name(),
        robot.links().len(),
        robot.joints().len(),
        robot.position_count(),
        robot.velocity_count(),
        robot.actuators().len(),
        world.body_count(),
        world.collision().collider_count()
    );
    for line in robot.skipped() {
        println!("skipped: {line}");
    }
    // `--q0 a,b,c`: start from these joint positions (the swing tests' way).
    if let Some(q0) = args
        .iter()
        .position(|a| a == "--q0")
        .and_then(|i| args.get(i + 1))
    {
        let q: Vec<Real> = q0.split(',').map(|x| x.parse().expect("numbers")).collect();
        robot.set_joint_positions(&mut world, &q)?;
    }
    if let Some(n) = std::env::var("KEA_SUBSTEPS")
        .ok()
        .and_then(|s| s.parse().ok())
    {
        world
            .dynamics_mut()
            .update_settings(|s| s.world_substeps = n)?;
    }
    let h = robot.timestep().unwrap_or(1e-3);
    let start = std::time::Instant::now();
    let seconds: f64 = std::env::var("KEA_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    let steps = (seconds / h as f64).round() as usize;
    for k in 0..steps {
        world.step(h)?;
        if std::env::var("KEA_TRACE").is_ok() && (k + 1) % (steps / 10).max(1) == 0 {
            let q = robot.joint_positions(&world)?;
            println!("t = {:.2} s: {q:.4?}", (k + 1) as f64 * h as f64);
        }
    }
    println!(
        "1 s in {steps} steps of {h} s: {:.3} ms, {:.1} µs a step",
        start.elapsed().as_secs_f64() * 1e3,
        start.elapsed().as_secs_f64() * 1e6 / steps as f64
    );
    let q = robot.joint_positions(&world)?;
    println!("joint positions: {q:.4?}");
    Ok(())
}
