//! The common constraint API on joints (issue 4): fixed-path tracking, breakable joints,
//! γ override, readable dumps, momentum of powered joints, and bad joint input.

mod common;
use common::{world_on, F64, PATHS};
use kea::{inertia, BodyDef, Real, SingleLimit, SolverMode, Vec3, World};

#[test]
fn fixed_path_tracks_a_moving_path_within_a_millimetre() {
    for mode in PATHS {
        let mut world = world_on(mode, 4, 4);
        let b = world
            .create_body(&BodyDef {
                position: Vec3::new(0.5, 1.0, 0.0),
                inertia: inertia::solid_box(1.0, Vec3::splat(0.1)).unwrap(),
                ..Default::default()
            })
            .unwrap();
        let j = world
            .create_joint(
                b,
                None,
                kea::JointSpec::fixed_path(Vec3::new(0.5, 1.0, 0.0), false),
            )
            .unwrap();
        let (r, w, h): (Real, Real, Real) = (0.5, 2.0, 1.0 / 60.0);
        let path = |t: Real| Vec3::new(r * (w * t).cos(), 1.0, r * (w * t).sin());
        let vel = |t: Real| Vec3::new(-r * w * (w * t).sin(), 0.0, r * w * (w * t).cos());
        let mut worst: Real = 0.0;
        for n in 0..300 {
            let t = n as Real * h;
            j.set_path(&mut world, path(t), vel(t)).unwrap();
            world.step(h).unwrap();
            let p = world.body(b).unwrap().position();
            if n > 30 {
                worst = worst.max((p - path(t + h)).length());
            }
        }
        eprintln!("{mode:?}: fixed path tracking error {worst:e} m");
        assert!(worst < 1e-3, "{mode:?}: tracking error {worst}");
    }
}

#[test]
fn a_breakable_joint_breaks_at_its_threshold_not_before() {
    // A 1 kg box hangs from a fixed-orientation path joint that breaks above 15 N; a growing
    // downward pull breaks it once weight + pull passes 15 N, and only then.
    let mut world = World::with_capacity(4, 4).unwrap();
    let b = world.create_body(&BodyDef::default()).unwrap();
    let j = world
        .create_joint(b, None, kea::JointSpec::fixed_path(Vec3::ZERO, true))
        .unwrap();
    world.set_breakable(j, Some(15.0), None).unwrap();
    let mut broke_at = None;
    for n in 0..200 {
        let pull = 0.05 * n as Real;
        world
            .body_mut(b)
            .unwrap()
            .add_force(Vec3::new(0.0, -pull, 0.0))
            .unwrap();
        let stats = world.step(1.0 / 60.0).unwrap();
        if stats.broken_joints > 0 {
            assert_eq!(world.broken_last_step(), &[j.raw()]);
            broke_at = Some(9.81 + pull);
            break;
        }
    }
    let load = broke_at.expect("never broke");
    assert!(load > 15.0 && load < 15.0 + 0.1, "broke under {load} N");
    assert!(!world.is_constraint_enabled(j).unwrap());
    let log = world.constraint_log(j).unwrap();
    assert!(
        log.contains("fixed-path-fixed-orientation") && log.contains("disabled"),
        "{log}"
    );
}

