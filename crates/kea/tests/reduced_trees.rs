//! The reduced-coordinate path of a world step (`Routing::max_reduced_links`): which trees it
//! takes, the physics it gives (closed forms, energy, reactions, stops and motors, agreement
//! with the maximal path on a branched tree) and that it hands a tree back to the solver the
//! moment anything else touches it. Every figure holds in f32 and f64.

use kea::{BodyDef, BodyHandle, Mat3, Real, Routing, SingleLimit, SolverMode, Vec3, World};

const G: Real = 9.81;

fn world() -> World {
    let mut w = World::with_capacity(16, 32).unwrap();
    w.update_settings(|s| s.gravity = Vec3::new(0.0, -G, 0.0))
        .unwrap();
    w
}

fn forced(mode: SolverMode) -> Routing {
    Routing {
        mode,
        ..Routing::default()
    }
}

/// A rod of mass `m` and length `l` along −y from `top`, hinged there about z.
fn rod(w: &mut World, top: Vec3, m: Real, l: Real, parent: Option<BodyHandle>) -> BodyHandle {
    let i = m * l * l / 12.0;
    let b = w
        .create_body(&BodyDef {
            mass: m,
            inertia: Mat3::from_diagonal(Vec3::new(i, i, i)),
            position: top - Vec3::new(0.0, 0.5 * l, 0.0),
            ..BodyDef::default()
        })
        .unwrap();
    w.create_joint(b, parent, kea::JointSpec::hinge(top, Vec3::Z))
        .unwrap();
    b
}

/// The hinge angle of a body hanging from `pivot`, from −y, about z.
fn swing(w: &World, b: BodyHandle, pivot: Vec3) -> Real {
    let d = w.body(b).unwrap().position() - pivot;
    d.x.atan2(-d.y)
}

#[test]
fn a_rod_on_a_hinge_swings_with_the_closed_form_period_in_reduced_coordinates() {
    let (m, l) = (2.0, 1.2);
    let mut w = world();
    let b = rod(&mut w, Vec3::ZERO, m, l, None);
    // Released 0.05 rad from the bottom: T = 2π √(I_pivot / (m g l/2)) (1 + θ₀²/16).
    let theta0: Real = 0.05;
    let c = Vec3::new(0.5 * l * theta0.sin(), -0.5 * l * theta0.cos(), 0.0);
    let body = w.body_mut(b).unwrap();
    body.set_position(c).unwrap();
    body.set_orientation(kea::Quat::from_rotation_z(theta0))
        .unwrap();
    let pivot_inertia = m * l * l / 3.0;
    let period = 2.0
        * kea::PI_REAL
        * (pivot_inertia / (m * G * 0.5 * l)).sqrt()
        * (1.0 + theta0 * theta0 / 16.0);
    let h: Real = 1e-4;
    let (mut t, mut last, mut crossings) = (0.0, swing(&w, b, Vec3::ZERO), Vec::new());
    while crossings.len() < 5 {
        let stats = w.step(h).unwrap();
        assert_eq!(
            stats.reduced_trees, 1,
            "the pendulum is a tree on the world"
        );
        t += h;
        let now = swing(&w, b, Vec3::ZERO);
        if last > 0.0 && now <= 0.0 {
            crossings.push(t - h * now / (now - last));
        }
        last = now;
    }
    let measured = (crossings[4] - crossings[0]) / 4.0;
    assert!(
        (measured - period).abs() < 1e-3 * period,
        "period {measured} s, closed form {period} s"
    );
    // The joint holds exactly: the rod's top stays on the pivot.
    let top = w.body(b).unwrap().position()
        + w.body(b).unwrap().orientation() * Vec3::new(0.0, 0.5 * l, 0.0);
    assert!(top.length() < 1e-5, "pivot drift {top}");
}

