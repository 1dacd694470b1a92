//! VALIDATION #7 and #8, in both solver paths: Coulomb friction on a slope (hold above tanθ,
//! slide with a = g(sinθ − μcosθ) below), and box friction holding up to n_contacts × F_max.

mod common;
use common::{world_on, BoxPlaneContacts, PATHS};
use kea::{inertia, BodyDef, ContactParams, FrictionModel, Quat, Real, SolverMode, Vec3};

const HALF: Vec3 = Vec3::new(0.5, 0.25, 0.5);
const G: Real = 9.81;

/// Runs a box on a slope of angle `theta` (descending towards +x) with Coulomb `mu` for
/// `seconds`; returns the distance travelled down the slope after each step.
fn slope_run(mode: SolverMode, theta: Real, mu: Real, seconds: Real, h: Real) -> Vec<Real> {
    let mut world = world_on(mode, 4, 32);
    let n = Vec3::new(theta.sin(), theta.cos(), 0.0); // slope normal
    let down = Vec3::new(theta.cos(), -theta.sin(), 0.0); // down-slope direction
    let start = n * HALF.y;
    let body = world
        .create_body(&BodyDef {
            position: start,
            orientation: Quat::from_rotation_z(-theta),
            inertia: inertia::solid_box(1.0, HALF).unwrap(),
            ..Default::default()
        })
        .unwrap();
    let params = ContactParams {
        friction: [FrictionModel::Coulomb { mu }; 2],
        ..Default::default()
    };
    let mut contacts = BoxPlaneContacts::default();
    let mut s = Vec::new();
    for _ in 0..(seconds / h).round() as usize {
        contacts.update(&mut world, body, HALF, n, 0.0, 0.01, params, None);
        let stats = world.step(h).unwrap();
        assert!(stats.solver.is_clean(), "{stats:?}");
        s.push((world.body(body).unwrap().position() - start).dot(down));
    }
    s
}

#[test]
fn block_holds_on_slope_when_mu_exceeds_tan_theta() {
    let theta: Real = 0.35; // ~20°
    for mode in PATHS {
        let s = slope_run(mode, theta, 1.05 * theta.tan(), 5.0, 1.0 / 60.0);
        let drift = s.last().unwrap().abs();
        eprintln!("{mode:?}: slope hold drift {drift:e} m");
        assert!(drift < 1.0e-3, "{mode:?}: drift {drift} m");
    }
}

#[test]
fn block_slides_with_coulomb_acceleration() {
    let theta: Real = 0.35;
    let mu = 0.5 * theta.tan();
    let h: Real = 1.0 / 60.0;
    let a_expected = G * (theta.sin() - mu * theta.cos());
    let mut measured = Vec::new();
    for (mode, tol) in PATHS.into_iter().zip([5.0e-3, 2.0e-2]) {
        let s = slope_run(mode, theta, mu, 2.0, h);
        // Second difference of positions at 0.5 s, 1.25 s and 2 s.
        let (i1, i2, i3) = (30usize, 75usize, 120usize);
        let dt = (i2 - i1) as Real * h;
        let a = (s[i3 - 1] - 2.0 * s[i2 - 1] + s[i1 - 1]) / (dt * dt);
        let rel = (a - a_expected).abs() / a_expected;
        eprintln!("{mode:?}: slope slide a = {a}, expected {a_expected}, rel {rel:e}");
        assert!(
            rel < tol,
            "{mode:?}: a = {a}, expected {a_expected} (rel {rel})"
        );
        measured.push(a);
    }
    assert!(
        (measured[0] - measured[1]).abs() < 0.02 * a_expected,
        "paths disagree: {measured:?}"
    );
}

/// Pushes a box on flat ground with box friction; returns (final x, acceleration over the
/// second half).
fn push_run(mode: SolverMode, push: Real, max_force: Real, seconds: Real) -> (Real, Real) {
    let h: Real = 1.0 / 60.0;
    let mut world = world_on(mode, 4, 32);
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
    let mut contacts = BoxPlaneContacts::default();
    let steps = (seconds / h).round() as usize;
    let mut v_half = 0.0;
    for i in 0..steps {
        contacts.update(&mut world, body, HALF, Vec3::Y, 0.0, 0.01, params, None);
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
    for mode in PATHS {
        let (x, _) = push_run(mode, 0.98 * 4.0 * f_max, f_max, 3.0);
        assert!(x.abs() < 1.0e-3, "{mode:?}: held box moved {x}");
        let (x, _) = push_run(mode, 1.02 * 4.0 * f_max, f_max, 3.0);
        assert!(x > 0.05, "{mode:?}: box above its limit moved only {x}");
        // Sliding: a = (P − 4 F_max)/m
        let (_, a) = push_run(mode, 6.0, f_max, 2.0);
        eprintln!("{mode:?}: box friction sliding a = {a} (expected 2)");
        assert!(
            (a - 2.0).abs() < 0.02 * 2.0,
            "{mode:?}: sliding acceleration {a}"
        );
    }
}
