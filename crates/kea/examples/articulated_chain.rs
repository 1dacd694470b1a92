//! Times the reduced-coordinate tree (`kea::articulation`) on a 7-link arm like the KUKA
//! iiwa's: µs per step, to set beside the maximal-coordinate step of the same arm
//! (`cargo run --release -p kea3d --example small_worlds`).
//!
//! `cargo run --release -p kea --example articulated_chain`

use glam::{DMat3, DQuat, DVec3};
use kea::articulation::{ArticulatedTree, TreeJointKind, TreeLink};
use std::time::Instant;

fn main() {
    // Seven links 0.2 m apart, axes alternating z and y, each 3 kg.
    let links: Vec<TreeLink> = (0..7usize)
        .map(|k| TreeLink {
            parent: k.checked_sub(1),
            kind: TreeJointKind::Hinge,
            origin: (
                DVec3::new(0.0, 0.0, if k == 0 { 0.1 } else { 0.2 }),
                DQuat::IDENTITY,
            ),
            axis: if k % 2 == 0 { DVec3::Z } else { DVec3::Y },
            anchor: DVec3::ZERO,
            mass: 3.0 - 0.3 * k as f64,
            com: DVec3::new(0.0, 0.02, 0.1),
            inertia: DMat3::from_diagonal(DVec3::new(0.03, 0.028, 0.01)),
            armature: 0.0,
            damping: 0.5,
            limits: Some((-2.9, 2.9)),
            motor: None,
            friction: 0.0,
            soft_limit: None,
            servo: None,
            spring: None,
            stop_recovery_speed: f64::INFINITY,
        })
        .collect();
    let mut tree = ArticulatedTree::new(links, DVec3::new(0.0, 0.0, -9.81)).unwrap();
    let mut q: Vec<f64> = vec![0.4, 0.5, -0.3, -1.1, 0.5, 0.8, 0.2];
    let mut qd = vec![0.0; 7];
    let tau = vec![0.0; 7];
    let steps = 200_000;
    let start = Instant::now();
    for _ in 0..steps {
        tree.step(&mut q, &mut qd, &tau, 0.002).unwrap();
    }
    let per = start.elapsed().as_secs_f64() * 1e6 / steps as f64;
    println!("7-link tree: {per:.3} µs a step (q = {q:.3?})");
}
