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
    world
        .create_joint(bob, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
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
    world
        .create_joint(arm, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::Y))
        .unwrap();
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

#[test]
fn projection_closes_joints_in_steps_where_a_limit_comes_or_goes() {
    // A fast pendulum on a hinge that swings into its stops: in the steps where a stop row
    // appears or disappears, the rows written at the new state differ from the step's, and
    // projection must still close the joint (it used to skip those steps).
    let def = kea::WorldDef {
        max_bodies: 2,
        max_constraints: 4,
        settings: kea::WorldSettings {
            projection_iterations: 4,
            // Nearly rigid: projection keeps a soft joint's stretch under load (ε h² λ / γ),
            // which would otherwise be most of what is measured.
            epsilon: 1e-6,
            // The maximal-coordinate path's projection (a reduced tree has no joint error).
            routing: kea::Routing {
                max_reduced_links: 0,
                ..Default::default()
            },
            ..Default::default()
        },
        ..kea::WorldDef::default()
    };
    let run = |def: kea::WorldDef| {
        let mut world = World::new(def).unwrap();
        let bob = world
            .create_body(&BodyDef {
                position: Vec3::new(1.0, 0.0, 0.0),
                linear_velocity: Vec3::new(0.0, -6.0, 0.0),
                ..BodyDef::default()
            })
            .unwrap();
        let hinge = world
            .create_joint(bob, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::Z))
            .unwrap();
        let stops = (
            kea::SingleLimit::hard(-0.6, 0.0),
            kea::SingleLimit::hard(0.6, 0.0),
        );
        hinge
            .limit_mut(&mut world)
            .unwrap()
            .set_limits(stops.0, stops.1)
            .unwrap();
        let mut worst: kea::Real = 0.0;
        let mut hits = 0;
        for _ in 0..240 {
            world.step(1.0 / 60.0).unwrap();
            worst = worst.max(world.joint_error());
            let limit = hinge.limit_mut(&mut world).unwrap();
            hits += usize::from(limit.is_at_limit(0.01));
        }
        (worst, hits)
    };
    let (projected, hits) = run(def.clone());
    let (unprojected, _) = run(kea::WorldDef {
        settings: kea::WorldSettings {
            projection_iterations: 0,
            ..def.settings
        },
        ..def
    });
    assert!(
        hits > 10,
        "the pendulum reached its stops only {hits} times"
    );
    assert!(projected < 1e-4, "with projection: {projected}");
    assert!(unprojected > 10.0 * projected, "without: {unprojected}");
}

/// Many resting boxes (so that a step lists its awake bodies' constraints rather than
/// scanning every slot) beside a pendulum; the pile is held by joints to the world.
fn pile_beside_a_pendulum(pile: usize) -> (World, kea::BodyHandle) {
    let mut world = World::with_capacity(pile + 1, 4 * pile + 8).unwrap();
    for i in 0..pile {
        let b = world
            .create_body(&BodyDef {
                position: Vec3::new(3.0 + i as kea::Real, 0.0, 0.0),
                ..BodyDef::default()
            })
            .unwrap();
        world
            .create_joint(
                b,
                None,
                kea::JointSpec::fixed(Vec3::new(3.0 + i as kea::Real, 0.0, 0.0)),
            )
            .unwrap();
    }
    let bob = world
        .create_body(&BodyDef {
            position: Vec3::new(1.0, 0.0, 0.0),
            ..BodyDef::default()
        })
        .unwrap();
    world
        .create_joint(bob, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    (world, bob)
}

#[test]
fn joint_error_sees_joints_made_and_worlds_copied_in_since_the_last_step() {
    let (mut world, bob) = pile_beside_a_pendulum(40);
    world
        .update_settings(|s| s.dem.mode = kea::DemMode::PartitionAutoDisable)
        .unwrap();
    for _ in 0..120 {
        world.step(1.0 / 60.0).unwrap();
    }
    // A joint made after the step, opened 0.1 m: the last step's listing did not have it.
    let other = world
        .create_body(&BodyDef {
            position: Vec3::new(-2.0, 0.0, 0.0),
            ..BodyDef::default()
        })
        .unwrap();
    world
        .create_joint(
            other,
            Some(bob),
            kea::JointSpec::ball(Vec3::new(-1.0, 0.0, 0.0)),
        )
        .unwrap();
    world
        .body_mut(other)
        .unwrap()
        .set_position(Vec3::new(-2.1, 0.0, 0.0))
        .unwrap();
    let e = world.joint_error();
    assert!(e > 0.09, "the new joint's gap is seen: {e}");
    // A smaller world's state copied in: nothing of the last step's listing is read.
    let (small, _) = pile_beside_a_pendulum(0);
    world.copy_state_from(&small);
    assert!(world.joint_error() < 1e-6);
}