#[test]
fn a_three_link_chain_keeps_its_energy_and_its_joints() {
    let mut w = world();
    let mut parent = None;
    let mut bodies = Vec::new();
    for k in 0..3 {
        let top = Vec3::new(0.8 * k as Real, 0.0, 0.0);
        let b = w
            .create_body(&BodyDef {
                mass: 1.0,
                inertia: Mat3::from_diagonal(Vec3::splat(0.05)),
                position: top + Vec3::new(0.4, 0.0, 0.0),
                ..BodyDef::default()
            })
            .unwrap();
        w.create_joint(b, parent, kea::JointSpec::hinge(top, Vec3::Z))
            .unwrap();
        parent = Some(b);
        bodies.push(b);
    }
    let energy = |w: &World| -> Real {
        bodies
            .iter()
            .map(|&b| {
                let b = w.body(b).unwrap();
                let wv = b.angular_velocity();
                0.5 * b.linear_velocity().length_squared()
                    + 0.5 * 0.05 * wv.length_squared()
                    + G * b.position().y
            })
            .sum()
    };
    let e0 = energy(&w);
    let mut worst_error: Real = 0.0;
    let mut reduced = 0;
    for _ in 0..3000 {
        reduced += w.step(1e-3).unwrap().reduced_trees;
        worst_error = worst_error.max(w.joint_error());
    }
    assert_eq!(reduced, 3000);
    // Swinging through 3 s of chaos, semi-implicit Euler keeps the energy to a few parts in a
    // hundred of the motion's scale (m g L ≈ 3 × 9.81 × 2.4 J).
    let scale = 3.0 * G * 2.4;
    assert!(
        (energy(&w) - e0).abs() < 0.03 * scale,
        "energy {} → {}",
        e0,
        energy(&w)
    );
    let tolerance = if cfg!(feature = "f64") { 1e-9 } else { 1e-4 };
    assert!(worst_error < tolerance, "joint error {worst_error}");
}

/// A cart on a slider along x with two rods hanging from it (a branched tree), released with
/// the rods at ±0.6 rad.
fn branched(
    w: &mut World,
) -> (
    BodyHandle,
    [BodyHandle; 2],
    kea::JointHandle<kea::Prismatic>,
) {
    let cart = w
        .create_body(&BodyDef {
            mass: 3.0,
            inertia: Mat3::from_diagonal(Vec3::splat(0.1)),
            ..BodyDef::default()
        })
        .unwrap();
    let slider = w
        .create_joint(cart, None, kea::JointSpec::prismatic(Vec3::ZERO, Vec3::X))
        .unwrap();
    let rods = [(-0.3, 0.6), (0.3, -0.6)].map(|(x, angle): (Real, Real)| {
        let top = Vec3::new(x, 0.0, 0.0);
        let b = rod(w, top, 1.0, 1.0, Some(cart));
        let turn = kea::Quat::from_rotation_z(angle);
        let body = w.body_mut(b).unwrap();
        body.set_position(top + turn * Vec3::new(0.0, -0.5, 0.0))
            .unwrap();
        body.set_orientation(turn).unwrap();
        b
    });
    // Re-made at the tilted poses, the hinges measure from there.
    (cart, rods, slider)
}

#[test]
fn a_branched_tree_moves_as_on_the_maximal_path() {
    let run = |routing: Routing| {
        let mut w = world();
        w.update_settings(|s| s.routing = routing).unwrap();
        let (cart, rods, _) = branched(&mut w);
        let mut reduced = 0;
        for _ in 0..1000 {
            reduced += w.step(1e-3).unwrap().reduced_trees;
        }
        let p = |b: BodyHandle| w.body(b).unwrap().position();
        (p(cart), rods.map(p), reduced)
    };
    let (cart, rods, reduced) = run(Routing::default());
    assert_eq!(reduced, 1000);
    let (cart_x, rods_x, maximal) = run(forced(SolverMode::Exact));
    assert_eq!(maximal, 0, "a forced mode never reduces");
    // Both first order in h: after 1 s at 1 ms they agree to about a millimetre.
    assert!((cart - cart_x).length() < 3e-3, "{cart} vs {cart_x}");
    for (a, b) in rods.iter().zip(&rods_x) {
        assert!((*a - *b).length() < 3e-3, "{a} vs {b}");
    }
    // The swing moved the cart: momentum along x stays 0, the centre of mass stays put.
    assert!(cart.x.abs() > 1e-3 || rods[0].x != -0.3);
    for routing in [forced(SolverMode::Iterative), forced(SolverMode::Split)] {
        assert_eq!(run(routing).2, 0);
    }
}

