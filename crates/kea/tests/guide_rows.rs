//! Rows of the guide that had code but no physics test (issue 35, item 6), each on every path a
//! user can force (hybrid, exact, iterative, split) and, through CI, in f32 and f64:
//!
//! - a step size changed every step (a falling body against the closed form, a pendulum's
//!   energy);
//! - a free body with a non-diagonal inertia tensor (world angular momentum and energy kept);
//! - angular damping (`ω(t) = ω₀ e^{−ct}`, `c = d/I`);
//! - the fixed-path-fixed-orientation joint holds its orientation while its path moves;
//! - a reset joint of every kind is the joint its default table describes;
//! - a joint moved to other bodies constrains the new pair;
//! - a disabled joint frees its body and, enabled again, holds it;
//! - the user's auto-disable thresholds and alive window decide when a body sleeps.
//!
//! The drop and hinge tutorials' physics live in `tutorials.rs`.

mod common;

use common::world_on;
use kea::{
    inertia, BodyDef, BodyHandle, DemMode, DemSettings, JointKind, JointSpec, Mat3, Quat, Real,
    SolverMode, Vec3, World,
};

const G: Real = 9.81;
const MODES: [SolverMode; 4] = [
    SolverMode::Hybrid,
    SolverMode::Exact,
    SolverMode::Iterative,
    SolverMode::Split,
];
/// Step sizes taken in turn, one per step.
const STEPS: [Real; 5] = [1.0 / 30.0, 1.0 / 60.0, 1.0 / 45.0, 1.0 / 120.0, 1.0 / 90.0];

/// Relative round-off allowance of the precision in use.
fn eps() -> Real {
    if common::F64 {
        1e-9
    } else {
        1e-5
    }
}

#[test]
fn a_step_size_changed_every_step_keeps_a_falling_body_on_the_closed_form() {
    for mode in MODES {
        let mut w = world_on(mode, 1, 1);
        let b = w
            .create_body(&BodyDef {
                position: Vec3::new(0.0, 10.0, 0.0),
                ..BodyDef::default()
            })
            .unwrap();
        let (mut t, mut squares): (f64, f64) = (0.0, 0.0);
        for k in 0..100 {
            let h = STEPS[k % STEPS.len()];
            w.step(h).unwrap();
            t += kea::math::wide(h);
            squares += kea::math::wide(h).powi(2);
            let body = w.body(b).unwrap();
            let (y, v) = (
                kea::math::wide(body.position().y),
                kea::math::wide(body.linear_velocity().y),
            );
            // The speed is exact: −g t, whatever the steps.
            let g = kea::math::wide(G);
            assert!(
                (v + g * t).abs() < 10.0 * kea::math::wide(eps()) * (1.0 + g * t),
                "{mode:?}, step {k}: v {v}, −g t {}",
                -g * t
            );
            // The height: the closed form 10 − ½ g t², less the semi-implicit step's own
            // ½ g Σ h² (each step moves at its end speed), exactly.
            let closed = 10.0 - 0.5 * g * t * t;
            let stepped = closed - 0.5 * g * squares;
            assert!(
                (y - stepped).abs() < 100.0 * kea::math::wide(eps()),
                "{mode:?}, step {k}: y {y}, closed form {closed}, less ½gΣh² {stepped}"
            );
        }
    }
}

/// A 1 m, 1 kg rod hinged at one end about z at the origin, lying along +x.
fn hinged_rod(mode: SolverMode) -> World {
    let mut w = world_on(mode, 1, 1);
    let rod = w
        .create_body(&BodyDef {
            position: Vec3::new(0.5, 0.0, 0.0),
            inertia: inertia::solid_box(1.0, Vec3::new(0.5, 0.02, 0.02)).unwrap(),
            ..BodyDef::default()
        })
        .unwrap();
    w.create_joint(rod, None, JointSpec::hinge(Vec3::ZERO, Vec3::Z))
        .unwrap();
    w
}

fn energy(w: &World) -> Real {
    w.kinetic_energy()
        + w.bodies()
            .map(|(_, b)| b.mass() * G * b.position().y)
            .sum::<Real>()
}

