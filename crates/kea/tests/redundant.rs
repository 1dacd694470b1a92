//! Redundant constraints with ε = 0 (the guide's over-determinacy): the system is singular, the
//! step says so in its stats, regularises, and stays finite and sensible.

mod common;
use common::world_on;
use kea::{BodyDef, Real, SolverMode, Vec3, World};

#[test]
fn redundant_ball_joints_with_zero_epsilon_are_reported_and_stay_finite() {
    let mut world = World::with_capacity(4, 8).unwrap();
    world.update_settings(|s| s.epsilon = 0.0).unwrap();
    let b = world
        .create_body(&BodyDef {
            position: Vec3::new(1.0, 0.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    // Two identical joints: 6 rows, rank 3.
    world
        .create_joint(b, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    world
        .create_joint(b, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    let mut singular_steps = 0;
    for _ in 0..300 {
        let stats = world.step(1.0 / 60.0).unwrap();
        if stats.solver.singular_islands > 0 {
            singular_steps += 1;
        }
        let p = world.body(b).unwrap().position();
        assert!(p.is_finite() && p.length() < 1.5, "blew up: {p}");
    }
    assert!(singular_steps > 0, "singularity never reported");
    let p = world.body(b).unwrap().position();
    assert!((p.length() - 1.0).abs() < 1e-3, "joint failed to hold: {p}");
}

#[test]
fn two_ball_joints_as_a_hinge_are_redundant_but_fine_with_default_epsilon() {
    // The guide's example of over-determinacy: a hinge made of two ball joints (6 rows for 5
    // DOF). With the default ε the system is regular: no warning, and it swings as a hinge.
    let mut world = World::with_capacity(4, 8).unwrap();
    let b = world
        .create_body(&BodyDef {
            position: Vec3::new(0.0, -1.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    world
        .create_joint(b, None, kea::JointSpec::ball(Vec3::new(0.0, 0.0, -0.5)))
        .unwrap();
    world
        .create_joint(b, None, kea::JointSpec::ball(Vec3::new(0.0, 0.0, 0.5)))
        .unwrap();
    world
        .body_mut(b)
        .unwrap()
        .set_linear_velocity(Vec3::new(1.0, 0.0, 0.0))
        .unwrap();
    for _ in 0..120 {
        let stats = world.step(1.0 / 60.0).unwrap();
        assert!(stats.solver.is_clean(), "{stats:?}");
    }
    let body = world.body(b).unwrap();
    let z: Real = body.position().z;
    assert!(z.abs() < 1e-3, "moved along the hinge axis: {z}");
}

#[test]
fn redundant_rows_with_zero_epsilon_stay_finite_in_the_iterative_path() {
    let mut world = world_on(SolverMode::Iterative, 4, 8);
    world.update_settings(|s| s.epsilon = 0.0).unwrap();
    let b = world
        .create_body(&BodyDef {
            position: Vec3::new(1.0, 0.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    world
        .create_joint(b, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    world
        .create_joint(b, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    for _ in 0..300 {
        let stats = world.step(1.0 / 60.0).unwrap();
        assert_eq!(stats.solver.iterative_islands, 1);
        let p = world.body(b).unwrap().position();
        assert!(p.is_finite() && p.length() < 1.5, "blew up: {p}");
    }
    let p = world.body(b).unwrap().position();
    assert!((p.length() - 1.0).abs() < 1e-3, "joint failed to hold: {p}");
}