#[test]
fn a_tree_touched_by_anything_else_goes_to_the_solver_and_comes_back() {
    let mut w = world();
    let (cart, rods, _) = branched(&mut w);
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 1);
    // A second joint to the world closes a loop.
    let extra = w
        .create_joint(
            rods[0],
            None,
            kea::JointSpec::ball(w.body(rods[0]).unwrap().position()),
        )
        .unwrap();
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 0);
    w.destroy_constraint(extra).unwrap();
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 1);
    // A contact on a link.
    let at = w.body(rods[1]).unwrap().position();
    let touching = kea::Contact::new(at, Vec3::Y, 0.0).unwrap();
    let contact = w.create_contact(rods[1], None, touching).unwrap();
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 0);
    w.destroy_constraint(contact).unwrap();
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 1);
    // A damped link is left to the solver.
    w.body_mut(cart).unwrap().set_linear_damping(0.5).unwrap();
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 0);
    w.body_mut(cart).unwrap().set_linear_damping(0.0).unwrap();
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 1);
    // A stop that bounces.
    let slider = kea::JointHandle::<kea::Prismatic>::from_raw(
        w.enabled_joints()
            .find(|(_, b)| b[0] == Some(cart))
            .unwrap()
            .0,
    );
    let limit = slider.limit_mut(&mut w).unwrap();
    limit
        .set_limits(SingleLimit::hard(-1.0, 0.5), SingleLimit::hard(1.0, 0.5))
        .unwrap();
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 0);
    let limit = slider.limit_mut(&mut w).unwrap();
    limit
        .set_limits(SingleLimit::hard(-1.0, 0.0), SingleLimit::hard(1.0, 0.0))
        .unwrap();
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 1);
    // The cart disabled is a fixed base: each rod is a tree of its own on it.
    w.body_mut(cart).unwrap().set_enabled(false);
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 2);
    w.body_mut(cart).unwrap().set_enabled(true);
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 1);
    // Off by setting.
    w.update_settings(|s| {
        s.routing = Routing {
            max_reduced_links: 2,
            ..Routing::default()
        }
    })
    .unwrap();
    assert_eq!(w.step(1e-3).unwrap().reduced_trees, 0, "three links > 2");
}

#[test]
fn a_hanging_rod_at_rest_carries_its_weight_through_its_hinge() {
    let (m, l) = (2.5, 0.8);
    let mut w = world();
    let b = rod(&mut w, Vec3::ZERO, m, l, None);
    let handle = w.enabled_joints().next().unwrap().0;
    for _ in 0..10 {
        w.step(1e-3).unwrap();
    }
    let [on_rod, _] = w.constraint_reaction(handle).unwrap();
    let weight = m * G;
    assert!(
        (on_rod.force - Vec3::new(0.0, weight, 0.0)).length() < 1e-3 * weight,
        "reaction {}",
        on_rod.force
    );
    assert!(
        on_rod.torque.length() < 1e-3 * weight * l,
        "{}",
        on_rod.torque
    );
    assert!(w.body(b).unwrap().linear_velocity().length() < 1e-6);
}

