//! The solver ends on any finite input, with a result or a named error, and never writes a
//! non-finite state: joints anchored at the edge of the number range, huge and tiny masses, and
//! redundant joints, in both paths.

mod common;
use common::{world_on, PATHS};
use kea::{BodyDef, Real, Vec3, World};

/// Steps `world` a few times; every step must come back, and the bodies stay finite whatever
/// it answered.
fn steps_end_finite(world: &mut World, label: &str) {
    for _ in 0..5 {
        let _ = world.step(1.0 / 60.0); // Ok or a named error: either way it returned
        for (_, b) in world.bodies() {
            let (p, v) = (b.position(), b.linear_velocity());
            assert!(p.is_finite() && v.is_finite(), "{label}: {p} {v}");
        }
    }
}

#[test]
fn joints_anchored_at_the_edge_of_the_range_end_in_every_path() {
    for mode in PATHS {
        let far: &[f64] = if common::F64 {
            &[1.0e300, -1.0e300, 1.0e160, 3.0e38, 1.0e20]
        } else {
            &[3.0e38, -3.0e38, 1.0e30, 1.0e20]
        };
        for &anchor in far {
            let anchor = anchor as Real;
            let mut world = world_on(mode, 4, 8);
            let b = world.create_body(&BodyDef::default()).unwrap();
            if world
                .create_joint(b, None, kea::JointSpec::ball(Vec3::new(anchor, 0.0, 0.0)))
                .is_ok()
            {
                steps_end_finite(&mut world, &format!("{mode:?}, anchor {anchor:e}"));
            }
        }
    }
}

#[test]
fn huge_and_tiny_masses_on_joints_end_in_every_path() {
    for mode in PATHS {
        for (m1, m2) in [(1.0e-6, 1.0e6), (1.0e12, 1.0e-12), (1.0e-20, 1.0e20)] {
            let mut world = world_on(mode, 4, 8);
            let body = |m: Real, x: Real| BodyDef {
                mass: m,
                inertia: kea::Mat3::from_diagonal(Vec3::splat(m)),
                position: Vec3::new(x, 0.0, 0.0),
                ..Default::default()
            };
            let (Ok(a), Ok(b)) = (
                world.create_body(&body(m1 as Real, 1.0)),
                world.create_body(&body(m2 as Real, 2.0)),
            ) else {
                continue; // refused by name: fine
            };
            world
                .create_joint(a, None, kea::JointSpec::ball(Vec3::ZERO))
                .unwrap();
            world
                .create_joint(b, Some(a), kea::JointSpec::ball(Vec3::new(1.5, 0.0, 0.0)))
                .unwrap();
            steps_end_finite(&mut world, &format!("{mode:?}, masses {m1:e} {m2:e}"));
        }
    }
}

#[test]
fn two_redundant_joints_on_one_body_never_produce_nan() {
    for mode in PATHS {
        for eps in [0.0, 1.0e-9] {
            let mut world = world_on(mode, 4, 8);
            world.update_settings(|s| s.epsilon = eps).unwrap();
            let b = world
                .create_body(&BodyDef {
                    position: Vec3::new(1.0, 0.0, 0.0),
                    linear_velocity: Vec3::new(0.0, 5.0, 3.0),
                    ..Default::default()
                })
                .unwrap();
            world
                .create_joint(b, None, kea::JointSpec::ball(Vec3::ZERO))
                .unwrap();
            world
                .create_joint(b, None, kea::JointSpec::ball(Vec3::ZERO))
                .unwrap();
            world
                .create_joint(b, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::Z))
                .unwrap();
            for _ in 0..600 {
                world.step(1.0 / 60.0).unwrap();
                let p = world.body(b).unwrap().position();
                assert!(p.is_finite(), "{mode:?}, ε {eps}: {p}");
                assert!(
                    (p.length() - 1.0).abs() < 0.05,
                    "{mode:?}, ε {eps}: joint gave: {p}"
                );
            }
        }
    }
}
