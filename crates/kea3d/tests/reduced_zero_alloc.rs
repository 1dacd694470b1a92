//! A fixed-base arm stepped in reduced coordinates (`kea::Routing::max_reduced_links`), once
//! warm, steps and takes its controls without touching the heap.

use kea3d::prelude::*;
use kea3d::robot::MjcfOptions;

mod counting;

use counting::allocations_in;

#[global_allocator]
static ALLOCATOR: counting::CountingAllocator = counting::CountingAllocator;

#[test]
fn a_warm_arm_in_reduced_coordinates_steps_without_allocating() {
    // A fixed-base arm with a branch (two fingers on sliders): hinges with stops, armature,
    // damping, springs and friction, a motor, a force and an uncapped servo — all stepped in
    // reduced coordinates.
    let xml = r#"<mujoco><option gravity="0 0 -9.81"/>
      <default><joint armature="0.05" damping="0.2" limited="true" range="-2 2"/></default>
      <worldbody>
        <body name="base" pos="0 0 1">
          <joint name="j1" type="hinge" axis="0 0 1" stiffness="3" frictionloss="0.05"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.04" contype="0" conaffinity="0"/>
          <body name="upper" pos="0.3 0 0">
            <joint name="j2" type="hinge" axis="0 1 0"/>
            <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.04" contype="0" conaffinity="0"/>
            <body name="left" pos="0.3 0.05 0">
              <joint name="f1" type="slide" axis="0 1 0" range="0 0.04"/>
              <geom type="box" size="0.02 0.01 0.03" contype="0" conaffinity="0"/>
            </body>
            <body name="right" pos="0.3 -0.05 0">
              <joint name="f2" type="slide" axis="0 -1 0" range="0 0.04"/>
              <geom type="box" size="0.02 0.01 0.03" contype="0" conaffinity="0"/>
            </body>
          </body>
        </body>
      </worldbody>
      <actuator>
        <motor joint="j1" gear="10"/>
        <position joint="j2" kp="40" kv="2"/>
        <velocity joint="f1" kv="3"/>
      </actuator></mujoco>"#;
    let mut world = PhysicsWorld::new();
    world.set_gravity([0.0, 0.0, -9.81]).unwrap();
    let robot = world
        .load_mjcf_str(xml, "arm.xml", &MjcfOptions::default())
        .unwrap();
    let controls: Vec<Vec<Real>> = (0..4).map(|k| vec![0.3 * k as Real, -0.5, 0.1]).collect();
    let motors = vec![0.0 as Real; robot.velocity_count()];
    let caps = vec![1.0 as Real; robot.velocity_count()];
    robot.set_joint_motors(&mut world, &motors, &caps).unwrap();
    for k in 0..240 {
        robot.set_controls(&mut world, &controls[k % 4]).unwrap();
        let stats = world.step(1.0 / 240.0).unwrap();
        assert_eq!(stats.reduced_trees, 1, "step {k}: the arm is one tree");
    }
    let n = allocations_in(|| {
        for k in 0..120 {
            robot.set_controls(&mut world, &controls[k % 4]).unwrap();
            world.step(1.0 / 240.0).unwrap();
        }
    });
    assert_eq!(n, 0, "{n} allocations in warm reduced steps");
    // The counter really counts on this thread.
    let n = allocations_in(|| drop(std::hint::black_box(vec![1u8; 64])));
    assert_eq!(n, 1, "a deliberate allocation counted {n} times");
}
