//! A joint's anchor and axis set after it was made (`JointHandle::set_position`,
//! `JointHandle::set_axis`): nothing jumps, the joint then holds about its new anchor and axis,
//! and a refusal changes nothing.

use kea::{BodyDef, BodyHandle, Mat3, Real, SingleLimit, Vec3, World};

fn world() -> World {
    let mut w = World::with_capacity(4, 8).unwrap();
    w.update_settings(|s| s.gravity = Vec3::new(0.0, -9.81, 0.0))
        .unwrap();
    w
}

fn rod(w: &mut World) -> BodyHandle {
    w.create_body(&BodyDef {
        mass: 1.0,
        inertia: Mat3::from_diagonal(Vec3::new(0.1, 0.02, 0.1)),
        position: Vec3::new(0.0, -0.5, 0.0),
        ..BodyDef::default()
    })
    .unwrap()
}

fn pose(w: &World, b: BodyHandle) -> (Vec3, kea::Quat) {
    let body = w.body(b).unwrap();
    (body.position(), body.orientation())
}

/// Where a point fixed on body `b` (given in its frame) is in the world.
fn on_body(w: &World, b: BodyHandle, local: Vec3) -> Vec3 {
    let (p, q) = pose(w, b);
    p + q * local
}

#[test]
fn a_hinge_moved_to_a_new_anchor_swings_about_it_without_a_jump() {
    let mut w = world();
    let b = rod(&mut w);
    let h = w
        .create_joint(b, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::Z))
        .unwrap();
    w.body_mut(b)
        .unwrap()
        .set_linear_velocity(Vec3::new(1.0, 0.0, 0.0))
        .unwrap();
    for _ in 0..30 {
        w.step(1.0 / 120.0).unwrap();
    }
    let angle = h.get(&w).unwrap().angle();
    let before = pose(&w, b);
    // The body's own centre becomes the pivot: the rod will turn about its middle.
    let centre = before.0;
    h.set_position(&mut w, centre).unwrap();
    assert_eq!(pose(&w, b), before, "setting the anchor moved nothing");
    assert!(
        w.joint_error() < 1e-5,
        "the joint holds where the bodies are"
    );
    assert_eq!(h.get(&w).unwrap().angle(), angle, "the angle is kept");
    for _ in 0..120 {
        w.step(1.0 / 120.0).unwrap();
    }
    // The centre stays put (gravity pulls at the pivot now: no torque).
    let moved = w.body(b).unwrap().position() - centre;
    assert!(moved.length() < 1e-3, "the centre moved by {moved}");
    assert!(w.joint_error() < 1e-4);
}

#[test]
fn a_hinge_turned_to_a_new_axis_turns_only_about_it() {
    let mut w = world();
    w.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let b = rod(&mut w);
    let h = w
        .create_joint(b, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::Z))
        .unwrap();
    h.limit_mut(&mut w)
        .unwrap()
        .set_limits(SingleLimit::hard(-2.0, 0.0), SingleLimit::hard(2.0, 0.0))
        .unwrap();
    let before = pose(&w, b);
    h.set_axis(&mut w, Vec3::Y).unwrap();
    assert_eq!(pose(&w, b), before, "setting the axis moved nothing");
    assert_eq!(
        h.get(&w).unwrap().angle(),
        0.0,
        "the angle starts at 0 about the new axis"
    );
    assert!(
        h.get(&w).unwrap().limit().is_limited(),
        "the limits are kept"
    );
    // A spin about x and y: only the y part survives the joint.
    w.body_mut(b)
        .unwrap()
        .set_angular_velocity(Vec3::new(2.0, 1.0, 0.0))
        .unwrap();
    for _ in 0..60 {
        w.step(1.0 / 120.0).unwrap();
    }
    let spin = w.body(b).unwrap().angular_velocity();
    assert!(spin.x.abs() < 1e-3 && spin.z.abs() < 1e-3, "{spin}");
    assert!(spin.y.abs() > 0.5, "{spin}");
    assert!((h.get(&w).unwrap().angle() - spin.y * 0.5).abs() < 0.05);
    // The anchor stays on the world's point.
    assert!(on_body(&w, b, Vec3::new(0.0, 0.5, 0.0)).length() < 1e-3);
}

