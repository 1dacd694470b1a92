//! Issue 12's reproductions in the dynamics layer, each under its own name: values that were
//! accepted and then broke every later step are refused by name, and an island that blows up is
//! quarantined while the rest of the world steps on.

mod common;
use common::world_on;
use kea::{
    BodyDef, BodyHandle, CustomConstraint, Jacobian, KeaError, Mat3, QuarantineReason, Real, Row,
    RowContext, RowWriter, SolverMode, SpeedLimits, Vec3, World, WorldDef,
};

fn refused_by_name(e: KeaError, arg: &str, value: &str) {
    let msg = e.to_string();
    assert!(msg.contains(arg), "`{msg}` does not name `{arg}`");
    assert!(msg.contains(value), "`{msg}` does not show `{value}`");
}

#[test]
fn a_mass_of_1e_minus_40_is_refused_by_name() {
    let mut w = World::with_capacity(2, 1).unwrap();
    let def = BodyDef {
        mass: 1.0e-40,
        ..Default::default()
    };
    refused_by_name(w.create_body(&def).unwrap_err(), "mass", "1e-40");
    assert_eq!(w.body_count(), 0);
    let b = w.create_body(&BodyDef::default()).unwrap();
    refused_by_name(
        w.body_mut(b).unwrap().set_mass(1.0e-40).unwrap_err(),
        "mass",
        "1e-40",
    );
    refused_by_name(
        w.body_mut(b).unwrap().set_mass(1.0e30).unwrap_err(),
        "mass",
        "1e30",
    );
    assert_eq!(w.body(b).unwrap().mass(), 1.0);
}

#[test]
fn an_inertia_of_1e30_is_refused_by_name() {
    let mut w = World::with_capacity(2, 1).unwrap();
    let def = BodyDef {
        inertia: Mat3::from_diagonal(Vec3::splat(1.0e30)),
        ..Default::default()
    };
    refused_by_name(w.create_body(&def).unwrap_err(), "inertia", "1e30");
    assert_eq!(w.body_count(), 0);
}

#[test]
fn inertias_at_both_ends_of_the_range_have_finite_inverses_and_step() {
    // The determinant of these overflows or underflows in f32; the check and the inverse work
    // on the tensor scaled to a unit diagonal.
    for scale in [1.0e-19, 1.0e19] {
        let mut w = World::with_capacity(2, 1).unwrap();
        let b = w
            .create_body(&BodyDef {
                mass: 1.0,
                inertia: Mat3::from_diagonal(Vec3::new(1.0, 2.0, 3.0) * scale),
                angular_velocity: Vec3::new(0.1, 0.2, 0.3),
                ..Default::default()
            })
            .unwrap();
        let inv = w.body(b).unwrap().inverse_inertia();
        assert!(inv.is_finite(), "{scale}: {inv}");
        let expected = 1.0 / scale;
        assert!(
            (inv.x_axis.x - expected).abs() <= 1e-4 * expected,
            "{scale}: {}",
            inv.x_axis.x
        );
        for _ in 0..10 {
            w.step(1.0 / 60.0).unwrap();
        }
        let body = w.body(b).unwrap();
        assert!(body.angular_velocity().is_finite() && body.orientation().is_finite());
    }
}

#[test]
fn with_capacity_usize_max_is_refused_by_name() {
    refused_by_name(
        World::with_capacity(usize::MAX, 1).unwrap_err(),
        "max_bodies",
        &usize::MAX.to_string(),
    );
    refused_by_name(
        World::with_capacity(1, usize::MAX).unwrap_err(),
        "max_constraints",
        &usize::MAX.to_string(),
    );
}

#[test]
fn a_capacity_of_1e9_is_refused_instead_of_aborting() {
    let e = World::new(WorldDef {
        max_bodies: 1_000_000_000,
        ..Default::default()
    })
    .unwrap_err();
    refused_by_name(e, "max_bodies", "1000000000");
    // The largest accepted capacity is stated and works.
    assert!(World::with_capacity(kea::MAX_CAPACITY, 1).is_ok());
}

/// A user constraint that asks two bodies to fly apart along x at 10⁹ m/s.
#[derive(Debug, Clone)]
struct Kick;

impl CustomConstraint for Kick {
    fn write_rows(&self, _ctx: &RowContext, out: &mut RowWriter<'_>) {
        out.push(
            Row::new(
                Jacobian::new(Vec3::X, Vec3::ZERO),
                Jacobian::new(-Vec3::X, Vec3::ZERO),
            )
            .with_target_velocity(1.0e9),
        );
    }
}

/// Two 1 kg bodies joined by a ball joint and by a user constraint driving them apart at
/// 10⁹ m/s (finite rows, so the step accepts them): the island runs away on its first step,
/// on every path.
fn blowing_island(w: &mut World) -> [BodyHandle; 2] {
    let body = |x: Real| BodyDef {
        position: Vec3::new(x, 0.0, 0.0),
        ..Default::default()
    };
    let a = w.create_body(&body(1.0)).unwrap();
    let b = w.create_body(&body(2.0)).unwrap();
    w.create_joint(a, Some(b), kea::JointSpec::ball(Vec3::new(1.5, 0.0, 0.0)))
        .unwrap();
    w.add_custom_constraint(a, Some(b), Kick).unwrap();
    [a, b]
}

