//! A batch's held worlds (the model/data split): each world a compact record of what its
//! steps change beside one model, stepped, read and written through a worker world with the
//! model's definitions. Every world comes out on the bits of the same world kept whole and
//! stepped on its own: snapshots byte for byte, joints and contacts, on robots whose
//! contacts come and go (the records hold them whole), with controls written on every
//! other call (and kept by the records between) and worlds driven apart; and a world whose joints stop matching the model's is held whole
//! from then on, without disturbing the others that share its worker.

mod common;
use common::{HOPPER, QUADRUPED};
use kea3d::robot::{MjcfOptions, Robot};
use kea3d::{HeldWorld, PhysicsWorld, Real};

fn bytes(w: &PhysicsWorld) -> Vec<u8> {
    w.snapshot().unwrap().to_binary().unwrap()
}

/// World `i`'s controls at call `call`: each world driven its own way.
fn controls(n: usize, call: usize, i: usize) -> Vec<Real> {
    (0..n)
        .map(|j| (0.5 * (call as Real * 0.2 + (i + 2 * j) as Real)).sin())
        .collect()
}

/// Everything a reader sees of a robot world: joint positions and velocities, and the
/// number of contacts.
fn seen(robot: &Robot, w: &PhysicsWorld) -> (Vec<Real>, Vec<Real>, usize) {
    let (mut q, mut v) = (
        vec![0.0; robot.position_count()],
        vec![0.0; robot.velocity_count()],
    );
    robot.joint_state_into(w, &mut q, &mut v).unwrap();
    (q, v, w.dynamics().contacts().count())
}

#[test]
fn held_worlds_step_through_one_worker_on_the_bits_of_whole_worlds() {
    let options = MjcfOptions::default();
    for (xml, name, n) in [(QUADRUPED, "quadruped.xml", 8), (HOPPER, "hopper.xml", 1)] {
        let mut model = PhysicsWorld::new();
        let robot = model.load_mjcf_str(xml, name, &options).unwrap();
        let h = robot.timestep().unwrap_or(0.005);
        let mut alone: Vec<PhysicsWorld> = (0..3).map(|_| model.clone()).collect();
        let mut held: Vec<HeldWorld> = (0..3).map(|_| model.held()).collect();
        assert!(held.iter().all(HeldWorld::is_compact), "{name}");
        let mut worker = model.clone();
        let mut touching = 0;
        for call in 0..60 {
            for i in 0..3 {
                // Controls on every other call: the others step on what the record kept.
                let u = controls(n, call, i);
                if call % 2 == 0 {
                    robot.set_controls(&mut alone[i], &u).unwrap();
                }
                alone[i].step_many(h, 5).unwrap();
                worker.enter(&mut held[i]);
                if call % 2 == 0 {
                    robot.set_controls(&mut worker, &u).unwrap();
                }
                worker.step_many(h, 5).unwrap();
                let what = format!("{name}, world {i}, call {call}");
                assert_eq!(seen(&robot, &worker), seen(&robot, &alone[i]), "{what}");
                if call % 6 == i {
                    assert!(bytes(&worker) == bytes(&alone[i]), "{what}: snapshots");
                }
                touching += usize::from(seen(&robot, &alone[i]).2 > 0);
                worker.leave(&mut held[i], &model);
                assert!(held[i].is_compact(), "{what}");
            }
        }
        assert!(
            touching > 30,
            "{name}: they touch the floor ({touching} of 180)"
        );
        // A reset world is the model again, bit for bit.
        let fresh = model.held();
        held[1].copy_from(&fresh);
        worker.enter(&mut held[1]);
        assert!(bytes(&worker) == bytes(&model), "{name}: reset");
        worker.leave(&mut held[1], &model);
    }
}

#[test]
fn a_held_world_whose_joints_part_from_the_models_is_held_whole_from_then_on() {
    let options = MjcfOptions::default();
    let mut model = PhysicsWorld::new();
    let robot = model
        .load_mjcf_str(QUADRUPED, "quadruped.xml", &options)
        .unwrap();
    let h = robot.timestep().unwrap_or(0.005);
    let knee = robot.joints().iter().rev().find_map(|j| j.raw).unwrap();
    let mut alone: Vec<PhysicsWorld> = (0..2).map(|_| model.clone()).collect();
    let mut held: Vec<HeldWorld> = (0..2).map(|_| model.held()).collect();
    let mut worker = model.clone();
    for call in 0..40 {
        for i in 0..2 {
            let u = controls(8, call, i);
            if call == 10 && i == 0 {
                alone[0].dynamics_mut().destroy_constraint(knee).unwrap();
                worker.enter(&mut held[0]);
                worker.dynamics_mut().destroy_constraint(knee).unwrap();
                worker.leave(&mut held[0], &model);
                assert!(
                    !held[0].is_compact(),
                    "its joints are no longer the model's"
                );
            }
            robot.set_controls(&mut alone[i], &u).ok();
            alone[i].step_many(h, 5).unwrap();
            worker.enter(&mut held[i]);
            robot.set_controls(&mut worker, &u).ok();
            worker.step_many(h, 5).unwrap();
            let what = format!("world {i}, call {call}");
            assert!(bytes(&worker) == bytes(&alone[i]), "{what}: snapshots");
            worker.leave(&mut held[i], &model);
            assert_eq!(held[i].is_compact(), i == 1 || call < 10, "{what}");
        }
    }
}

/// A worker that changes a definition the model holds (here a body's mass) while it holds a
/// world would change every world it steps after: debug builds refuse it when the world
/// leaves.
#[cfg(debug_assertions)]
#[test]
#[should_panic(expected = "changed a definition the model holds")]
fn a_definition_changed_in_a_worker_is_caught_when_its_world_leaves() {
    let mut model = PhysicsWorld::new();
    let robot = model
        .load_mjcf_str(HOPPER, "hopper.xml", &MjcfOptions::default())
        .unwrap();
    let mut held = model.held();
    let mut worker = model.clone();
    worker.enter(&mut held);
    let torso = robot.links()[0].body;
    worker
        .dynamics_mut()
        .body_mut(torso)
        .unwrap()
        .set_mass(9.0)
        .unwrap();
    worker.leave(&mut held, &model);
}
