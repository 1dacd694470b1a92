//! Contacts as a user meets them, through the collision world (issue 10's cases): resting
//! depth whatever the density, isotropic sliding friction, restitution whatever the phase of
//! the impact in the step, a heavy box holding on a slope, and stacks that stand: a column of
//! 40 boxes and one alternating 100 kg and 1 kg boxes.
//!
//! Each case runs in both paths where both can hold it. The soft step's contacts are springs
//! of 30 Hz per unit of weight, so the iterative path's 40-box column sags about 44 cm (as
//! Rapier's does) and it cannot hold a 1 kg box under a 100 kg one; the exact path, eight
//! times stiffer, holds both to the figures, and the hybrid routing sends a small
//! pile with such a mass ratio there (`Routing::mass_ratio`).

use kea::{BodyDef, BodyHandle, Quat, Real, Routing, SolverMode, Vec3, World, WorldDef};
use kea_collision::{ColliderDef, CollisionWorld, Shape, Surface};
mod common;

const G: Real = 9.81;
const DT: Real = 1.0 / 60.0;
const PATHS: [SolverMode; 2] = [SolverMode::Iterative, SolverMode::Exact];

fn world(bodies: usize, mode: SolverMode) -> World {
    let mut w = World::new(WorldDef {
        max_bodies: bodies + 1,
        max_constraints: 16 * bodies + 16,
        settings: kea::WorldSettings {
            gravity: Vec3::new(0.0, -G, 0.0),
            ..Default::default()
        },
        ..Default::default()
    })
    .unwrap();
    w.update_settings(|s| {
        s.routing = Routing {
            mode,
            ..Default::default()
        }
    })
    .unwrap();
    w
}

fn ground(c: &mut CollisionWorld, w: &World, normal: Vec3) {
    c.add_collider(w, ColliderDef::new(None, Shape::plane(normal).unwrap()))
        .unwrap();
}

/// A box of `half` extents and `density` at `position`, turned by `rotation`.
fn add_box(
    w: &mut World,
    c: &mut CollisionWorld,
    half: Vec3,
    density: Real,
    position: Vec3,
    rotation: Quat,
) -> BodyHandle {
    let shape = Shape::cuboid(half).unwrap();
    let mp = shape.mass_properties(density).unwrap();
    let b = w
        .create_body(&BodyDef {
            mass: mp.mass,
            inertia: mp.inertia,
            position,
            orientation: rotation,
            ..Default::default()
        })
        .unwrap();
    c.add_collider(w, ColliderDef::new(Some(b), shape)).unwrap();
    b
}

fn run(c: &mut CollisionWorld, w: &mut World, steps: usize) {
    for _ in 0..steps {
        common::step(c, w, DT).unwrap();
    }
}

#[test]
fn a_light_and_a_heavy_box_rest_less_than_a_millimetre_deep() {
    for mode in PATHS {
        for density in [1.0, 10_000.0] {
            let mut w = world(1, mode);
            let mut c = CollisionWorld::new();
            ground(&mut c, &w, Vec3::Y);
            let b = add_box(
                &mut w,
                &mut c,
                Vec3::splat(0.5),
                density,
                Vec3::new(0.0, 0.5, 0.0),
                Quat::IDENTITY,
            );
            run(&mut c, &mut w, 300);
            let body = w.body(b).unwrap();
            let depth = 0.5 - body.position().y;
            eprintln!(
                "{mode:?}, density {density}: rests {:.4} mm deep",
                depth * 1e3
            );
            assert!(
                depth > -1e-4 && depth < 1e-3,
                "{mode:?}, {density}: {depth}"
            );
            assert!(body.linear_velocity().length() < 1e-3, "{mode:?}: at rest");
        }
    }
}

/// A 1 m box of 1 t on μ = 0.4, launched at `speed` along `heading` (rad from +x): the distance
/// it slides, its heading change (degrees) and its largest |ω| on the way and at rest.
fn slide(mode: SolverMode, heading: Real, speed: Real) -> (Real, Real, Real) {
    let mut w = world(1, mode);
    let mut c = CollisionWorld::new();
    c.materials
        .set_surface(
            0,
            Surface {
                friction: 0.4,
                ..Default::default()
            },
        )
        .unwrap();
    ground(&mut c, &w, Vec3::Y);
    let b = add_box(
        &mut w,
        &mut c,
        Vec3::splat(0.5),
        1000.0,
        Vec3::new(0.0, 0.5, 0.0),
        Quat::IDENTITY,
    );
    run(&mut c, &mut w, 30);
    let dir = Vec3::new(heading.cos(), 0.0, heading.sin());
    let start = w.body(b).unwrap().position();
    w.body_mut(b)
        .unwrap()
        .set_linear_velocity(dir * speed)
        .unwrap();
    let mut spin: Real = 0.0;
    for _ in 0..300 + (speed / (0.4 * G) / DT) as usize {
        common::step(&mut c, &mut w, DT).unwrap();
        spin = spin.max(w.body(b).unwrap().angular_velocity().length());
    }
    let body = w.body(b).unwrap();
    assert!(body.linear_velocity().length() < 1e-3, "stopped");
    let d = body.position() - start;
    let flat = Vec3::new(d.x, 0.0, d.z);
    let turned = flat
        .normalize()
        .dot(dir)
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees();
    (flat.length(), turned, spin)
}