#[test]
fn powered_joints_keep_the_pair_momentum() {
    for mode in PATHS {
        for slider in [false, true] {
            let mut world = world_on(mode, 4, 4);
            world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
            let mk = |w: &mut World, x: Real, m: Real| {
                w.create_body(&BodyDef {
                    mass: m,
                    position: Vec3::new(x, 0.0, 0.0),
                    inertia: inertia::solid_box(m, Vec3::new(0.3, 0.2, 0.1)).unwrap(),
                    linear_velocity: Vec3::new(0.1 * x, 0.2, -0.1),
                    ..Default::default()
                })
                .unwrap()
            };
            let (a, b) = (mk(&mut world, 0.0, 2.0), mk(&mut world, 1.0, 1.0));
            let anchor = Vec3::new(0.5, 0.0, 0.0);
            let limit = if slider {
                let spec = kea::JointSpec::prismatic(anchor, Vec3::X);
                let j = world.create_joint(b, Some(a), spec).unwrap();
                j.limit_mut(&mut world)
            } else {
                let spec = kea::JointSpec::hinge(anchor, Vec3::Z);
                let j = world.create_joint(b, Some(a), spec).unwrap();
                j.limit_mut(&mut world)
            };
            limit.unwrap().set_motor(2.0, 5.0).unwrap();
            let momenta = |w: &World| {
                let mut p = Vec3::ZERO;
                let mut l = Vec3::ZERO;
                for h in [a, b] {
                    let bd = w.body(h).unwrap();
                    p += bd.mass() * bd.linear_velocity();
                    l += bd.angular_momentum()
                        + bd.position().cross(bd.mass() * bd.linear_velocity());
                }
                (p, l)
            };
            let (p0, l0) = momenta(&world);
            for _ in 0..120 {
                world.step(1.0 / 60.0).unwrap();
            }
            let (p, l) = momenta(&world);
            let dp = (p - p0).length() / p0.length();
            let dl = (l - l0).length() / l0.length().max(1.0);
            eprintln!(
                "{mode:?} {}: momentum drift linear {dp:e}, angular {dl:e}",
                if slider { "slider" } else { "hinge" }
            );
            assert!(
                dp < if F64 { 1e-9 } else { 1e-5 },
                "{mode:?}: linear momentum {dp}"
            );
            assert!(dl < 1e-4, "{mode:?}: angular momentum {dl}");
            let _ = SolverMode::Exact;
        }
    }
}

#[test]
fn gamma_override_changes_only_its_joint() {
    let run = |gamma: Option<Real>| {
        let mut world = World::with_capacity(4, 4).unwrap();
        world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
        // The maximal path's error reduction (a joint with its own γ always takes it; the
        // default routing would step this bob in reduced coordinates, its drift taken out).
        world
            .update_settings(|s| s.routing.mode = kea::SolverMode::Exact)
            .unwrap();
        let b = world
            .create_body(&BodyDef {
                position: Vec3::new(1.1, 0.0, 0.0),
                ..Default::default()
            })
            .unwrap();
        // The anchor sits 0.1 m off the body's anchor point: the joint pulls it back at rate γ.
        let j = world
            .create_joint(b, None, kea::JointSpec::ball(Vec3::new(1.0, 0.0, 0.0)))
            .unwrap();
        world
            .body_mut(b)
            .unwrap()
            .set_position(Vec3::new(1.2, 0.0, 0.0))
            .unwrap();
        world.set_constraint_gamma(j, gamma).unwrap();
        world.step(1.0 / 60.0).unwrap();
        world.body(b).unwrap().position().x - 1.1
    };
    let (default, fast) = (run(None), run(Some(0.8)));
    // Remaining error after one step: (1 − γ)·0.1 up to the softness.
    assert!(
        (default - 0.08).abs() < 2e-3 && (fast - 0.02).abs() < 2e-3,
        "{default} {fast}"
    );
}