#[test]
fn a_blown_island_is_quarantined_while_another_ball_keeps_falling_at_g() {
    let mut w = world_on(SolverMode::Iterative, 8, 8);
    let island = blowing_island(&mut w);
    let ball = w
        .create_body(&BodyDef {
            position: Vec3::new(50.0, 100.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    let g = w.settings().gravity.y;
    let dt: Real = 1.0 / 60.0;
    let mut frozen_at: Option<(u64, Vec<(Vec3, Vec3)>)> = None;
    for step in 1..=120u32 {
        let before: Vec<(Vec3, Vec3)> = island
            .iter()
            .map(|&h| {
                let b = w.body(h).unwrap();
                (b.position(), b.linear_velocity())
            })
            .collect();
        let stats = w.step(dt).unwrap();
        // The ball is in its own island and never notices: v = g t, exactly as free fall.
        let v = w.body(ball).unwrap().linear_velocity().y;
        let expected = g * dt * step as Real;
        assert!(
            (v - expected).abs() <= 1e-4 * expected.abs(),
            "step {step}: ball at {v}, free fall {expected}"
        );
        if stats.quarantined_bodies > 0 && frozen_at.is_none() {
            assert_eq!(stats.quarantined_bodies, 2);
            frozen_at = Some((w.step_count() - 1, before));
        }
        for &h in &island {
            let b = w.body(h).unwrap();
            assert!(
                b.position().is_finite() && b.linear_velocity().is_finite(),
                "step {step}: the island's state reached the world"
            );
        }
    }
    let (step, before) = frozen_at.expect("the redundant pair never blew up");
    // Reported by handles, with the step that failed; frozen where that step started.
    let report = w.quarantine_report();
    assert_eq!(report.len(), 1, "{report:?}");
    assert_eq!(report[0].step, step);
    let mut bodies = report[0].bodies.clone();
    bodies.sort();
    let mut expected = island.to_vec();
    expected.sort();
    assert_eq!(bodies, expected);
    assert!(matches!(
        report[0].reason,
        QuarantineReason::NonFinite | QuarantineReason::Runaway { .. }
    ));
    for (&h, &(p, v)) in island.iter().zip(&before) {
        let b = w.body(h).unwrap();
        assert!(b.is_quarantined() && !b.is_enabled());
        assert_eq!((b.position(), b.linear_velocity()), (p, v));
    }
    assert!(!w.body(ball).unwrap().is_quarantined());
    // Cleared: released and simulated again.
    assert_eq!(w.clear_quarantine(), 2);
    assert!(w.quarantine_report().is_empty());
    for &h in &island {
        let b = w.body(h).unwrap();
        assert!(!b.is_quarantined() && b.is_enabled());
    }
}

#[test]
fn a_runaway_island_is_quarantined_by_the_speed_limit() {
    // Exact path: a ball dropped with 30 m/s down under a 20 m/s limit is frozen at its start.
    for mode in common::PATHS {
        let mut w = world_on(mode, 4, 4);
        w.update_settings(|s| {
            s.speed_limits = SpeedLimits {
                linear: 20.0,
                angular: 1.0e4,
            }
        })
        .unwrap();
        let b = w
            .create_body(&BodyDef {
                linear_velocity: Vec3::new(0.0, -19.95, 0.0),
                ..Default::default()
            })
            .unwrap();
        let stats = w.step(0.01).unwrap();
        assert_eq!(stats.quarantined_bodies, 1, "{mode:?}");
        let body = w.body(b).unwrap();
        assert_eq!(body.position(), Vec3::ZERO);
        assert_eq!(body.linear_velocity(), Vec3::new(0.0, -19.95, 0.0));
        match w.quarantine_report()[0].reason {
            QuarantineReason::Runaway { linear, .. } => {
                assert!((linear - 20.0481).abs() < 1e-3, "{mode:?}: {linear}")
            }
            r => panic!("{mode:?}: {r:?}"),
        }
        // Bad limits are refused by name.
        let e = w
            .update_settings(|s| {
                s.speed_limits = SpeedLimits {
                    linear: -1.0,
                    angular: 1.0,
                }
            })
            .unwrap_err();
        refused_by_name(e, "speed_limits.linear", "-1");
    }
}

#[test]
fn an_anchor_of_3e38_is_refused_by_name_instead_of_hanging_the_exact_solver() {
    let mut w = world_on(SolverMode::Exact, 4, 4);
    let b = w.create_body(&BodyDef::default()).unwrap();
    let far = Vec3::new(3.0e38, 0.0, 0.0);
    refused_by_name(
        w.create_joint(b, None, kea::JointSpec::ball(far))
            .unwrap_err(),
        "anchor",
        "3e38",
    );
    refused_by_name(
        w.create_joint(b, None, kea::JointSpec::hinge(far, Vec3::Y))
            .unwrap_err(),
        "anchor",
        "3e38",
    );
    refused_by_name(
        w.body_mut(b).unwrap().set_position(far).unwrap_err(),
        "position",
        "3e38",
    );
    assert_eq!(w.constraint_count(), 0);
    // At the edge of the accepted range the step still finishes (and stays finite).
    let edge = Vec3::new(kea::error::MAX_COORDINATE, 0.0, 0.0);
    w.body_mut(b).unwrap().set_position(edge).unwrap();
    w.create_joint(b, None, kea::JointSpec::ball(edge + Vec3::Y))
        .unwrap();
    for _ in 0..10 {
        w.step(1.0 / 60.0).unwrap();
    }
    assert!(w.body(b).unwrap().position().is_finite());
}
