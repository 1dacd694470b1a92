//! The URDF importer on small files written here: masses, inertias and frames against hand
//! computation, every joint type and geometry, joint vectors, the physics of what it builds,
//! and errors that name the file, line and element and leave the world as it was.

use kea3d::collision::QueryFilter;
use kea3d::prelude::*;
use kea3d::robot::{ImportError, JointType, UrdfOptions};
use kea3d::Mat3;

fn fixed() -> UrdfOptions {
    UrdfOptions {
        fixed_base: true,
        ..UrdfOptions::default()
    }
}

fn z_up() -> PhysicsWorld {
    let mut w = PhysicsWorld::new();
    w.set_gravity([0.0, 0.0, -9.81]).unwrap();
    w
}

/// Whether two unit quaternions are one rotation (up to sign), to float precision.
fn same_rotation(a: Quat, b: Quat) -> bool {
    a.dot(b).abs() > 1.0 - 1e-6
}

fn close(a: Vec3, b: Vec3, tol: Real) -> bool {
    (a - b).length() <= tol
}

/// A link whose inertial frame is off its own: turned 90° about z and shifted.
const OFFSET_INERTIAL: &str = r#"<?xml version="1.0"?>
<robot name="offset">
  <link name="base"/>
  <link name="arm">
    <inertial>
      <origin xyz="0.1 0.2 0.3" rpy="0 0 1.5707963267948966"/>
      <mass value="2.0"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/>
    </inertial>
  </link>
  <joint name="j" type="revolute">
    <parent link="base"/><child link="arm"/>
    <origin xyz="0 0 1" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="2"/>
  </joint>
</robot>"#;

#[test]
fn an_inertial_frame_off_the_link_gives_the_hand_computed_mass_properties() {
    let mut world = z_up();
    let robot = world
        .load_urdf_str(OFFSET_INERTIAL, "offset.urdf", &fixed())
        .unwrap();
    let arm = robot.body("arm").unwrap();
    let b = world.body(arm).unwrap();
    assert_eq!(b.mass(), 2.0);
    // The centre of mass: the link's origin (0, 0, 1) plus the inertial offset.
    assert!(
        close(b.position(), Vec3::new(0.1, 0.2, 1.3), 1e-6),
        "{}",
        b.position()
    );
    // The tensor turned 90° about z: ixx and iyy swap.
    let i = b.inertia();
    let expected = Mat3::from_diagonal(Vec3::new(0.2, 0.1, 0.3));
    for k in 0..3 {
        assert!(close(i.col(k), expected.col(k), 1e-6), "{i}");
    }
    // The link frame sits where the joint's origin puts it.
    assert!(close(
        world.position(arm).unwrap(),
        Vec3::new(0.0, 0.0, 1.0),
        1e-6
    ));
    assert_eq!(
        world.local_center_of_mass(arm).unwrap(),
        Vec3::new(0.1, 0.2, 0.3)
    );
    let j = robot.joint("j").unwrap();
    assert_eq!(j.kind, JointType::Revolute);
    assert_eq!(j.limits(), vec![Some((-1.0, 1.0))]);
    assert_eq!(j.efforts(), vec![Some(10.0)]);
}

/// Two links welded by a fixed joint become one body with the summed mass properties.
const WELDED: &str = r#"<robot name="welded">
  <link name="base"/>
  <link name="a">
    <inertial><origin xyz="0 0 0"/><mass value="1"/>
      <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="b">
    <inertial><origin xyz="0 0 0"/><mass value="3"/>
      <inertia ixx="0.02" iyy="0.02" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="hinge" type="continuous">
    <parent link="base"/><child link="a"/><axis xyz="0 1 0"/>
  </joint>
  <joint name="weld" type="fixed">
    <parent link="a"/><child link="b"/><origin xyz="0.4 0 0"/>
  </joint>
</robot>"#;

