//! The solver without a world (the guide's KeaOnly): bodies and rows in, states and forces out.
//! It gives bit-identical results to the world for the same problem, reports islands, and
//! rejects inconsistent input.

use kea::constraint::ball::write_anchor_rows;
use kea::constraint::RowBody;
use kea::solver::ConstraintBlock;
use kea::{
    inertia, BodyDef, Quat, Reaction, Real, Routing, Row, RowWriter, Solver, SolverBody,
    SolverMode, SolverParams, Vec3, World,
};

const ANCHOR: Vec3 = Vec3::new(0.0, 0.0, 1.0);
const LOCAL: Vec3 = Vec3::new(-1.0, 0.0, 0.0);

/// The body as the joint's rows see it: pose and spin (the world's ball joint writes the
/// same, its anchors' curvature included).
fn row_body(b: &SolverBody) -> RowBody {
    RowBody {
        angular_velocity: b.angular_velocity,
        linear_velocity: b.linear_velocity,
        ..RowBody::fixed(b.position, b.orientation)
    }
}

fn cuboid_inertia() -> kea::Mat3 {
    inertia::solid_box(2.0, Vec3::new(0.15, 0.15, 1.5)).unwrap()
}

#[test]
fn kea_only_pendulum_matches_the_world_bit_for_bit() {
    let h: Real = 0.01;
    let g = Vec3::new(0.0, -10.0, 0.0);
    let start = Vec3::new(1.0, 0.0, 1.0);
    let v0 = Vec3::new(0.0, 0.0, 1.0);

    // Immediate mode.
    let mut bodies = [SolverBody::new(
        2.0,
        cuboid_inertia(),
        start,
        Quat::IDENTITY,
    )];
    bodies[0].linear_velocity = v0;
    let params = SolverParams {
        dt: h,
        gravity: g,
        ..Default::default()
    };
    let mut solver = Solver::new();
    let mut rows: Vec<Row> = Vec::new();
    let mut lambda = vec![0.0; 3];
    let mut reactions = [[Reaction::default(); 2]];

    // Retained mode, without the world's extra position projection (the raw solver is compared).
    let mut world = World::with_capacity(2, 2).unwrap();
    // The maximal paths (a tree of ball joints on the world would step in reduced coordinates).
    world
        .update_settings(|s| s.routing.max_reduced_links = 0)
        .unwrap();
    world
        .update_settings(|s| s.projection_iterations = 0)
        .unwrap();
    world.update_settings(|s| s.gravity = g).unwrap();
    let b = world
        .create_body(&BodyDef {
            mass: 2.0,
            inertia: cuboid_inertia(),
            position: start,
            linear_velocity: v0,
            ..Default::default()
        })
        .unwrap();
    let joint = world
        .create_joint(b, None, kea::JointSpec::ball(ANCHOR))
        .unwrap();

    for _ in 0..500 {
        rows.clear();
        let body = &bodies[0];
        let a1 = body.position + body.orientation * LOCAL;
        write_anchor_rows(
            &row_body(body),
            &RowBody::STATIC,
            a1,
            ANCHOR,
            h,
            &mut RowWriter::new(&mut rows),
        );
        let blocks = [ConstraintBlock {
            bodies: [Some(0), None],
            first_row: 0,
            row_count: 3,
        }];
        let stats = solver
            .step(
                &mut bodies,
                &blocks,
                &rows,
                &mut [],
                &params,
                &mut lambda,
                &mut reactions,
            )
            .unwrap();
        assert_eq!(stats.islands, 1);
        world.step(h).unwrap();
        let wb = world.body(b).unwrap();
        assert_eq!(bodies[0].position, wb.position());
        assert_eq!(bodies[0].orientation, wb.orientation());
        assert_eq!(lambda.as_slice(), world.constraint_lambdas(joint).unwrap());
    }
    // The reaction is the force on the body: with the constraint force reported in the body.
    assert_eq!(reactions[0][0].force, bodies[0].constraint_force);
    let gap = (bodies[0].position + bodies[0].orientation * LOCAL - ANCHOR).length();
    // Velocity-level rows drift by (v h)²/(2r) per step on a curved path, removed at rate γ.
    assert!(gap < 5e-3, "joint gap {gap}");
}

