//! VALIDATION #5: a ball-joint pendulum (small sphere) swings with T = 2π√(L/g)(1 + θ₀²/16)
//! within 0.5% at 60 Hz, and the joint gap stays below 1 mm.

mod common;
use common::{world_on, PATHS};
use kea::{inertia, BodyDef, Real, SolverMode, Vec3, PI_REAL};

#[test]
fn ball_joint_pendulum_period_and_joint_gap() {
    for mode in PATHS {
        pendulum(mode);
    }
}

fn pendulum(mode: SolverMode) {
    let l: Real = 1.0;
    let g: Real = 9.81;
    let theta0: Real = 5.0_f64.to_radians() as Real;
    let h: Real = 1.0 / 60.0;
    let mut world = world_on(mode, 4, 4);
    let r: Real = 0.02;
    let bob = world
        .create_body(&BodyDef {
            position: Vec3::new(l * theta0.sin(), -l * theta0.cos(), 0.0),
            inertia: inertia::solid_sphere(1.0, r).unwrap(),
            ..Default::default()
        })
        .unwrap();
    let joint = world
        .create_joint(bob, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    let mut crossings: Vec<Real> = Vec::new();
    let mut prev_x = world.body(bob).unwrap().position().x;
    let mut max_gap: Real = 0.0;
    for i in 0..1200 {
        let stats = world.step(h).unwrap();
        assert!(stats.solver.is_clean());
        let body = world.body(bob).unwrap();
        let p = body.position();
        let anchor = body.point_to_world(joint.get(&world).unwrap().local_anchor1);
        max_gap = max_gap.max(anchor.length()); // the socket is at the origin
        if prev_x > 0.0 && p.x <= 0.0 {
            // Interpolate the downward crossing time.
            let frac = prev_x / (prev_x - p.x);
            crossings.push((i as Real + frac) * h);
        }
        prev_x = p.x;
    }
    let periods: Vec<Real> = crossings.windows(2).map(|w| w[1] - w[0]).collect();
    let mean = periods.iter().sum::<Real>() / periods.len() as Real;
    // A sphere of radius r adds I = 2/5 m r² to the pendulum: a factor √(1 + 2r²/(5L²)).
    let expected = 2.0
        * PI_REAL
        * (l / g).sqrt()
        * (1.0 + theta0 * theta0 / 16.0)
        * (1.0 + 0.4 * r * r / (l * l)).sqrt();
    let rel = (mean - expected).abs() / expected;
    eprintln!("{mode:?}: pendulum: T = {mean} s, expected {expected} s (rel {rel:e}); max gap {max_gap:e} m; {} periods", periods.len());
    assert!(periods.len() >= 5);
    assert!(rel < 5.0e-3, "{mode:?}: period {mean} vs {expected}");
    assert!(max_gap < 1.0e-3, "{mode:?}: joint gap {max_gap}");
    // The joint force holds the bob: on average it balances gravity vertically.
    let f = world.constraint_reaction(joint).unwrap()[0].force;
    assert!(f.y > 0.9 * g && f.y < 1.1 * g, "{mode:?}: joint force {f}");
}

/// VALIDATION #29: a conical pendulum (1 m, a small sphere) set circling at 0.5 rad from the
/// vertical with `v² = g·r·tan θ` keeps its period `2πr/v` within 0.5% over 10 s at 60 Hz,
/// and its angle, on every path a user can force.
#[test]
fn conical_pendulum_period_on_every_path() {
    let g: Real = 9.81;
    let th: Real = 0.5;
    let (r, y) = (th.sin(), -th.cos());
    let v = (g * r * th.tan()).sqrt();
    let expected = 2.0 * PI_REAL * r / v;
    for mode in [
        SolverMode::Hybrid,
        SolverMode::Exact,
        SolverMode::Iterative,
        SolverMode::Split,
    ] {
        let mut world = world_on(mode, 2, 2);
        let bob = world
            .create_body(&BodyDef {
                position: Vec3::new(r, y, 0.0),
                linear_velocity: Vec3::new(0.0, 0.0, v),
                inertia: inertia::solid_sphere(1.0, 0.02).unwrap(),
                ..Default::default()
            })
            .unwrap();
        world
            .create_joint(bob, None, kea::JointSpec::ball(Vec3::ZERO))
            .unwrap();
        // The angle swept about the vertical, unwrapped.
        let (mut swept, mut last): (Real, Real) = (0.0, 0.0);
        for _ in 0..600 {
            world.step(1.0 / 60.0).unwrap();
            let p = world.body(bob).unwrap().position();
            let a = p.z.atan2(p.x);
            let mut d = a - last;
            if d < -PI_REAL {
                d += 2.0 * PI_REAL;
            }
            swept += d;
            last = a;
        }
        let period = 10.0 * 2.0 * PI_REAL / swept;
        let p = world.body(bob).unwrap().position();
        let angle = Vec3::new(p.x, 0.0, p.z).length().atan2(-p.y);
        let rel = (period - expected) / expected;
        eprintln!("{mode:?}: conical period {period:.4} s (expected {expected:.4}, {rel:+.2e}), angle {angle:.4} rad");
        assert!(
            rel.abs() < 5.0e-3,
            "{mode:?}: period {period} vs {expected}"
        );
        assert!((angle - th).abs() < 0.01, "{mode:?}: angle {angle}");
    }
}