#[test]
fn links_welded_by_a_fixed_joint_are_one_body_with_summed_mass_properties() {
    let mut world = z_up();
    let bodies_before = world.body_count();
    let robot = world
        .load_urdf_str(WELDED, "welded.urdf", &fixed())
        .unwrap();
    // The world link and one moving body: the weld added none.
    assert_eq!(world.body_count() - bodies_before, 2);
    let (a, b) = (robot.body("a").unwrap(), robot.body("b").unwrap());
    assert_eq!(a, b);
    let body = world.body(a).unwrap();
    assert_eq!(body.mass(), 4.0);
    // Centre of mass 3/4 of the way to b; inertia about it by the parallel-axis theorem.
    assert!(close(body.position(), Vec3::new(0.3, 0.0, 0.0), 1e-6));
    let i = body.inertia();
    let about_y = 0.01 + 0.02 + 1.0 * 0.3 * 0.3 + 3.0 * 0.1 * 0.1;
    assert!((i.col(1).y - about_y).abs() < 1e-6, "{i}");
    assert!((i.col(0).x - 0.03).abs() < 1e-6, "{i}");
    assert_eq!(robot.position_count(), 1, "fixed joints have no coordinate");
    // Link b's frame is 0.4 m along x of a's.
    let pose = robot.link_pose(&world, 3).unwrap();
    assert!(close(pose.translation, Vec3::new(0.4, 0.0, 0.0), 1e-6));
}

/// A compound pendulum: the small-swing period is 2π √(I_pivot / (m g l)).
#[test]
fn a_urdf_pendulum_swings_with_the_compound_pendulum_period() {
    let urdf = r#"<robot name="p">
      <link name="base"/>
      <link name="bob">
        <inertial><origin xyz="0 0 -0.8"/><mass value="1.5"/>
          <inertia ixx="0.02" iyy="0.02" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
      </link>
      <joint name="pivot" type="continuous">
        <parent link="base"/><child link="bob"/><origin xyz="0 0 2"/><axis xyz="0 1 0"/>
      </joint>
    </robot>"#;
    for step in [1.0 / 240.0, 1.0 / 1000.0] {
        let mut world = z_up();
        let robot = world.load_urdf_str(urdf, "p.urdf", &fixed()).unwrap();
        robot.set_joint_positions(&mut world, &[0.05]).unwrap();
        let (m, l, g): (Real, Real, Real) = (1.5, 0.8, 9.81);
        let period = 2.0 * kea3d::dynamics::PI_REAL * ((0.02 + m * l * l) / (m * g * l)).sqrt();
        // Time between the first two downward zero crossings of the angle.
        let (mut t, mut last) = (0.0, robot.joint_positions(&world).unwrap()[0]);
        let mut crossings = Vec::new();
        while crossings.len() < 3 && t < 10.0 {
            world.step(step).unwrap();
            t += step;
            let q = robot.joint_positions(&world).unwrap()[0];
            if last > 0.0 && q <= 0.0 {
                crossings.push(t - step * q / (q - last));
            }
            last = q;
        }
        let measured = crossings[2] - crossings[1];
        assert!(
            (measured - period).abs() < 0.01 * period,
            "step {step}: period {measured} s, closed form {period} s"
        );
    }
}

/// Every URDF joint type, set to a pose by its vector and read back; the free base leads.
const EVERY_JOINT: &str = r#"<robot name="every">
  <link name="root"><inertial><mass value="5"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="r"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="c"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="p"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="f"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="pl"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="fl"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="rev" type="revolute"><parent link="root"/><child link="r"/><origin xyz="1 0 0" rpy="0.3 0 0"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="5" velocity="1"/><dynamics damping="0.1" friction="0.2"/></joint>
  <joint name="cont" type="continuous"><parent link="r"/><child link="c"/><origin xyz="0 1 0"/><axis xyz="1 0 0"/></joint>
  <joint name="pri" type="prismatic"><parent link="c"/><child link="p"/><origin xyz="0 0 1"/><axis xyz="0 1 1"/><limit lower="-0.5" upper="0.5" effort="5" velocity="1"/></joint>
  <joint name="fix" type="fixed"><parent link="p"/><child link="f"/><origin xyz="0.2 0 0"/></joint>
  <joint name="pla" type="planar"><parent link="root"/><child link="pl"/><origin xyz="-1 0 0"/><axis xyz="0 0 1"/></joint>
  <joint name="flo" type="floating"><parent link="root"/><child link="fl"/><origin xyz="0 -1 0"/></joint>
</robot>"#;

