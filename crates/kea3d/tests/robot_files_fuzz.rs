//! Robot files damaged at random — characters dropped, repeated or replaced, numbers made
//! huge, tiny, negative or not numbers — are loaded or refused, never a panic, and a refused
//! one leaves the world as it was; what loads steps without a NaN.

use kea3d::prelude::*;
use kea3d::robot::{MjcfOptions, UrdfOptions};

const URDF: &str = r#"<robot name="r">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="a"><inertial><origin xyz="0 0 0.2" rpy="0.1 0 0"/><mass value="2"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.01" ixy="0.001" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 0.2"/><geometry><cylinder radius="0.05" length="0.4"/></geometry></collision></link>
  <link name="b"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><sphere radius="0.06"/></geometry></collision></link>
  <link name="c"><inertial><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="1"/><dynamics damping="0.1" friction="0.05"/></joint>
  <joint name="j2" type="prismatic"><parent link="a"/><child link="b"/><origin xyz="0 0 0.4" rpy="0 0.3 0"/><axis xyz="1 0 0"/>
    <limit lower="-0.1" upper="0.1" effort="10" velocity="1"/></joint>
  <joint name="j3" type="planar"><parent link="b"/><child link="c"/><axis xyz="0 1 0"/></joint>
</robot>"#;

const MJCF: &str = r#"<mujoco><compiler angle="degree"/>
  <default><joint damping="0.2" armature="0.05"/><geom density="800"/>
    <default class="leg"><joint range="-60 60"/></default></default>
  <option gravity="0 0 -9.81" timestep="0.005"/>
  <worldbody><geom type="plane" size="5 5 0.1"/>
    <body name="torso" pos="0 0 0.6" euler="0 10 0"><freejoint/>
      <geom type="capsule" fromto="-0.2 0 0 0.2 0 0" size="0.05"/>
      <body name="leg" pos="0.2 0 0" childclass="leg"><joint name="hip" type="hinge" axis="0 1 0"/>
        <geom type="box" pos="0 0 -0.2" size="0.03 0.03 0.2"/>
        <body name="foot" pos="0 0 -0.4"><joint name="ankle" type="hinge" axis="1 0 0" stiffness="2"/>
          <geom type="ellipsoid" size="0.05 0.03 0.02"/></body></body></body>
  </worldbody>
  <actuator><motor joint="hip" gear="20" ctrlrange="-1 1"/><position joint="ankle" kp="5"/></actuator>
</mujoco>"#;

/// SplitMix64.
fn next(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

const REPLACEMENTS: [&str; 10] = ["1e30", "-1", "0", "nan", "inf", "1e-30", "x", "", "\"", "<"];

fn damaged(text: &str, seed: u64) -> String {
    let mut state = seed;
    let mut out = text.to_string();
    for _ in 0..1 + next(&mut state) % 3 {
        let at = (next(&mut state) as usize) % out.len();
        let at = (0..=at)
            .rev()
            .find(|&i| out.is_char_boundary(i))
            .unwrap_or(0);
        match next(&mut state) % 4 {
            0 => {
                out.remove(at);
            }
            1 => {
                let c = out[at..].chars().next().unwrap_or(' ');
                out.insert(at, c);
            }
            2 => {
                // Replace a number (the digits from here) by an edge value.
                let end = out[at..]
                    .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
                    .map_or(out.len(), |e| at + e);
                let r = REPLACEMENTS[(next(&mut state) % 10) as usize];
                out.replace_range(at..end, r);
            }
            _ => out.insert_str(at, REPLACEMENTS[(next(&mut state) % 10) as usize]),
        }
    }
    out
}

fn check(
    load: impl Fn(&mut PhysicsWorld, &str) -> Option<kea3d::robot::Robot>,
    text: &str,
    seeds: u64,
) {
    let (mut loaded, mut refused) = (0, 0);
    for seed in 0..seeds {
        let text = damaged(text, seed);
        let mut world = PhysicsWorld::new();
        world.set_gravity([0.0, 0.0, -9.81]).unwrap();
        let bodies = world.body_count();
        match load(&mut world, &text) {
            Some(robot) => {
                loaded += 1;
                for _ in 0..20 {
                    if world.step(0.005).is_err() {
                        break;
                    }
                }
                let q = robot.joint_positions(&world).unwrap();
                assert!(
                    q.iter().all(|x| x.is_finite()),
                    "seed {seed}: {q:?}\n{text}"
                );
            }
            None => {
                refused += 1;
                assert_eq!(
                    world.body_count(),
                    bodies,
                    "seed {seed}: a refused file added bodies"
                );
            }
        }
    }
    println!("{loaded} loaded, {refused} refused of {seeds}");
    assert!(loaded > 0 && refused > 0);
}

#[test]
fn damaged_urdf_files_load_or_are_refused_never_a_panic() {
    check(
        |w, t| {
            w.load_urdf_str(t, "damaged.urdf", &UrdfOptions::default())
                .ok()
        },
        URDF,
        1000,
    );
}

#[test]
fn damaged_mjcf_files_load_or_are_refused_never_a_panic() {
    check(
        |w, t| {
            w.load_mjcf_str(t, "damaged.xml", &MjcfOptions::default())
                .ok()
        },
        MJCF,
        1000,
    );
}
