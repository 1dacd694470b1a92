//! Floating trees in reduced coordinates (`WorldSettings::reduced_free_trees`): bodies joined
//! by a tree's joints and held to nothing step in joint coordinates, the root's six first. A
//! hinged pair and a three-link chain with a ball joint, tumbling in zero gravity, keep their
//! linear and angular momentum and their energy; under gravity their centre of mass falls on
//! the parabola (to the integrator's truncation). In f32 and f64.

use kea::{inertia, BodyDef, JointSpec, Real, Vec3, World, WorldDef, WorldSettings};

fn world(gravity: Vec3) -> World {
    World::new(WorldDef {
        settings: WorldSettings {
            gravity,
            reduced_free_trees: true,
            ..WorldSettings::default()
        },
        ..WorldDef::default()
    })
    .unwrap()
}

/// A 2 kg box and a 1 kg rod on a hinge, and (with `ball`) a half-kilogram ball on a ball
/// joint at the rod's end, spinning and drifting with velocities the joints allow.
fn tumbler(w: &mut World, ball: bool) {
    let (xa, va, wa) = (
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.3, 0.5, -0.2),
        Vec3::new(0.4, 2.0, 0.7),
    );
    let (xb, hinge) = (Vec3::new(0.6, 1.0, 0.0), Vec3::new(0.3, 1.0, 0.0));
    let wb = wa + Vec3::Z * 3.0;
    let vb = va + wa.cross(hinge - xa) + wb.cross(xb - hinge);
    let a = w
        .create_body(&BodyDef {
            position: xa,
            linear_velocity: va,
            angular_velocity: wa,
            inertia: inertia::solid_box(2.0, Vec3::new(0.2, 0.1, 0.15)).unwrap(),
            ..Default::default()
        })
        .unwrap();
    let b = w
        .create_body(&BodyDef {
            position: xb,
            linear_velocity: vb,
            angular_velocity: wb,
            inertia: inertia::solid_box(1.0, Vec3::new(0.3, 0.05, 0.05)).unwrap(),
            ..Default::default()
        })
        .unwrap();
    w.create_joint(b, Some(a), JointSpec::hinge(hinge, Vec3::Z))
        .unwrap();
    if ball {
        let (xc, pivot) = (Vec3::new(1.2, 1.0, 0.0), Vec3::new(0.9, 1.0, 0.0));
        let wc = Vec3::new(-1.0, 0.5, 1.5);
        let vc = vb + wb.cross(pivot - xb) + wc.cross(xc - pivot);
        let c = w
            .create_body(&BodyDef {
                position: xc,
                linear_velocity: vc,
                angular_velocity: wc,
                inertia: inertia::solid_sphere(0.5, 0.1).unwrap(),
                ..Default::default()
            })
            .unwrap();
        w.create_joint(c, Some(b), JointSpec::ball(pivot)).unwrap();
    }
}

fn momenta(w: &World) -> (Vec3, Vec3, Real, Vec3) {
    let (mut p, mut l, mut m, mut c) = (Vec3::ZERO, Vec3::ZERO, 0.0, Vec3::ZERO);
    for (_, b) in w.bodies() {
        let v = b.linear_velocity();
        p += v * b.mass();
        m += b.mass();
        c += b.position() * b.mass();
        let r = b.position();
        let rot = kea::Mat3::from_quat(b.orientation());
        let i_world = rot * b.inertia() * rot.transpose();
        l += r.cross(v * b.mass()) + i_world * b.angular_velocity();
    }
    (p, l, m, c / m)
}

#[test]
fn a_floating_tree_keeps_its_momentum_and_energy() {
    for ball in [false, true] {
        let mut w = world(Vec3::ZERO);
        tumbler(&mut w, ball);
        let (p0, l0, _, _) = momenta(&w);
        let e0 = w.kinetic_energy();
        let h = 1.0 / 240.0;
        for k in 0..480 {
            let stats = w.step(h).unwrap();
            assert_eq!(stats.reduced_trees, 1, "step {k}: one floating tree");
        }
        let (p, l, _, _) = momenta(&w);
        let e = w.kinetic_energy();
        // Round-off in f32; Runge-Kutta 4's truncation (it keeps momenta only to its order)
        // in f64: 2e-9 measured.
        let tol: Real = if cfg!(feature = "f64") { 1e-8 } else { 1e-5 };
        eprintln!(
            "ball {ball}: momentum drift {:.2e}, angular {:.2e}, energy {:.2e} (relative) over 2 s",
            (p - p0).length() / p0.length(),
            (l - l0).length() / l0.length(),
            (e - e0).abs() / e0
        );
        assert!((p - p0).length() < tol * p0.length(), "{p} vs {p0}");
        assert!((l - l0).length() < 10.0 * tol * l0.length(), "{l} vs {l0}");
        assert!((e - e0).abs() < 10.0 * tol * e0, "energy {e} vs {e0}");
        assert!(w.joint_error() < 1e-4, "joints closed: {}", w.joint_error());
    }
}