#[test]
fn every_joint_type_round_trips_its_coordinates() {
    let mut world = z_up();
    let options = UrdfOptions::default(); // free base
    let robot = world
        .load_urdf_str(EVERY_JOINT, "every.urdf", &options)
        .unwrap();
    let kinds: Vec<JointType> = robot.joints().iter().map(|j| j.kind).collect();
    assert_eq!(
        kinds,
        [
            JointType::Free,
            JointType::Revolute,
            JointType::Continuous,
            JointType::Prismatic,
            JointType::Fixed,
            JointType::Planar,
            JointType::Free
        ]
    );
    // free base 7 + 1 + 1 + 1 + planar 3 + floating 7
    assert_eq!(robot.position_count(), 20);
    assert_eq!(robot.velocity_count(), 18);
    let q0 = robot.joint_positions(&world).unwrap();
    let expect0 = [
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0,
        0.0, 0.0,
    ];
    for (a, b) in q0.iter().zip(expect0) {
        assert!((a - b).abs() < 1e-6, "{q0:?}");
    }
    let h = (0.5 as Real).sin();
    let mut q = vec![
        0.3,
        -0.2,
        1.5,
        (0.5 as Real).cos(),
        0.0,
        h,
        0.0, // base: moved and turned 1 rad about y
        1.2,
        -2.5,
        0.3, // rev, cont, pri
        0.4,
        -0.7,
        2.8, // planar
        0.5,
        -1.5,
        0.2,
        0.0,
        0.0,
        0.0,
        1.0, // floating: turned π about z
    ];
    robot.set_joint_positions(&mut world, &q).unwrap();
    let back = robot.joint_positions(&world).unwrap();
    // A quaternion and its negative are one rotation: compare the floating one up to sign.
    if back[16] * q[16] < 0.0 {
        for x in &mut q[16..20] {
            *x = -*x;
        }
    }
    for (k, (a, b)) in back.iter().zip(&q).enumerate() {
        assert!(
            (a - b).abs() < 1e-5,
            "entry {k}: set {b}, read {a}\n{back:?}"
        );
    }
    // Velocities round-trip too, and the revolute one matches the relative spin.
    let v: Vec<Real> = (0..18).map(|k| 0.1 * k as Real - 0.7).collect();
    robot.set_joint_velocities(&mut world, &v).unwrap();
    let vb = robot.joint_velocities(&world).unwrap();
    for (k, (a, b)) in vb.iter().zip(&v).enumerate() {
        assert!(
            (a - b).abs() < 1e-5,
            "velocity {k}: set {b}, read {a}\n{vb:?}"
        );
    }
    // The joints hold what the vectors set: a step moves the coordinates by about v·dt.
    world.set_gravity([0.0, 0.0, 0.0]).unwrap();
    world.step(1e-3).unwrap();
    let after = robot.joint_positions(&world).unwrap();
    assert!(
        (after[7] - (q[7] + 1e-3 * v[6])).abs() < 2e-3,
        "{} {}",
        after[7],
        q[7]
    );
    // Wrong lengths and non-finite entries are refused by name, and change nothing.
    let before = robot.joint_positions(&world).unwrap();
    let e = robot.set_joint_positions(&mut world, &q[..5]).unwrap_err();
    assert!(e.to_string().contains("q"), "{e}");
    let mut bad = q.clone();
    bad[3] = Real::NAN;
    assert!(robot.set_joint_positions(&mut world, &bad).is_err());
    assert_eq!(robot.joint_positions(&world).unwrap(), before);
}

#[test]
fn hinge_angles_follow_the_urdf_axis_and_sign() {
    // The child turns by +q about the axis (right hand), as URDF says.
    let mut world = z_up();
    let robot = world
        .load_urdf_str(OFFSET_INERTIAL, "offset.urdf", &fixed())
        .unwrap();
    robot.set_joint_positions(&mut world, &[0.7]).unwrap();
    let arm = robot.body("arm").unwrap();
    let r = world.rotation(arm).unwrap();
    let expected = Quat::from_rotation_z(0.7);
    assert!(same_rotation(r, expected), "{r}");
    // A motor-free step under a torque about +z turns the angle up.
    world.step(1e-3).unwrap();
    robot.set_joint_forces(&mut world, &[5.0]).unwrap();
    for _ in 0..10 {
        world.step(1e-3).unwrap();
    }
    assert!(robot.joint_velocities(&world).unwrap()[0] > 0.0);
}