/// A hinged rod released horizontal stepped for 10 s at steps taken in turn from `steps`:
/// the largest rise of its energy and its change at the end, as fractions of its swing's.
fn rod_energy(mode: SolverMode, steps: &[Real]) -> (Real, Real) {
    let mut w = hinged_rod(mode);
    let e0 = energy(&w);
    let mut rise: Real = 0.0;
    let (mut t, mut k) = (0.0, 0);
    while t < 10.0 {
        let h = steps[k % steps.len()];
        let stats = w.step(h).unwrap();
        assert!(stats.solver.is_clean(), "{mode:?}: {:?}", stats.solver);
        rise = rise.max(energy(&w) - e0);
        t += h;
        k += 1;
    }
    let swing = 0.5 * G;
    (rise / swing, (energy(&w) - e0) / swing)
}

#[test]
fn a_step_size_changed_every_step_keeps_a_pendulums_energy() {
    // A step size changed every step does as well as fixed steps of the sizes it runs
    // between (1/30 to 1/120 s): its energy's change lies between theirs. Measured (f32),
    // varied / 1/30 s / 1/120 s, change after 10 s: hybrid (reduced, RK4) −0.000% each;
    // exact −32% / −60% / −6.4%; iterative / split in the note. On the default routing the
    // rod steps in reduced coordinates and keeps VALIDATION's bounds whatever the steps; the
    // exact path's loss at large steps (one linearisation a step) is left to issue 36.
    for mode in MODES {
        let (rise, change) = rod_energy(mode, &STEPS);
        let (coarse_rise, coarse) = rod_energy(mode, &[1.0 / 30.0]);
        let (fine_rise, fine) = rod_energy(mode, &[1.0 / 120.0]);
        eprintln!(
            "{mode:?}: pendulum, steps changed every step: rise {:.3}%, {:.3}% after 10 s (fixed 1/30 s: {:.3}%, {:.3}%; 1/120 s: {:.3}%, {:.3}%)",
            rise * 100.0,
            change * 100.0,
            coarse_rise * 100.0,
            coarse * 100.0,
            fine_rise * 100.0,
            fine * 100.0
        );
        let (low, high) = (coarse.min(fine), coarse.max(fine));
        assert!(
            change > low - 0.002 && change < high + 0.002,
            "{mode:?}: {change} outside the fixed steps' {low}..{high}"
        );
        assert!(
            rise < coarse_rise.max(fine_rise) + 0.002,
            "{mode:?}: rose {rise}"
        );
        if mode == SolverMode::Hybrid {
            assert!(rise < 0.005 && change > -0.02, "{mode:?}: {rise}, {change}");
        }
    }
}

#[test]
fn a_free_body_with_a_non_diagonal_inertia_keeps_its_momentum_and_energy() {
    // Principal moments 0.5, 1 and 1.5 kg·m², turned off the body's axes.
    let turn = Mat3::from_quat(Quat::from_axis_angle(
        Vec3::new(1.0, 2.0, 0.5).normalize(),
        0.7,
    ));
    let inertia = turn * Mat3::from_diagonal(Vec3::new(0.5, 1.0, 1.5)) * turn.transpose();
    assert!(inertia.x_axis.y.abs() > 0.1, "off-diagonal");
    for mode in MODES {
        let mut w = world_on(mode, 1, 1);
        w.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
        let b = w
            .create_body(&BodyDef {
                inertia,
                orientation: Quat::from_axis_angle(Vec3::new(0.3, -1.0, 0.2).normalize(), 1.1),
                angular_velocity: Vec3::new(1.0, 2.0, -1.5),
                ..BodyDef::default()
            })
            .unwrap();
        let (l0, e0) = {
            let body = w.body(b).unwrap();
            (body.angular_momentum(), body.kinetic_energy())
        };
        let (mut worst_l, mut worst_e): (Real, Real) = (0.0, 0.0);
        for _ in 0..600 {
            w.step(1.0 / 60.0).unwrap();
            let body = w.body(b).unwrap();
            worst_l = worst_l.max((body.angular_momentum() - l0).length() / l0.length());
            worst_e = worst_e.max((body.kinetic_energy() - e0).abs() / e0);
        }
        eprintln!("{mode:?}: |ΔL|/|L| ≤ {worst_l:.2e}, |ΔE|/E ≤ {worst_e:.2e} over 10 s");
        let momentum_bound = if common::F64 { 1e-6 } else { 1e-4 };
        assert!(
            worst_l < momentum_bound,
            "{mode:?}: momentum drifted {worst_l}"
        );
        assert!(worst_e < 1e-3, "{mode:?}: energy drifted {worst_e}");
    }
}

