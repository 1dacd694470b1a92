//! The guide's KeaOnly example: a cuboid pendulum on a ball-and-socket joint, written against
//! the solver alone — no world. We build the body, write the joint's three rows with the row
//! helpers (the guide's MdtBcl), and call the solver each tick (the guide's MdtKeaStep).
//!
//! Run: `cargo run --release --example kea_only`

use kea::constraint::ball::write_anchor_rows;
use kea::constraint::RowBody;
use kea::solver::{memory_required, ConstraintBlock};
use kea::{Mat3, Quat, Reaction, Real, Row, RowWriter, Solver, SolverBody, SolverParams, Vec3};

const CUBOID_LENGTH: Real = 3.0;
const RATIO: Real = 10.0;
const MASS: Real = 2.0;

fn main() -> Result<(), kea::KeaError> {
    // Inertia of a solid cuboid, long along z (as in the guide's example).
    let ir = 1.0 / (RATIO * RATIO);
    let l2 = CUBOID_LENGTH * CUBOID_LENGTH;
    let inertia = Mat3::from_diagonal(Vec3::new(
        MASS * (1.0 + ir) * l2 / 12.0,
        MASS * (1.0 + ir) * l2 / 12.0,
        MASS * 2.0 * ir * l2 / 12.0,
    ));
    let mut bodies = [SolverBody::new(
        MASS,
        inertia,
        Vec3::new(1.0, 0.0, 1.0),
        Quat::IDENTITY,
    )];
    bodies[0].linear_velocity = Vec3::new(0.0, 0.0, 1.0);
    let joint_in_body = Vec3::new(-1.0, 0.0, 0.0); // pos1
    let joint_in_world = Vec3::new(0.0, 0.0, 1.0); // pos2

    let params = SolverParams {
        dt: 0.01,
        epsilon: 0.01,
        gamma: 0.2,
        ..Default::default()
    };
    let mut solver = Solver::with_capacity(1, 1, 3, 0, 3);
    println!(
        "kea_only: solver workspace {} bytes (memory_required for one 3-row island: {} bytes)",
        solver.memory_used(),
        memory_required(&[3], 1)
    );
    let blocks = [ConstraintBlock {
        bodies: [Some(0), None],
        first_row: 0,
        row_count: 3,
    }];
    let mut rows: Vec<Row> = Vec::with_capacity(3);
    let mut lambda = [0.0; 3];
    let mut reactions = [[Reaction::default(); 2]];
    println!(
        "{:>6} {:>26} {:>12} {:>26}",
        "t [s]", "centre of mass [m]", "gap [m]", "joint force on body [N]"
    );
    for tick in 1..=300 {
        // External forces are set every tick (here gravity, as the guide's UpdateCuboid does).
        bodies[0].force = Vec3::new(0.0, -10.0, 0.0) * MASS;
        // The joint's rows for the current state (the guide's UpdateBallAndSocketJoint).
        let b = &bodies[0];
        let p = b.orientation * joint_in_body;
        rows.clear();
        // Its pose and spin: the rows' anchor and their curvature (`Row::curvature`).
        let body = RowBody {
            angular_velocity: b.angular_velocity,
            ..RowBody::fixed(b.position, b.orientation)
        };
        write_anchor_rows(
            &body,
            &RowBody::STATIC,
            b.position + p,
            joint_in_world,
            params.dt,
            &mut RowWriter::new(&mut rows),
        );
        let stats = solver.step(
            &mut bodies,
            &blocks,
            &rows,
            &mut [],
            &params,
            &mut lambda,
            &mut reactions,
        )?;
        if tick % 30 == 0 {
            let b = &bodies[0];
            let gap = (b.position + b.orientation * joint_in_body - joint_in_world).length();
            let x = b.position;
            let f = reactions[0][0].force;
            println!(
                "{:>6.2} ({:7.3}, {:7.3}, {:7.3}) {:>12.2e} ({:7.2}, {:7.2}, {:7.2})  [{} LCP iterations]",
                tick as Real * params.dt, x.x, x.y, x.z, gap, f.x, f.y, f.z, stats.lcp_iterations
            );
        }
    }
    Ok(())
}
