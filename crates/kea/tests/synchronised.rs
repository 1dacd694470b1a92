//! The substepped paths hand on a synchronised state for islands without contacts (Störmer–
//! Verlet: half kicks at the step's two ends, velocities projected on the joints at the poses
//! reached; `solver/iterative/substep.rs`). Checked against closed forms on the paths that
//! substep (iterative and split islands), f32 and f64:
//! - a jointed pair tumbling in free fall: its centre of mass follows `x₀ + v₀t + gt²/2` at
//!   every step's end (leapfrog is exact under constant acceleration; symplectic Euler was
//!   off by `g·h·t/(2n)`), and its velocity is `v₀ + gt`;
//! - a pendulum hanging at rest reports no velocity (the last half kick is held by the
//!   joint, not handed on as a sag of `g·hs/2`).
//!
//! Energy: `energy.rs`; motors' budgets and stops' rebounds: `joints.rs`.

mod common;
use common::{world_on, F64};
use kea::{inertia, BodyDef, Real, SolverMode, Vec3};

const G: Real = 9.81;
const H: Real = 1.0 / 60.0;
const PATHS: [SolverMode; 2] = [SolverMode::Iterative, SolverMode::Split];

/// Round-off allowed on positions of order metres after `steps` steps.
fn round_off(steps: usize) -> Real {
    let eps = if F64 { 1e-12 } else { 2e-6 };
    eps * (1.0 + steps as Real)
}

#[test]
fn a_jointed_pair_in_free_fall_follows_the_parabola() {
    for mode in PATHS {
        let mut w = world_on(mode, 2, 1);
        let v0 = Vec3::new(1.0, 4.0, -0.5);
        let w0 = Vec3::new(0.3, 2.0, 5.0);
        let make = |x: Real| BodyDef {
            position: Vec3::new(x, 0.0, 0.0),
            linear_velocity: v0 + w0.cross(Vec3::new(x, 0.0, 0.0)),
            angular_velocity: w0,
            inertia: inertia::solid_box(1.0, Vec3::new(0.5, 0.1, 0.1)).unwrap(),
            ..Default::default()
        };
        let a = w.create_body(&make(-0.5)).unwrap();
        let b = w.create_body(&make(0.5)).unwrap();
        w.create_joint(a, Some(b), kea::JointSpec::ball(Vec3::ZERO))
            .unwrap();
        let (mut worst_x, mut worst_v): (Real, Real) = (0.0, 0.0);
        for n in 1..=120 {
            w.step(H).unwrap();
            let t = n as Real * H;
            let (pa, pb) = (w.body(a).unwrap(), w.body(b).unwrap());
            let com = 0.5 * (pa.position() + pb.position());
            let vcom = 0.5 * (pa.linear_velocity() + pb.linear_velocity());
            let expected = v0 * t + Vec3::new(0.0, -0.5 * G * t * t, 0.0);
            worst_x = worst_x.max((com - expected).length());
            worst_v = worst_v.max((vcom - (v0 - Vec3::Y * G * t)).length());
        }
        eprintln!(
            "{mode:?}: centre of mass off the parabola by {worst_x:.2e} m, {worst_v:.2e} m/s"
        );
        // The pair's internal forces cancel exactly only to round-off of order their size.
        assert!(worst_x < 50.0 * round_off(120), "{mode:?}: {worst_x} m");
        assert!(worst_v < 50.0 * round_off(120), "{mode:?}: {worst_v} m/s");
    }
}

#[test]
fn a_pendulum_hanging_at_rest_reports_no_velocity() {
    for mode in PATHS {
        let mut w = world_on(mode, 1, 1);
        let bob = w
            .create_body(&BodyDef {
                position: Vec3::new(0.0, -1.0, 0.0),
                inertia: inertia::solid_sphere(1.0, 0.05).unwrap(),
                ..Default::default()
            })
            .unwrap();
        w.create_joint(bob, None, kea::JointSpec::ball(Vec3::ZERO))
            .unwrap();
        let mut worst: Real = 0.0;
        for _ in 0..120 {
            w.step(H).unwrap();
            worst = worst.max(w.body(bob).unwrap().linear_velocity().length());
        }
        eprintln!("{mode:?}: hanging bob's speed at most {worst:.2e} m/s");
        // Half a substep's sag would be g·h/8 = 0.02 m/s.
        let tol = if F64 { 1e-9 } else { 1e-5 };
        assert!(worst < tol, "{mode:?}: the bob moves at {worst} m/s");
    }
}
