//! A robot world once warm steps, and takes its controls and motors, without touching the
//! heap: joint dynamics, actuators, stops, contacts and world substeps included.

use kea3d::prelude::*;
use kea3d::robot::MjcfOptions;

mod counting;

use counting::allocations_in;

#[global_allocator]
static ALLOCATOR: counting::CountingAllocator = counting::CountingAllocator;

#[test]
fn a_warm_robot_world_steps_and_takes_its_controls_without_allocating() {
    // A planar hopper-like root, joint dynamics and springs, a ball joint with a cone limit
    // (a boxed joint: copying states reuses its box), actuators of every kind, stops,
    // a fixed tendon with a spring, a damper and a range, contacts with a floor (in joint
    // space: the tree stays reduced), and world substeps:
    // everything a robot adds to a step.
    let xml = r#"<mujoco><compiler angle="degree"/>
      <default><joint armature="0.1" damping="0.5" limited="true"/></default>
      <worldbody>
        <geom type="plane" size="5 5 0.1"/>
        <body name="torso" pos="0 0 1">
          <joint name="x" type="slide" axis="1 0 0" limited="false" armature="0" damping="0"/>
          <joint name="z" type="slide" axis="0 0 1" limited="false" armature="0" damping="0"/>
          <joint name="pitch" type="hinge" axis="0 1 0" limited="false" armature="0" damping="0"/>
          <geom type="capsule" size="0.05 0.2"/>
          <body name="thigh" pos="0 0 -0.2">
            <joint name="hip" type="hinge" axis="0 -1 0" range="-150 0" stiffness="5" frictionloss="0.1"/>
            <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.05"/>
            <body name="shin" pos="0 0 -0.4">
              <joint name="knee" type="hinge" axis="0 -1 0" range="-150 0"/>
              <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.04"/>
              <body name="foot" pos="0 0 -0.4">
                <joint name="ankle" type="ball" range="0 30"/>
                <geom type="sphere" size="0.05" contype="0" conaffinity="0"/>
              </body>
            </body>
          </body>
        </body>
      </worldbody>
      <actuator>
        <motor joint="hip" gear="50" ctrlrange="-1 1"/>
        <position joint="knee" kp="30" kv="1"/>
        <velocity joint="x" kv="5"/>
      </actuator>
      <tendon>
        <fixed name="hipknee" stiffness="2" damping="0.1" range="-0.5 0.5">
          <joint joint="hip" coef="1"/><joint joint="knee" coef="-1"/>
        </fixed>
      </tendon></mujoco>"#;
    let mut world = PhysicsWorld::new();
    let robot = world
        .load_mjcf_str(xml, "hopper.xml", &MjcfOptions::default())
        .unwrap();
    world
        .dynamics_mut()
        .update_settings(|s| s.world_substeps = 2)
        .unwrap();
    let template = world.clone();
    let controls: Vec<Vec<Real>> = (0..4).map(|k| vec![0.3 * k as Real, -0.2, 0.1]).collect();
    let motors = vec![0.0 as Real; robot.velocity_count()];
    let caps = vec![10.0 as Real; robot.velocity_count()];
    robot.set_joint_motors(&mut world, &motors, &caps).unwrap();
    for k in 0..240 {
        robot.set_controls(&mut world, &controls[k % 4]).unwrap();
        world.step(1.0 / 240.0).unwrap();
    }
    let n = allocations_in(|| {
        for k in 0..120 {
            robot.set_controls(&mut world, &controls[k % 4]).unwrap();
            world.step(1.0 / 240.0).unwrap();
        }
        robot.set_joint_motors(&mut world, &motors, &caps).unwrap();
        world.step(1.0 / 240.0).unwrap();
    });
    assert_eq!(n, 0, "{n} allocations in warm robot steps");
    // Another world's state copied in and out (a batch's reset, a worker's swap) once warm.
    let mut other = world.clone();
    for k in 0..60 {
        robot
            .set_controls(&mut other, &controls[(k + 1) % 4])
            .unwrap();
        other.step(1.0 / 240.0).unwrap();
    }
    let mut worker = world.clone();
    for _ in 0..2 {
        worker.copy_state_from(&other);
        worker.step(1.0 / 240.0).unwrap();
        worker.copy_state_from(&world);
        worker.step(1.0 / 240.0).unwrap();
    }
    let n = allocations_in(|| {
        for _ in 0..10 {
            worker.copy_state_from(&other);
            worker.step(1.0 / 240.0).unwrap();
            other.copy_state_only(&worker);
            worker.copy_state_from(&world);
            worker.step(1.0 / 240.0).unwrap();
        }
    });
    assert_eq!(n, 0, "{n} allocations copying warm worlds' states");
    // A batch's way: worlds that hold only their states (trimmed of the step's scratch),
    // traded into one worker, stepped there and traded back; as `kea.Batch` makes them, from
    // a world not yet stepped (no kept tree), so the worker and the worlds it trades with
    // hold different numbers of trees at first.
    let mut worker = template.clone();
    let mut held = [template.clone(), template.clone(), other.clone()];
    for h in &mut held {
        h.trim_to_state();
    }
    let trade = |worker: &mut PhysicsWorld, held: &mut [PhysicsWorld; 3]| {
        for h in held.iter_mut() {
            worker.swap_state(h);
            worker.step(1.0 / 240.0).unwrap();
            worker.swap_state(h);
        }
    };
    for _ in 0..3 {
        trade(&mut worker, &mut held);
    }
    let n = allocations_in(|| {
        for _ in 0..10 {
            trade(&mut worker, &mut held);
        }
    });
    assert_eq!(
        n, 0,
        "{n} allocations stepping warm held states in a worker"
    );
    // The same with held worlds, as `kea.Batch` keeps them: compact records beside the
    // model, taken into a worker with the model's definitions, stepped, given back; contacts
    // come and go in the records.
    let mut worker = template.clone();
    let mut held = [template.held(), template.held(), other.held()];
    let visit = |worker: &mut PhysicsWorld, held: &mut [kea3d::HeldWorld; 3]| {
        for h in held.iter_mut() {
            worker.enter(h);
            worker.step(1.0 / 240.0).unwrap();
            worker.leave(h, &template);
        }
    };
    for _ in 0..3 {
        visit(&mut worker, &mut held);
    }
    let n = allocations_in(|| {
        for _ in 0..10 {
            visit(&mut worker, &mut held);
        }
    });
    assert_eq!(
        n, 0,
        "{n} allocations stepping warm held worlds in a worker"
    );
    // Those steps were in reduced coordinates, with the contacts solved in joint space.
    let stats = world.step(1.0 / 240.0).unwrap();
    assert_eq!(stats.reduced_trees, 1, "the hopper is one reduced tree");
    assert!(
        world.dynamics().contacts().count() > 0,
        "it stands on the floor"
    );
    // The counter really counts on this thread.
    let n = allocations_in(|| drop(std::hint::black_box(vec![1u8; 64])));
    assert_eq!(n, 1, "a deliberate allocation counted {n} times");
}
