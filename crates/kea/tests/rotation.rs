//! VALIDATION #2–#4: constant torque, the torque-free symmetric top, and the tennis-racket flip,
//! with |L| conserved; plus the fast-spin axis.

mod common;
use common::F64;
use kea::{inertia, BodyDef, Quat, Real, Vec3, World};

fn free_world() -> World {
    let mut w = World::with_capacity(4, 4).unwrap();
    w.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    w
}

#[test]
fn constant_torque_about_principal_axis_gives_linear_spin_up() {
    let mut world = free_world();
    let i = inertia::solid_box(3.0, Vec3::new(0.5, 1.0, 1.5)).unwrap();
    let b = world
        .create_body(&BodyDef {
            mass: 3.0,
            inertia: i,
            ..Default::default()
        })
        .unwrap();
    let tau: Real = 2.0;
    let h: Real = 0.01;
    for _ in 0..500 {
        world
            .body_mut(b)
            .unwrap()
            .add_torque(Vec3::new(0.0, tau, 0.0))
            .unwrap();
        world.step(h).unwrap();
    }
    let w = world.body(b).unwrap().angular_velocity();
    let expected = tau * 5.0 / i.y_axis.y;
    let rel = (w.y - expected).abs() / expected;
    assert!(
        rel < if F64 { 1e-9 } else { 1e-5 },
        "ω = {w}, expected {expected}"
    );
    assert!(w.x.abs() < 1e-6 && w.z.abs() < 1e-6);
}

#[test]
fn torque_free_box_keeps_angular_momentum_and_flips_about_intermediate_axis() {
    let mut world = free_world();
    let half = Vec3::new(0.1, 0.4, 0.8); // I_x > I_y > I_z: y is the intermediate axis
    let i = inertia::solid_box(1.0, half).unwrap();
    let b = world
        .create_body(&BodyDef {
            inertia: i,
            angular_velocity: Vec3::new(0.01, 5.0, 0.01),
            ..Default::default()
        })
        .unwrap();
    let l0 = world.body(b).unwrap().angular_momentum();
    let e0 = world.body(b).unwrap().kinetic_energy();
    let h: Real = 1.0 / 60.0;
    let mut min_dot: Real = 1.0;
    let mut max_l_err: Real = 0.0;
    let mut max_e_err: Real = 0.0;
    for _ in 0..600 {
        world.step(h).unwrap();
        let body = world.body(b).unwrap();
        let l = body.angular_momentum();
        max_l_err = max_l_err.max((l.length() - l0.length()).abs() / l0.length());
        max_l_err = max_l_err.max((l - l0).length() / l0.length());
        max_e_err = max_e_err.max((body.kinetic_energy() - e0).abs() / e0);
        // The body's y axis starts along L; a flip turns it against L.
        min_dot = min_dot.min((body.orientation() * Vec3::Y).dot(l0.normalize()));
    }
    eprintln!("tennis racket: |L| rel err {max_l_err:e}, energy rel err {max_e_err:e}, min axis·L {min_dot}");
    assert!(
        max_l_err < if F64 { 1e-9 } else { 1e-4 },
        "|L| drift {max_l_err}"
    );
    assert!(min_dot < -0.9, "no flip: min dot {min_dot}");
    assert!(max_e_err < 2e-3, "energy drift {max_e_err}");
}

#[test]
fn symmetric_top_precesses_at_the_euler_rate() {
    // I₁ = I₂ ≠ I₃: in the body frame ω precesses about the symmetry axis at
    // Ω = (I₃ − I₁)/I₁ · ω₃, with ω₃ constant.
    let mut world = free_world();
    let i = Vec3::new(1.0, 1.0, 2.0);
    let w0 = Vec3::new(0.3, 0.0, 2.0);
    let b = world
        .create_body(&BodyDef {
            inertia: kea::Mat3::from_diagonal(i),
            angular_velocity: w0,
            ..Default::default()
        })
        .unwrap();
    let omega = (i.z - i.x) / i.x * w0.z;
    let h: Real = 1.0 / 60.0;
    let l0 = world.body(b).unwrap().angular_momentum();
    let mut angle: Real = 0.0;
    let mut prev = w0;
    let steps = 600;
    for _ in 0..steps {
        world.step(h).unwrap();
        let body = world.body(b).unwrap();
        let wb = body.orientation().inverse() * body.angular_velocity();
        assert!((wb.z - w0.z).abs() < 1e-3, "ω₃ drifted: {wb}");
        let d = prev.x * wb.y - prev.y * wb.x;
        let c = prev.x * wb.x + prev.y * wb.y;
        angle += d.atan2(c);
        prev = wb;
    }
    let l = world.body(b).unwrap().angular_momentum();
    assert!((l - l0).length() / l0.length() < if F64 { 1e-9 } else { 1e-5 });
    let measured = angle / (steps as Real * h);
    // Body-frame precession runs opposite to the spin for an oblate top: compare magnitudes.
    let rel = (measured.abs() - omega.abs()) / omega.abs();
    eprintln!("symmetric top: Ω = {measured} rad/s, expected ±{omega} (rel {rel:e})");
    assert!(rel.abs() < 0.01, "precession {measured} vs {omega}");
}

#[test]
fn fast_spin_axis_rotates_exactly_about_the_axle() {
    let mut world = free_world();
    let b = world
        .create_body(&BodyDef {
            inertia: inertia::solid_cylinder(1.0, 0.3, 0.1).unwrap(),
            angular_velocity: Vec3::new(0.0, 200.0, 0.0),
            fast_spin_axis: Some(Vec3::Y),
            ..Default::default()
        })
        .unwrap();
    let h: Real = 1.0 / 60.0;
    for _ in 0..10 {
        world.step(h).unwrap();
    }
    let q = world.body(b).unwrap().orientation();
    let expected = Quat::from_rotation_y(200.0 * h * 10.0);
    assert!(q.dot(expected).abs() > 1.0 - 1e-5, "{q} vs {expected}");
    assert!(((q * Vec3::Y) - Vec3::Y).length() < 1e-5, "axle tilted");
}