#[test]
fn islands_are_independent_and_static_bodies_do_not_join_them() {
    let mut world = World::with_capacity(8, 8).unwrap();
    // The maximal paths (a tree of ball joints on the world would step in reduced coordinates).
    world
        .update_settings(|s| s.routing.max_reduced_links = 0)
        .unwrap();
    let mk = |w: &mut World, x: Real| {
        w.create_body(&BodyDef {
            position: Vec3::new(x, -1.0, 0.0),
            ..Default::default()
        })
        .unwrap()
    };
    let a = mk(&mut world, 0.0);
    let b = mk(&mut world, 3.0);
    let c = mk(&mut world, 6.0);
    let fixed = mk(&mut world, 9.0);
    world.body_mut(fixed).unwrap().set_enabled(false);
    world
        .create_joint(a, None, kea::JointSpec::ball(Vec3::new(0.0, 0.0, 0.0)))
        .unwrap();
    world
        .create_joint(
            b,
            Some(fixed),
            kea::JointSpec::ball(Vec3::new(3.0, 0.0, 0.0)),
        )
        .unwrap();
    world
        .create_joint(
            c,
            Some(fixed),
            kea::JointSpec::ball(Vec3::new(6.0, 0.0, 0.0)),
        )
        .unwrap();
    let stats = world.step(0.01).unwrap();
    assert_eq!(
        stats.solver.islands, 3,
        "the disabled body must not merge b and c"
    );
    assert_eq!(stats.bodies, 3);
    assert_eq!(
        world.body(fixed).unwrap().position(),
        Vec3::new(9.0, -1.0, 0.0)
    );
    // Joining a and b makes one island of them.
    world
        .create_joint(a, Some(b), kea::JointSpec::ball(Vec3::new(1.5, -1.0, 0.0)))
        .unwrap();
    assert_eq!(world.step(0.01).unwrap().solver.islands, 2);
}

#[test]
fn same_inputs_give_bit_identical_results() {
    for mode in [SolverMode::Exact, SolverMode::Iterative] {
        let run = || chain_run(mode);
        assert_eq!(run(), run(), "{mode:?}");
    }
}

fn chain_run(mode: SolverMode) -> Vec<(Vec3, Quat, Vec3)> {
    {
        let mut world = World::with_capacity(8, 8).unwrap();
        // The maximal paths (a tree of ball joints on the world would step in reduced coordinates).
        world
            .update_settings(|s| s.routing.max_reduced_links = 0)
            .unwrap();
        world
            .update_settings(|s| {
                s.routing = Routing {
                    mode,
                    ..Default::default()
                }
            })
            .unwrap();
        let mut prev = None;
        let mut handles = Vec::new();
        for i in 0..5 {
            let b = world
                .create_body(&BodyDef {
                    position: Vec3::new(i as Real * 0.5 + 0.5, -0.1 * i as Real, 0.0),
                    inertia: inertia::solid_box(1.0, Vec3::new(0.25, 0.05, 0.1)).unwrap(),
                    ..Default::default()
                })
                .unwrap();
            let anchor = Vec3::new(i as Real * 0.5, 0.0, 0.0);
            world
                .create_joint(b, prev, kea::JointSpec::ball(anchor))
                .unwrap();
            prev = Some(b);
            handles.push(b);
        }
        for _ in 0..300 {
            world.step(1.0 / 60.0).unwrap();
        }
        handles
            .iter()
            .map(|&h| {
                let b = world.body(h).unwrap();
                (b.position(), b.orientation(), b.angular_velocity())
            })
            .collect::<Vec<_>>()
    }
}

#[test]
fn inconsistent_immediate_input_is_rejected_without_change() {
    let mut bodies = [SolverBody::new(
        1.0,
        kea::Mat3::IDENTITY,
        Vec3::ZERO,
        Quat::IDENTITY,
    )];
    let before = bodies;
    let rows = [Row::new(
        kea::Jacobian::new(Vec3::X, Vec3::ZERO),
        kea::Jacobian::ZERO,
    )];
    let mut lambda = [0.0];
    let mut reactions = [[Reaction::default(); 2]];
    let mut solver = Solver::new();
    let params = SolverParams::default();
    let bad_block = [ConstraintBlock {
        bodies: [Some(3), None],
        first_row: 0,
        row_count: 1,
    }];
    let e = solver
        .step(
            &mut bodies,
            &bad_block,
            &rows,
            &mut [],
            &params,
            &mut lambda,
            &mut reactions,
        )
        .unwrap_err();
    assert!(
        e.to_string().contains("blocks") && e.to_string().contains("body 3"),
        "{e}"
    );
    let block = [ConstraintBlock {
        bodies: [Some(0), None],
        first_row: 0,
        row_count: 2,
    }];
    let e = solver
        .step(
            &mut bodies,
            &block,
            &rows,
            &mut [],
            &params,
            &mut lambda,
            &mut reactions,
        )
        .unwrap_err();
    assert!(e.to_string().contains("rows up to 2"), "{e}");
    let bad_params = SolverParams {
        dt: -1.0,
        ..Default::default()
    };
    let block = [ConstraintBlock {
        bodies: [Some(0), None],
        first_row: 0,
        row_count: 1,
    }];
    let e = solver
        .step(
            &mut bodies,
            &block,
            &rows,
            &mut [],
            &bad_params,
            &mut lambda,
            &mut reactions,
        )
        .unwrap_err();
    assert!(e.to_string().contains("dt"), "{e}");
    assert_eq!(bodies, before);
}