#[test]
fn bad_joint_input_is_named_and_changes_nothing() {
    let mut world = World::with_capacity(4, 4).unwrap();
    let a = world.create_body(&BodyDef::default()).unwrap();
    let count = world.constraint_count();
    let e = world
        .create_joint(a, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::ZERO))
        .unwrap_err()
        .to_string();
    assert!(e.contains("axis") && e.contains("length 0"), "{e}");
    let e = world
        .create_joint(a, Some(a), kea::JointSpec::prismatic(Vec3::ZERO, Vec3::X))
        .unwrap_err()
        .to_string();
    assert!(e.contains("same body"), "{e}");
    let e = world
        .create_joint(
            a,
            None,
            kea::JointSpec::universal(Vec3::ZERO, Vec3::X, Vec3::X),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("axis2") && e.contains("perpendicular"), "{e}");
    let e = world
        .create_joint(
            a,
            None,
            kea::JointSpec::linear2(Vec3::new(Real::NAN, 0.0, 0.0), Vec3::X),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("anchor") && e.contains("NaN"), "{e}");
    let w = world.create_body(&BodyDef::default()).unwrap();
    let e = world
        .create_joint(
            a,
            Some(w),
            kea::JointSpec::car_wheel(Vec3::Y, Vec3::Y, 100.0, 1.0),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("axle") && e.contains("perpendicular"), "{e}");
    let e = world
        .create_joint(
            a,
            Some(w),
            kea::JointSpec::car_wheel(Vec3::Y, Vec3::X, 0.0, 1.0),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("`k`") && e.contains('0'), "{e}");
    let e = world
        .create_joint(
            a,
            Some(w),
            kea::JointSpec::car_wheel(Vec3::Y, Vec3::X, 100.0, -1.0),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("`d`") && e.contains("-1"), "{e}");
    let ball2 = world
        .create_joint(a, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    let e = ball2.set_limit_axes(&mut world, Vec3::Y, Vec3::Y);
    assert!(e.unwrap_err().to_string().contains("orthogonal"));
    assert_eq!(world.constraint_count(), count + 1); // only the ball joint was created
    let h = world
        .create_joint(a, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::Y))
        .unwrap();
    let limit = h.limit_mut(&mut world).unwrap();
    let e = limit
        .set_limits(SingleLimit::hard(1.0, 0.0), SingleLimit::hard(-1.0, 0.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("lower.stop"), "{e}");
    let e = limit
        .set_limits(
            SingleLimit::soft(-1.0, -5.0, 0.0),
            SingleLimit::hard(1.0, 0.0),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("lower.stiffness") && e.contains("-5"), "{e}");
    let e = limit
        .set_limits(
            SingleLimit::soft(-1.0, 5.0, -1.0),
            SingleLimit::hard(1.0, 0.0),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("lower.damping"), "{e}");
    let e = limit.set_motor(1.0, -2.0).unwrap_err().to_string();
    assert!(e.contains("max_force") && e.contains("-2"), "{e}");
    let e = limit
        .set_motor(Real::INFINITY, 2.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("desired_velocity"), "{e}");
    assert!(
        !limit.is_limited() && limit.motor().is_none(),
        "a failed call changed the limit"
    );
    let e = world
        .set_breakable(h, Some(-1.0), None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("max_force"), "{e}");
    let e = world
        .set_constraint_gamma(h, Some(2.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("gamma"), "{e}");
    let ball = world
        .create_joint(a, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    let not_a_hinge = kea::JointHandle::<kea::Hinge>::from_raw(ball.raw());
    let e = not_a_hinge.limit_mut(&mut world).unwrap_err().to_string();
    assert!(e.contains("hinge") && e.contains("ball joint"), "{e}");
}

#[test]
fn reset_restores_the_guide_defaults() {
    let mut world = World::with_capacity(4, 4).unwrap();
    let b = world
        .create_body(&BodyDef {
            position: Vec3::new(0.0, -1.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    let h = world
        .create_joint(
            b,
            None,
            kea::JointSpec::hinge(Vec3::new(0.0, -0.5, 0.0), Vec3::X),
        )
        .unwrap();
    h.limit_mut(&mut world)
        .unwrap()
        .set_motor(1.0, 1.0)
        .unwrap();
    world.set_constraint_gamma(h, Some(0.5)).unwrap();
    world.reset_constraint(h).unwrap();
    let hinge = h.get(&world).unwrap();
    assert!(hinge.limit().motor().is_none() && !hinge.limit().is_limited());
    // Default position: the world origin; default axis: +y.
    assert!((hinge.local_anchor2 - Vec3::ZERO).length() < 1e-6);
    assert!((hinge.local_axis2 - Vec3::Y).length() < 1e-6);
    assert!(world.constraint_log(h).unwrap().contains("γ override None"));
}

#[test]
fn a_weld_holds_a_settable_relative_orientation() {
    let mut world = World::with_capacity(4, 4).unwrap();
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let b = world.create_body(&BodyDef::default()).unwrap();
    let j = world
        .create_joint(b, None, kea::JointSpec::fixed(Vec3::ZERO))
        .unwrap();
    let target = kea::Quat::from_rotation_y(0.3);
    j.set_relative_orientation(&mut world, target).unwrap();
    for _ in 0..120 {
        world.step(1.0 / 60.0).unwrap();
    }
    let q = world.body(b).unwrap().orientation();
    assert!(q.dot(target).abs() > 1.0 - 1e-5, "{q} vs {target}");
    let stored = j.get(&world).unwrap().relative_orientation;
    assert!(stored.abs_diff_eq(target, 1e-6), "{stored} vs {target}");
    let e = j
        .set_relative_orientation(&mut world, kea::Quat::from_xyzw(0.0, 0.0, 0.0, 0.0))
        .unwrap_err();
    assert!(e.to_string().contains('q'));
}
