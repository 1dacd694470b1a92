//! VALIDATION #29 (energy) and #34: pendulums keep their energy at 60 Hz for 10 s: it never
//! rises above its start by more than 0.5% of the swing's energy, and loses less than 2% in
//! all, on every path a user can force.
//!
//! A joint's rows aim their velocity along the chord of each step or substep
//! (`Row::curvature`): without it the exact path lost 16% of `mgL` in 10 s from a 57° swing
//! and 60% of a double pendulum's.
//!
//! On the default routing a tree of hinges and ball joints on the world goes to the
//! reduced-coordinate path, whose default integrator is fourth-order Runge–Kutta: measured
//! there, a hinged pendulum, a hinged double pendulum, a ball pendulum and a conical pendulum
//! keep their energy to 0.14% at 60 and 240 Hz, where semi-implicit Euler rose 30% (60 Hz)
//! and 11% (240 Hz).

mod common;
use common::world_on;
use kea::{inertia, BodyDef, Integrator, Real, SolverMode, Vec3, World};

const G: Real = 9.81;
const H: Real = 1.0 / 60.0;
const PATHS: [SolverMode; 4] = [
    SolverMode::Hybrid,
    SolverMode::Exact,
    SolverMode::Iterative,
    SolverMode::Split,
];

/// Kinetic plus potential energy, the potential measured from `y = 0`.
fn energy(w: &World) -> Real {
    w.kinetic_energy()
        + w.bodies()
            .map(|(_, b)| b.mass() * G * b.position().y)
            .sum::<Real>()
}

/// Steps `w` for 10 s at 60 Hz; returns the largest rise above the start and the change at
/// the end, as fractions of `swing` (the energy that moves: the start's above the lowest
/// state).
fn run(w: &mut World, swing: Real) -> (Real, Real) {
    run_at(w, swing, H)
}

/// [`run`] at steps of `h`.
fn run_at(w: &mut World, swing: Real, h: Real) -> (Real, Real) {
    let e0 = energy(w);
    let mut rise: Real = 0.0;
    for _ in 0..(10.0 / h).round() as usize {
        let stats = w.step(h).unwrap();
        assert!(stats.solver.is_clean(), "{:?}", stats.solver);
        rise = rise.max(energy(w) - e0);
    }
    (rise / swing, (energy(w) - e0) / swing)
}

/// Prints and checks one run: the rise stays under `max_rise` and the loss under 2% (both
/// fractions of the swing's energy).
fn check(what: &str, mode: SolverMode, (rise, change): (Real, Real), max_rise: Real) {
    eprintln!(
        "{mode:?} {what}: rise at most {:.3}%, {:.3}% after 10 s",
        rise * 100.0,
        change * 100.0
    );
    assert!(rise < max_rise, "{mode:?} {what}: energy rose {rise}");
    assert!(change > -0.02, "{mode:?} {what}: energy lost {change}");
}

/// VALIDATION's bound on the rise.
const RISE: Real = 0.005;

