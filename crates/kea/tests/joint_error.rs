//! `World::joint_error`: how far rigid joints have come apart, measured at the present poses.

use kea::{BodyDef, Vec3, World};

#[test]
fn joint_error_is_the_gap_a_moved_body_opens() {
    let mut world = World::with_capacity(4, 16).unwrap();
    let bob = world
        .create_body(&BodyDef {
            position: Vec3::new(1.0, 0.0, 0.0),
            ..BodyDef::default()
        })
        .unwrap();
    world.create_ball_joint(bob, None, Vec3::ZERO).unwrap();
    assert!(
        world.joint_error() < 1e-6,
        "a joint built in place is closed"
    );
    // Pull the bob 0.1 m out along the rod (x): the anchor points are now 0.1 m apart.
    world
        .body_mut(bob)
        .unwrap()
        .set_position(Vec3::new(1.1, 0.0, 0.0))
        .unwrap();
    let e = world.joint_error();
    assert!((e - 0.1).abs() < 1e-5, "{e}");
    world
        .body_mut(bob)
        .unwrap()
        .set_position(Vec3::new(1.0, 0.0, 0.0))
        .unwrap();
    for _ in 0..60 {
        world.step(1.0 / 60.0).unwrap();
    }
    // Swinging at ~4 m/s on a 1 m rod, each step drifts ~v²h²/r ≈ 4 mm off the circle and
    // γ = 0.2 takes back a fifth of the error per step (no projection here).
    assert!(world.joint_error() < 0.02, "{}", world.joint_error());
}

#[test]
fn a_hinge_folded_back_on_itself_reports_the_angle_not_its_sine() {
    let mut world = World::with_capacity(4, 16).unwrap();
    let arm = world
        .create_body(&BodyDef {
            position: Vec3::new(1.0, 0.0, 0.0),
            ..BodyDef::default()
        })
        .unwrap();
    world.create_hinge(arm, None, Vec3::ZERO, Vec3::Y).unwrap();
    // Turn the arm 170° about x, about the anchor: its hinge axis now points nearly down.
    let q = kea::Quat::from_rotation_x(170f32.to_radians() as kea::Real);
    let b = world.body_mut(arm).unwrap();
    b.set_orientation(q).unwrap();
    b.set_position(q * Vec3::new(1.0, 0.0, 0.0)).unwrap();
    let e = world.joint_error();
    let expected = (170.0 as kea::Real).to_radians();
    assert!(
        (e - expected).abs() < 1e-3,
        "{e} (sin would be {})",
        expected.sin()
    );
}
