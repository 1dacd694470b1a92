//! The small-world step that batches of learning environments spend their time in: 1,024
//! cart-poles (a cart on a slider with a motor, a pole on a hinge, colliders that touch
//! nothing) and 1,024 KUKA iiwa arms from pybullet_data's URDF (7 hinges, no contacts),
//! stepped one after another on one thread. Prints µs per world step: the figure to profile
//! (`perf record -g target/release/examples/small_worlds`).
//!
//! `cargo run --release -p kea3d --example small_worlds [-- KUKA_URDF [--euler]]` (`--euler`:
//! the arm stepped with explicit Euler, as `crates/kea-py/bench/batch_vs_mujoco.py` steps it).

use kea3d::prelude::*;
use kea3d::robot::{Robot, UrdfOptions};
use kea3d::HeldWorld;
use std::time::Instant;

fn cart_pole() -> PhysicsWorld {
    let mut w = PhysicsWorld::new();
    let cart = w.insert_body(Body::dynamic().mass(1.0)).unwrap();
    w.insert_collider(Collider::cuboid([0.25, 0.1, 0.15]), Some(cart))
        .unwrap();
    let pole = w.insert_body(Body::dynamic().mass(0.1)).unwrap();
    w.insert_collider(
        Collider::capsule([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 0.03),
        Some(pole),
    )
    .unwrap();
    let slider = Joint::prismatic([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
        .limits(-2.4, 2.4)
        .motor(0.5, 30.0);
    w.insert_joint(cart, None, slider).unwrap();
    w.insert_joint(
        pole,
        Some(cart),
        Joint::hinge([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
    )
    .unwrap();
    w.set_step_timing(false);
    w
}

/// One free body and nothing else: the pipeline's floor.
fn one_body() -> PhysicsWorld {
    let mut w = PhysicsWorld::new();
    let b = w.insert_body(Body::dynamic().mass(1.0)).unwrap();
    w.insert_collider(Collider::ball(0.1), Some(b)).unwrap();
    w.set_step_timing(false);
    w
}

fn time(name: &str, template: &PhysicsWorld, dt: Real, steps: usize) {
    let mut worlds = vec![template.clone(); 1024];
    for w in &mut worlds {
        w.step(dt).unwrap(); // warm
    }
    let start = Instant::now();
    for w in &mut worlds {
        for _ in 0..steps {
            w.step(dt).unwrap();
        }
    }
    let per = start.elapsed().as_secs_f64() * 1e6 / (worlds.len() * steps) as f64;
    let last = worlds[0].step(dt).unwrap();
    println!(
        "{name}: {per:.2} µs per world step ({} worlds × {steps} steps of {dt} s; {} rows, {} pairs, {} manifolds)",
        worlds.len(),
        last.rows,
        last.collision.pairs,
        last.collision.manifolds
    );
}

fn main() {
    let steps: usize = std::env::var("KEA_STEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(200);
    // `KEA_ONLY=arm`: the arm alone (a profile of its step with nothing else in it).
    if std::env::var("KEA_ONLY").as_deref() != Ok("arm") {
        time("one falling ball", &one_body(), 0.01, steps);
        time("cart-pole", &cart_pole(), 0.01, steps);
    }
    if let Some(path) = std::env::args().nth(1) {
        let mut arm = PhysicsWorld::new();
        arm.set_gravity([0.0, 0.0, -9.81]).unwrap();
        let options = UrdfOptions {
            fixed_base: true,
            ..UrdfOptions::default()
        };
        let robot = arm.load_urdf(&path, &options).unwrap();
        robot
            .set_joint_positions(&mut arm, &[0.4, 0.5, -0.3, -1.1, 0.5, 0.8, 0.2])
            .unwrap();
        if std::env::args().any(|a| a == "--euler") {
            arm.dynamics_mut()
                .update_settings(|s| s.integrator = kea3d::dynamics::Integrator::Euler)
                .unwrap();
        }
        arm.set_step_timing(false);
        if std::env::var("KEA_WORLDS").is_err() {
            time("kuka iiwa", &arm, 0.002, steps);
        }
        closed_loop("kuka iiwa", &arm, &robot, 0.002, steps);
    }
}

/// The arm as `kea.Batch` steps it in a closed loop: each world is held as a compact record
/// beside the model, a hot worker with the model's definitions takes it in, steps five
/// times, reads its joint positions and velocities while it holds it, and gives it back (`KEA_SUBSTEPS` steps per environment step, 5 by
/// default).
fn closed_loop(name: &str, template: &PhysicsWorld, robot: &Robot, dt: Real, steps: usize) {
    let substeps: usize = std::env::var("KEA_SUBSTEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let held = template.held();
    let count: usize = std::env::var("KEA_WORLDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1024);
    let mut worlds = vec![held; count];
    let mut worker = template.clone();
    let mut q = vec![0.0; robot.position_count()];
    let mut v = vec![0.0; robot.velocity_count()];
    let mut env_step = |worlds: &mut [HeldWorld]| {
        for k in 0..worlds.len() {
            if let Some(next) = worlds.get(k + 1) {
                next.prefetch();
            }
            let w = &mut worlds[k];
            worker.enter(w);
            for _ in 0..substeps {
                worker.step(dt).unwrap();
            }
            robot.joint_state_into(&worker, &mut q, &mut v).unwrap();
            worker.leave(w, template);
        }
    };
    env_step(&mut worlds); // warm
    let env_steps = (steps / substeps).max(1);
    let start = Instant::now();
    for _ in 0..env_steps {
        env_step(&mut worlds);
    }
    let per = start.elapsed().as_secs_f64() * 1e6 / (worlds.len() * env_steps * substeps) as f64;
    println!(
        "{name}, closed loop: {per:.2} µs per world step ({} worlds × {env_steps} environment \
         steps of {substeps} steps, each world traded into a worker, its joints read there)",
        worlds.len()
    );
}
