//! VALIDATION #1: free fall follows the semi-implicit Euler recurrence to round-off, and ½gt²
//! with the known O(h) error ½·g·h·t.

mod common;
use common::F64;
use kea::{BodyDef, Mat3, Real, Vec3, World};

fn drop(h: Real, steps: usize) -> (Vec<Real>, Vec<Real>) {
    let mut world = World::with_capacity(4, 4).unwrap();
    let ball = world
        .create_body(&BodyDef {
            position: Vec3::new(0.0, 100.0, 0.0),
            linear_velocity: Vec3::new(1.0, 2.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    let mut y = Vec::new();
    let mut vy = Vec::new();
    for _ in 0..steps {
        world.step(h).unwrap();
        let b = world.body(ball).unwrap();
        y.push(b.position().y);
        vy.push(b.linear_velocity().y);
    }
    (y, vy)
}

#[test]
fn free_fall_matches_discrete_recurrence() {
    let h: Real = 1.0 / 60.0;
    let g: Real = -9.81;
    let (y, vy) = drop(h, 300);
    let tol: Real = if F64 { 1e-12 } else { 2e-5 };
    for (i, (&yn, &vn)) in y.iter().zip(&vy).enumerate() {
        let n = (i + 1) as Real;
        let t = n * h;
        let y_exact = 100.0 + 2.0 * t + 0.5 * g * h * h * n * (n + 1.0);
        let v_exact = 2.0 + g * t;
        // Relative to the problem's scale (100 m), since y crosses zero.
        assert!(
            ((yn - y_exact) / 100.0).abs() < tol,
            "step {n}: {yn} vs {y_exact}"
        );
        assert!(
            (vn - v_exact).abs() < tol * 100.0,
            "step {n}: v {vn} vs {v_exact}"
        );
    }
}

#[test]
fn free_fall_error_against_half_g_t_squared_is_first_order() {
    // Semi-implicit Euler gives y_n − (y₀ + v₀t + ½gt²) = ½·g·h·t exactly; halving h halves it.
    let g: Real = -9.81;
    let mut errors = Vec::new();
    for &h in &[0.02 as Real, 0.01, 0.005] {
        let steps = (1.0 / h).round() as usize;
        let (y, _) = drop(h, steps);
        let t: Real = 1.0;
        let continuous = 100.0 + 2.0 * t + 0.5 * g * t * t;
        let err = y[steps - 1] - continuous;
        let predicted = 0.5 * g * h * t;
        assert!(
            (err - predicted).abs() < if F64 { 1e-9 } else { 2e-4 },
            "h={h}: {err} vs {predicted}"
        );
        errors.push(err);
    }
    assert!((errors[0] / errors[1] - 2.0).abs() < 1e-2);
    assert!((errors[1] / errors[2] - 2.0).abs() < 1e-2);
}

#[test]
fn forces_are_applied_for_one_step_and_cleared() {
    let mut world = World::with_capacity(2, 2).unwrap();
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let b = world
        .create_body(&BodyDef {
            mass: 2.0,
            ..Default::default()
        })
        .unwrap();
    world
        .body_mut(b)
        .unwrap()
        .add_force(Vec3::new(4.0, 0.0, 0.0))
        .unwrap();
    world.step(0.5).unwrap();
    let body = world.body(b).unwrap();
    assert!((body.linear_velocity().x - 1.0).abs() < 1e-6); // a = 2 m/s² for 0.5 s
    assert!((body.linear_acceleration().x - 2.0).abs() < 1e-5);
    assert_eq!(body.force(), Vec3::ZERO);
    world.step(0.5).unwrap();
    assert!((world.body(b).unwrap().linear_velocity().x - 1.0).abs() < 1e-6);
}

#[test]
fn force_at_a_point_off_the_centre_moves_and_turns_the_body_after_a_step() {
    // A body away from the origin, turned, with three different moments of inertia: a force
    // at a point off its centre gives a = f / m and α = I_w⁻¹ ((p − x) × f) over a step.
    let mut world = World::with_capacity(2, 2).unwrap();
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let (m, centre) = (2.5, Vec3::new(3.0, -1.0, 2.0));
    let orientation = kea::Quat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1);
    let inertia = Mat3::from_diagonal(Vec3::new(0.4, 0.9, 1.6));
    let b = world
        .create_body(&BodyDef {
            mass: m,
            inertia,
            position: centre,
            orientation,
            ..BodyDef::default()
        })
        .unwrap();
    let (f, lever) = (Vec3::new(0.5, 1.0, -2.0), Vec3::new(2.0, 0.0, 0.5));
    world
        .body_mut(b)
        .unwrap()
        .add_force_at_point(f, centre + lever)
        .unwrap();
    let torque = lever.cross(f);
    let body = world.body(b).unwrap();
    assert!((body.force() - f).length() < 1e-6);
    assert!(
        (body.torque() - torque).length() < 1e-5,
        "{}",
        body.torque()
    );
    let h = 0.1;
    world.step(h).unwrap();
    let body = world.body(b).unwrap();
    assert!((body.linear_acceleration() - f / m).length() < 1e-5);
    assert!((body.linear_velocity() - f / m * h).length() < 1e-5);
    // The torque's impulse is the angular momentum gained, I_w ω = (p − x) × f · h, whatever
    // the body turned through meanwhile (free rotation keeps it), and at the start the
    // angular acceleration is I_w⁻¹ τ to first order in h.
    let r = Mat3::from_quat(body.orientation());
    let momentum = r * inertia * r.transpose() * body.angular_velocity();
    assert!(
        (momentum - torque * h).length() < 1e-5 * torque.length().max(1.0),
        "{momentum} vs {}",
        torque * h
    );
    let r0 = Mat3::from_quat(orientation);
    let alpha = r0 * inertia.inverse() * r0.transpose() * torque;
    assert!(
        (body.angular_acceleration() - alpha).length() < 0.05 * alpha.length(),
        "{} vs {alpha}",
        body.angular_acceleration()
    );
    // The accumulators are spent by the step.
    assert_eq!((body.force(), body.torque()), (Vec3::ZERO, Vec3::ZERO));
}

#[test]
fn damping_is_implicit_and_exact() {
    // v_{n+1} = v_n / (1 + h d / m)
    let mut world = World::with_capacity(2, 2).unwrap();
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let b = world
        .create_body(&BodyDef {
            mass: 2.0,
            linear_velocity: Vec3::new(3.0, 0.0, 0.0),
            linear_damping: 4.0,
            ..Default::default()
        })
        .unwrap();
    let h: Real = 0.1;
    for _ in 0..10 {
        world.step(h).unwrap();
    }
    let expected = 3.0 / (1.0 + h * 4.0 / 2.0 as Real).powi(10);
    let v = world.body(b).unwrap().linear_velocity().x;
    assert!((v - expected).abs() < 1e-5, "{v} vs {expected}");
}
