//! Fast spin held by joints: a wheel spinning on a turning chassis stays on its axle, and a
//! gyroscope precesses at mgr/(Iω) while keeping its spin (on the substepped paths and by
//! default; level at 60 Hz and on the exact path not yet: ignored, see the test).
//! The hinge takes its free axis from a spinning wheel's own axle (`spin_axle`), so the
//! fast-spin rotation cannot leak the spin into sideways rotation.

mod common;
use common::{world_on, PATHS};
use kea::{inertia, BodyDef, Quat, Real, Vec3};

/// A wheel (disk, axle along its y) spinning at `spin` on a hinge on a heavy chassis turning at
/// 1 rad/s about the vertical; returns the worst angle between the wheel's axle and the
/// chassis's hinge axis over 5 s, rad.
fn wheel_misalignment(mode: kea::SolverMode, spin: Real, fast_spin: bool) -> Real {
    let mut world = world_on(mode, 4, 8);
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let turn = Vec3::new(0.0, 1.0, 0.0);
    let chassis = world
        .create_body(&BodyDef {
            mass: 1.0e4,
            inertia: inertia::solid_box(1.0e4, Vec3::new(1.0, 0.3, 2.0)).unwrap(),
            angular_velocity: turn,
            ..Default::default()
        })
        .unwrap();
    // The wheel's axle (its local y) along the world x, 1 m to the side.
    let q = Quat::from_rotation_z(-std::f64::consts::FRAC_PI_2 as Real);
    let at = Vec3::new(1.2, 0.0, 0.0);
    let wheel = world
        .create_body(&BodyDef {
            mass: 10.0,
            inertia: inertia::solid_cylinder(10.0, 0.4, 0.05).unwrap(),
            position: at,
            orientation: q,
            linear_velocity: turn.cross(at),
            angular_velocity: turn + Vec3::X * spin,
            fast_spin_axis: fast_spin.then_some(Vec3::Y),
            ..Default::default()
        })
        .unwrap();
    world
        .create_joint(wheel, Some(chassis), kea::JointSpec::hinge(at, Vec3::X))
        .unwrap();
    let mut worst: Real = 0.0;
    for _ in 0..300 {
        world.step(1.0 / 60.0).unwrap();
        let axle = world.body(wheel).unwrap().orientation() * Vec3::Y;
        let hinge = world.body(chassis).unwrap().orientation() * Vec3::X;
        worst = worst.max(axle.cross(hinge).length().asin());
    }
    worst
}

#[test]
fn a_wheel_spinning_on_a_turning_chassis_stays_on_its_axle() {
    // The substepped paths re-linearise the hinge at every substep and hold a 300 rad/s wheel
    // to ~16 µrad; the default routing sends an island with a fast-spinning body there. The
    // exact path, forced, has one linearisation per step: 3.2 mrad (it tore off, 1.5 rad,
    // before the hinge took its free axis from the wheel's fast-spin axle).
    let mut runs = Vec::new();
    for mode in [
        kea::SolverMode::Iterative,
        kea::SolverMode::Split,
        kea::SolverMode::Hybrid,
        kea::SolverMode::Exact,
    ] {
        for spin in [10.0, 100.0, 300.0] {
            let worst = wheel_misalignment(mode, spin, true);
            eprintln!("{mode:?}, spin {spin} rad/s: worst misalignment {worst:.2e} rad");
            runs.push((mode, spin, worst));
        }
    }
    for (mode, spin, worst) in runs {
        let bound = if mode == kea::SolverMode::Exact {
            4.0e-3
        } else {
            1.0e-3
        };
        assert!(
            worst < bound,
            "{mode:?}, {spin} rad/s: misalignment {worst}"
        );
    }
}