#[test]
fn angular_damping_decays_the_spin_exponentially() {
    // A 1 kg ball of radius 0.5 m (I = 0.1 kg·m²) with d = 0.05 N·m·s: c = d/I = 0.5 /s.
    let (d, i, w0) = (0.05, 0.1, 4.0);
    for mode in MODES {
        let mut w = world_on(mode, 1, 1);
        w.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
        let b = w
            .create_body(&BodyDef {
                inertia: inertia::solid_sphere(1.0, 0.5).unwrap(),
                angular_velocity: Vec3::new(0.0, 0.0, w0),
                angular_damping: d,
                ..BodyDef::default()
            })
            .unwrap();
        let h: Real = 1.0 / 60.0;
        for n in 1..=180 {
            w.step(h).unwrap();
            let t = n as Real * h;
            let expected = w0 * (-(d / i) * t).exp();
            let spin = w.body(b).unwrap().angular_velocity();
            assert!(
                (spin.z - expected).abs() < 0.01 * expected,
                "{mode:?}, t = {t}: ω {} vs ω₀e^(−ct) {expected}",
                spin.z
            );
            assert!(spin.x.abs() + spin.y.abs() < 1e-6, "{mode:?}: {spin}");
        }
    }
}

#[test]
fn a_fixed_path_fixed_orientation_joint_holds_its_orientation_while_the_path_moves() {
    let q0 = Quat::from_axis_angle(Vec3::new(1.0, 1.0, 0.0).normalize(), 0.6);
    for mode in MODES {
        let mut w = world_on(mode, 1, 1);
        // Held 0.3 m off its centre: gravity and the path's swings both pull it round.
        let b = w
            .create_body(&BodyDef {
                orientation: q0,
                inertia: inertia::solid_box(1.0, Vec3::new(0.4, 0.1, 0.2)).unwrap(),
                ..BodyDef::default()
            })
            .unwrap();
        let anchor = Vec3::new(0.3, 0.0, 0.0);
        let j = w
            .create_joint(b, None, JointSpec::fixed_path(anchor, true))
            .unwrap();
        let local = q0.inverse() * anchor;
        let h: Real = 1.0 / 60.0;
        let (mut worst_turn, mut worst_gap): (Real, Real) = (0.0, 0.0);
        // A circle of radius 0.5 m in the x-y plane, one turn in 2 s.
        let pi = std::f32::consts::PI as Real;
        let path_at = |t: Real| anchor + Vec3::new((pi * t).cos() - 1.0, (pi * t).sin(), 0.0) * 0.5;
        for n in 1..=240 {
            // Where the path is at the step's start, and its velocity: it carries the point
            // through the step.
            let t = (n - 1) as Real * h;
            let speed = Vec3::new(-(pi * t).sin(), (pi * t).cos(), 0.0) * (0.5 * pi);
            j.set_path(&mut w, path_at(t), speed).unwrap();
            w.step(h).unwrap();
            let path = path_at(t + h);
            let body = w.body(b).unwrap();
            worst_turn = worst_turn.max(body.orientation().angle_between(q0));
            worst_gap = worst_gap.max((body.point_to_world(local) - path).length());
        }
        eprintln!("{mode:?}: turned at most {worst_turn:.2e} rad, {worst_gap:.2e} m off the path");
        assert!(worst_turn < 1e-3, "{mode:?}: turned {worst_turn} rad");
        assert!(worst_gap < 0.01, "{mode:?}: {worst_gap} m off the path");
    }
}

/// A body off the origin, turned and moving, as the first body of every joint below.
fn moving_body() -> BodyDef {
    BodyDef {
        position: Vec3::new(0.4, -0.7, 0.25),
        orientation: Quat::from_axis_angle(Vec3::new(0.2, 1.0, -0.3).normalize(), 0.8),
        linear_velocity: Vec3::new(0.3, 0.0, 0.2),
        angular_velocity: Vec3::new(0.5, -0.2, 0.1),
        inertia: inertia::solid_box(1.0, Vec3::new(0.3, 0.2, 0.1)).unwrap(),
        ..BodyDef::default()
    }
}

