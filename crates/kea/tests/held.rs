//! Held worlds (the model/data split of batches, `World::held`): worlds stepped, read and
//! written through one worker with the model's definitions come out on the bits of the
//! same worlds stepped on their own — a hinge and a slider with motors (their records hold
//! the motion only), a ball-joint chain and a fixed joint (held whole, boxed), a free body
//! and a quarantine-free solver path — with motors written on every other call and the
//! worlds driven apart. A world whose joint is removed is held whole from then on.

use kea::{BodyDef, BodyHandle, ConstraintHandle, HeldState, JointSpec, Real, Vec3, World};

struct Model {
    world: World,
    bodies: Vec<BodyHandle>,
    hinge: kea::JointHandle<kea::constraint::Hinge>,
    slider: kea::JointHandle<kea::constraint::Prismatic>,
    ball: ConstraintHandle,
    joints: Vec<ConstraintHandle>,
}

fn model() -> Model {
    let mut w = World::with_capacity(16, 64).unwrap();
    w.update_settings(|s| s.gravity = Vec3::new(0.0, -9.81, 0.0))
        .unwrap();
    let body = |w: &mut World, x: Real, y: Real| {
        w.create_body(&BodyDef {
            position: Vec3::new(x, y, 0.0),
            ..BodyDef::default()
        })
        .unwrap()
    };
    let arm = body(&mut w, 1.0, 0.0);
    let hinge = w
        .create_joint(
            arm,
            None,
            JointSpec::hinge(Vec3::ZERO, Vec3::Z).motor(0.0, 2.0),
        )
        .unwrap();
    let cart = body(&mut w, 0.0, -3.0);
    let slider = w
        .create_joint(
            cart,
            None,
            JointSpec::prismatic(Vec3::new(0.0, -3.0, 0.0), Vec3::X).motor(0.0, 5.0),
        )
        .unwrap();
    let (a, b) = (body(&mut w, 3.0, 0.0), body(&mut w, 4.0, 0.0));
    let ball = w
        .create_joint(a, None, JointSpec::ball(Vec3::new(2.5, 0.0, 0.0)))
        .unwrap();
    let ball2 = w
        .create_joint(b, Some(a), JointSpec::ball(Vec3::new(3.5, 0.0, 0.0)))
        .unwrap();
    let c = body(&mut w, 5.0, 0.0);
    let fixed = w
        .create_joint(c, Some(b), JointSpec::fixed(Vec3::new(4.5, 0.0, 0.0)))
        .unwrap();
    let free = body(&mut w, -3.0, 2.0);
    Model {
        world: w,
        bodies: vec![arm, cart, a, b, c, free],
        hinge,
        slider,
        ball: ball.into(),
        joints: vec![
            hinge.into(),
            slider.into(),
            ball.into(),
            ball2.into(),
            fixed.into(),
        ],
    }
}

/// The bits of a real, widened (in f32 and f64 alike).
#[allow(clippy::unnecessary_cast)] // a no-op in f64
fn bits_of(x: Real) -> u64 {
    x.to_bits() as u64
}

/// The bits of every body's pose and velocities and of every joint's reactions.
fn bits(m: &Model, w: &World) -> Vec<u64> {
    let mut out = Vec::new();
    for &h in &m.bodies {
        let b = w.body(h).unwrap();
        let (p, q) = (b.position(), b.orientation());
        let (v, a) = (b.linear_velocity(), b.angular_velocity());
        for x in [
            p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, a.x, a.y, a.z,
        ] {
            out.push(bits_of(x));
        }
    }
    // (A removed joint has none.)
    for r in m
        .joints
        .iter()
        .filter_map(|&h| w.constraint_reaction(h).ok())
    {
        for r in r {
            for x in r.force.to_array().into_iter().chain(r.torque.to_array()) {
                out.push(bits_of(x));
            }
        }
    }
    out
}

/// World `i`'s drive at call `call`: motors, and a push on the free body.
fn drive(m: &Model, w: &mut World, call: usize, i: usize) {
    let s = (0.3 * call as Real + i as Real).sin();
    m.hinge.set_motor(w, 2.0 * s, 2.0).unwrap();
    m.slider.set_motor(w, -s, 5.0).unwrap();
    w.body_mut(m.bodies[5])
        .unwrap()
        .set_linear_velocity(Vec3::new(s, 1.0, 0.0))
        .unwrap();
}

#[test]
fn held_worlds_step_through_one_worker_on_the_bits_of_whole_worlds() {
    let m = model();
    let mut alone: Vec<World> = (0..3).map(|_| m.world.clone()).collect();
    let mut held: Vec<HeldState> = (0..3).map(|_| m.world.held()).collect();
    assert!(held.iter().all(HeldState::is_compact));
    let mut worker = m.world.clone();
    for call in 0..40 {
        for i in 0..3 {
            // Drives on every other call: the others step on what the records kept.
            if call % 2 == 0 {
                drive(&m, &mut alone[i], call, i);
            }
            alone[i].step_many(1.0 / 120.0, 4).unwrap();
            worker.enter(&mut held[i]);
            if call % 2 == 0 {
                drive(&m, &mut worker, call, i);
            }
            worker.step_many(1.0 / 120.0, 4).unwrap();
            assert_eq!(
                bits(&m, &worker),
                bits(&m, &alone[i]),
                "world {i}, call {call}"
            );
            worker.leave(&mut held[i], &m.world);
            assert!(held[i].is_compact());
        }
    }
    // Apart: the motors turned the worlds' arms differently.
    let angle = |w: &World| m.hinge.angle(w).unwrap();
    assert!((angle(&alone[0]) - angle(&alone[1])).abs() > 1e-3);
    // A reset world is the model again.
    held[2].copy_from(&m.world.held());
    worker.enter(&mut held[2]);
    assert_eq!(bits(&m, &worker), bits(&m, &m.world));
    worker.leave(&mut held[2], &m.world);
}

#[test]
fn a_held_world_whose_joint_is_removed_is_held_whole_from_then_on() {
    let m = model();
    let mut alone: Vec<World> = (0..2).map(|_| m.world.clone()).collect();
    let mut held: Vec<HeldState> = (0..2).map(|_| m.world.held()).collect();
    let mut worker = m.world.clone();
    alone[0].destroy_constraint(m.ball).unwrap();
    worker.enter(&mut held[0]);
    worker.destroy_constraint(m.ball).unwrap();
    worker.leave(&mut held[0], &m.world);
    assert!(
        !held[0].is_compact(),
        "its joints are no longer the model's"
    );
    for call in 0..20 {
        for i in 0..2 {
            drive(&m, &mut alone[i], call, i);
            alone[i].step(1.0 / 60.0).unwrap();
            worker.enter(&mut held[i]);
            drive(&m, &mut worker, call, i);
            worker.step(1.0 / 60.0).unwrap();
            assert_eq!(
                bits(&m, &worker),
                bits(&m, &alone[i]),
                "world {i}, call {call}"
            );
            worker.leave(&mut held[i], &m.world);
            assert_eq!(held[i].is_compact(), i == 1, "world {i}");
        }
    }
}
