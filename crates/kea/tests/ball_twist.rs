//! A ball joint's twist limit between bodies whose frames differ (a limb on a pelvis lying
//! across it): the twist is measured about the limb's own axis and the stop holds.

mod common;
use common::{world_on, PATHS};
use kea::{inertia, BodyDef, Quat, Real, SingleLimit, Vec3};

#[test]
fn twist_limit_holds_when_the_bodies_frames_differ() {
    for mode in PATHS {
        let mut world = world_on(mode, 4, 8);
        let box_inertia = inertia::solid_box(1.0, Vec3::new(0.3, 0.2, 0.1)).unwrap();
        // The parent is turned 90° about z and held still (disabled).
        let parent = world
            .create_body(&BodyDef {
                inertia: box_inertia,
                orientation: Quat::from_rotation_z(kea::PI_REAL / 2.0),
                enabled: false,
                ..Default::default()
            })
            .unwrap();
        let limb = world
            .create_body(&BodyDef {
                inertia: box_inertia,
                position: Vec3::new(0.0, -1.0, 0.0),
                ..Default::default()
            })
            .unwrap();
        let j = world
            .create_joint(limb, Some(parent), kea::JointSpec::ball(Vec3::ZERO))
            .unwrap();
        j.set_limit_axes(&mut world, -Vec3::Y, Vec3::X).unwrap();
        j.limits_mut(&mut world)
            .unwrap()
            .twist
            .set_limits(SingleLimit::hard(-0.5, 0.0), SingleLimit::hard(0.5, 0.0))
            .unwrap();
        for _ in 0..120 {
            world
                .body_mut(limb)
                .unwrap()
                .add_torque(Vec3::new(0.0, 2.0, 0.0))
                .unwrap();
            world.step(1.0 / 60.0).unwrap();
        }
        let twist = j.limits_mut(&mut world).unwrap().twist.position();
        let q = world.body(limb).unwrap().orientation();
        let (axis, angle) = q.to_axis_angle();
        let turned: Real = angle * axis.y.signum();
        eprintln!("{mode:?}: twist limit 0.5 rad, twist {twist}, the limb turned {turned} about y");
        assert!((twist.abs() - 0.5).abs() < 5e-3, "{mode:?}: twist {twist}");
        assert!(
            (turned.abs() - 0.5).abs() < 1e-2,
            "{mode:?}: turned {turned}"
        );
    }
}