#[test]
fn memory_required_covers_what_a_step_uses() {
    // A solver that reserved nothing grows to what the problem needs; the guide's
    // MdtKeaMemoryRequired counterpart must be an upper bound of it.
    let mut solver = Solver::new();
    let mut bodies = [SolverBody::new(
        2.0,
        cuboid_inertia(),
        Vec3::new(1.0, 0.0, 1.0),
        Quat::IDENTITY,
    )];
    let mut rows: Vec<Row> = Vec::new();
    let b = &bodies[0];
    let a1 = b.position + b.orientation * LOCAL;
    write_anchor_rows(
        &row_body(b),
        &RowBody::STATIC,
        a1,
        ANCHOR,
        SolverParams::default().dt,
        &mut RowWriter::new(&mut rows),
    );
    let blocks = [ConstraintBlock {
        bodies: [Some(0), None],
        first_row: 0,
        row_count: 3,
    }];
    let mut lambda = [0.0; 3];
    let mut reactions = [[Reaction::default(); 2]];
    let stats = solver
        .step(
            &mut bodies,
            &blocks,
            &rows,
            &mut [],
            &SolverParams::default(),
            &mut lambda,
            &mut reactions,
        )
        .unwrap();
    assert!(stats.workspace_grew);
    let used = solver.memory_used();
    let required = kea::solver::memory_required(&[3], 1);
    assert!(
        used > 0 && used <= required,
        "used {used} > required {required}"
    );
    // The high-water mark is what the step needed, not what is held.
    assert_eq!(solver.memory_high_water(), required);
}

#[test]
fn the_memory_pool_size_is_the_most_any_step_needed_not_what_was_reserved() {
    // Reserved for 64 bodies up front, nothing used yet: the pool is empty.
    let mut world = World::with_capacity(64, 256).unwrap();
    // The maximal paths (a tree of ball joints on the world would step in reduced coordinates).
    world
        .update_settings(|s| s.routing.max_reduced_links = 0)
        .unwrap();
    assert!(world.reserved_bytes() > 0);
    assert_eq!(world.memory_pool_size(), 0);
    let chain = |world: &mut World, n: usize| {
        let mut last = None;
        let mut bodies = Vec::new();
        for k in 0..n {
            let b = world
                .create_body(&kea::BodyDef {
                    position: Vec3::new(k as kea::Real + 1.0, 0.0, 0.0),
                    ..kea::BodyDef::default()
                })
                .unwrap();
            world
                .create_joint(
                    b,
                    last,
                    kea::JointSpec::ball(Vec3::new(k as kea::Real + 0.5, 0.0, 0.0)),
                )
                .unwrap();
            last = Some(b);
            bodies.push(b);
        }
        bodies
    };
    let small = chain(&mut world, 2);
    world.step(0.01).unwrap();
    let after_small = world.memory_pool_size();
    assert!(after_small > 0);
    assert!(after_small <= kea::solver::memory_required(&[6], 2));
    // A bigger island raises the mark ...
    let big = chain(&mut world, 12);
    world.step(0.01).unwrap();
    let after_big = world.memory_pool_size();
    assert!(after_big > after_small, "{after_big} <= {after_small}");
    // ... which stays when the island goes: it is the most used so far.
    for b in big {
        world.destroy_body(b).unwrap();
    }
    world.step(0.01).unwrap();
    assert_eq!(world.memory_pool_size(), after_big);
    assert!(!small.is_empty());
}
