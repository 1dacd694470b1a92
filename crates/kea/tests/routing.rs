//! Hybrid routing: small islands of joints exact, big ones split (joints direct inside the
//! substeps), with hysteresis, a per-body request for the exact path, visible stats; and bad
//! solver settings rejected with nothing changed.

use kea::{
    BodyDef, BodyHandle, IterativeParams, Real, Routing, SolverMode, SolverPath, Vec3, World,
};

/// A chain of `n` ball-jointed bodies hanging from the world: 3n rows in one island.
fn chain(
    world: &mut World,
    n: usize,
    x0: Real,
) -> (Vec<BodyHandle>, Vec<kea::JointHandle<kea::BallJoint>>) {
    let (mut bodies, mut joints, mut prev) = (Vec::new(), Vec::new(), None);
    for i in 0..n {
        let p = Vec3::new(x0, -(i as Real + 1.0) * 0.2, 0.0);
        let b = world
            .create_body(&BodyDef {
                position: p,
                ..Default::default()
            })
            .unwrap();
        joints.push(
            world
                .create_joint(b, prev, kea::JointSpec::ball(p + Vec3::new(0.0, 0.2, 0.0)))
                .unwrap(),
        );
        bodies.push(b);
        prev = Some(b);
    }
    (bodies, joints)
}

#[test]
fn hybrid_sends_small_islands_exact_and_big_ones_split() {
    let mut world = World::with_capacity(64, 64).unwrap();
    // The maximal paths (a tree of ball joints on the world would step in reduced coordinates).
    world
        .update_settings(|s| s.routing.max_reduced_links = 0)
        .unwrap();
    chain(&mut world, 3, 0.0); // 9 rows
    chain(&mut world, 30, 5.0); // 90 rows
    let stats = world.step(1.0 / 60.0).unwrap();
    assert_eq!(
        (
            stats.solver.exact_islands,
            stats.solver.split_islands,
            stats.solver.iterative_islands
        ),
        (1, 1, 0)
    );
    assert_eq!(
        (
            stats.solver.exact_rows,
            stats.solver.split_rows,
            stats.solver.direct_rows,
            stats.solver.iterative_rows
        ),
        (9, 90, 90, 0)
    );
    // Two direct solves a substep (biased, relax), four substeps, then up to three
    // post-stabilisation passes.
    assert!(
        (8..=11).contains(&stats.solver.direct_solves),
        "{}",
        stats.solver.direct_solves
    );
    let reports = world.island_reports();
    assert_eq!(reports.len(), 2);
    assert_eq!(
        (reports[0].path, reports[0].rows, reports[0].bodies),
        (SolverPath::Exact, 9, 3)
    );
    assert_eq!(
        (reports[1].path, reports[1].rows, reports[1].bodies),
        (SolverPath::Split, 90, 30)
    );
    assert!(reports[0].iterations >= 1 && reports[1].iterations >= 1);
    assert!(stats.solver.time_solve >= stats.solver.time_solve_exact);
}

#[test]
fn an_island_near_the_threshold_does_not_flip() {
    let mut world = World::with_capacity(32, 32).unwrap();
    let (bodies, joints) = chain(&mut world, 24, 0.0); // 72 rows > 64: split
    world.step(1.0 / 60.0).unwrap();
    assert_eq!(world.island_reports()[0].path, SolverPath::Split);
    // Shorten to 20 links (60 rows ≤ 64) — but it was split, and 60 > 0.75 × 64.
    for &j in &joints[20..] {
        world.destroy_constraint(j).unwrap();
    }
    for &b in &bodies[20..] {
        world.destroy_body(b).unwrap();
    }
    for _ in 0..5 {
        world.step(1.0 / 60.0).unwrap();
        assert_eq!(
            world.island_reports()[0].path,
            SolverPath::Split,
            "flipped back too soon"
        );
    }
    // Down to 15 links (45 rows < 48): exact again.
    for &b in &bodies[15..20] {
        world.destroy_body(b).unwrap();
    }
    world.step(1.0 / 60.0).unwrap();
    assert_eq!(world.island_reports()[0].path, SolverPath::Exact);
    assert_eq!(
        world.body(bodies[0]).unwrap().last_solver_path(),
        SolverPath::Exact
    );
}