#[test]
fn a_floating_tree_falls_on_the_parabola() {
    let g = Vec3::new(0.0, -9.81, 0.0);
    let mut w = world(g);
    tumbler(&mut w, true);
    let (p0, _, m, c0) = momenta(&w);
    let v0 = p0 / m;
    let h = 1.0 / 60.0;
    let steps = 60;
    for _ in 0..steps {
        assert_eq!(w.step(h).unwrap().reduced_trees, 1);
    }
    let t = steps as Real * h;
    let (_, _, _, c) = momenta(&w);
    let expected = c0 + v0 * t + g * (0.5 * t * t);
    // Gravity moves the centre on the parabola exactly; the joint coordinates it is read
    // through carry Runge-Kutta 4's truncation at 60 Hz (6e-7 m measured, f32 and f64 alike).
    let tol: Real = 1e-5;
    eprintln!("centre of mass {c}, parabola {expected}");
    assert!((c - expected).length() < tol, "{c} vs {expected}");
}

/// Under Euler (MuJoCo's, whose turns Kea's charts now follow: `ball_charts.rs`) the hinged
/// pair and the chain with a ball joint keep their momenta and energy to the step's first
/// order: their drifts over 2 s are small and halve with the step. A lone box spinning fast:
/// below.
#[test]
fn euler_keeps_momentum_to_first_order_and_fast_spins_finite() {
    let drifts = |ball: bool, steps: usize| {
        let mut w = world(Vec3::ZERO);
        w.update_settings(|s| s.integrator = kea::Integrator::Euler)
            .unwrap();
        tumbler(&mut w, ball);
        let (p0, l0, _, _) = momenta(&w);
        let e0 = w.kinetic_energy();
        for k in 0..steps {
            let stats = w.step(2.0 / steps as Real).unwrap();
            assert_eq!(stats.reduced_trees, 1, "step {k}: one floating tree");
        }
        let (p, l, _, _) = momenta(&w);
        let e = w.kinetic_energy();
        [
            (p - p0).length() / p0.length(),
            (l - l0).length() / l0.length(),
            (e - e0).abs() / e0,
        ]
    };
    for ball in [false, true] {
        let (coarse, fine) = (drifts(ball, 480), drifts(ball, 960));
        eprintln!(
            "Euler, ball {ball}: drifts (momentum, angular, energy) over 2 s {coarse:?} at \
             1/240 s, {fine:?} at 1/480 s"
        );
        for (c, f) in coarse.iter().zip(fine) {
            assert!(*c < 0.05, "ball {ball}: drift {c} at 1/240 s");
            // First order: half the step, half the drift (f32 round-off aside).
            assert!(
                f < 0.65 * c || *c < 1e-4,
                "ball {ball}: {f} at 1/480 s from {c}"
            );
        }
    }
    // A lone box spinning fast about its middle axis (50 rad/s). With `reduced_lone_bodies` a
    // floating tree of one body, its chart re-centred again and again: under RK4 at 60 Hz
    // (0.83 rad a step) its energy within 40% over 10 s (its truncation; 0.3% at 240 Hz);
    // under Euler it runs away, as MuJoCo's Euler does (an explicit gyroscopic term; MuJoCo's
    // too, even at 240 Hz), and is quarantined: nothing non-finite reaches the user. Without
    // it (an MJCF asking for `implicitfast`), the free-body path's implicit gyroscopic step
    // keeps it within 1%, as MuJoCo's `implicitfast` keeps it bounded.
    for (integrator, lone, runs_away, bound) in [
        (kea::Integrator::RungeKutta4, true, false, 0.4),
        (kea::Integrator::Euler, true, true, 0.0),
        (kea::Integrator::Euler, false, false, 0.01),
    ] {
        let hz = 60;
        let mut w = world(Vec3::ZERO);
        w.update_settings(|s| {
            s.integrator = integrator;
            s.reduced_lone_bodies = lone;
        })
        .unwrap();
        let b = w
            .create_body(&BodyDef {
                angular_velocity: Vec3::new(0.5, 50.0, -0.3),
                inertia: inertia::solid_box(1.0, Vec3::new(0.3, 0.2, 0.1)).unwrap(),
                ..Default::default()
            })
            .unwrap();
        let e0 = w.kinetic_energy();
        let mut reduced = 0;
        for _ in 0..10 * hz {
            reduced += w.step(1.0 / hz as Real).unwrap().reduced_trees;
        }
        let e = w.kinetic_energy();
        let spin = w.body(b).unwrap().angular_velocity();
        eprintln!(
            "lone box at 50 rad/s, {integrator:?} at {hz} Hz for 10 s: energy {e} from {e0}, \
             {reduced} steps a tree, {} quarantined",
            w.quarantine_report().len()
        );
        assert!(
            e.is_finite() && spin.is_finite(),
            "{integrator:?} at {hz} Hz"
        );
        if runs_away {
            assert_eq!(
                w.quarantine_report().len(),
                1,
                "runs away and is quarantined"
            );
        } else {
            let trees = if lone { 10 * hz } else { 0 };
            assert_eq!(reduced, trees, "{integrator:?}, lone {lone}: trees");
            assert!(
                w.quarantine_report().is_empty(),
                "{integrator:?}: nothing ran away"
            );
            assert!((e - e0).abs() < bound * e0, "{integrator:?}: {e} from {e0}");
        }
    }
}
