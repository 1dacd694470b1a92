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