#[test]
fn a_body_can_ask_for_the_exact_path_and_the_world_can_force_any() {
    let mut world = World::with_capacity(64, 64).unwrap();
    let (bodies, _) = chain(&mut world, 30, 0.0);
    world.body_mut(bodies[7]).unwrap().set_prefer_exact(true);
    assert_eq!(world.step(1.0 / 60.0).unwrap().solver.exact_islands, 1);
    world.body_mut(bodies[7]).unwrap().set_prefer_exact(false);
    assert_eq!(world.step(1.0 / 60.0).unwrap().solver.split_islands, 1);
    // A small island, forced each way.
    let mut small = World::with_capacity(8, 8).unwrap();
    chain(&mut small, 2, 0.0);
    small
        .update_settings(|s| {
            s.routing = Routing {
                mode: SolverMode::Iterative,
                ..Default::default()
            }
        })
        .unwrap();
    assert_eq!(small.step(1.0 / 60.0).unwrap().solver.iterative_islands, 1);
    small
        .update_settings(|s| {
            s.routing = Routing {
                mode: SolverMode::Exact,
                ..Default::default()
            }
        })
        .unwrap();
    assert_eq!(small.step(1.0 / 60.0).unwrap().solver.exact_islands, 1);
    small
        .update_settings(|s| {
            s.routing = Routing {
                mode: SolverMode::Split,
                ..Default::default()
            }
        })
        .unwrap();
    assert_eq!(small.step(1.0 / 60.0).unwrap().solver.split_islands, 1);
    assert_eq!(small.island_reports()[0].path, SolverPath::Split);
}

#[test]
fn bad_solver_settings_are_rejected_and_change_nothing() {
    let mut world = World::with_capacity(4, 4).unwrap();
    let before = (
        world.settings().iterative,
        world.settings().routing,
        world.settings().projection_iterations,
    );
    let cases: Vec<(IterativeParams, &str, &str)> = vec![
        (
            IterativeParams {
                substeps: 0,
                ..Default::default()
            },
            "substeps",
            "0",
        ),
        (
            IterativeParams {
                substeps: 1000,
                ..Default::default()
            },
            "substeps",
            "1000",
        ),
        (
            IterativeParams {
                iterations: 0,
                ..Default::default()
            },
            "iterations",
            "0",
        ),
        (
            IterativeParams {
                max_correction_speed: -1.0,
                ..Default::default()
            },
            "max_correction_speed",
            "-1",
        ),
        (
            IterativeParams {
                max_correction_speed: Real::NAN,
                ..Default::default()
            },
            "max_correction_speed",
            "NaN",
        ),
    ];
    for (p, arg, value) in cases {
        let e = world
            .update_settings(|s| s.iterative = p)
            .unwrap_err()
            .to_string();
        assert!(e.contains(arg) && e.contains(value), "{e}");
    }
    for h in [0.0 as Real, 1.5, Real::NAN] {
        let e = world
            .update_settings(|s| {
                s.routing = Routing {
                    hysteresis: h,
                    ..Default::default()
                }
            })
            .unwrap_err()
            .to_string();
        assert!(e.contains("hysteresis"), "{e}");
    }
    let e = world
        .update_settings(|s| {
            s.routing = Routing {
                stack_bodies: 0,
                ..Default::default()
            }
        })
        .unwrap_err()
        .to_string();
    assert!(e.contains("stack_bodies") && e.contains('0'), "{e}");
    let e = world
        .update_settings(|s| s.projection_iterations = 17)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("projection_iterations") && e.contains("17"),
        "{e}"
    );
    assert_eq!(
        (
            world.settings().iterative,
            world.settings().routing,
            world.settings().projection_iterations
        ),
        before
    );
}
