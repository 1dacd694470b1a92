//! The one-world API: builders, density-derived mass against closed forms, body types,
//! kinematic bodies pushing dynamic ones, typed joints, growing capacities. Physics checks
//! run on the exact and the iterative path.

use kea::{Routing, SolverMode, PI_REAL as PI};
use kea3d::prelude::*;
use kea3d::{Error, Mat3};

const DT: Real = 1.0 / 60.0;

fn world_on(mode: SolverMode) -> PhysicsWorld {
    let mut w = PhysicsWorld::new();
    let routing = Routing {
        mode,
        ..Routing::default()
    };
    w.dynamics_mut()
        .update_settings(|s| s.routing = routing)
        .unwrap();
    w
}

fn close(a: Real, b: Real, rel: Real) -> bool {
    (a - b).abs() <= rel * b.abs().max(1e-12)
}

fn assert_mat_close(a: Mat3, b: Mat3, rel: Real) {
    let scale = b
        .to_cols_array()
        .iter()
        .fold(0.0 as Real, |m, x| m.max(x.abs()));
    for (x, y) in a.to_cols_array().iter().zip(b.to_cols_array()) {
        assert!((x - y).abs() <= rel * scale, "{a} vs {b}");
    }
}

#[test]
fn a_box_weighs_its_density_times_its_volume() {
    let mut w = PhysicsWorld::new();
    let b = w.insert_body(Body::dynamic()).unwrap();
    let (hx, hy, hz, rho) = (0.5, 0.25, 1.0, 700.0);
    w.insert_collider(Collider::cuboid([hx, hy, hz]).density(rho), Some(b))
        .unwrap();
    let m = 8.0 * hx * hy * hz * rho;
    let body = w.body(b).unwrap();
    assert!(close(body.mass(), m, 1e-5), "mass {}", body.mass());
    let i = Mat3::from_diagonal(Vec3::new(
        m / 3.0 * (hy * hy + hz * hz),
        m / 3.0 * (hx * hx + hz * hz),
        m / 3.0 * (hx * hx + hy * hy),
    ));
    assert_mat_close(body.inertia(), i, 1e-4);
}

#[test]
fn a_ball_and_a_capsule_along_x_weigh_as_the_closed_forms_say() {
    let mut w = PhysicsWorld::new();
    let (r, rho) = (0.3, 1000.0);
    let ball = w.insert_body(Body::dynamic()).unwrap();
    w.insert_collider(Collider::ball(r), Some(ball)).unwrap();
    let m = 4.0 / 3.0 * PI * r * r * r * rho;
    let body = w.body(ball).unwrap();
    assert!(close(body.mass(), m, 1e-5));
    assert_mat_close(body.inertia(), Mat3::IDENTITY * (0.4 * m * r * r), 1e-4);

    // A capsule turned onto x: its long axis is x, so x has the small moment, y and z the
    // big one; the same numbers as a capsule along y with x and y swapped.
    let (hh, cr) = (0.5, 0.1);
    let upright = w.insert_body(Body::dynamic()).unwrap();
    w.insert_collider(Collider::capsule_y(hh, cr), Some(upright))
        .unwrap();
    let lying = w.insert_body(Body::dynamic()).unwrap();
    w.insert_collider(Collider::capsule_x(hh, cr), Some(lying))
        .unwrap();
    let iu = w.body(upright).unwrap().inertia();
    let il = w.body(lying).unwrap().inertia();
    assert!(close(il.x_axis.x, iu.y_axis.y, 1e-4), "{il} vs {iu}");
    assert!(close(il.y_axis.y, iu.x_axis.x, 1e-4), "{il} vs {iu}");
    // Closed form of the capsule's mass: cylinder plus sphere.
    let mc = rho * (PI * cr * cr * 2.0 * hh + 4.0 / 3.0 * PI * cr * cr * cr);
    assert!(close(w.body(lying).unwrap().mass(), mc, 1e-4));
    // A capsule between two points is oriented freely: along (1, 1, 0) its axis moment
    // sits on that diagonal.
    let slanted = w.insert_body(Body::dynamic()).unwrap();
    w.insert_collider(
        Collider::capsule([-0.5, -0.5, 0.0], [0.5, 0.5, 0.0], cr),
        Some(slanted),
    )
    .unwrap();
    let i = w.body(slanted).unwrap().inertia();
    let d = Vec3::new(1.0, 1.0, 0.0).normalize();
    let axial = d.dot(i * d);
    let len_hh = (0.5 as Real) * (2.0 as Real).sqrt();
    let upright2 = w.insert_body(Body::dynamic()).unwrap();
    w.insert_collider(Collider::capsule_y(len_hh, cr), Some(upright2))
        .unwrap();
    assert!(close(
        axial,
        w.body(upright2).unwrap().inertia().y_axis.y,
        1e-3
    ));
}