#[test]
fn a_sliding_box_stops_at_v_squared_over_2_mu_g_in_every_direction() {
    // Symplectic Euler stops a slide v·h/2 short of the continuous v²/(2μg), h the step it
    // integrates with: that is μgh/v of the distance. The iterative path's substep (1/240 s)
    // keeps it under 1% from 1.7 m/s, the exact path's whole step (1/60 s) from 6.6 m/s.
    for (mode, speeds) in [
        (SolverMode::Iterative, [2.0, 4.0, 8.0]),
        (SolverMode::Exact, [8.0, 12.0, 16.0]),
    ] {
        for k in 0..16 {
            let heading = k as Real * std::f64::consts::PI as Real / 8.0;
            for speed in speeds {
                let (distance, turned, spin) = slide(mode, heading, speed);
                let expected = speed * speed / (2.0 * 0.4 * G);
                let error = (distance - expected).abs() / expected;
                assert!(
                    error < 0.01 && turned < 0.5 && spin < 0.01,
                    "{mode:?}, heading {k}/16 π, {speed} m/s: slid {distance:.4} m \
                     (v²/2μg = {expected:.4}, {:.2}%), turned {turned:.3}°, |ω| {spin:.4}",
                    error * 100.0
                );
            }
        }
    }
}

#[test]
fn equal_balls_with_e_1_exchange_velocities_whatever_the_phase_of_the_impact() {
    for mode in PATHS {
        for k in 0..10 {
            // The balls touch after (3 + f) steps, f = 0.05 … 0.95.
            let f = (k as Real + 0.5) / 10.0;
            let (v, r) = (2.0, 0.5);
            let mut w = world(2, mode);
            w.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
            let mut c = CollisionWorld::new();
            c.materials
                .set_surface(
                    0,
                    Surface {
                        friction: 0.0,
                        restitution: 1.0,
                        restitution_threshold: 0.0,
                        ..Default::default()
                    },
                )
                .unwrap();
            let gap = 2.0 * v * (3.0 + f) * DT;
            let mut ball = |x: Real, vx: Real| {
                let shape = Shape::sphere(r).unwrap();
                let mp = shape.mass_properties(1000.0).unwrap();
                let b = w
                    .create_body(&BodyDef {
                        mass: mp.mass,
                        inertia: mp.inertia,
                        position: Vec3::new(x, 0.0, 0.0),
                        linear_velocity: Vec3::new(vx, 0.0, 0.0),
                        ..Default::default()
                    })
                    .unwrap();
                c.add_collider(&w, ColliderDef::new(Some(b), shape))
                    .unwrap();
                b
            };
            let a = ball(-(r + 0.5 * gap), v);
            let b = ball(r + 0.5 * gap, -v);
            run(&mut c, &mut w, 20);
            let va = w.body(a).unwrap().linear_velocity().x;
            let vb = w.body(b).unwrap().linear_velocity().x;
            assert!(
                (va + v).abs() < 0.01 * v && (vb - v).abs() < 0.01 * v,
                "{mode:?}, impact at {f} of a step: {va} and {vb}, want {} and {v}",
                -v
            );
        }
    }
}

#[test]
fn a_heavy_box_holds_on_a_slope_whose_mu_is_1_2_tan_theta() {
    for mode in PATHS {
        let theta: Real = (30.0 as Real).to_radians();
        let mut w = world(1, mode);
        let mut c = CollisionWorld::new();
        c.materials
            .set_surface(
                0,
                Surface {
                    friction: 1.2 * theta.tan(),
                    ..Default::default()
                },
            )
            .unwrap();
        let tilt = Quat::from_rotation_z(theta);
        let n = tilt * Vec3::Y;
        ground(&mut c, &w, n);
        let b = add_box(&mut w, &mut c, Vec3::splat(0.5), 1000.0, n * 0.5, tilt);
        run(&mut c, &mut w, 60);
        let start = w.body(b).unwrap().position();
        run(&mut c, &mut w, 3600);
        let drift = (w.body(b).unwrap().position() - start).length();
        eprintln!(
            "{mode:?}: 1 t box on 30°, μ = 1.2 tan θ: {:.4} mm in 60 s",
            drift * 1e3
        );
        assert!(drift < 1e-3, "{mode:?}: crept {drift} m in 60 s");
    }
}

