//! What the tests share: the demo scene files, and two small robots of our own.

/// Every demo scene file in `scenes/`, sorted by name.
#[allow(dead_code)] // not every test file runs the scenes
pub fn demo_scene_paths() -> Vec<std::path::PathBuf> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .expect("scenes/ exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    files
}

/// Four legs on a free torso, each a hip and a knee with stops and a motor: an MJCF robot
/// that stands on the floor in reduced coordinates, its contacts solved in joint space.
#[allow(dead_code)] // not every test file steps the robots
pub const QUADRUPED: &str = r#"
<mujoco model="quadruped">
  <option timestep="0.005"/>
  <default><geom contype="1" conaffinity="0" friction="1"/><joint range="-40 40"/></default>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1" conaffinity="1"/>
    <body name="torso" pos="0 0 0.45">
      <freejoint/>
      <geom type="box" size="0.25 0.15 0.05" mass="6"/>
      <body pos="0.2 0.15 0"><joint name="h1" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.03"/>
        <body pos="0 0 -0.2"><joint name="k1" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.03"/></body></body>
      <body pos="0.2 -0.15 0"><joint name="h2" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.03"/>
        <body pos="0 0 -0.2"><joint name="k2" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.03"/></body></body>
      <body pos="-0.2 0.15 0"><joint name="h3" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.03"/>
        <body pos="0 0 -0.2"><joint name="k3" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.03"/></body></body>
      <body pos="-0.2 -0.15 0"><joint name="h4" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.03"/>
        <body pos="0 0 -0.2"><joint name="k4" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.03"/></body></body>
    </body>
  </worldbody>
  <actuator>
    <motor joint="h1" gear="20"/><motor joint="k1" gear="20"/><motor joint="h2" gear="20"/><motor joint="k2" gear="20"/>
    <motor joint="h3" gear="20"/><motor joint="k3" gear="20"/><motor joint="h4" gear="20"/><motor joint="k4" gear="20"/>
  </actuator>
</mujoco>
"#;

/// A planar hopper of our own: a root on two slides and a hinge, a leg, a floor.
#[allow(dead_code)]
pub const HOPPER: &str = r#"<mujoco><compiler angle="degree"/>
  <option timestep="0.005"/>
  <default><joint armature="0.1" damping="0.5" limited="true"/></default>
  <worldbody>
    <geom type="plane" size="5 5 0.1"/>
    <body name="torso" pos="0 0 0.9">
      <joint name="x" type="slide" axis="1 0 0" limited="false" armature="0" damping="0"/>
      <joint name="z" type="slide" axis="0 0 1" limited="false" armature="0" damping="0"/>
      <joint name="pitch" type="hinge" axis="0 1 0" limited="false" armature="0" damping="0"/>
      <geom type="capsule" size="0.05 0.2"/>
      <body name="thigh" pos="0 0 -0.2">
        <joint name="hip" type="hinge" axis="0 -1 0" range="-150 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.05"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="hip" gear="30" ctrlrange="-1 1"/></actuator>
</mujoco>"#;