#[test]
fn two_colliders_put_the_centre_of_mass_between_them_and_keep_the_origin() {
    let mut w = PhysicsWorld::new();
    let b = w
        .insert_body(Body::dynamic().position([1.0, 2.0, 3.0]))
        .unwrap();
    let r = 0.2;
    w.insert_collider(Collider::ball(r).translation([-1.0, 0.0, 0.0]), Some(b))
        .unwrap();
    w.insert_collider(
        Collider::ball(r)
            .translation([1.0, 0.0, 0.0])
            .density(3000.0),
        Some(b),
    )
    .unwrap();
    // Masses 1:3 at x = -1 and +1: the centre sits at x = 0.5.
    let com = w.local_center_of_mass(b).unwrap();
    assert!((com - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-5, "{com}");
    let p = w.position(b).unwrap();
    assert!((p - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-5, "origin {p}");
    assert!((w.body(b).unwrap().position() - Vec3::new(1.5, 2.0, 3.0)).length() < 1e-5);
    // Parallel axis: about y, m1 d1² + m2 d2² on top of the two balls' own moments.
    let m1 = 4.0 / 3.0 * PI * r * r * r * 1000.0;
    let m2 = 3.0 * m1;
    let own = 0.4 * (m1 + m2) * r * r;
    let iyy = own + m1 * 1.5 * 1.5 + m2 * 0.5 * 0.5;
    assert!(close(w.body(b).unwrap().inertia().y_axis.y, iyy, 1e-4));
}

#[test]
fn an_explicit_mass_wins_and_keeps_the_shape_of_the_inertia() {
    let mut w = PhysicsWorld::new();
    let b = w.insert_body(Body::dynamic().mass(2.0)).unwrap();
    w.insert_collider(Collider::cuboid([1.0, 0.5, 0.25]), Some(b))
        .unwrap();
    let body = w.body(b).unwrap();
    assert_eq!(body.mass(), 2.0);
    let i = Mat3::from_diagonal(Vec3::new(
        2.0 / 3.0 * (0.25 + 0.0625),
        2.0 / 3.0 * (1.0 + 0.0625),
        2.0 / 3.0 * (1.0 + 0.25),
    ));
    assert_mat_close(body.inertia(), i, 1e-4);
}

#[test]
fn free_fall_follows_the_closed_form_on_both_paths() {
    for mode in [SolverMode::Exact, SolverMode::Iterative] {
        let mut w = world_on(mode);
        let b = w
            .insert_body(Body::dynamic().position((0.0, 100.0, 0.0)))
            .unwrap();
        w.insert_collider(Collider::ball(0.5), Some(b)).unwrap();
        let n = 60;
        for _ in 0..n {
            w.step(DT).unwrap();
        }
        // Semi-implicit Euler: v_n = -g n h, y_n = y0 - g h² n(n+1)/2.
        let g = 9.81;
        let y = 100.0 - g * DT * DT * (n * (n + 1)) as Real / 2.0;
        let p = w.position(b).unwrap();
        assert!((p.y - y).abs() < 1e-3, "{mode:?}: {} vs {y}", p.y);
        assert!((w.linear_velocity(b).unwrap().y + g * DT * n as Real).abs() < 1e-3);
    }
}

/// A kinematic pusher moving at 1 m/s along x meets a 1 kg box resting on a static floor.
fn pusher_scene(mode: SolverMode, kind: BodyType) -> (PhysicsWorld, BodyHandle, BodyHandle) {
    let mut w = world_on(mode);
    let floor = w.insert_body(Body::fixed()).unwrap();
    w.insert_collider(Collider::cuboid([20.0, 0.5, 20.0]), Some(floor))
        .unwrap();
    let boxed = w
        .insert_body(Body::dynamic().position([1.0, 1.0, 0.0]))
        .unwrap();
    w.insert_collider(
        Collider::cuboid([0.5, 0.5, 0.5]).density(125.0),
        Some(boxed),
    )
    .unwrap();
    let pusher = w
        .insert_body(Body::new(kind).position([-1.0, 1.1, 0.0]))
        .unwrap();
    w.insert_collider(Collider::cuboid([0.5, 0.55, 1.0]), Some(pusher))
        .unwrap();
    (w, boxed, pusher)
}

#[test]
fn a_kinematic_body_pushes_a_dynamic_one_and_is_not_pushed_back() {
    for mode in [SolverMode::Exact, SolverMode::Iterative] {
        let (mut w, boxed, pusher) = pusher_scene(mode, BodyType::KinematicVelocity);
        w.set_linear_velocity(pusher, [1.0, 0.0, 0.0]).unwrap();
        let steps = 180;
        for _ in 0..steps {
            w.step(DT).unwrap();
        }
        // The pusher moved exactly at its set speed, whatever it hit.
        let px = w.position(pusher).unwrap().x;
        assert!(
            (px - (-1.0 + steps as Real * DT)).abs() < 1e-4,
            "{mode:?}: pusher at {px}"
        );
        assert_eq!(w.linear_velocity(pusher).unwrap(), Vec3::new(1.0, 0.0, 0.0));
        // The box is carried ahead of it at its speed, face to face (1 m between centres).
        let bx = w.position(boxed).unwrap().x;
        assert!(
            (bx - px - 1.0).abs() < 0.02,
            "{mode:?}: box {bx}, pusher {px}"
        );
        let v = w.linear_velocity(boxed).unwrap().x;
        assert!((v - 1.0).abs() < 0.05, "{mode:?}: box speed {v}");
        let y = w.position(boxed).unwrap().y;
        assert!((y - 1.0).abs() < 0.02, "{mode:?}: box y {y}");
    }
}

#[test]
fn a_position_driven_kinematic_body_reaches_each_target_and_pushes() {
    for mode in [SolverMode::Exact, SolverMode::Iterative] {
        let (mut w, boxed, pusher) = pusher_scene(mode, BodyType::KinematicPosition);
        let steps = 180;
        for i in 1..=steps {
            let x = -1.0 + i as Real * DT;
            let q = Quat::from_rotation_y(0.0);
            w.set_kinematic_target(pusher, [x, 1.1, 0.0], q).unwrap();
            w.step(DT).unwrap();
            let p = w.position(pusher).unwrap();
            assert!((p.x - x).abs() < 1e-4, "{mode:?} step {i}: {} vs {x}", p.x);
        }
        // Without a target it stands still.
        w.step(DT).unwrap();
        assert_eq!(w.linear_velocity(pusher).unwrap(), Vec3::ZERO);
        let (bx, px) = (w.position(boxed).unwrap().x, w.position(pusher).unwrap().x);
        assert!(
            (bx - px - 1.0).abs() < 0.05,
            "{mode:?}: box {bx}, pusher {px}"
        );
        // A rotation target is reached too.
        let q = Quat::from_rotation_y(0.3);
        w.set_kinematic_target(pusher, [px, 1.1, 0.0], q).unwrap();
        w.step(DT).unwrap();
        let got = w.rotation(pusher).unwrap();
        assert!(got.angle_between(q) < 1e-4, "{got} vs {q}");
    }
}

#[test]
fn a_hinge_pendulum_swings_with_the_small_angle_period() {
    for mode in [SolverMode::Exact, SolverMode::Iterative] {
        let mut w = world_on(mode);
        let l = 1.0;
        let bob = w
            .insert_body(Body::dynamic().position([
                l * 0.05_f64.sin() as Real,
                -l * 0.05_f64.cos() as Real,
                0.0,
            ]))
            .unwrap();
        w.insert_collider(Collider::ball(0.01).density(1.0e4), Some(bob))
            .unwrap();
        let hinge = w
            .insert_joint(bob, None, Joint::hinge([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]))
            .unwrap();
        // Period of the first two upward zero crossings of x's velocity sign change.
        let mut last_x = w.position(bob).unwrap().x;
        let mut crossings = Vec::new();
        for i in 1..=1200 {
            w.step(1.0 / 240.0).unwrap();
            let x = w.position(bob).unwrap().x;
            if last_x < 0.0 && x >= 0.0 {
                crossings.push(i as Real / 240.0);
            }
            last_x = x;
        }
        let period = crossings[1] - crossings[0];
        let expected = 2.0 * PI * (l / 9.81).sqrt();
        assert!(
            (period - expected).abs() < 0.02,
            "{mode:?}: {period} vs {expected}"
        );
        // The hinge's angle is the swing since its creation.
        let p = w.position(bob).unwrap();
        let swing = p.x.atan2(-p.y) - 0.05;
        let angle = hinge.angle(&w).unwrap();
        assert!(
            (angle.abs() - swing.abs()).abs() < 1e-3,
            "{angle} vs {swing}"
        );
    }
}

#[test]
fn typed_joint_handles_carry_their_calls_and_check_their_kind() {
    let mut w = PhysicsWorld::new();
    let a = w.insert_body(Body::dynamic().mass(1.0)).unwrap();
    let slider = w
        .insert_joint(
            a,
            None,
            Joint::prismatic([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
                .limits(-0.5, 0.5)
                .motor(2.0, 100.0),
        )
        .unwrap();
    w.set_gravity([0.0, 0.0, 0.0]).unwrap();
    for _ in 0..60 {
        w.step(DT).unwrap();
    }
    // The motor drives it to the upper stop and it stays there.
    let d = slider.distance(&w).unwrap();
    assert!((d - 0.5).abs() < 0.01, "distance {d}");
    assert!(slider.get(&w).unwrap().limit().is_limited());
    slider.set_motor(&mut w, -2.0, 100.0).unwrap();
    for _ in 0..60 {
        w.step(DT).unwrap();
    }
    assert!((slider.distance(&w).unwrap() + 0.5).abs() < 0.01);
    let err = kea3d::JointHandle::<Hinge>::try_from_raw(&w, slider.raw()).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("hinge") && text.contains("prismatic"),
        "{text}"
    );
}

#[test]
fn bad_input_is_refused_by_name_and_changes_nothing() {
    let mut w = PhysicsWorld::new();
    let b = w.insert_body(Body::dynamic()).unwrap();
    let before = w.body(b).unwrap().clone();
    let err = w
        .insert_collider(Collider::cuboid([1.0, 1.0, 1.0]).density(-3.0), Some(b))
        .unwrap_err();
    assert!(err.to_string().contains("density"), "{err}");
    let err = w
        .insert_collider(Collider::ball(Real::NAN), Some(b))
        .unwrap_err();
    assert!(err.to_string().contains("radius"), "{err}");
    assert_eq!(w.body(b).unwrap(), &before);
    assert_eq!(w.collision().collider_count(), 0);
    let err = w
        .insert_body(Body::fixed().linear_velocity([1.0, 0.0, 0.0]))
        .unwrap_err();
    assert!(matches!(err, Error::Kea(_)), "{err}");
    let err = w.step(-1.0).unwrap_err();
    assert!(err.to_string().contains("dt"), "{err}");
    // A bad collision setting is refused before the drivers move anything: a kinematic body
    // with a target keeps its velocity, the clock stands.
    let k = w.insert_body(Body::kinematic_position_based()).unwrap();
    w.set_kinematic_target(k, [1.0, 0.0, 0.0], Quat::IDENTITY)
        .unwrap();
    w.collision_mut().margin = -1.0;
    let err = w.step(1.0 / 60.0).unwrap_err();
    assert!(err.to_string().contains("margin"), "{err}");
    assert_eq!(w.dynamics().body(k).unwrap().linear_velocity(), Vec3::ZERO);
    assert_eq!(w.time(), 0.0);
    w.collision_mut().margin = 0.0;
    w.step(1.0 / 60.0).unwrap();
    let v = w.dynamics().body(k).unwrap().linear_velocity();
    assert!(
        (v.x - 60.0).abs() < 1e-3,
        "the target drives it once accepted: {v}"
    );
    w.remove_body(k).unwrap();
    let err = w
        .insert_joint(b, None, Joint::hinge([0.0, 0.0, 0.0], [0.0, 0.0, 0.0]))
        .unwrap_err();
    assert!(err.to_string().contains("axis"), "{err}");
    assert_eq!(w.dynamics().constraint_count(), 0);
    // A collider added after a joint that would move the centre of mass is refused.
    w.insert_joint(b, None, Joint::ball([0.0, 0.0, 0.0]))
        .unwrap();
    let err = w
        .insert_collider(Collider::ball(0.1).translation([1.0, 0.0, 0.0]), Some(b))
        .unwrap_err();
    assert!(err.to_string().contains("joints"), "{err}");
    assert_eq!(w.collision().collider_count(), 0);
}

#[test]
fn capacities_grow_as_a_pyramid_fills_a_tiny_world() {
    let mut w = PhysicsWorld::with_def(kea::WorldDef {
        max_bodies: 1,
        max_constraints: 1,
        ..kea::WorldDef::default()
    })
    .unwrap();
    w.insert_collider(Collider::halfspace([0.0, 1.0, 0.0]), None)
        .unwrap();
    let mut boxes = Vec::new();
    for row in 0..5 {
        for i in 0..(5 - row) {
            let x = (i as Real - (4 - row) as Real * 0.5) * 1.05;
            let b = w
                .insert_body(Body::dynamic().position([x, 0.5 + row as Real, 0.0]))
                .unwrap();
            w.insert_collider(Collider::cuboid([0.5, 0.5, 0.5]), Some(b))
                .unwrap();
            boxes.push((b, x, 0.5 + row as Real));
        }
    }
    for _ in 0..120 {
        let stats = w.step(DT).unwrap();
        assert_eq!(stats.collision.dropped_manifolds, 0);
    }
    assert!(w.dynamics().max_constraints() >= w.dynamics().constraint_count());
    for (b, x, y) in boxes {
        let p = w.position(b).unwrap();
        assert!(
            (p - Vec3::new(x, y, 0.0)).length() < 0.05,
            "{p} vs ({x}, {y})"
        );
    }
}