/// Every body's pose and velocities, to compare two runs.
fn states(w: &World) -> Vec<[Vec3; 3]> {
    w.bodies()
        .map(|(_, b)| {
            let q = b.orientation();
            [
                b.position(),
                Vec3::new(q.x, q.y, q.z) * q.w.signum(),
                b.angular_velocity() + b.linear_velocity() * 10.0,
            ]
        })
        .collect()
}

/// A world holding `spec` (made with odd settings, then reset) and one holding `default` (the
/// reset table's joint, made fresh) step the same bits; returns the reset world.
fn reset_matches<J: JointKind>(
    mode: SolverMode,
    odd: JointSpec<J>,
    default: JointSpec<J>,
    wheel: bool,
) -> World {
    let make = |spec: JointSpec<J>, reset: bool| {
        let mut w = world_on(mode, 2, 2);
        let b1 = w.create_body(&moving_body()).unwrap();
        let b2 = wheel.then(|| {
            w.create_body(&BodyDef {
                position: Vec3::new(-0.3, 0.2, 0.1),
                ..BodyDef::default()
            })
            .unwrap()
        });
        let j = w.create_joint(b1, b2, spec).unwrap();
        if reset {
            // A γ override and breaking thresholds that would break it at once: reset clears
            // them.
            w.set_constraint_gamma(j, Some(0.5)).unwrap();
            w.set_breakable(j, Some(1e-6), Some(1e-6)).unwrap();
            w.reset_constraint(j).unwrap();
        }
        for _ in 0..60 {
            w.step(1.0 / 60.0).unwrap();
        }
        w
    };
    let reset = make(odd, true);
    let fresh = make(default, false);
    let (a, b) = (states(&reset), states(&fresh));
    for (x, y) in a.iter().zip(&b) {
        for (u, v) in x.iter().zip(y) {
            assert!(
                (*u - *v).length() < 100.0 * eps(),
                "{mode:?}, {}: reset {a:?} vs fresh {b:?}",
                J::NAME
            );
        }
    }
    reset
}

#[test]
fn a_reset_joint_of_every_kind_is_its_default_table() {
    let o = Vec3::ZERO;
    let (p, a, b) = (
        Vec3::new(0.1, -0.5, 0.3),
        Vec3::new(0.6, 0.0, 0.8),
        Vec3::new(0.0, 1.0, 0.0),
    );
    for mode in MODES {
        // Ball: the body's point at the world origin stays there.
        let w = reset_matches(mode, JointSpec::ball(p), JointSpec::ball(o), false);
        let body = w.bodies().next().unwrap().1;
        let start = moving_body();
        let local = start.orientation.inverse() * (o - start.position);
        let gap = body.point_to_world(local).length();
        assert!(
            gap < 0.01,
            "{mode:?}: the ball's anchor is {gap} m off the origin"
        );
        reset_matches(
            mode,
            JointSpec::hinge(p, a).limits(-0.1, 0.1).motor(1.0, 5.0),
            JointSpec::hinge(o, Vec3::Y),
            false,
        );
        reset_matches(
            mode,
            JointSpec::prismatic(p, a).limits(-0.1, 0.1).motor(1.0, 5.0),
            JointSpec::prismatic(o, Vec3::Y),
            false,
        );
        reset_matches(mode, JointSpec::fixed(p), JointSpec::fixed(o), false);
        reset_matches(
            mode,
            JointSpec::universal(p, b, a),
            JointSpec::universal(o, Vec3::X, Vec3::Y),
            false,
        );
        reset_matches(
            mode,
            JointSpec::linear1(p, a),
            JointSpec::linear1(o, Vec3::Y),
            false,
        );
        reset_matches(
            mode,
            JointSpec::linear2(p, a),
            JointSpec::linear2(o, Vec3::Y),
            false,
        );
        for rotates in [false, true] {
            reset_matches(
                mode,
                JointSpec::planar(p, a, b, rotates),
                JointSpec::planar(o, Vec3::Y, Vec3::X, rotates),
                false,
            );
        }
        for fixed in [false, true] {
            reset_matches(
                mode,
                JointSpec::fixed_path(p, fixed),
                JointSpec::fixed_path(o, fixed),
                false,
            );
        }
        reset_matches(
            mode,
            JointSpec::car_wheel(a, b, 2000.0, 50.0),
            JointSpec::car_wheel(Vec3::Y, Vec3::X, 2000.0, 50.0),
            true,
        );
    }
}