/// A column of `n` unit boxes (alternating `heavy` and 1 kg from the bottom if `heavy` is
/// set) after `seconds`: the top's sag, its drift off the axis, the deepest contact.
fn column(mode: SolverMode, n: usize, heavy: Option<Real>, seconds: Real) -> (Real, Real, Real) {
    let mut w = world(n, mode);
    let mut c = CollisionWorld::new();
    ground(&mut c, &w, Vec3::Y);
    let mut top = None;
    for i in 0..n {
        let density = match heavy {
            Some(m) if i % 2 == 0 => m,
            _ => 1.0,
        };
        let at = Vec3::new(0.0, 0.5 + i as Real, 0.0);
        top = Some(add_box(
            &mut w,
            &mut c,
            Vec3::splat(0.5),
            density,
            at,
            Quat::IDENTITY,
        ));
    }
    let mut deepest: Real = 0.0;
    for step in 0..(seconds / DT).round() as usize {
        common::step(&mut c, &mut w, DT).unwrap();
        if step >= 60 {
            for (_, contact, _) in w.contacts() {
                deepest = deepest.max(contact.penetration());
            }
        }
    }
    let p = w.body(top.unwrap()).unwrap().position();
    let sag = (n as Real - 0.5) - p.y;
    (sag, Vec3::new(p.x, 0.0, p.z).length(), deepest)
}

/// The sag of a column of `n` unit boxes of 1 kg on the exact path, from its contact
/// springs: each contact between two boxes (effective mass ½ kg) at the exact path's
/// stiffened frequency `f` yields `2g/(2πf)²` per box it carries, and the ground's contact
/// (against a body that cannot move: `2f`) a quarter of that per box.
fn exact_column_sag(n: usize) -> Real {
    let f = kea::DEFAULT_CONTACT_SPRING.hertz * kea::EXACT_CONTACT_STIFFENING;
    let per_box = 2.0 * G / (2.0 * std::f64::consts::PI as Real * f).powi(2);
    let carried = (n * (n - 1) / 2) as Real;
    per_box * carried + 0.25 * per_box * n as Real
}

#[test]
fn a_column_of_40_boxes_stands_60_s() {
    // Forced exact, and by default: a stack of contacts only goes exact
    // (`Routing::stack_bodies`), where it factorises without fill.
    for mode in [SolverMode::Exact, SolverMode::Hybrid] {
        let (sag, drift, _) = column(mode, 40, None, 60.0);
        eprintln!(
            "{mode:?}: sag {:.2} mm (springs: {:.2} mm), drift {:.3} mm",
            sag * 1e3,
            exact_column_sag(40) * 1e3,
            drift * 1e3
        );
        assert!(
            sag < 0.01 && drift < 0.005,
            "{mode:?}: sag {sag}, drift {drift}"
        );
        let want = exact_column_sag(40);
        assert!(
            (sag - want).abs() < 0.05 * want,
            "{mode:?}: sag {sag} against the springs' {want}"
        );
    }
    // The soft step's 30 Hz contacts sag 0.55 mm per box carried (44 cm in all), and the
    // column sways, but it stands.
    let (sag, drift, _) = column(SolverMode::Iterative, 40, None, 60.0);
    eprintln!(
        "iterative: sag {:.1} cm, drift {:.1} cm",
        sag * 1e2,
        drift * 1e2
    );
    assert!(
        sag < 0.47 && drift < 1.5,
        "iterative: sag {sag}, drift {drift}"
    );
}

#[test]
fn columns_of_60_and_100_boxes_stand_by_default() {
    // The soft step's columns of 60 fall; a stack goes exact by default and holds, sagging
    // as its springs say.
    for n in [60, 100] {
        let (sag, drift, _) = column(SolverMode::Hybrid, n, None, 30.0);
        let want = exact_column_sag(n);
        eprintln!(
            "{n} boxes: sag {:.2} mm (springs: {:.2} mm), drift {:.3} mm",
            sag * 1e3,
            want * 1e3,
            drift * 1e3
        );
        assert!(drift < 0.005, "{n} boxes: drift {drift}");
        assert!(
            (sag - want).abs() < 0.05 * want,
            "{n} boxes: sag {sag} against the springs' {want}"
        );
    }
}

