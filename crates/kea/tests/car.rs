//! VALIDATION #20 and the car wheel joint: the suspension deflects by m·g/k under the chassis
//! and rings at √(k/m)/2π; a locked steering holds; the drive motor spins the wheel; the
//! steering motor turns at its rate into hard stops; suspension stops, hard and soft.

mod common;
use common::{world_on, PATHS};
use kea::{inertia, BodyDef, Real, SolverMode, Vec3, World, PI_REAL};

const K: Real = 2000.0;
const M: Real = 10.0;

/// A chassis of mass M above a wheel held fixed, on one car-wheel joint with a vertical
/// steering/suspension axis and an axle along x.
fn rig(
    mode: SolverMode,
    damping: Real,
) -> (World, kea::BodyHandle, kea::JointHandle<kea::CarWheel>) {
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
        .create_joint(
            chassis,
            Some(wheel),
            kea::JointSpec::car_wheel(Vec3::Y, Vec3::X, K, damping),
        )
        .unwrap();
    (world, chassis, j)
}

/// A free wheel under a chassis held fixed, no gravity: only its joint's motors move it.
fn free_wheel(mode: SolverMode) -> (World, kea::BodyHandle, kea::JointHandle<kea::CarWheel>) {
    let mut world = world_on(mode, 4, 4);
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
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
        .create_joint(
            chassis,
            Some(wheel),
            kea::JointSpec::car_wheel(Vec3::Y, Vec3::X, K, 50.0),
        )
        .unwrap();
    (world, wheel, j)
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
        let d = j.get(&world).unwrap().suspension_position();
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
        let steer = j.get(&world).unwrap().steering_angle();
        assert!(
            steer.abs() < 1e-3,
            "{mode:?}: locked steering turned by {steer}"
        );
        // A free wheel under a chassis held fixed: the drive motor spins it up.
        let (mut world, wheel, j) = free_wheel(mode);
        j.wheel_mut(&mut world)
            .unwrap()
            .drive_mut()
            .set_motor(10.0, 5.0)
            .unwrap();
        for _ in 0..120 {
            world.step(1.0 / 60.0).unwrap();
        }
        let spin = j.get(&world).unwrap().spin_rate();
        eprintln!("{mode:?}: wheel spin {spin} rad/s (target 10)");
        assert!((spin - 10.0).abs() < 1e-2, "{mode:?}: spin {spin}");
        let w = world.body(wheel).unwrap().angular_velocity();
        assert!(
            (w - Vec3::new(10.0, 0.0, 0.0)).length() < 2e-2,
            "{mode:?}: wheel ω {w}"
        );
    }
}

#[test]
fn the_steering_motor_turns_at_its_rate_until_the_stops_hold_it() {
    for mode in PATHS {
        // A wheel on a chassis held fixed, no gravity: only the steering moves it.
        let (mut world, _, j) = free_wheel(mode);
        {
            let cw = j.wheel_mut(&mut world).unwrap();
            cw.steering_locked = false;
            let steering = cw.steering_limit_mut();
            steering
                .set_limits(
                    kea::SingleLimit::hard(-0.4, 0.0),
                    kea::SingleLimit::hard(0.4, 0.0),
                )
                .unwrap();
            steering.set_motor(1.0, 20.0).unwrap();
        }
        let h: Real = 1.0 / 120.0;
        let mut angles = Vec::new();
        for _ in 0..120 {
            world.step(h).unwrap();
            angles.push(j.get(&world).unwrap().steering_angle());
        }
        // At 1 rad/s: 0.2 rad after 0.2 s (the motor's force reaches the rate at once).
        let at = angles[23];
        assert!((at - 0.2).abs() < 0.02, "{mode:?}: {at} rad after 0.2 s");
        let rate = (angles[35] - angles[11]) / (24.0 * h);
        assert!((rate - 1.0).abs() < 0.02, "{mode:?}: steering rate {rate}");
        // Then the upper stop holds it against the motor.
        let last = *angles.last().unwrap();
        assert!((last - 0.4).abs() < 2e-3, "{mode:?}: held at {last}");
        assert!(
            angles.iter().all(|&a| a < 0.4 + 5e-3),
            "{mode:?}: past the stop"
        );
        // Reversed, it runs to the lower stop.
        j.wheel_mut(&mut world)
            .unwrap()
            .steering_limit_mut()
            .set_motor(-1.0, 20.0)
            .unwrap();
        for _ in 0..120 {
            world.step(h).unwrap();
        }
        let last = j.get(&world).unwrap().steering_angle();
        assert!((last + 0.4).abs() < 2e-3, "{mode:?}: held at {last}");
    }
}

#[test]
fn suspension_stops_cap_the_travel_hard_and_share_the_load_soft() {
    let sag = M * 9.81 / K; // 4.9 cm on the spring alone
    for mode in PATHS {
        // A hard stop at 2 cm of compression: the chassis rests on it.
        let (mut world, _, j) = rig(mode, 200.0);
        j.wheel_mut(&mut world)
            .unwrap()
            .suspension_limit_mut()
            .set_limits(
                kea::SingleLimit::hard(-0.1, 0.0),
                kea::SingleLimit::hard(0.02, 0.0),
            )
            .unwrap();
        for _ in 0..600 {
            world.step(1.0 / 60.0).unwrap();
        }
        let d = j.get(&world).unwrap().suspension_position();
        assert!(
            sag > 0.04 && (d - 0.02).abs() < 1e-3,
            "{mode:?}: hard stop at {d}"
        );
        // A soft stop (k_s = 8,000 N/m) at 2 cm: spring and stop share the weight,
        // K d + k_s (d − 0.02) = M g.
        let (mut world, _, j) = rig(mode, 200.0);
        let ks: Real = 8000.0;
        j.wheel_mut(&mut world)
            .unwrap()
            .suspension_limit_mut()
            .set_limits(
                kea::SingleLimit::soft(-0.1, ks, 400.0),
                kea::SingleLimit::soft(0.02, ks, 400.0),
            )
            .unwrap();
        for _ in 0..600 {
            world.step(1.0 / 60.0).unwrap();
        }
        let d = j.get(&world).unwrap().suspension_position();
        let expected = (M * 9.81 + ks * 0.02) / (K + ks);
        assert!(
            (d - expected).abs() < 0.02 * expected,
            "{mode:?}: soft stop at {d}, expected {expected}"
        );
    }
}