/// A gyroscope: a 1 kg disk (radius 0.2 m) spinning at `spin` about a horizontal axle
/// pivoted by a ball joint 0.3 m from its centre, started at its steady precession. Returns
/// (measured precession rate, expected mgr/(Iω), spin at the end, lowest axle elevation).
fn gyroscope(mode: kea::SolverMode, spin: Real) -> (Real, Real, Real, Real) {
    let mut world = world_on(mode, 2, 4);
    let (m, radius, arm, g) = (1.0, 0.2, 0.3, 9.81);
    world
        .update_settings(|s| s.gravity = Vec3::new(0.0, -g, 0.0))
        .unwrap();
    let i_axle = 0.5 * m * radius * radius;
    let expected = m * g * arm / (i_axle * spin);
    let centre = Vec3::new(arm, 0.0, 0.0);
    let precession = Vec3::new(0.0, expected, 0.0);
    let disk = world
        .create_body(&BodyDef {
            mass: m,
            inertia: inertia::solid_cylinder(m, radius, 0.02).unwrap(),
            position: centre,
            orientation: Quat::from_rotation_z(-std::f64::consts::FRAC_PI_2 as Real),
            linear_velocity: precession.cross(centre),
            angular_velocity: Vec3::X * spin + precession,
            fast_spin_axis: Some(Vec3::Y),
            ..Default::default()
        })
        .unwrap();
    world
        .create_joint(disk, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    let h: Real = 1.0 / 60.0;
    let steps = 240;
    let (mut angle, mut lowest): (Real, Real) = (0.0, 0.0);
    let mut prev = Vec3::X;
    for _ in 0..steps {
        world.step(h).unwrap();
        let axle = world.body(disk).unwrap().orientation() * Vec3::Y;
        lowest = lowest.min(axle.y.asin());
        let flat = Vec3::new(axle.x, 0.0, axle.z);
        // Turning from +x towards −z is positive about +y.
        angle += prev.cross(flat).y.atan2(prev.dot(flat));
        prev = flat;
    }
    let body = world.body(disk).unwrap();
    let axle = body.orientation() * Vec3::Y;
    let spin_now = body.angular_velocity().dot(axle);
    (angle / (steps as Real * h), expected, spin_now, lowest)
}

#[test]
fn a_gyroscope_keeps_its_spin_and_precesses_at_mgr_over_i_omega() {
    // Default routing (a fast-spinning body sends its island to the substeps) and the
    // substepped paths forced: the spin is carried exactly, the precession within 1%.
    let modes = [
        kea::SolverMode::Hybrid,
        kea::SolverMode::Iterative,
        kea::SolverMode::Split,
    ];
    let runs = modes.map(|mode| (mode, gyroscope(mode, 100.0)));
    for (mode, (rate, expected, spin, lowest)) in runs {
        eprintln!(
            "{mode:?}: precession {rate:.4} rad/s (mgr/Iω = {expected:.4}), spin {spin:.2} rad/s, lowest axle {lowest:.4} rad"
        );
    }
    for (mode, (rate, expected, spin, lowest)) in runs {
        assert!(
            ((rate - expected) / expected).abs() < 0.01,
            "{mode:?}: {rate} vs {expected}"
        );
        assert!((spin - 100.0).abs() < 1.0, "{mode:?}: spin {spin}");
        // It does not fall: the axle dips no further than its (growing) nutation takes it.
        assert!(lowest > -0.3, "{mode:?}: the disk fell to {lowest} rad");
    }
}

#[test]
#[ignore = "known failure (issue 11): at 60 Hz the substepped paths' nutation grows from a steady start (axle dips 0.14 rad in 4 s, energy +25% in 20 s); the exact path, one linearisation per step, lets the disk fall"]
fn a_gyroscope_stays_level_on_both_paths() {
    for mode in PATHS {
        let (rate, expected, spin, lowest) = gyroscope(mode, 100.0);
        eprintln!("{mode:?}: precession {rate:.4} (expected {expected:.4}), spin {spin:.2}, lowest {lowest:.4}");
        assert!(
            ((rate - expected) / expected).abs() < 0.01,
            "{mode:?}: {rate}"
        );
        assert!((spin - 100.0).abs() < 1.0, "{mode:?}: spin {spin}");
        assert!(lowest > -0.05, "{mode:?}: the disk fell to {lowest} rad");
    }
}
