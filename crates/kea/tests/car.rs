//! VALIDATION #20 and the car wheel joint: the suspension deflects by m·g/k under the chassis
//! and rings at √(k/m)/2π; a locked steering holds; the drive motor spins the wheel.

mod common;
use common::{world_on, PATHS};
use kea::{inertia, BodyDef, Real, SolverMode, Vec3, World, PI_REAL};

const K: Real = 2000.0;
const M: Real = 10.0;

/// A chassis of mass M above a wheel held fixed, on one car-wheel joint with a vertical
/// steering/suspension axis and an axle along x.
fn rig(mode: SolverMode, damping: Real) -> (World, kea::BodyHandle, kea::ConstraintHandle) {
    let mut world = world_on(mode, 4, 4);
    let chassis = world
        .create_body(&BodyDef {
            mass: M,
            position: Vec3::new(0.0, 0.5, 0.0),
            inertia: inertia::solid_box(M, Vec3::new(1.0, 0.2, 0.5)).unwrap(),
            ..Default::default()
        })
        .unwrap();
    let wheel = world
        .create_body(&BodyDef {
            inertia: inertia::solid_cylinder(1.0, 0.3, 0.1).unwrap(),
            enabled: false, // held fixed: the chassis hangs on the suspension
            ..Default::default()
        })
        .unwrap();
    let j = world
        .create_car_wheel(chassis, wheel, Vec3::Y, Vec3::X, K, damping)
        .unwrap();
    (world, chassis, j)
}

#[test]
fn suspension_deflects_by_mg_over_k_and_rings_at_its_frequency() {
    for mode in PATHS {
        // Damped: static deflection.
        let (mut world, chassis, j) = rig(mode, 200.0);
        for _ in 0..600 {
            world.step(1.0 / 60.0).unwrap();
        }
        let sag = 0.5 - world.body(chassis).unwrap().position().y;
        let expected = M * 9.81 / K;
        eprintln!("{mode:?}: suspension sag {sag} m, m g/k = {expected} m");
        assert!(
            (sag - expected).abs() < 0.01 * expected,
            "{mode:?}: sag {sag}"
        );
        // The joint reports it: the wheel centre sits above its rest point by the sag.
        let d = world.car_wheel(j).unwrap().suspension_position();
        assert!(
            (d - expected).abs() < 0.01 * expected,
            "{mode:?}: suspension position {d}"
        );
        // Undamped: the bounce frequency.
        let (mut world, chassis, _) = rig(mode, 0.0);
        let h: Real = 1.0 / 240.0;
        let mut ups = Vec::new();
        let mut prev: Real = 0.0;
        for n in 0..1200 {
            world.step(h).unwrap();
            let y = 0.5 - world.body(chassis).unwrap().position().y - expected;
            if prev < 0.0 && y >= 0.0 {
                ups.push(n as Real * h);
            }
            prev = y;
        }
        let periods: Vec<Real> = ups.windows(2).map(|w| w[1] - w[0]).collect();
        let period = periods.iter().sum::<Real>() / periods.len() as Real;
        let expected_period = 2.0 * PI_REAL * (M / K).sqrt();
        eprintln!("{mode:?}: bounce period {period} s, 2π√(m/k) = {expected_period} s");
        assert!(
            (period - expected_period).abs() < 0.02 * expected_period,
            "{mode:?}: period {period}"
        );
    }
}

#[test]
fn locked_steering_holds_and_the_drive_spins_the_wheel() {
    for mode in PATHS {
        let (mut world, chassis, j) = rig(mode, 200.0);
        for _ in 0..120 {
            world
                .body_mut(chassis)
                .unwrap()
                .add_torque(Vec3::new(0.0, 5.0, 0.0))
                .unwrap();
            world.step(1.0 / 60.0).unwrap();
        }
        let steer = world.car_wheel(j).unwrap().steering_angle();
        assert!(
            steer.abs() < 1e-3,
            "{mode:?}: locked steering turned by {steer}"
        );
        // A free wheel under a chassis held fixed: the drive motor spins it up.
        let mut world = world_on(mode, 4, 4);
        world.set_gravity(Vec3::ZERO).unwrap();
        let chassis = world
            .create_body(&BodyDef {
                mass: M,
                enabled: false,
                ..Default::default()
            })
            .unwrap();
        let wheel = world
            .create_body(&BodyDef {
                position: Vec3::new(1.0, -0.3, 0.0),
                inertia: inertia::solid_cylinder(1.0, 0.3, 0.1).unwrap(),
                ..Default::default()
            })
            .unwrap();
        let j = world
            .create_car_wheel(chassis, wheel, Vec3::Y, Vec3::X, K, 50.0)
            .unwrap();
        world
            .car_wheel_mut(j)
            .unwrap()
            .drive_mut()
            .set_motor(10.0, 5.0)
            .unwrap();
        for _ in 0..120 {
            world.step(1.0 / 60.0).unwrap();
        }
        let spin = world.car_wheel(j).unwrap().spin_rate();
        eprintln!("{mode:?}: wheel spin {spin} rad/s (target 10)");
        assert!((spin - 10.0).abs() < 1e-2, "{mode:?}: spin {spin}");
        let w = world.body(wheel).unwrap().angular_velocity();
        assert!(
            (w - Vec3::new(10.0, 0.0, 0.0)).length() < 2e-2,
            "{mode:?}: wheel ω {w}"
        );
    }
}
