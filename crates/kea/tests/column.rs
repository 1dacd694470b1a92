//! VALIDATION #18: a column of 10 unit boxes with analytic face contacts (4 per face pair)
//! stands for 5 s: top lateral drift < 1 mm exact, < 5 mm iterative; the ground carries the
//! column's weight, 10·m·g, within 0.5% exact and 2% iterative.

mod common;
use common::{world_on, BoxPlaneContacts, PATHS};
use kea::{inertia, BodyDef, ContactParams, Real, SolverMode, Vec3};

const HALF: Vec3 = Vec3::splat(0.5);
const N: usize = 10;

fn column(mode: SolverMode) -> (Real, Real, f64) {
    let mut world = world_on(mode, N + 1, 4 * N + 8);
    let mut boxes = Vec::new();
    for i in 0..N {
        boxes.push(
            world
                .create_body(&BodyDef {
                    position: Vec3::new(0.0, 0.5 + i as Real, 0.0),
                    inertia: inertia::solid_box(1.0, HALF).unwrap(),
                    ..Default::default()
                })
                .unwrap(),
        );
    }
    let params = ContactParams::default();
    let mut ground = BoxPlaneContacts::default();
    let mut stacked: Vec<BoxPlaneContacts> = (1..N)
        .map(|i| BoxPlaneContacts::against(boxes[i - 1]))
        .collect();
    let h: Real = 1.0 / 60.0;
    let top0 = world.body(boxes[N - 1]).unwrap().position();
    let start = std::time::Instant::now();
    for _ in 0..300 {
        ground.update(&mut world, boxes[0], HALF, Vec3::Y, 0.0, 0.02, params, None);
        for i in 1..N {
            stacked[i - 1].update_on_box(&mut world, boxes[i], HALF, 0.02, params);
        }
        let stats = world.step(h).unwrap();
        assert_eq!(stats.solver.islands, 1, "{mode:?} {:?}", stats.solver);
        if mode == SolverMode::Hybrid {
            assert_eq!(stats.solver.exact_islands, 1, "{:?}", stats.solver);
        }
    }
    let ms = start.elapsed().as_secs_f64() * 1000.0 / 300.0;
    let top = world.body(boxes[N - 1]).unwrap().position();
    let drift = ((top - top0) * Vec3::new(1.0, 0.0, 1.0)).length();
    let ground_force: Vec3 = ground
        .handles()
        .map(|c| world.contact_force(c).unwrap())
        .sum();
    (drift, ground_force.y, ms)
}

#[test]
fn a_column_with_a_contact_per_corner_is_a_stack_and_goes_exact_by_default() {
    // Four one-point contacts on each face pair follow one another on one pair of bodies:
    // the column is still a stack (`Routing::stack_bodies`), routed exact, and holds there.
    let (drift, normal, _) = column(SolverMode::Hybrid);
    let weight = N as Real * 9.81;
    eprintln!("hybrid: top drift {drift:e} m, ground force {normal} N (weight {weight})");
    assert!(drift < 1e-3, "hybrid: top drifted {drift} m");
    assert!(
        (normal - weight).abs() < 5e-3 * weight,
        "ground force {normal}"
    );
}

#[test]
fn column_of_ten_boxes_stands_and_carries_its_weight() {
    let weight = N as Real * 9.81;
    for mode in PATHS {
        let (drift, normal, ms) = column(mode);
        let (max_drift, tol) = match mode {
            SolverMode::Exact => (1e-3, 5e-3),
            _ => (5e-3, 2e-2),
        };
        eprintln!(
            "{mode:?}: top drift {drift:e} m, ground force {normal} N (weight {weight}), {ms:.2} ms/step (test build)"
        );
        assert!(drift < max_drift, "{mode:?}: top drifted {drift} m");
        assert!(
            (normal - weight).abs() < tol * weight,
            "{mode:?}: ground force {normal} vs {weight}"
        );
    }
}