#[test]
fn joint_damping_decays_a_spin_at_d_over_i() {
    // A wheel on a frictionless axle with damping d: ω(t) = ω₀ exp(−d t / I).
    let urdf = r#"<robot name="wheel">
      <link name="base"/>
      <link name="wheel"><inertial><mass value="2"/><inertia ixx="0.5" iyy="0.3" izz="0.3" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="axle" type="continuous"><parent link="base"/><child link="wheel"/><axis xyz="1 0 0"/><dynamics damping="0.25"/></joint>
    </robot>"#;
    let mut world = z_up();
    let robot = world.load_urdf_str(urdf, "wheel.urdf", &fixed()).unwrap();
    robot.set_joint_velocities(&mut world, &[10.0]).unwrap();
    let h = 1e-3;
    for _ in 0..2000 {
        world.step(h).unwrap();
    }
    let w = robot.joint_velocities(&world).unwrap()[0];
    let expected = 10.0 * (-0.25 * 2.0 / 0.5 as Real).exp();
    assert!(
        (w - expected).abs() < 0.01 * expected,
        "ω = {w}, closed form {expected}"
    );
}

#[test]
fn joint_friction_holds_below_its_torque_and_slips_above() {
    let urdf = r#"<robot name="knob">
      <link name="base"/>
      <link name="knob"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="turn" type="continuous"><parent link="base"/><child link="knob"/><axis xyz="0 0 1"/><dynamics friction="2"/></joint>
    </robot>"#;
    for (torque, moves) in [(1.5, false), (3.0, true)] {
        let mut world = z_up();
        let robot = world.load_urdf_str(urdf, "knob.urdf", &fixed()).unwrap();
        robot.set_joint_forces(&mut world, &[torque]).unwrap();
        for _ in 0..500 {
            world.step(1e-3).unwrap();
        }
        let q = robot.joint_positions(&world).unwrap()[0];
        if moves {
            // Net torque 1 N·m on 0.1 kg·m² for 0.5 s: θ = ½ (1/0.1) 0.25 = 1.25 rad.
            assert!((q - 1.25).abs() < 0.03, "slips: θ = {q}");
        } else {
            assert!(q.abs() < 1e-4, "holds: θ = {q}");
        }
    }
}