#[test]
fn a_prismatic_joint_turned_to_a_new_axis_slides_along_it_and_keeps_its_travel_when_moved() {
    let mut w = world();
    let b = rod(&mut w);
    let j = w
        .create_joint(b, None, kea::JointSpec::prismatic(Vec3::ZERO, Vec3::X))
        .unwrap();
    // Along x gravity does nothing; turned to the diagonal of x and −y it slides down it.
    let axis = Vec3::new(1.0, -1.0, 0.0).normalize();
    j.set_axis(&mut w, axis).unwrap();
    for _ in 0..60 {
        w.step(1.0 / 60.0).unwrap();
    }
    let v = w.body(b).unwrap().linear_velocity();
    assert!((v.normalize() - axis).length() < 1e-3, "slides along {v}");
    let expected = 9.81 * axis.dot(Vec3::new(0.0, -1.0, 0.0));
    assert!(
        (v.length() - expected).abs() < 0.02 * expected,
        "{} vs {expected}",
        v.length()
    );
    // Moving its anchor keeps the travel it reads: the next step reads as without the move.
    let mut control = w.clone();
    let at = w.body(b).unwrap().position();
    j.set_position(&mut w, at + Vec3::new(0.0, 0.0, 0.3))
        .unwrap();
    w.step(1.0 / 60.0).unwrap();
    control.step(1.0 / 60.0).unwrap();
    let (now, then) = (
        j.get(&w).unwrap().distance(),
        j.get(&control).unwrap().distance(),
    );
    assert!(now > 1.0, "it slid: {now}");
    assert!(
        (now - then).abs() < 1e-4,
        "travel {now}, without the move {then}"
    );
    assert!(w.joint_error() < 1e-3);
}

#[test]
fn universal_and_linear2_axes_turn_and_bad_requests_change_nothing() {
    let mut w = world();
    let b = rod(&mut w);
    let c = w
        .create_body(&BodyDef {
            position: Vec3::new(0.0, -1.5, 0.0),
            ..BodyDef::default()
        })
        .unwrap();
    let u = w
        .create_joint(
            b,
            None,
            kea::JointSpec::universal(Vec3::ZERO, Vec3::X, Vec3::Z),
        )
        .unwrap();
    let l = w
        .create_joint(
            c,
            Some(b),
            kea::JointSpec::linear2(Vec3::new(0.0, -1.5, 0.0), Vec3::Y),
        )
        .unwrap();
    u.set_axis(&mut w, Vec3::new(1.0, 0.0, 1.0).normalize())
        .unwrap();
    l.set_axis(&mut w, Vec3::X).unwrap();
    assert!(w.joint_error() < 1e-5);
    for _ in 0..60 {
        w.step(1.0 / 60.0).unwrap();
    }
    assert!(w.joint_error() < 1e-3, "{}", w.joint_error());
    // Refusals, each naming what is wrong and changing nothing.
    let ball = w
        .create_joint(c, None, kea::JointSpec::ball(Vec3::new(0.0, -1.5, 0.0)))
        .unwrap();
    let snapshot = format!("{:?}", (u.get(&w).unwrap(), ball.get(&w).unwrap()));
    let e = u.set_axis(&mut w, Vec3::new(2.0, 0.0, 0.0)).unwrap_err();
    assert!(e.to_string().contains("axis"), "{e}");
    let e = ball.set_axis(&mut w, Vec3::X).unwrap_err();
    assert!(e.to_string().contains("set_axis"), "{e}");
    let e = u
        .set_position(&mut w, Vec3::new(Real::NAN, 0.0, 0.0))
        .unwrap_err();
    assert!(e.to_string().contains("anchor"), "{e}");
    assert_eq!(
        snapshot,
        format!("{:?}", (u.get(&w).unwrap(), ball.get(&w).unwrap()))
    );
}