#[test]
fn stops_hold_and_a_motor_drives_the_cart() {
    let mut w = world();
    let (cart, _, slider) = branched(&mut w);
    slider
        .limit_mut(&mut w)
        .unwrap()
        .set_limits(SingleLimit::hard(-0.5, 0.0), SingleLimit::hard(0.5, 0.0))
        .unwrap();
    slider
        .limit_mut(&mut w)
        .unwrap()
        .set_motor(1.0, 200.0)
        .unwrap();
    let mut speeds = Vec::new();
    let mut furthest: Real = 0.0;
    for _ in 0..1500 {
        assert_eq!(w.step(1e-3).unwrap().reduced_trees, 1);
        let b = w.body(cart).unwrap();
        speeds.push(b.linear_velocity().x);
        furthest = furthest.max(b.position().x);
    }
    // The motor holds 1 m/s against the swinging rods until the stop at 0.5 m.
    assert!(
        speeds[100..400].iter().all(|v| (v - 1.0).abs() < 1e-3),
        "{:?}",
        &speeds[100..110]
    );
    assert!(furthest < 0.5 + 1e-4, "past the stop: {furthest}");
    let x = w.body(cart).unwrap().position().x;
    assert!((x - 0.5).abs() < 1e-3, "resting on the stop at {x}");
    let limit = slider.limit_mut(&mut w).unwrap();
    assert!(
        limit.is_at_limit(1e-3),
        "the joint reads {}",
        limit.position()
    );
}

#[test]
fn a_reduced_world_is_the_same_bits_after_a_clone() {
    let mut w = world();
    branched(&mut w);
    for _ in 0..100 {
        w.step(1e-3).unwrap();
    }
    let mut copy = w.clone();
    for _ in 0..100 {
        w.step(1e-3).unwrap();
        copy.step(1e-3).unwrap();
    }
    for (a, b) in w.bodies().zip(copy.bodies()) {
        assert_eq!(a.1.position(), b.1.position());
        assert_eq!(a.1.linear_velocity(), b.1.linear_velocity());
    }
}

/// A body on a planar joint (two slides, and a turn) falls in its plane onto the stop of its
/// second travel and rests there, keeps its first travel's speed, and turns freely — on every
/// path, and on the default routing in reduced coordinates (two sliders and a hinge).
#[test]
fn a_body_on_a_planar_joint_falls_in_its_plane_onto_its_stop_on_every_path() {
    for mode in [
        SolverMode::Hybrid,
        SolverMode::Exact,
        SolverMode::Iterative,
        SolverMode::Split,
    ] {
        for rotates in [false, true] {
            let mut w = World::with_capacity(2, 2).unwrap();
            w.update_settings(|s| {
                s.routing = Routing {
                    mode,
                    ..Routing::default()
                }
            })
            .unwrap();
            let b = w
                .create_body(&BodyDef {
                    linear_velocity: Vec3::new(0.3, 0.0, 0.0),
                    angular_velocity: Vec3::new(0.0, 0.0, if rotates { 0.5 } else { 0.0 }),
                    ..BodyDef::default()
                })
                .unwrap();
            let j = w
                .create_joint(
                    b,
                    None,
                    kea::JointSpec::planar(Vec3::ZERO, Vec3::Z, Vec3::X, rotates),
                )
                .unwrap();
            j.limit_mut(&mut w, 1)
                .unwrap()
                .set_limits(SingleLimit::hard(-0.5, 0.0), SingleLimit::hard(1.0, 0.0))
                .unwrap();
            let mut reduced = 0;
            for _ in 0..60 {
                reduced += w.step(1.0 / 60.0).unwrap().reduced_trees;
            }
            let body = w.body(b).unwrap();
            let (p, spin) = (body.position(), body.angular_velocity());
            let what = format!("{mode:?}, turning {rotates}");
            assert!((p.x - 0.3).abs() < 0.01, "{what}: x {}", p.x);
            assert!((p.y + 0.5).abs() < 0.01, "{what}: rests on the stop: {p}");
            assert!(p.z.abs() < 1e-3, "{what}: in its plane: {p}");
            let turn = if rotates { 0.5 } else { 0.0 };
            assert!(
                (spin.z - turn).abs() < 1e-3 && spin.x.abs() + spin.y.abs() < 1e-3,
                "{what}: {spin}"
            );
            let travel = j.get(&w).unwrap().limit(1).unwrap().position();
            assert!(
                (travel + 0.5).abs() < 0.01,
                "{what}: the joint reads {travel}"
            );
            if mode == SolverMode::Hybrid {
                assert_eq!(reduced, 60, "{what}: in reduced coordinates");
            }
        }
    }
}