#[test]
fn each_geometry_becomes_a_collider_and_meshes_load_from_stl_and_obj() {
    let dir = std::env::temp_dir().join(format!("kea-urdf-geoms-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    // A unit tetrahedron as ASCII STL and as OBJ.
    let stl = "solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\nfacet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\nfacet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\nfacet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid t\n";
    std::fs::write(dir.join("meshes/tet.stl"), stl).unwrap();
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    std::fs::write(dir.join("meshes/tet.obj"), obj).unwrap();
    let urdf = r#"<robot name="g">
      <link name="base">
        <collision><geometry><box size="1 2 3"/></geometry></collision>
        <collision><origin xyz="0 0 2"/><geometry><cylinder radius="0.5" length="2"/></geometry></collision>
        <collision><geometry><sphere radius="0.25"/></geometry></collision>
        <collision><geometry><mesh filename="package://robot/meshes/tet.stl" scale="2 2 2"/></geometry></collision>
        <collision><geometry><mesh filename="meshes/tet.obj"/></geometry></collision>
      </link>
    </robot>"#;
    let file = dir.join("g.urdf");
    std::fs::write(&file, urdf).unwrap();
    let mut world = z_up();
    let before = world.collision().collider_count();
    let options = UrdfOptions {
        fixed_base: true,
        ..UrdfOptions::default()
    };
    world.load_urdf(&file, &options).unwrap();
    assert_eq!(world.collision().collider_count() - before, 5);
    // The cylinder stands along z, 2 m long, from z = 1 to 3: a ray down the z axis from
    // above meets its top at z = 3.
    let ray = |o: Vec3, d: Vec3| {
        world
            .collision()
            .cast_ray(
                world.dynamics(),
                &kea_collision::RayCast::new(o, d, 100.0),
                QueryFilter::default(),
            )
            .unwrap()
    };
    let hit = ray(Vec3::new(0.0, 0.0, 10.0), Vec3::new(0.0, 0.0, -1.0)).unwrap();
    assert!((hit.distance - 7.0).abs() < 1e-4, "{}", hit.distance);
    // The STL tetrahedron scaled by 2 has the face x + y + z = 2: a ray along −x at
    // y = z = 0.01 meets it at x = 1.98 (the OBJ one, unscaled, at 0.98; the box at 0.5).
    let hit = ray(Vec3::new(5.0, 0.01, 0.01), Vec3::new(-1.0, 0.0, 0.0)).unwrap();
    assert!((hit.distance - 3.02).abs() < 1e-4, "{}", hit.distance);
    std::fs::remove_dir_all(&dir).ok();
}

fn error_of(text: &str) -> (ImportError, usize, usize) {
    let mut world = z_up();
    let (b, c) = (world.body_count(), world.collision().collider_count());
    let e = world.load_urdf_str(text, "bad.urdf", &fixed()).unwrap_err();
    assert_eq!(world.body_count(), b, "a refused file adds no body");
    assert_eq!(world.collision().collider_count(), c, "nor a collider");
    (e, b, c)
}

#[test]
fn bad_files_are_refused_naming_file_line_and_element_and_add_nothing() {
    let cases: [(&str, &[&str]); 6] = [
        (
            "<robot name=\"r\">\n<link name=\"a\">\n<collision><geometry><mesh filename=\"nowhere.stl\"/></geometry></collision>\n</link>\n</robot>",
            &["bad.urdf:3", "mesh", "nowhere.stl", "not found"],
        ),
        (
            "<robot name=\"r\">\n<link name=\"a\">\n<inertial><mass value=\"one\"/></inertial>\n</link>\n</robot>",
            &["bad.urdf:3", "<mass>", "\"one\" is not a finite number"],
        ),
        (
            "<robot name=\"r\">\n<link name=\"a\"/><link name=\"b\"/>\n<joint name=\"j\" type=\"hinge\"><parent link=\"a\"/><child link=\"b\"/></joint>\n</robot>",
            &["bad.urdf:3", "joint \"j\"", "\"hinge\" is not a URDF joint type"],
        ),
        (
            "<robot name=\"r\">\n<link name=\"a\"/><link name=\"b\"/><link name=\"c\"/>\n<joint name=\"j1\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>\n<joint name=\"j2\" type=\"fixed\"><parent link=\"b\"/><child link=\"c\"/></joint>\n<joint name=\"j3\" type=\"fixed\"><parent link=\"c\"/><child link=\"b\"/></joint>\n</robot>",
            &["bad.urdf:5", "joint \"j3\"", "loop"],
        ),
        (
            "<robot name=\"r\">\n<link name=\"a\"/>\n<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"ghost\"/></joint>\n</robot>",
            &["bad.urdf:3", "no link named \"ghost\""],
        ),
        (
            "<robot name=\"r\">\n<link name=\"a\"/><link name=\"b\"/>\n<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/></joint>\n</robot>",
            &["link \"b\"", "mass"],
        ),
    ];
    for (text, needles) in cases {
        let (e, _, _) = error_of(text);
        let msg = e.to_string();
        for n in needles {
            assert!(msg.contains(n), "`{msg}` should contain `{n}`");
        }
    }
}

#[test]
fn a_robot_world_restores_from_its_snapshot_and_steps_on_the_same_bits() {
    let mut world = z_up();
    let robot = world
        .load_urdf_str(EVERY_JOINT, "every.urdf", &fixed())
        .unwrap();
    let q: Vec<Real> = (0..robot.position_count())
        .map(|k| 0.05 * k as Real)
        .collect();
    robot.set_joint_positions(&mut world, &q).unwrap();
    for _ in 0..10 {
        world.step(1e-3).unwrap();
    }
    let bytes = world.snapshot().unwrap().to_binary().unwrap();
    let snapshot = kea3d::scene::SceneSnapshot::from_binary(&bytes).unwrap();
    let mut restored = PhysicsWorld::restore(snapshot).unwrap();
    // The same handle reads the restored world: link frames and centres of mass are kept.
    assert_eq!(
        robot.joint_positions(&restored).unwrap(),
        robot.joint_positions(&world).unwrap()
    );
    for _ in 0..100 {
        world.step(1e-3).unwrap();
        restored.step(1e-3).unwrap();
    }
    let (a, b) = (
        robot.joint_positions(&world).unwrap(),
        robot.joint_positions(&restored).unwrap(),
    );
    assert!(
        a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
        "{a:?}\n{b:?}"
    );
}

const ARM: &str = r#"<robot name="arm">
  <link name="base"/>
  <link name="a"><inertial><origin xyz="0 0 0.2"/><mass value="2"/>
    <inertia ixx="0.03" iyy="0.03" izz="0.004" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><origin xyz="0.1 0 0.2"/><mass value="1.5"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.003" ixy="0.001" ixz="0" iyz="0"/></inertial></link>
  <link name="c"><inertial><origin xyz="0 0 0.1"/><mass value="0.5"/>
    <inertia ixx="0.004" iyy="0.004" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="50" velocity="2"/></joint>
  <joint name="j2" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.4"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="50" velocity="2"/>
    <dynamics damping="0.3" friction="0.05"/></joint>
  <joint name="j3" type="prismatic"><parent link="b"/><child link="c"/><origin xyz="0.2 0 0.4"/>
    <axis xyz="1 0 0"/><limit lower="-0.1" upper="0.1" effort="20" velocity="1"/></joint>
</robot>"#;

#[test]
fn an_arm_in_reduced_coordinates_restores_from_its_snapshots_on_the_same_bits() {
    let mut world = z_up();
    let robot = world.load_urdf_str(ARM, "arm.urdf", &fixed()).unwrap();
    robot
        .set_joint_positions(&mut world, &[0.4, 0.9, 0.05])
        .unwrap();
    for _ in 0..50 {
        let stats = world.step(1e-3).unwrap();
        assert_eq!(stats.reduced_trees, 1, "the arm is one tree");
    }
    let snapshot = world.snapshot().unwrap();
    let binary = snapshot.to_binary().unwrap();
    let json = snapshot.to_json().unwrap();
    let mut restored = [
        kea3d::scene::SceneSnapshot::from_binary(&binary),
        kea3d::scene::SceneSnapshot::from_json(&json),
    ]
    .map(|s| PhysicsWorld::restore(s.unwrap()).unwrap());
    for _ in 0..300 {
        world.step(1e-3).unwrap();
        for r in &mut restored {
            assert_eq!(r.step(1e-3).unwrap().reduced_trees, 1);
        }
    }
    let a = robot.joint_positions(&world).unwrap();
    assert!((a[1] - 0.9).abs() > 0.1, "the arm swung: {a:?}");
    for r in &restored {
        let b = robot.joint_positions(r).unwrap();
        assert!(
            a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
            "{a:?}\n{b:?}"
        );
    }
}

#[test]
fn files_as_tools_write_them_load_as_pybullet_reads_them() {
    // Comma-separated numbers, a declaration after a blank line, a trailing NUL, PyBullet's
    // `spherical` joint and `plane` geometry, and a massless free base (static).
    let text = "\n<?xml version=\"1.0\"?>\n<robot name=\"tools\">\n\
      <link name=\"floor\"><collision><geometry><plane normal=\"0 0 1\"/></geometry></collision></link>\n\
      <link name=\"ball\"><inertial><origin xyz=\"0, 0, 0\"/><mass value=\"1\"/>\
      <inertia ixx=\"0.1\" iyy=\"0.1\" izz=\"0.1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n\
      <joint name=\"neck\" type=\"spherical\"><parent link=\"floor\"/><child link=\"ball\"/>\
      <origin xyz=\"0, 0, 1\"/></joint>\n</robot>\n\0";
    let mut world = z_up();
    let robot = world
        .load_urdf_str(text, "tools.urdf", &UrdfOptions::default())
        .unwrap();
    assert!(robot
        .skipped()
        .iter()
        .any(|s| s.contains("floor") && s.contains("static")));
    assert_eq!(robot.joint("neck").unwrap().kind, JointType::Ball);
    assert_eq!(
        robot.position_count(),
        4,
        "the floor is static: only the ball joint's quaternion"
    );
    let ball = robot.body("ball").unwrap();
    assert!(close(
        world.position(ball).unwrap(),
        Vec3::new(0.0, 0.0, 1.0),
        1e-6
    ));
    // A flat mesh collides as the mesh, with a note.
    let dir = std::env::temp_dir().join(format!("kea-urdf-flat-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("sheet.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n",
    )
    .unwrap();
    let sheet = r#"<robot name="s"><link name="s">
        <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
        <collision><geometry><mesh filename="sheet.obj"/></geometry></collision></link></robot>"#;
    std::fs::write(dir.join("s.urdf"), sheet).unwrap();
    let robot = z_up()
        .load_urdf(dir.join("s.urdf"), &UrdfOptions::default())
        .unwrap();
    assert!(
        robot.skipped().iter().any(|s| s.contains("flat")),
        "{:?}",
        robot.skipped()
    );
    std::fs::remove_dir_all(&dir).ok();
}