/// Two 1 kg bobs 1 m either side of the pivot (0, 2, 0), the second turned half a turn; a ball
/// joint holds the first to the world at the pivot.
fn two_bobs(mode: SolverMode) -> (World, [BodyHandle; 2], kea::JointHandle<kea::BallJoint>) {
    let mut w = world_on(mode, 2, 2);
    let bob = |w: &mut World, x: Real| {
        w.create_body(&BodyDef {
            position: Vec3::new(x + 1.0, 2.0, 0.0),
            inertia: inertia::solid_sphere(1.0, 0.05).unwrap(),
            ..BodyDef::default()
        })
        .unwrap()
    };
    let a = bob(&mut w, 0.0);
    // Turned half a turn about y at (−1, 2, 0): its point 1 m along its own −x is the pivot.
    let b = w
        .create_body(&BodyDef {
            position: Vec3::new(-1.0, 2.0, 0.0),
            orientation: Quat::from_rotation_y(std::f32::consts::PI as Real),
            inertia: inertia::solid_sphere(1.0, 0.05).unwrap(),
            ..BodyDef::default()
        })
        .unwrap();
    let j = w
        .create_joint(a, None, JointSpec::ball(Vec3::new(0.0, 2.0, 0.0)))
        .unwrap();
    (w, [a, b], j)
}

#[test]
fn a_joint_given_other_bodies_constrains_the_new_pair() {
    for mode in MODES {
        let (mut w, [a, b], j) = two_bobs(mode);
        // Refused while enabled, nothing changed.
        let e = w.set_constraint_bodies(j, b, None).unwrap_err().to_string();
        assert!(e.contains("disable"), "{e}");
        assert_eq!(w.constraint_bodies(j).unwrap(), [Some(a), None]);
        j.set_enabled(&mut w, false).unwrap();
        w.set_constraint_bodies(j, b, None).unwrap();
        j.set_enabled(&mut w, true).unwrap();
        assert_eq!(w.constraint_bodies(j).unwrap(), [Some(b), None]);
        // The joint keeps its anchors in the bodies' frames: the world's at the pivot, the
        // body's 1 m along its own −x, where b's is too: b now swings from the pivot.
        let pivot = Vec3::new(0.0, 2.0, 0.0);
        let h: Real = 1.0 / 60.0;
        let mut worst: Real = 0.0;
        for n in 1..=120 {
            w.step(h).unwrap();
            let t = n as Real * h;
            // a falls freely (below ½gt² by the semi-implicit step's ½ g h t).
            let ya = w.body(a).unwrap().position().y;
            let expected = 2.0 - 0.5 * G * t * t - 0.5 * G * h * t;
            assert!((ya - expected).abs() < 1e-3, "{mode:?}: a at y {ya}, t {t}");
            let point = w.body(b).unwrap().point_to_world(Vec3::new(-1.0, 0.0, 0.0));
            worst = worst.max((point - pivot).length());
        }
        eprintln!("{mode:?}: b's anchor at most {worst} m off the pivot");
        assert!(
            worst < STRETCH,
            "{mode:?}: b's anchor {worst} m off the pivot"
        );
        let pb = w.body(b).unwrap().position();
        assert!(pb.y < 1.5, "{mode:?}: b swings down: {pb}");
    }
}

/// How far a ball joint's anchors part on a 1 m pendulum swinging from horizontal at 60 Hz,
/// at most, on any path (the exact path's one linearisation a step, measured 1 cm).
const STRETCH: Real = 0.015;

