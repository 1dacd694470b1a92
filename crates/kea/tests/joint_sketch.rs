//! `World::joint_sketch`: a joint's anchors, axes and limit range in world coordinates, checked
//! against the geometry of swinging and sliding bodies.

use kea::{BodyDef, JointRange, Quat, Real, SingleLimit, Vec3, World};

const DT: Real = 1.0 / 120.0;

fn body(world: &mut World, position: Vec3) -> kea::BodyHandle {
    world
        .create_body(&BodyDef {
            position,
            ..BodyDef::default()
        })
        .unwrap()
}

#[test]
fn a_swinging_hinge_shows_its_angle_turning_zero_onto_body_ones_reference() {
    let mut world = World::with_capacity(4, 16).unwrap();
    let arm = body(&mut world, Vec3::new(1.0, 0.0, 0.0));
    let h = world
        .create_joint(arm, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::Z))
        .unwrap();
    let lower = SingleLimit::hard(-1.2, 0.0);
    let upper = SingleLimit::hard(0.4, 0.0);
    h.limit_mut(&mut world)
        .unwrap()
        .set_limits(lower, upper)
        .unwrap();
    for _ in 0..40 {
        world.step(DT).unwrap();
    }
    let s = world.joint_sketch(h).unwrap().unwrap();
    assert_eq!(s.kind, "hinge");
    let axis = s.axes[0].unwrap();
    assert!((axis - Vec3::Z).length() < 1e-5, "{axis}");
    // The arm hangs from the origin: the anchors meet there.
    for a in s.anchors {
        assert!(a.length() < 2e-3, "anchor {a}");
    }
    let Some(JointRange::Angle { zero, stops, now }) = s.range else {
        panic!("a limited hinge has an angle range: {:?}", s.range);
    };
    assert_eq!(stops, (-1.2, 0.4));
    assert!(now < -0.1, "gravity swung the arm down: {now}");
    // Zero turned by the angle about the axis is where the arm's own reference points now.
    let arm_direction = world.body(arm).unwrap().position().normalize();
    let turned = Quat::from_axis_angle(axis, now) * zero;
    let reference = world.body(arm).unwrap().orientation() * h.get(&world).unwrap().local_ref1;
    assert!(
        (turned - reference).length() < 1e-3,
        "{turned} vs {reference}"
    );
    // The arm starts along +x with zero along its reference: its direction turns the same way.
    let expected = Quat::from_axis_angle(axis, now) * Vec3::X;
    assert!(
        (arm_direction - expected).length() < 2e-3,
        "{arm_direction} vs {expected}"
    );
}

#[test]
fn a_slider_shows_its_stops_along_its_axis_and_its_distance() {
    let mut world = World::with_capacity(4, 16).unwrap();
    world
        .update_settings(|s| s.gravity = Vec3::new(0.0, -9.81, 0.0))
        .unwrap();
    let carriage = body(&mut world, Vec3::new(0.0, 2.0, 0.0));
    let h = world
        .create_joint(
            carriage,
            None,
            kea::JointSpec::prismatic(Vec3::new(0.0, 2.0, 0.0), Vec3::Y),
        )
        .unwrap();
    let (lower, upper) = (SingleLimit::hard(-0.5, 0.0), SingleLimit::hard(0.5, 0.0));
    h.limit_mut(&mut world)
        .unwrap()
        .set_limits(lower, upper)
        .unwrap();
    for _ in 0..120 {
        world.step(DT).unwrap();
    }
    let s = world.joint_sketch(h).unwrap().unwrap();
    let axis = s.axes[0].unwrap();
    let Some(JointRange::Slide { stops, now }) = s.range else {
        panic!("a limited slider has a slide range: {:?}", s.range);
    };
    assert_eq!(stops, (-0.5, 0.5));
    // It fell to its lower stop; the anchors are apart by the distance along the axis.
    assert!((now + 0.5).abs() < 0.01, "{now}");
    let apart = (s.anchors[0] - s.anchors[1]).dot(axis);
    assert!((apart - now).abs() < 1e-4, "{apart} vs {now}");
    let y = world.body(carriage).unwrap().position().y;
    assert!((y - (2.0 + now)).abs() < 1e-4, "{y}");
}

#[test]
fn a_ball_joints_cone_keeps_body_ones_axis_within_the_half_angle() {
    let mut world = World::with_capacity(4, 16).unwrap();
    world
        .update_settings(|s| s.gravity = Vec3::new(0.0, -9.81, 0.0))
        .unwrap();
    // A bob hanging sideways from the origin, its cone about −y of half angle 0.5 rad.
    let bob = body(&mut world, Vec3::new(1.0, 0.0, 0.0));
    let h = world
        .create_joint(bob, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    h.set_limit_axes(&mut world, -Vec3::X, Vec3::Z).unwrap();
    let cone = SingleLimit::hard(0.5, 0.0);
    h.limits_mut(&mut world)
        .unwrap()
        .cone
        .set_limits(SingleLimit::hard(0.0, 0.0), cone)
        .unwrap();
    for _ in 0..240 {
        world.step(DT).unwrap();
    }
    let s = world.joint_sketch(h).unwrap().unwrap();
    let Some(JointRange::Cone {
        axis,
        half_angle,
        now,
    }) = s.range
    else {
        panic!("a ball joint with a cone limit has a cone: {:?}", s.range);
    };
    assert!((half_angle - 0.5).abs() < 1e-6);
    let angle = axis.dot(now).clamp(-1.0, 1.0).acos();
    // Gravity pulls the bob down, out of its sideways cone: it rests at the cone's edge.
    assert!((angle - 0.5).abs() < 0.05, "angle {angle}");
}

#[test]
fn a_contact_is_not_a_joint_and_a_free_joint_has_no_range() {
    let mut world = World::with_capacity(4, 16).unwrap();
    let a = body(&mut world, Vec3::ZERO);
    let b = body(&mut world, Vec3::new(0.0, 1.0, 0.0));
    let hinge = world
        .create_joint(
            a,
            Some(b),
            kea::JointSpec::hinge(Vec3::new(0.0, 0.5, 0.0), Vec3::X),
        )
        .unwrap();
    let s = world.joint_sketch(hinge).unwrap().unwrap();
    assert!(s.range.is_none());
    assert!((s.anchors[0] - s.anchors[1]).length() < 1e-6);
    let contact = world
        .create_contact(a, None, kea::Contact::default())
        .unwrap();
    assert!(world.joint_sketch(contact).is_err());
}
