//! The guide's drop and hinge tutorials (`examples/drop.rs`, `examples/hinge.rs`) as physics
//! checks, on every path a user can force: the dropped ball follows the closed form and a box
//! dropped on the ground comes to rest at its half height; the hinged door turns at its motor's
//! speed and stops at its limits.

mod common;

use common::{box_plane_contacts, clear_contacts, world_on};
use kea::{inertia, BodyDef, ContactParams, Real, SingleLimit, SolverMode, Vec3};

const MODES: [SolverMode; 4] = [
    SolverMode::Hybrid,
    SolverMode::Exact,
    SolverMode::Iterative,
    SolverMode::Split,
];

#[test]
fn the_drop_tutorials_ball_falls_on_the_closed_form() {
    // drop.c: a 1 kg ball released at 10 m, g = 9.8, steps of 0.03 s. The semi-implicit step
    // is below ½gt² by exactly ½·g·h·t.
    let (g, h): (Real, Real) = (9.8, 0.03);
    for mode in MODES {
        let mut w = world_on(mode, 1, 1);
        w.update_settings(|s| s.gravity = Vec3::new(0.0, -g, 0.0))
            .unwrap();
        let ball = w
            .create_body(&BodyDef {
                position: Vec3::new(0.0, 10.0, 0.0),
                inertia: inertia::solid_sphere(1.0, 0.5).unwrap(),
                ..BodyDef::default()
            })
            .unwrap();
        for n in 1..=50 {
            w.step(h).unwrap();
            let t = n as Real * h;
            let b = w.body(ball).unwrap();
            let expected = 10.0 - 0.5 * g * t * t - 0.5 * g * h * t;
            assert!(
                (b.position().y - expected).abs() < 1e-4,
                "{mode:?}, t {t}: y {} vs {expected}",
                b.position().y
            );
            assert!((b.linear_velocity().y + g * t).abs() < 1e-4, "{mode:?}");
        }
    }
}

#[test]
fn a_box_dropped_on_the_ground_rests_at_its_half_height() {
    let half = Vec3::new(0.3, 0.2, 0.25);
    for mode in MODES {
        let mut w = world_on(mode, 1, 16);
        let b = w
            .create_body(&BodyDef {
                position: Vec3::new(0.0, 1.5, 0.0),
                orientation: kea::Quat::from_rotation_z(0.2),
                inertia: inertia::solid_box(1.0, half).unwrap(),
                ..BodyDef::default()
            })
            .unwrap();
        let mut contacts = Vec::new();
        for _ in 0..240 {
            clear_contacts(&mut w, &mut contacts);
            box_plane_contacts(
                &mut w,
                b,
                half,
                Vec3::Y,
                0.0,
                0.05,
                ContactParams::default(),
                None,
                &mut contacts,
            );
            w.step(1.0 / 60.0).unwrap();
        }
        let body = w.body(b).unwrap();
        let (y, v) = (body.position().y, body.linear_velocity().length());
        let upright = (body.orientation() * Vec3::Y).angle_between(Vec3::Y);
        eprintln!("{mode:?}: rests at y {y}, speed {v}, {upright} rad from flat");
        // On its face, the contact spring's sink (millimetres) below its half height.
        assert!(upright < 0.01, "{mode:?}: it came to rest on its face");
        assert!(y < half.y + 1e-3 && y > half.y - 0.005, "{mode:?}: y {y}");
        assert!(v < 0.01, "{mode:?}: still moving at {v}");
    }
}

/// The hinge tutorial's door: 2 kg, 1 m × 1 m, hinged to the world along its edge about x at
/// the origin, stops at −0.75 and 1.2 rad, a motor at `speed` rad/s and at most 30 N·m.
fn door(mode: SolverMode, speed: Real) -> (kea::World, kea::JointHandle<kea::Hinge>) {
    let mut w = world_on(mode, 1, 1);
    let body = w
        .create_body(&BodyDef {
            mass: 2.0,
            position: Vec3::new(0.0, 0.0, 0.5),
            inertia: inertia::solid_box(2.0, Vec3::new(0.5, 0.05, 0.5)).unwrap(),
            ..BodyDef::default()
        })
        .unwrap();
    let hinge = w
        .create_joint(body, None, kea::JointSpec::hinge(Vec3::ZERO, Vec3::X))
        .unwrap();
    let limit = hinge.limit_mut(&mut w).unwrap();
    limit
        .set_limits(SingleLimit::hard(-0.75, 0.0), SingleLimit::hard(1.2, 0.0))
        .unwrap();
    limit.set_motor(speed, 30.0).unwrap();
    (w, hinge)
}

#[test]
fn the_hinge_tutorials_door_turns_at_its_motors_speed_and_stops_at_its_limits() {
    // Gravity's torque on the door is at most m·g·0.5 = 9.8 N·m, under the motor's 30 N·m:
    // it turns at 2 rad/s until a stop, and rests there.
    for mode in MODES {
        for (speed, stop) in [(2.0, 1.2), (-2.0, -0.75)] {
            let (mut w, hinge) = door(mode, speed);
            let h: Real = 1.0 / 60.0;
            let mut at_stop = None;
            for n in 1..=120 {
                w.step(h).unwrap();
                let l = hinge.get(&w).unwrap().limit();
                let (angle, rate) = (l.position(), l.velocity());
                assert!(
                    (-0.75 - 0.02..=1.2 + 0.02).contains(&angle),
                    "{mode:?}: past a stop at {angle}"
                );
                if at_stop.is_none() && (angle - stop).abs() < 0.02 {
                    at_stop = Some(n);
                }
                // Travelling (after a few steps to reach speed, before the stop): at the
                // motor's speed.
                if n > 5 && at_stop.is_none() {
                    assert!(
                        (rate - speed).abs() < 0.02 * speed.abs(),
                        "{mode:?}, step {n}: {rate} rad/s, motor {speed}"
                    );
                }
            }
            let reached = at_stop.expect("reached its stop") as Real * h;
            // At 2 rad/s it covers the stop's angle in |stop|/2 s.
            assert!(
                (reached - stop.abs() / 2.0).abs() < 0.1,
                "{mode:?}: at the stop after {reached} s"
            );
            let l = hinge.get(&w).unwrap().limit();
            assert!(
                (l.position() - stop).abs() < 0.01 && l.velocity().abs() < 0.05,
                "{mode:?}: rests at {} ({} rad/s), stop {stop}",
                l.position(),
                l.velocity()
            );
        }
    }
}
