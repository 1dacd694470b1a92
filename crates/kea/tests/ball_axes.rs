//! A ball joint's limit axes kept per body (the guide's `MdtBSJointSetPrimaryAxis` /
//! `SetOrthogonalAxis`, with a body index): the cone is measured between the two bodies'
//! primary axes, so tilting the world's axis tilts where a hanging rod comes to rest.

mod common;

use common::world_on;
use kea::{BallJoint, BodyDef, JointHandle, JointSpec, Mat3, Real, SingleLimit, SolverMode, Vec3};

const CONE: Real = 0.2;
const TILT: Real = 0.5;

/// A 1 m rod of 1 kg hanging from the world at the origin on a ball joint, damped so that it
/// settles; its primary axis runs down the rod, the world's is tilted by `TILT` about z.
fn tilted_cone(mode: SolverMode) -> (kea::World, kea::BodyHandle, JointHandle<BallJoint>) {
    let mut w = world_on(mode, 2, 2);
    let rod = w
        .create_body(&BodyDef {
            position: Vec3::new(0.0, -0.5, 0.0),
            inertia: Mat3::from_diagonal(Vec3::new(1.0 / 12.0, 0.01, 1.0 / 12.0)),
            angular_damping: 0.5,
            ..BodyDef::default()
        })
        .unwrap();
    let j = w
        .create_joint(rod, None, JointSpec::ball(Vec3::ZERO))
        .unwrap();
    let world_axis = Vec3::new(TILT.sin(), -TILT.cos(), 0.0);
    j.set_primary_axis(&mut w, 0, -Vec3::Y).unwrap();
    j.set_primary_axis(&mut w, 1, world_axis).unwrap();
    let cone = &mut j.limits_mut(&mut w).unwrap().cone;
    cone.set_limits(SingleLimit::hard(-1.0, 0.0), SingleLimit::hard(CONE, 0.0))
        .unwrap();
    (w, rod, j)
}

#[test]
fn a_hanging_rod_rests_on_the_edge_of_a_cone_about_the_tilted_world_axis() {
    for mode in [
        SolverMode::Hybrid,
        SolverMode::Exact,
        SolverMode::Iterative,
        SolverMode::Split,
    ] {
        let (mut w, rod, j) = tilted_cone(mode);
        for _ in 0..600 {
            w.step(1.0 / 60.0).unwrap();
        }
        let down = (w.body(rod).unwrap().position()).normalize();
        let from_vertical = down.angle_between(-Vec3::Y);
        let from_axis = down.angle_between(j.limit_axis(&w, 1, false).unwrap());
        // Gravity pulls it to vertical; the cone keeps it within 0.2 rad of the axis tilted by
        // 0.5: it rests on the cone's edge, 0.3 rad out, on the tilted side.
        assert!(down.x > 0.0, "{mode:?}: on the tilted side: {down}");
        assert!(
            (from_vertical - (TILT - CONE)).abs() < 0.01,
            "{mode:?}: {from_vertical} rad from vertical"
        );
        assert!(
            (from_axis - CONE).abs() < 0.01,
            "{mode:?}: {from_axis} rad from the axis"
        );
        // Body 1's axis turned with the rod.
        let rod_axis = j.limit_axis(&w, 0, false).unwrap();
        assert!(
            (rod_axis - down).length() < 1e-3,
            "{mode:?}: {rod_axis} vs {down}"
        );
    }
}