#[test]
fn ten_boxes_alternating_100_kg_and_1_kg_stand_20_s() {
    // Exact, and under the default hybrid routing (which sends this pile exact).
    for mode in [SolverMode::Exact, SolverMode::Hybrid] {
        let (sag, drift, deepest) = column(mode, 10, Some(100.0), 20.0);
        eprintln!(
            "{mode:?}: sag {:.2} mm, drift {:.3} mm, deepest {:.2} mm",
            sag * 1e3,
            drift * 1e3,
            deepest * 1e3
        );
        assert!(
            deepest < 0.005 && drift < 0.005 && sag < 0.05,
            "{mode:?}: sag {sag}, drift {drift}, deepest contact {deepest}"
        );
    }
}

#[test]
fn a_pile_too_big_for_the_dense_exact_path_is_solved_iteratively_and_says_so() {
    // A 3 × 3 × 2 block of unit boxes forced exact: its contacts make loops (no stack), and
    // its rows pass DENSE_EXACT_MAX_ROWS, so each step solves it on the iterative path and
    // reports the island as rerouted, rather than stalling in the dense LCP.
    let mut w = world(18, SolverMode::Exact);
    let mut c = CollisionWorld::new();
    ground(&mut c, &w, Vec3::Y);
    let mut boxes = Vec::new();
    for i in 0..18 {
        let at = Vec3::new(
            (i % 3) as Real,
            0.5 + (i / 9) as Real,
            ((i / 3) % 3) as Real,
        );
        boxes.push(add_box(
            &mut w,
            &mut c,
            Vec3::splat(0.5),
            1.0,
            at,
            Quat::IDENTITY,
        ));
    }
    let start: Vec<Vec3> = boxes
        .iter()
        .map(|&b| w.body(b).unwrap().position())
        .collect();
    let mut rerouted = 0;
    for _ in 0..120 {
        let stats = common::step(&mut c, &mut w, DT).unwrap();
        if stats.solver.rerouted_islands > 0 {
            assert_eq!(stats.solver.exact_islands, 0, "{:?}", stats.solver);
            assert_eq!(stats.solver.iterative_islands, 1, "{:?}", stats.solver);
            assert!(stats.solver.rows > kea::DENSE_EXACT_MAX_ROWS);
            assert!(!stats.solver.is_clean(), "a rerouted island is a warning");
            rerouted += 1;
        }
    }
    assert!(rerouted > 100, "rerouted in {rerouted} of 120 steps");
    let moved = boxes
        .iter()
        .zip(&start)
        .map(|(&b, p)| (w.body(b).unwrap().position() - *p).length())
        .fold(0.0, Real::max);
    assert!(moved < 0.01, "the block moved {moved} m");
}

#[test]
fn a_row_of_boxes_sliding_on_the_ground_stops_where_friction_says() {
    // Eight unit boxes side by side, all launched at 3 m/s along the row, μ = 0.5: they
    // slide together and stop after v²/(2μg). Side by side is not a stack (their contacts
    // face across gravity), so by default the contact solver takes them; forced exact, the
    // exact path either settles them or hands them to the contact solver for the step, and
    // nothing runs away.
    let want = 3.0 * 3.0 / (2.0 * 0.5 * G);
    for mode in [SolverMode::Hybrid, SolverMode::Exact] {
        let mut w = world(8, mode);
        let mut c = CollisionWorld::new();
        ground(&mut c, &w, Vec3::Y);
        let boxes: Vec<_> = (0..8)
            .map(|i| {
                let at = Vec3::new(i as Real, 0.5, 0.0);
                add_box(&mut w, &mut c, Vec3::splat(0.5), 1.0, at, Quat::IDENTITY)
            })
            .collect();
        for &b in &boxes {
            w.body_mut(b)
                .unwrap()
                .set_linear_velocity(Vec3::new(3.0, 0.0, 0.0))
                .unwrap();
        }
        for _ in 0..180 {
            let stats = common::step(&mut c, &mut w, DT).unwrap();
            assert_eq!(stats.quarantined_bodies, 0, "{mode:?}");
        }
        for (i, &b) in boxes.iter().enumerate() {
            let body = w.body(b).unwrap();
            let slid = body.position().x - i as Real;
            assert!(
                (slid - want).abs() < 0.03 * want,
                "{mode:?}: box {i} slid {slid} m (friction: {want} m)"
            );
            assert!(
                body.linear_velocity().length() < 1e-3,
                "{mode:?}: box {i} moves"
            );
        }
    }
}
