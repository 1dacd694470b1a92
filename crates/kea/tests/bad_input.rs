//! Bad input gets a clear error naming the argument and the value, and leaves the world exactly
//! as it was.

use kea::{
    BodyDef, BodyHandle, Contact, ContactParams, CustomConstraint, FrictionModel, Jacobian,
    KeaError, Mat3, Quat, Real, Row, RowContext, RowWriter, Vec3, World, WorldDef,
};

fn world_with_things() -> (World, BodyHandle) {
    let mut w = World::with_capacity(3, 3).unwrap();
    let b = w
        .create_body(&BodyDef {
            position: Vec3::new(0.0, 1.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    w.create_joint(b, None, kea::JointSpec::ball(Vec3::new(0.0, 2.0, 0.0)))
        .unwrap();
    w.step(0.01).unwrap();
    (w, b)
}

type Snapshot = (Vec<(BodyHandle, kea::Body)>, usize, f64, Vec3, Real, Real);

fn snapshot(w: &World) -> Snapshot {
    (
        w.bodies().map(|(h, b)| (h, b.clone())).collect(),
        w.constraint_count(),
        w.time(),
        w.settings().gravity,
        w.settings().epsilon,
        w.settings().gamma,
    )
}

/// Asserts the error message names `arg` and shows `value`, and the world did not change.
fn expect_err(w: &World, before: &Snapshot, e: KeaError, arg: &str, value: &str) {
    let msg = e.to_string();
    assert!(msg.contains(arg), "`{msg}` does not name `{arg}`");
    assert!(msg.contains(value), "`{msg}` does not show `{value}`");
    assert!(snapshot(w) == *before, "world changed after: {msg}");
}

#[test]
fn bad_body_definitions() {
    let (mut w, _) = world_with_things();
    let before = snapshot(&w);
    let cases: Vec<(BodyDef, &str, &str)> = vec![
        (
            BodyDef {
                mass: 0.0,
                ..Default::default()
            },
            "mass",
            "0",
        ),
        (
            BodyDef {
                mass: -2.0,
                ..Default::default()
            },
            "mass",
            "-2",
        ),
        (
            BodyDef {
                mass: Real::INFINITY,
                ..Default::default()
            },
            "mass",
            "inf",
        ),
        (
            BodyDef {
                position: Vec3::new(Real::NAN, 0.0, 0.0),
                ..Default::default()
            },
            "position",
            "NaN",
        ),
        (
            BodyDef {
                linear_velocity: Vec3::new(0.0, Real::INFINITY, 0.0),
                ..Default::default()
            },
            "linear_velocity",
            "inf",
        ),
        (
            BodyDef {
                inertia: Mat3::from_diagonal(Vec3::new(1.0, -1.0, 1.0)),
                ..Default::default()
            },
            "inertia",
            "positive definite",
        ),
        (
            BodyDef {
                inertia: Mat3::from_cols(
                    Vec3::new(1.0, 0.5, 0.0),
                    Vec3::new(0.0, 1.0, 0.0),
                    Vec3::Z,
                ),
                ..Default::default()
            },
            "inertia",
            "symmetric",
        ),
        (
            BodyDef {
                orientation: Quat::from_xyzw(0.0, 0.0, 0.0, 0.0),
                ..Default::default()
            },
            "orientation",
            "length 0",
        ),
        (
            BodyDef {
                orientation: Quat::from_xyzw(0.0, 0.0, 0.0, 2.0),
                ..Default::default()
            },
            "orientation",
            "length 2",
        ),
        (
            BodyDef {
                linear_damping: -1.0,
                ..Default::default()
            },
            "linear_damping",
            "-1",
        ),
        (
            BodyDef {
                fast_spin_axis: Some(Vec3::ZERO),
                ..Default::default()
            },
            "fast_spin_axis",
            "length 0",
        ),
    ];
    for (def, arg, value) in cases {
        let e = w.create_body(&def).unwrap_err();
        expect_err(&w, &before, e, arg, value);
    }
}

#[test]
fn bad_setters_change_nothing() {
    let (mut w, b) = world_with_things();
    let before = snapshot(&w);
    let e = w.body_mut(b).unwrap().set_mass(-1.0).unwrap_err();
    expect_err(&w, &before, e, "mass", "-1");
    let e = w
        .body_mut(b)
        .unwrap()
        .set_position(Vec3::new(0.0, Real::NAN, 0.0))
        .unwrap_err();
    expect_err(&w, &before, e, "position", "NaN");
    let e = w
        .body_mut(b)
        .unwrap()
        .set_orientation(Quat::from_xyzw(0.0, 0.0, 0.0, 0.0))
        .unwrap_err();
    expect_err(&w, &before, e, "orientation", "0");
    let e = w
        .body_mut(b)
        .unwrap()
        .add_force(Vec3::new(Real::NAN, 0.0, 0.0))
        .unwrap_err();
    expect_err(&w, &before, e, "force", "NaN");
    let e = w.body_mut(b).unwrap().set_inertia(Mat3::ZERO).unwrap_err();
    expect_err(&w, &before, e, "inertia", "positive definite");
    let e = w
        .update_settings(|s| s.gravity = Vec3::new(0.0, Real::NAN, 0.0))
        .unwrap_err();
    expect_err(&w, &before, e, "gravity", "NaN");
    let e = w.update_settings(|s| s.gamma = 1.5).unwrap_err();
    expect_err(&w, &before, e, "gamma", "1.5");
    let e = w.update_settings(|s| s.epsilon = -0.1).unwrap_err();
    expect_err(&w, &before, e, "epsilon", "-0.1");
    // A force whose total for the step would overflow: refused, the total kept as it was.
    let big = Vec3::new(0.0, 0.0, 0.75 * Real::MAX);
    w.body_mut(b).unwrap().add_force(big).unwrap();
    let total = w.body(b).unwrap().force();
    for e in [
        w.body_mut(b).unwrap().add_force(big).unwrap_err(),
        w.body_mut(b)
            .unwrap()
            .add_force_at_point(big, Vec3::ZERO)
            .unwrap_err(),
    ] {
        assert!(e.to_string().contains("force"), "{e}");
        assert_eq!(w.body(b).unwrap().force(), total);
    }
    w.body_mut(b).unwrap().add_torque(big).unwrap();
    let e = w.body_mut(b).unwrap().add_torque(big).unwrap_err();
    assert!(e.to_string().contains("torque"), "{e}");
    assert!(w.body(b).unwrap().torque().is_finite());
}

#[test]
fn bad_time_steps() {
    let (mut w, _) = world_with_things();
    let before = snapshot(&w);
    for (dt, shown) in [
        (0.0 as Real, "0"),
        (-0.01, "-0.01"),
        (Real::NAN, "NaN"),
        (Real::INFINITY, "inf"),
        // Below a nanosecond: a step reads subnormal numbers as zero (`kea::float_mode`).
        (1e-10, "1e-10"),
        (
            Real::MIN_POSITIVE / 4.0,
            &kea::error::format_real(Real::MIN_POSITIVE / 4.0),
        ),
    ] {
        let e = w.step(dt).unwrap_err();
        expect_err(&w, &before, e, "dt", shown);
    }
    // A subnormal mass would be a zero mass in a step: refused by name.
    let tiny = Real::MIN_POSITIVE / 4.0;
    assert!(tiny > 0.0 && !tiny.is_normal());
    let e = w
        .create_body(&BodyDef {
            mass: tiny,
            ..Default::default()
        })
        .unwrap_err();
    expect_err(&w, &before, e, "mass", &kea::error::format_real(tiny));
}

#[test]
fn bad_contacts() {
    let (mut w, b) = world_with_things();
    let before = snapshot(&w);
    let e = Contact::new(Vec3::ZERO, Vec3::ZERO, 0.0).unwrap_err();
    expect_err(&w, &before, e, "normal", "length 0");
    let e = Contact::new(Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0), 0.0).unwrap_err();
    expect_err(&w, &before, e, "normal", "length 2");
    let e = Contact::new(Vec3::ZERO, Vec3::Y, Real::NAN).unwrap_err();
    expect_err(&w, &before, e, "penetration", "NaN");
    let mut c = Contact::new(Vec3::ZERO, Vec3::Y, 0.0).unwrap();
    let e = c.set_direction(Some(Vec3::Y)).unwrap_err();
    assert!(e.to_string().contains("direction") && e.to_string().contains("perpendicular"));
    let bad = ContactParams {
        friction: [FrictionModel::Coulomb { mu: -0.5 }; 2],
        ..Default::default()
    };
    let e = c.set_params(bad).unwrap_err();
    expect_err(&w, &before, e, "friction[0]", "-0.5");
    let bad = ContactParams {
        restitution: Real::NAN,
        ..Default::default()
    };
    let e = c.set_params(bad).unwrap_err();
    expect_err(&w, &before, e, "restitution", "NaN");
    // A contact on a destroyed body.
    let other = w.create_body(&BodyDef::default()).unwrap();
    w.destroy_body(other).unwrap();
    let before = snapshot(&w);
    let e = w.create_contact(other, None, c).unwrap_err();
    expect_err(&w, &before, e, "body", "stale");
    let e = w.create_contact(b, Some(b), c).unwrap_err();
    expect_err(&w, &before, e, "body2", "same body");
}

#[test]
fn stale_and_foreign_handles() {
    let (mut w, b) = world_with_things();
    let (other_world, foreign) = world_with_things();
    let before = snapshot(&w);
    let e = w.body(foreign).unwrap_err();
    assert!(matches!(e, KeaError::ForeignHandle { .. }), "{e}");
    expect_err(
        &w,
        &before,
        e,
        "body",
        &format!("world {}", other_world.id()),
    );
    w.destroy_body(b).unwrap();
    assert_eq!(
        w.constraint_count(),
        0,
        "attached joint destroyed with its body"
    );
    let before = snapshot(&w);
    let e = w.body_mut(b).unwrap_err();
    expect_err(&w, &before, e, "body", "stale");
    // The slot is reused by a new body; the old handle stays stale.
    let b2 = w.create_body(&BodyDef::default()).unwrap();
    assert_eq!(b2.index(), b.index());
    assert!(w.body(b).is_err() && w.body(b2).is_ok());
}

#[test]
fn a_full_world_grows_and_zero_capacity_is_refused() {
    let mut w = World::with_capacity(2, 1).unwrap();
    let a = w.create_body(&BodyDef::default()).unwrap();
    let b = w.create_body(&BodyDef::default()).unwrap();
    let c = w.create_body(&BodyDef::default()).unwrap();
    assert_eq!(w.max_bodies(), 4, "doubled when full");
    w.create_joint(a, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    w.create_joint(b, Some(c), kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    assert_eq!(w.max_constraints(), 2);
    assert!(
        w.body(a).is_ok() && w.body(c).is_ok(),
        "handles survive the growth"
    );
    w.step(0.01).unwrap();
    w.reserve(100, 50);
    assert!(w.max_bodies() >= 100 && w.max_constraints() >= 50);
    let e = World::new(WorldDef {
        max_bodies: 0,
        ..Default::default()
    })
    .unwrap_err();
    assert!(e.to_string().contains("max_bodies"));
}

#[test]
fn constraint_state_rules() {
    let (mut w, b) = world_with_things();
    let j = w
        .create_joint(b, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    let before = snapshot(&w);
    let e = w.set_constraint_bodies(j, b, None).unwrap_err();
    expect_err(&w, &before, e, "set_constraint_bodies", "disable it first");
    let e = w.contact_mut(j.into()).unwrap_err();
    expect_err(&w, &before, e, "contact", "ball joint");
    w.set_constraint_enabled(j, false).unwrap();
    w.set_constraint_bodies(j, b, None).unwrap();
    w.destroy_constraint(j).unwrap();
    assert!(w.is_constraint_enabled(j).is_err());
}

#[derive(Debug, Clone)]
struct Broken;
impl CustomConstraint for Broken {
    fn write_rows(&self, _: &RowContext, out: &mut RowWriter<'_>) {
        out.push(
            Row::new(Jacobian::new(Vec3::X, Vec3::ZERO), Jacobian::ZERO).with_error(Real::NAN),
        );
    }
}

#[test]
fn a_custom_constraint_writing_nan_fails_the_step_cleanly() {
    let (mut w, b) = world_with_things();
    w.add_custom_constraint(b, None, Broken).unwrap();
    let before = snapshot(&w);
    let e = w.step(0.01).unwrap_err();
    expect_err(&w, &before, e, "rows", "xi");
}

#[test]
fn a_failed_step_commits_neither_waking_nor_contact_state() {
    // A sleeping box with a persistent contact, touched by an awake ball through a contact,
    // and a broken custom constraint: the step fails, and nothing may have changed.
    let mut w = World::with_capacity(4, 8).unwrap();
    w.update_settings(|s| {
        s.dem = kea::DemSettings {
            mode: kea::DemMode::PartitionAutoDisable,
            alive_window: 0.0,
            ..Default::default()
        }
    })
    .unwrap();
    let resting = w
        .create_body(&BodyDef {
            position: Vec3::new(0.0, 0.5, 0.0),
            ..Default::default()
        })
        .unwrap();
    let ground = Contact::new(Vec3::ZERO, Vec3::Y, 0.0).unwrap();
    let support = w.create_contact(resting, None, ground).unwrap();
    w.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    w.step(0.01).unwrap();
    assert!(w.body(resting).unwrap().is_sleeping());
    let ball = w
        .create_body(&BodyDef {
            position: Vec3::new(0.0, 1.5, 0.0),
            ..Default::default()
        })
        .unwrap();
    w.create_contact(
        ball,
        Some(resting),
        Contact::new(Vec3::new(0.0, 1.0, 0.0), Vec3::Y, 0.0).unwrap(),
    )
    .unwrap();
    w.add_custom_constraint(ball, None, Broken).unwrap();
    let before = snapshot(&w);
    let contact_before = *w.contact(support).unwrap();
    assert!(w.step(0.01).is_err());
    assert!(snapshot(&w) == before);
    assert!(
        w.body(resting).unwrap().is_sleeping(),
        "a failed step woke a body"
    );
    assert_eq!(*w.contact(support).unwrap(), contact_before);
}