#[test]
fn axes_read_back_and_bad_ones_are_refused_without_change() {
    let (mut w, _, j) = tilted_cone(SolverMode::Exact);
    let axis = j.limit_axis(&w, 1, false).unwrap();
    assert!((axis - Vec3::new(TILT.sin(), -TILT.cos(), 0.0)).length() < 1e-6);
    let o = j.limit_axis(&w, 1, true).unwrap();
    assert!(o.dot(axis).abs() < 1e-6, "kept ⊥ the primary axis: {o}");
    let before = *j.get(&w).unwrap();
    // Not perpendicular to that body's primary axis, not unit, a third body: refused,
    // nothing changed.
    let e = j
        .set_orthogonal_axis(&mut w, 1, Vec3::X)
        .unwrap_err()
        .to_string();
    assert!(e.contains("perpendicular") && e.contains("body 2"), "{e}");
    let e = j
        .set_orthogonal_axis(&mut w, 0, -Vec3::Y)
        .unwrap_err()
        .to_string();
    assert!(e.contains("perpendicular") && e.contains("body 1"), "{e}");
    assert!(j
        .set_orthogonal_axis(&mut w, 1, Vec3::new(0.0, 0.0, 2.0))
        .is_err());
    assert!(j.set_orthogonal_axis(&mut w, 2, Vec3::Z).is_err());
    let e = j
        .set_primary_axis(&mut w, 2, Vec3::X)
        .unwrap_err()
        .to_string();
    assert!(e.contains("body") && e.contains('2'), "{e}");
    assert_eq!(*j.get(&w).unwrap(), before);
    // A perpendicular one is kept, for either body.
    j.set_orthogonal_axis(&mut w, 1, Vec3::Z).unwrap();
    assert!((j.limit_axis(&w, 1, true).unwrap() - Vec3::Z).length() < 1e-6);
    j.set_orthogonal_axis(&mut w, 0, Vec3::Z).unwrap();
    assert!((j.limit_axis(&w, 0, true).unwrap() - Vec3::Z).length() < 1e-6);
}

/// Body 1's orthogonal axis is kept too (the guide's call with a body index) and sets where
/// the twist is zero: a hanging rod whose twist is held at zero by stops turns about its own
/// axis until its new orthogonal axis lies along body 2's, on every path.
#[test]
fn body_ones_orthogonal_axis_sets_the_twists_zero() {
    const TURN: Real = 0.4;
    for mode in [
        SolverMode::Hybrid,
        SolverMode::Exact,
        SolverMode::Iterative,
        SolverMode::Split,
    ] {
        let mut w = world_on(mode, 2, 2);
        let rod = w
            .create_body(&BodyDef {
                position: Vec3::new(0.0, -0.5, 0.0),
                inertia: Mat3::from_diagonal(Vec3::new(1.0 / 12.0, 0.01, 1.0 / 12.0)),
                angular_damping: 2.0,
                ..BodyDef::default()
            })
            .unwrap();
        let j = w
            .create_joint(rod, None, JointSpec::ball(Vec3::ZERO))
            .unwrap();
        j.set_limit_axes(&mut w, -Vec3::Y, Vec3::X).unwrap();
        // Turned by TURN about the (downward) primary axis: the twist now reads TURN.
        let turned = kea::Quat::from_axis_angle(-Vec3::Y, TURN) * Vec3::X;
        assert!(turned.dot(-Vec3::Y).abs() < 1e-6);
        j.set_orthogonal_axis(&mut w, 0, turned).unwrap();
        let read = j.limit_axis(&w, 0, true).unwrap();
        assert!((read - turned).length() < 1e-5, "{mode:?}: {read}");
        assert!((j.limit_axis(&w, 1, true).unwrap() - Vec3::X).length() < 1e-5);
        // Stops far off: one step at rest reads the twist as it stands.
        let twist = &mut j.limits_mut(&mut w).unwrap().twist;
        twist
            .set_limits(SingleLimit::hard(-3.0, 0.0), SingleLimit::hard(3.0, 0.0))
            .unwrap();
        w.step(1.0 / 60.0).unwrap();
        let first = j.limits_mut(&mut w).unwrap().twist.position();
        assert!(
            (first - TURN).abs() < 1e-3,
            "{mode:?}: the twist read {first}, not {TURN}"
        );
        let twist = &mut j.limits_mut(&mut w).unwrap().twist;
        twist
            .set_limits(SingleLimit::hard(-0.01, 0.0), SingleLimit::hard(0.01, 0.0))
            .unwrap();
        for _ in 0..600 {
            w.step(1.0 / 60.0).unwrap();
        }
        // The stops turned the rod about its axis by −TURN: body 1's orthogonal axis now
        // lies along body 2's (the world's x), and the twist reads (about) zero.
        let o1 = j.limit_axis(&w, 0, true).unwrap();
        let gap = o1.angle_between(Vec3::X);
        assert!(
            gap < 0.02,
            "{mode:?}: body 1's orthogonal axis {o1} is {gap} rad off"
        );
        let twist = j.limits_mut(&mut w).unwrap().twist.position();
        assert!(twist.abs() < 0.02, "{mode:?}: twist {twist}");
        let down = w.body(rod).unwrap().position().normalize();
        assert!(down.angle_between(-Vec3::Y) < 0.01, "{mode:?}: {down}");
    }
}