/// A 1 kg bob (a 2 cm sphere) on a 1 m ball joint at the origin.
fn bob(w: &mut World, at: Vec3, v: Vec3) {
    let b = w
        .create_body(&BodyDef {
            position: at,
            linear_velocity: v,
            inertia: inertia::solid_sphere(1.0, 0.02).unwrap(),
            ..Default::default()
        })
        .unwrap();
    w.create_joint(b, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
}

/// A pendulum released at 30° and a conical pendulum circling at 0.5 rad, on `mode`.
fn pendulums(mode: SolverMode) -> [(Real, Real); 2] {
    pendulums_at(mode, H)
}

/// [`pendulums`] at steps of `h`.
fn pendulums_at(mode: SolverMode, h: Real) -> [(Real, Real); 2] {
    let th: Real = 30.0_f64.to_radians() as Real;
    let mut w = world_on(mode, 2, 2);
    bob(&mut w, Vec3::new(th.sin(), -th.cos(), 0.0), Vec3::ZERO);
    let simple = run_at(&mut w, G * (1.0 - th.cos()), h);
    // v² = g·r·tan θ. Its energy all moves.
    let th: Real = 0.5;
    let r = th.sin();
    let v = (G * r * th.tan()).sqrt();
    let mut w = world_on(mode, 2, 2);
    bob(&mut w, Vec3::new(r, -th.cos(), 0.0), Vec3::new(0.0, 0.0, v));
    let conical = run_at(&mut w, 0.5 * v * v + G * (1.0 - th.cos()), h);
    [simple, conical]
}

#[test]
fn pendulums_keep_their_energy_on_the_substepped_paths() {
    // Synchronised (half kicks at the step's ends, velocities projected at the poses
    // reached): iterative 0.000% rise, −0.47% (pendulum), −0.40% (conical); split 0.000%,
    // −0.004%; −0.011%; the double pendulum 0.000%, −0.18%. Before, the velocity handed on
    // belonged half a substep back and the energy read from it swung by (hs/2)·v·∇V: split
    // 0.65% / 0.55% up, iterative 0.44%.
    let [simple, conical] = pendulums(SolverMode::Iterative);
    check("pendulum at 30°", SolverMode::Iterative, simple, RISE);
    check("conical pendulum", SolverMode::Iterative, conical, RISE);
    let [simple, conical] = pendulums(SolverMode::Split);
    check("pendulum at 30°", SolverMode::Split, simple, RISE);
    check("conical pendulum", SolverMode::Split, conical, RISE);
    let double = double_pendulum(SolverMode::Split);
    check("double pendulum", SolverMode::Split, double, RISE);
}

/// Two 1 m, 1 kg rods on hinges about z, the first pinned at the origin, released
/// horizontal along +x: 2·m·g of energy to move (their centres fall 0.5 m and 1.5 m).
fn double_pendulum(mode: SolverMode) -> (Real, Real) {
    let mut w = hinged_rods(mode, 2);
    run(&mut w, 2.0 * G)
}

/// `n` hinged 1 m, 1 kg rods about z in a chain from the origin, horizontal along +x.
fn hinged_rods(mode: SolverMode, n: usize) -> World {
    let mut w = world_on(mode, n, n);
    let rod = |x: Real| BodyDef {
        position: Vec3::new(x, 0.0, 0.0),
        inertia: inertia::solid_box(1.0, Vec3::new(0.5, 0.02, 0.02)).unwrap(),
        ..Default::default()
    };
    let mut parent = None;
    for k in 0..n {
        let b = w.create_body(&rod(k as Real + 0.5)).unwrap();
        let anchor = Vec3::new(k as Real, 0.0, 0.0);
        w.create_joint(b, parent, kea::JointSpec::hinge(anchor, Vec3::Z))
            .unwrap();
        parent = Some(b);
    }
    w
}

/// A 1 m, 1 kg rod on a hinge about z at the origin, released horizontal: `m g L/2` of
/// energy to move.
fn hinged_rod_swing(integrator: Integrator, h: Real) -> ((Real, Real), u32) {
    let mut w = hinged_rods(SolverMode::Hybrid, 1);
    w.update_settings(|s| s.integrator = integrator).unwrap();
    let reduced = w.step(h).unwrap().reduced_trees;
    let mut w = hinged_rods(SolverMode::Hybrid, 1);
    w.update_settings(|s| s.integrator = integrator).unwrap();
    (run_at(&mut w, 0.5 * G, h), reduced)
}

/// The hinged double pendulum on the default routing (the reduced path) with `integrator`.
fn reduced_double_pendulum(integrator: Integrator, h: Real) -> ((Real, Real), u32) {
    let mut w = hinged_rods(SolverMode::Hybrid, 2);
    w.update_settings(|s| s.integrator = integrator).unwrap();
    let reduced = w.step(h).unwrap().reduced_trees;
    let mut w = hinged_rods(SolverMode::Hybrid, 2);
    w.update_settings(|s| s.integrator = integrator).unwrap();
    (run_at(&mut w, 2.0 * G, h), reduced)
}

/// VALIDATION #29 and #34 on the default routing and its default integrator, at 60 and
/// 240 Hz: every pendulum loses less than 2% of its swing's energy and never rises above its
/// start by more than 0.5%, in reduced coordinates (checked for the hinged ones here, for the
/// ball-jointed ones below).
#[test]
fn default_routing_keeps_pendulums_energy_at_60_and_240_hz() {
    assert_eq!(
        kea::WorldSettings::default().integrator,
        Integrator::RungeKutta4
    );
    for hz in [60.0, 240.0] {
        let h = 1.0 / hz as Real;
        let (rod, reduced) = hinged_rod_swing(Integrator::RungeKutta4, h);
        assert_eq!(reduced, 1, "the hinged rod steps in reduced coordinates");
        check(
            &format!("hinged rod, {hz} Hz"),
            SolverMode::Hybrid,
            rod,
            RISE,
        );
        let (double, reduced) = reduced_double_pendulum(Integrator::RungeKutta4, h);
        assert_eq!(
            reduced, 1,
            "the double pendulum steps in reduced coordinates"
        );
        check(
            &format!("double pendulum, {hz} Hz"),
            SolverMode::Hybrid,
            double,
            RISE,
        );
        // Ball joints step in reduced coordinates too (three hinges, their chart centred
        // each step): held to VALIDATION's bounds.
        let (simple, conical) = simple_and_conical(h);
        for (what, result) in [
            ("ball pendulum at 30°", simple),
            ("conical pendulum", conical),
        ] {
            check(
                &format!("{what}, {hz} Hz"),
                SolverMode::Hybrid,
                result,
                RISE,
            );
        }
    }
}

/// The conical pendulum on the default routing goes round at `Ω = √(g / (L cos θ))` and keeps
/// its angle from the vertical, in reduced coordinates (checked), at 60 Hz.
#[test]
fn a_conical_pendulum_on_the_default_routing_keeps_its_period_and_its_angle() {
    let th: Real = 0.5;
    let r = th.sin();
    let v = (G * r * th.tan()).sqrt();
    let mut w = world_on(SolverMode::Hybrid, 2, 2);
    bob(&mut w, Vec3::new(r, -th.cos(), 0.0), Vec3::new(0.0, 0.0, v));
    let b = w.bodies().next().unwrap().0;
    let omega = (G / th.cos()).sqrt();
    let mut turned: Real = 0.0;
    let mut last = Vec3::X;
    let mut worst: Real = 0.0;
    for _ in 0..600 {
        let stats = w.step(H).unwrap();
        assert_eq!(
            stats.reduced_trees, 1,
            "the ball-jointed bob steps in reduced coordinates"
        );
        let p = w.body(b).unwrap().position();
        let flat = Vec3::new(p.x, 0.0, p.z).normalize();
        // Turning from +x towards −z (the bob starts moving along +z from +x: about −y).
        turned += last.cross(flat).dot(-Vec3::Y).atan2(last.dot(flat));
        last = flat;
        worst = worst.max((p.normalize().dot(-Vec3::Y).acos() - th).abs());
    }
    let expected = omega * 10.0;
    eprintln!(
        "conical pendulum, 60 Hz, 10 s: turned {turned:.4} rad, Ω t = {expected:.4} ({:.3}%), angle off by at most {worst:.2e} rad",
        100.0 * (turned - expected) / expected
    );
    assert!(
        ((turned - expected) / expected).abs() < 0.005,
        "period: {turned} vs {expected}"
    );
    assert!(worst < 0.01, "the angle from the vertical moved by {worst}");
}

/// The ball-jointed pendulum and conical pendulum on the default routing at steps of `h`.
fn simple_and_conical(h: Real) -> ((Real, Real), (Real, Real)) {
    let [simple, conical] = pendulums_at(SolverMode::Hybrid, h);
    (simple, conical)
}

/// The reduced path's integrators side by side on the double pendulum (the note quotes the
/// figures): only Runge–Kutta is held to VALIDATION's bounds; Euler and the implicit step
/// (first order) drift by tens of percent at 60 Hz.
#[test]
fn reduced_path_integrators_compared() {
    for integrator in [
        Integrator::Euler,
        Integrator::Implicit,
        Integrator::RungeKutta4,
    ] {
        for hz in [60.0, 240.0] {
            let ((rise, change), _) = reduced_double_pendulum(integrator, 1.0 / hz as Real);
            eprintln!(
                "{integrator:?}, double pendulum, {hz} Hz: rise at most {:.3}%, {:.3}% after 10 s",
                rise * 100.0,
                change * 100.0
            );
            assert!(rise.is_finite() && change.is_finite());
            if integrator == Integrator::RungeKutta4 {
                check("double pendulum", SolverMode::Hybrid, (rise, change), RISE);
            }
        }
    }
}

#[test]
#[ignore = "known failure (issue 36, item 5): VALIDATION #29 and #34 to the letter on the paths a user forces. Split islands keep every pendulum (0.000% rise, at most 0.18% lost) and the iterative path the single and conical ones (0.000%, -0.47%), since their step hands on a synchronised state; left: the forced exact path (one linearisation a step at 60 Hz: a 30° swing rises 1.45% and loses 1.1%, the conical pendulum loses 2.3%, the double pendulum 30%) and Gauss-Seidel's double pendulum (rises 3.3%: the lever shift that keeps a pair's momentum feeds it; without the shift it loses 10%). Substepping the forced exact path on the direct solve keeps them all, but breaks VALIDATION #11 and #17 on that path (a soft row then follows implicit Euler at the substep, and the substeps' bodies drift 1.1e-3 of their angular momentum a second). The default routing steps all of them in reduced coordinates with Runge-Kutta 4 and keeps their energy (tested above)"]
fn pendulums_keep_their_energy_on_every_path() {
    for mode in PATHS {
        let [simple, conical] = pendulums(mode);
        check("pendulum at 30°", mode, simple, RISE);
        check("conical pendulum", mode, conical, RISE);
        check("double pendulum", mode, double_pendulum(mode), RISE);
    }
}
