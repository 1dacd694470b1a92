//! VALIDATION #7 and #8: Coulomb friction on a slope (hold above tanθ, slide with
//! a = g(sinθ − μcosθ) below), and box friction holding up to n_contacts × F_max.

mod common;
use common::{box_plane_contacts, clear_contacts, ground_box_contacts};
use kea::{inertia, BodyDef, ContactParams, FrictionModel, Quat, Real, Vec3, World};

const HALF: Vec3 = Vec3::new(0.5, 0.25, 0.5);
const G: Real = 9.81;

/// Runs a box on a slope of angle `theta` (descending towards +x) with Coulomb `mu` for
/// `seconds`; returns (distance along the slope over time) samples at each step.
fn slope_run(theta: Real, mu: Real, seconds: Real, h: Real) -> Vec<Real> {
    let mut world = World::with_capacity(4, 32).unwrap();
    let n = Vec3::new(theta.sin(), theta.cos(), 0.0); // slope normal
    let down = Vec3::new(theta.cos(), -theta.sin(), 0.0); // down-slope direction
    let rot = Quat::from_rotation_z(-theta);
    let start = n * HALF.y;
    let body = world
        .create_body(&BodyDef {
            position: start,
            orientation: rot,
            inertia: inertia::solid_box(1.0, HALF).unwrap(),
            ..Default::default()
        })
        .unwrap();
    let params = ContactParams {
        friction: [FrictionModel::Coulomb { mu }; 2],
        ..Default::default()
    };
    let mut contacts = Vec::new();
    let mut s = Vec::new();
    let steps = (seconds / h).round() as usize;
    for _ in 0..steps {
        clear_contacts(&mut world, &mut contacts);
        box_plane_contacts(
            &mut world,
            body,
            HALF,
            n,
            0.0,
            0.01,
            params,
            None,
            &mut contacts,
        );
        let stats = world.step(h).unwrap();
        assert!(stats.solver.is_clean(), "{stats:?}");
        s.push((world.body(body).unwrap().position() - start).dot(down));
    }
    s
}

#[test]
fn block_holds_on_slope_when_mu_exceeds_tan_theta() {
    let theta: Real = 0.35; // ~20°
    let mu = 1.05 * theta.tan();
    let s = slope_run(theta, mu, 5.0, 1.0 / 60.0);
    let drift = s.last().unwrap().abs();
    eprintln!("slope hold drift {drift:e} m");
    assert!(drift < 1.0e-3, "drift {drift} m");
}

#[test]
fn block_slides_with_coulomb_acceleration() {
    let theta: Real = 0.35;
    let mu = 0.5 * theta.tan();
    let h: Real = 1.0 / 60.0;
    let s = slope_run(theta, mu, 2.0, h);
    // Fit the acceleration from positions at 0.5 s and 2 s: s = ½ a t² + v₀ t + s₀.
    let a_expected = G * (theta.sin() - mu * theta.cos());
    let (i1, i2, i3) = (30usize, 75usize, 120usize);
    let t = |i: usize| (i + 1) as Real * h;
    // Second difference over equal intervals.
    let dt = t(i2) - t(i1);
    let a = (s[i3 - 1] - 2.0 * s[i2 - 1] + s[i1 - 1]) / (dt * dt);
    let rel = (a - a_expected).abs() / a_expected;
    eprintln!("slope slide a = {a}, expected {a_expected}, rel {rel:e}");
    assert!(rel < 5.0e-3, "a = {a}, expected {a_expected} (rel {rel})");
}

fn push_run(push: Real, max_force: Real, seconds: Real) -> (Real, Real) {
    let h: Real = 1.0 / 60.0;
    let mut world = World::with_capacity(4, 32).unwrap();
    let body = world
        .create_body(&BodyDef {
            position: Vec3::new(0.0, HALF.y, 0.0),
            inertia: inertia::solid_box(1.0, HALF).unwrap(),
            ..Default::default()
        })
        .unwrap();
    let params = ContactParams {
        friction: [FrictionModel::Box { max_force }; 2],
        ..Default::default()
    };
    let mut contacts = Vec::new();
    let steps = (seconds / h).round() as usize;
    let mut v_half = 0.0;
    for i in 0..steps {
        clear_contacts(&mut world, &mut contacts);
        ground_box_contacts(&mut world, body, HALF, params, None, &mut contacts);
        world
            .body_mut(body)
            .unwrap()
            .add_force(Vec3::new(push, 0.0, 0.0))
            .unwrap();
        world.step(h).unwrap();
        if i + 1 == steps / 2 {
            v_half = world.body(body).unwrap().linear_velocity().x;
        }
    }
    let b = world.body(body).unwrap();
    let a = (b.linear_velocity().x - v_half) / (seconds / 2.0);
    (b.position().x, a)
}

#[test]
fn box_friction_holds_below_its_limit_and_slides_above() {
    let f_max: Real = 1.0; // per contact, 4 contacts
    let (x, _) = push_run(0.98 * 4.0 * f_max, f_max, 3.0);
    assert!(x.abs() < 1.0e-3, "held box moved {x}");
    let (x, _) = push_run(1.02 * 4.0 * f_max, f_max, 3.0);
    assert!(x > 0.05, "box above its limit moved only {x}");
    // Sliding: a = (P − 4 F_max)/m
    let (_, a) = push_run(6.0, f_max, 2.0);
    eprintln!("box friction: sliding a = {a} (expected 2)");
    assert!((a - 2.0).abs() < 0.02 * 2.0, "sliding acceleration {a}");
}
