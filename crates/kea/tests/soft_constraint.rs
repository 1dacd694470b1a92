//! VALIDATION #11 and #12: a soft row with stiffness k and damping d is exactly the
//! implicit-Euler spring, and a constant load against a soft stop deflects by F/k.

mod common;
use common::{world_on, F64, PATHS};
use kea::{
    BodyDef, CustomConstraint, Jacobian, Real, Row, RowContext, RowWriter, Softness, SolverMode,
    Vec3,
};

#[derive(Debug, Clone)]
struct Spring {
    k: Real,
    d: Real,
    stop: bool,
}

impl CustomConstraint for Spring {
    fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let x = ctx.bodies[0].position.x;
        let mut row = Row::new(Jacobian::new(Vec3::X, Vec3::ZERO), Jacobian::ZERO)
            .with_error(x)
            .with_softness(Softness::from_spring(self.k, self.d, ctx.dt).unwrap());
        if self.stop {
            // A stop only pushes towards +x.
            row = row.with_bounds(0.0, Real::INFINITY);
        }
        out.push(row);
    }
}

#[test]
fn soft_row_follows_the_implicit_euler_spring() {
    for mode in PATHS {
        spring_run(mode);
    }
}

/// VALIDATION #11: the exact path reproduces one implicit-Euler step of the spring per step
/// (1e-9); the iterative path re-discretises it at its substep, so it follows the same spring
/// within 1e-4 of the amplitude and oscillates at the same frequency.
fn spring_run(mode: SolverMode) {
    let (m, k, d, h): (Real, Real, Real, Real) = (2.0, 300.0, 3.0, 0.01);
    let mut world = world_on(mode, 2, 2);
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let b = world
        .create_body(&BodyDef {
            mass: m,
            position: Vec3::new(0.1, 0.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    world
        .add_custom_constraint(b, None, Spring { k, d, stop: false })
        .unwrap();
    // The exact path takes one implicit-Euler step of the spring per step; the iterative path
    // one per substep (the same spring re-discretised at hs = h/n).
    let n = if mode == SolverMode::Exact {
        1
    } else {
        kea::IterativeParams::default().substeps
    };
    let hs = h / n as Real;
    let (mut x, mut v): (Real, Real) = (0.1, 0.0);
    let mut crossings = 0;
    let mut max_err: Real = 0.0;
    for _ in 0..2000 {
        world.step(h).unwrap();
        let x_prev = x;
        for _ in 0..n {
            v = (v - hs * k / m * x) / (1.0 + hs * d / m + hs * hs * k / m);
            x += hs * v;
        }
        if x_prev > 0.0 && x <= 0.0 {
            crossings += 1;
        }
        let body = world.body(b).unwrap();
        max_err = max_err.max((body.position().x - x).abs());
        let tol = if mode == SolverMode::Exact && F64 {
            1e-9
        } else {
            1e-4
        } * 0.1;
        assert!(
            (body.position().x - x).abs() < tol,
            "{mode:?}: x {} vs {x}",
            body.position().x
        );
    }
    eprintln!(
        "{mode:?}: spring follows its implicit-Euler recurrence to {max_err:e} m (amplitude 0.1 m)"
    );
    // Period ≈ 2π√(m/k) = 0.513 s: 20 s gives ~39 crossings while the oscillation lasts.
    assert!(
        crossings > 10,
        "it should oscillate ({crossings} crossings)"
    );
}

#[test]
fn constant_load_against_a_soft_stop_deflects_by_f_over_k() {
    for mode in PATHS {
        stop_run(mode);
    }
}

fn stop_run(mode: SolverMode) {
    let (k, f): (Real, Real) = (500.0, 20.0);
    let mut world = world_on(mode, 2, 2);
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let b = world.create_body(&BodyDef::default()).unwrap();
    world
        .add_custom_constraint(
            b,
            None,
            Spring {
                k,
                d: 5.0,
                stop: true,
            },
        )
        .unwrap();
    for _ in 0..3000 {
        world
            .body_mut(b)
            .unwrap()
            .add_force(Vec3::new(-f, 0.0, 0.0))
            .unwrap();
        world.step(0.01).unwrap();
    }
    let x = world.body(b).unwrap().position().x;
    let rel = (x + f / k).abs() / (f / k);
    assert!(
        rel < if F64 { 1e-6 } else { 1e-4 },
        "deflection {x} vs {}",
        -f / k
    );
}
