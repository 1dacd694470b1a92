//! A robot's link states and actuator forces (what Gymnasium's Ant and Humanoid observe):
//! checked against statics and definitions on a small legged robot of our own.

use kea3d::prelude::*;
use kea3d::robot::{LinkState, MjcfOptions};

/// A box on two legs (a hinge each, one with a foot welded on) on a floor, a motor per hip,
/// the legs' geoms contacting the floor only (MuJoCo's contype/conaffinity).
const ROBOT: &str = r#"
<mujoco model="biped">
  <option timestep="0.002" gravity="0 0 -9.81"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1" conaffinity="1" contype="1"/>
    <body name="torso" pos="0 0 0.5">
      <freejoint name="root"/>
      <geom type="box" size="0.2 0.1 0.05" mass="4" contype="1" conaffinity="0"/>
      <body name="left" pos="0.15 0 -0.05">
        <joint name="left_hip" type="hinge" axis="0 1 0" range="-30 30"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.03" mass="1" contype="1" conaffinity="0"/>
        <body name="left_foot" pos="0 0 -0.3">
          <geom type="sphere" size="0.05" mass="0.5" contype="1" conaffinity="0"/>
        </body>
      </body>
      <body name="right" pos="-0.15 0 -0.05">
        <joint name="right_hip" type="hinge" axis="0 1 0" range="-30 30"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.35" size="0.03" mass="1" contype="1" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor joint="left_hip" gear="20" ctrlrange="-1 1"/>
    <motor joint="right_hip" gear="30" ctrlrange="-0.5 0.5"/>
  </actuator>
</mujoco>
"#;

fn biped() -> (PhysicsWorld, kea3d::robot::Robot) {
    let mut world = PhysicsWorld::new();
    let robot = world
        .load_mjcf_str(ROBOT, "biped.xml", &MjcfOptions::default())
        .unwrap();
    (world, robot)
}

fn states(world: &PhysicsWorld, robot: &kea3d::robot::Robot) -> Vec<LinkState> {
    let mut out = Vec::new();
    robot.link_states(world, &mut out).unwrap();
    out
}

#[test]
fn a_robot_at_rest_stands_on_contact_forces_equal_to_its_weight() {
    let (mut world, robot) = biped();
    let h = robot.timestep().unwrap();
    for _ in 0..1500 {
        world.step(h).unwrap();
    }
    let s = states(&world, &robot);
    let names: Vec<&str> = robot.links().iter().map(|l| l.name.as_str()).collect();
    let at = |n: &str| names.iter().position(|x| *x == n).unwrap();
    // Each link's own mass, also the foot welded to its leg's body.
    let masses: Vec<Real> = s.iter().map(|x| x.mass).collect();
    assert!((masses[at("torso")] - 4.0).abs() < 1e-4, "{masses:?}");
    assert!((masses[at("left_foot")] - 0.5).abs() < 1e-4, "{masses:?}");
    assert!((masses[at("left")] - 1.0).abs() < 1e-4, "{masses:?}");
    let total: Real = masses.iter().sum();
    assert!((total - 6.5).abs() < 1e-3, "total {total}");
    // At rest the contacts carry the weight: on the robot's links m g up, on the floor the
    // same down; the foot's contacts are on the foot, none on the leg above it.
    let on_robot: Vec3 = s[1..].iter().map(|x| x.contact_force).sum();
    let weight: Real = 6.5 * 9.81;
    assert!(
        (on_robot.z - weight).abs() < 0.01 * weight,
        "contacts on the robot {on_robot}, weight {weight}"
    );
    assert!(on_robot.x.hypot(on_robot.y) < 0.01 * weight, "{on_robot}");
    assert!(
        (s[0].contact_force + on_robot).length() < 1e-3 * weight,
        "floor {}",
        s[0].contact_force
    );
    assert!(
        s[at("left_foot")].contact_force.z > 0.1 * weight,
        "{:?}",
        s[at("left_foot")]
    );
    assert_eq!(s[at("left")].contact_force, Vec3::ZERO);
    // The moments balance too: about the robot's centre of mass the contacts' torques sum
    // to zero (gravity has none there), within what the last step still moves.
    let centre: Vec3 = s[1..]
        .iter()
        .map(|x| x.center_of_mass * x.mass)
        .sum::<Vec3>()
        / 6.5;
    let torque: Vec3 = s[1..]
        .iter()
        .map(|x| x.contact_torque + (x.center_of_mass - centre).cross(x.contact_force))
        .sum();
    assert!(torque.length() < 0.02 * weight * 0.3, "torque {torque}");
}

#[test]
fn link_velocities_are_their_bodies_rigid_motion_at_each_centre_of_mass() {
    let (mut world, robot) = biped();
    let v = vec![0.3, -0.2, 0.1, 0.5, -1.0, 2.0, 1.5, -0.7];
    robot.set_joint_velocities(&mut world, &v).unwrap();
    let s = states(&world, &robot);
    let names: Vec<&str> = robot.links().iter().map(|l| l.name.as_str()).collect();
    let (leg, foot) = (
        names.iter().position(|x| *x == "left").unwrap(),
        names.iter().position(|x| *x == "left_foot").unwrap(),
    );
    // The foot is welded to the leg: one rigid motion, v_foot = v_leg + ω × (c_foot − c_leg).
    let (a, b) = (s[leg], s[foot]);
    assert!((a.angular_velocity - b.angular_velocity).length() < 1e-5);
    let expected = a.linear_velocity
        + a.angular_velocity
            .cross(b.center_of_mass - a.center_of_mass);
    assert!(
        (b.linear_velocity - expected).length() < 1e-4,
        "{} vs {expected}",
        b.linear_velocity
    );
    // The torso turns at the free joint's rate (given in its own frame) and its centre moves
    // at the joint's linear rate (its origin is its centre of mass here).
    let torso = s[names.iter().position(|x| *x == "torso").unwrap()];
    assert!(
        (torso.linear_velocity - Vec3::new(0.3, -0.2, 0.1)).length() < 1e-4,
        "{}",
        torso.linear_velocity
    );
    assert!((torso.angular_velocity - Vec3::new(0.5, -1.0, 2.0)).length() < 1e-4);
    // The world link neither weighs nor moves.
    assert_eq!((s[0].mass, s[0].linear_velocity), (0.0, Vec3::ZERO));
}

#[test]
fn actuator_forces_are_gear_times_the_clamped_control_on_their_coordinates() {
    let (world, robot) = biped();
    let f = robot.actuator_forces(&world, &[0.5, 2.0]).unwrap();
    assert_eq!(f.len(), robot.velocity_count());
    // Free joint first (6), then the hips: 20 × 0.5 and 30 × 0.5 (clamped from 2).
    assert_eq!(&f[..6], &[0.0; 6]);
    assert!(
        (f[6] - 10.0).abs() < 1e-5 && (f[7] - 15.0).abs() < 1e-5,
        "{f:?}"
    );
    // A wrong length or a NaN is refused, naming the argument.
    let e = robot
        .actuator_forces(&world, &[0.5])
        .unwrap_err()
        .to_string();
    assert!(e.contains("controls"), "{e}");
    assert!(robot.actuator_forces(&world, &[Real::NAN, 0.0]).is_err());
}