#[test]
fn a_disabled_joint_frees_its_body_and_enabled_again_holds_it() {
    for mode in MODES {
        let (mut w, [a, _], j) = two_bobs(mode);
        let pivot = Vec3::new(0.0, 2.0, 0.0);
        let h: Real = 1.0 / 60.0;
        for _ in 0..30 {
            w.step(h).unwrap();
        }
        let held = (w.body(a).unwrap().position() - pivot).length();
        eprintln!("{mode:?}: {held} m from the pivot after 0.5 s");
        assert!(
            (held - 1.0).abs() < STRETCH,
            "{mode:?}: on its string: {held}"
        );
        j.set_enabled(&mut w, false).unwrap();
        assert!(!w.is_constraint_enabled(j).unwrap());
        let v0 = w.body(a).unwrap().linear_velocity();
        for n in 1..=12 {
            w.step(h).unwrap();
            // Free: gravity alone changes its velocity.
            let v = w.body(a).unwrap().linear_velocity();
            let expected = v0 - Vec3::Y * (G * n as Real * h);
            assert!(
                (v - expected).length() < 1e-3,
                "{mode:?}: {v} vs {expected}"
            );
        }
        let freed = (w.body(a).unwrap().position() - pivot).length();
        assert!(freed > 1.05, "{mode:?}: it fell off its string: {freed}");
        j.set_enabled(&mut w, true).unwrap();
        for _ in 0..120 {
            w.step(h).unwrap();
        }
        let back = (w.body(a).unwrap().position() - pivot).length();
        eprintln!("{mode:?}: {back} m from the pivot, enabled again");
        assert!(
            (back - 1.0).abs() < STRETCH,
            "{mode:?}: held again at {back} m"
        );
    }
}

/// Seconds until a lone body drifting at `speed` m/s and spinning at `spin` rad/s in zero
/// gravity falls asleep under `dem` (auto-disable on), or `None` within 4 s.
fn asleep_after(mode: SolverMode, dem: DemSettings, speed: Real, spin: Real) -> Option<Real> {
    let mut w = world_on(mode, 1, 1);
    w.update_settings(|s| {
        s.gravity = Vec3::ZERO;
        s.dem = DemSettings {
            mode: DemMode::PartitionAutoDisable,
            ..dem
        };
    })
    .unwrap();
    let b = w
        .create_body(&BodyDef {
            linear_velocity: Vec3::new(speed, 0.0, 0.0),
            angular_velocity: Vec3::new(0.0, spin, 0.0),
            ..BodyDef::default()
        })
        .unwrap();
    let h: Real = 1.0 / 60.0;
    for n in 1..=240 {
        w.step(h).unwrap();
        if w.body(b).unwrap().is_sleeping() {
            return Some(n as Real * h);
        }
    }
    None
}

#[test]
fn the_users_auto_disable_thresholds_and_alive_window_decide_when_a_body_sleeps() {
    let d = DemSettings::default();
    for mode in MODES {
        // At rest: asleep after the alive window (0.5 s by default, or the user's 2 s).
        let t = asleep_after(mode, d, 0.0, 0.0).expect("at rest, it sleeps");
        assert!((0.5..0.6).contains(&t), "{mode:?}: asleep at {t} s");
        let long = DemSettings {
            alive_window: 2.0,
            ..d
        };
        let t = asleep_after(mode, long, 0.0, 0.0).expect("at rest, it sleeps");
        assert!((2.0..2.1).contains(&t), "{mode:?}: asleep at {t} s");
        // Drifting at 2 cm/s: above the default 1 cm/s it never sleeps; under a 5 cm/s
        // threshold it does.
        assert_eq!(asleep_after(mode, d, 0.02, 0.0), None, "{mode:?}");
        let loose = DemSettings {
            velocity_threshold: 0.05,
            ..d
        };
        let t = asleep_after(mode, loose, 0.02, 0.0).expect("under the threshold");
        assert!((0.5..0.6).contains(&t), "{mode:?}: asleep at {t} s");
        // Spinning at 0.05 rad/s: above the default 0.03 rad/s; under a 0.1 rad/s threshold.
        assert_eq!(asleep_after(mode, d, 0.0, 0.05), None, "{mode:?}");
        let loose = DemSettings {
            angular_velocity_threshold: 0.1,
            ..d
        };
        let t = asleep_after(mode, loose, 0.0, 0.05).expect("under the threshold");
        assert!((0.5..0.6).contains(&t), "{mode:?}: asleep at {t} s");
        // A threshold the user sets badly is refused by name, nothing changed.
        let mut w = World::with_capacity(1, 1).unwrap();
        let e = w
            .update_settings(|s| s.dem.alive_window = -1.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("alive_window"), "{e}");
        assert_eq!(w.settings().dem, d);
    }
}
