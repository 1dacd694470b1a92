//! The MJCF importer on small files written here: frames in degrees and radians, default
//! classes, inertial frames and mass from geometry against hand computation, every joint
//! type, armature, actuators, MuJoCo's collision rule, and errors that name the line and
//! element and leave the world as it was.

use kea3d::prelude::*;
use kea3d::robot::{JointType, MjcfOptions};
use kea3d::Mat3;

fn load(xml: &str) -> (PhysicsWorld, kea3d::robot::Robot) {
    let mut world = PhysicsWorld::new();
    let robot = world
        .load_mjcf_str(xml, "test.xml", &MjcfOptions::default())
        .unwrap();
    (world, robot)
}

/// Whether two unit quaternions are one rotation (up to sign), to float precision.
fn same_rotation(a: Quat, b: Quat) -> bool {
    a.dot(b).abs() > 1.0 - 1e-6
}

fn close(a: Vec3, b: Vec3, tol: Real) -> bool {
    (a - b).length() <= tol
}

#[test]
fn frames_read_alike_in_degrees_and_radians_and_every_orientation_form() {
    let body = |compiler: &str, frame: &str| {
        format!(
            r#"<mujoco><compiler {compiler}/><worldbody>
              <body name="b" pos="1 2 3" {frame}><joint type="free"/><geom size="0.1"/></body>
            </worldbody></mujoco>"#
        )
    };
    let expected = Quat::from_rotation_z(kea3d::dynamics::PI_REAL / 2.0);
    for (compiler, frame) in [
        (r#"angle="degree""#, r#"euler="0 0 90""#),
        (r#"angle="radian""#, r#"euler="0 0 1.5707963267948966""#),
        (r#"angle="degree""#, r#"axisangle="0 0 1 90""#),
        (
            r#"angle="radian""#,
            r#"quat="0.7071067811865476 0 0 0.7071067811865476""#,
        ),
        (r#"angle="radian""#, r#"xyaxes="0 1 0 -1 0 0""#),
        ("", r#"euler="0 0 90""#), // MuJoCo's default unit is the degree
    ] {
        let (world, robot) = load(&body(compiler, frame));
        let b = robot.body("b").unwrap();
        assert!(close(
            world.position(b).unwrap(),
            Vec3::new(1.0, 2.0, 3.0),
            1e-6
        ));
        let r = world.rotation(b).unwrap();
        assert!(same_rotation(r, expected), "{compiler} {frame}: {r}");
    }
    // Euler angles about moving axes (MuJoCo's default "xyz"): x by 90°, then the new y.
    let (world, robot) = load(&body(r#"angle="degree""#, r#"euler="90 90 0""#));
    let r = world.rotation(robot.body("b").unwrap()).unwrap();
    let moving = Quat::from_rotation_x(kea3d::dynamics::PI_REAL / 2.0)
        * Quat::from_rotation_y(kea3d::dynamics::PI_REAL / 2.0);
    assert!(same_rotation(r, moving), "{r}");
}

#[test]
fn an_inertial_off_the_body_frame_gives_the_hand_computed_mass_properties() {
    let (world, robot) = load(
        r#"<mujoco><compiler angle="degree"/><worldbody>
          <body name="b" pos="0 0 1">
            <joint type="hinge" axis="1 0 0"/>
            <inertial pos="0.1 0 0.2" quat="0.7071067811865476 0 0 0.7071067811865476" mass="3" diaginertia="0.1 0.2 0.3"/>
            <geom type="sphere" size="0.05"/>
          </body>
        </worldbody></mujoco>"#,
    );
    let b = world.body(robot.body("b").unwrap()).unwrap();
    assert_eq!(b.mass(), 3.0, "the inertial wins over the geometry");
    assert!(close(b.position(), Vec3::new(0.1, 0.0, 1.2), 1e-6));
    let i = b.inertia();
    let expected = Mat3::from_diagonal(Vec3::new(0.2, 0.1, 0.3));
    for k in 0..3 {
        assert!(close(i.col(k), expected.col(k), 1e-6), "{i}");
    }
}

#[test]
fn mass_comes_from_the_geometry_with_its_density_and_fromto() {
    let (world, robot) = load(
        r#"<mujoco><compiler angle="radian" inertiafromgeom="true"/><worldbody>
          <body name="b">
            <joint type="slide" axis="0 0 1"/>
            <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.05" density="500"/>
            <geom type="box" pos="0 0 1" size="0.1 0.2 0.3" mass="2"/>
          </body>
        </worldbody></mujoco>"#,
    );
    let b = world.body(robot.body("b").unwrap()).unwrap();
    let pi = kea3d::dynamics::PI_REAL;
    let capsule = 500.0 * (pi * 0.05 * 0.05 * 0.4 + 4.0 / 3.0 * pi * 0.05f32.powi(3) as Real);
    assert!(
        (b.mass() - (capsule + 2.0)).abs() < 1e-3,
        "{} vs {}",
        b.mass(),
        capsule + 2.0
    );
    // The centre of mass: the capsule's middle (0.2, 0, 0) and the box's (0, 0, 1), weighted.
    let com =
        (Vec3::new(0.2, 0.0, 0.0) * capsule + Vec3::new(0.0, 0.0, 1.0) * 2.0) / (capsule + 2.0);
    assert!(close(b.position(), com, 1e-4), "{}", b.position());
}

#[test]
fn default_classes_inherit_and_childclass_applies() {
    let (world, robot) = load(
        r#"<mujoco><compiler angle="radian"/>
          <default>
            <joint damping="0.5" armature="0.1"/>
            <geom density="100"/>
            <default class="heavy">
              <geom density="2000"/>
              <joint damping="2"/>
            </default>
          </default>
          <worldbody>
            <body name="light"><joint name="a" type="hinge"/><geom size="0.1"/></body>
            <body name="dense" childclass="heavy" pos="1 0 0"><joint name="b" type="hinge"/><geom size="0.1"/></body>
            <body name="own" pos="2 0 0"><joint name="c" class="heavy" type="hinge" damping="7"/><geom class="heavy" size="0.1"/></body>
          </worldbody></mujoco>"#,
    );
    let sphere = 4.0 / 3.0 * kea3d::dynamics::PI_REAL * 0.001;
    let mass = |n: &str| world.body(robot.body(n).unwrap()).unwrap().mass();
    assert!((mass("light") - 100.0 * sphere).abs() < 1e-4);
    assert!((mass("dense") - 2000.0 * sphere).abs() < 1e-3);
    assert!((mass("own") - 2000.0 * sphere).abs() < 1e-3);
    let damping = |n: &str| {
        let raw = robot.joint(n).unwrap().raw.unwrap();
        let hinge = kea3d::JointHandle::<kea3d::dynamics::Hinge>::from_raw(raw);
        hinge.get(&world).unwrap().limit().dynamics()
    };
    assert_eq!(damping("a").damping, 0.5);
    assert_eq!(damping("b").damping, 2.0);
    assert_eq!(damping("b").armature, 0.1, "inherited from the top class");
    assert_eq!(damping("c").damping, 7.0, "the element's own value wins");
}

#[test]
fn armature_slows_a_pendulum_as_an_added_inertia() {
    // A point-like bob of 1 kg at 0.5 m: I = 0.25 (+ its own 1e-4); armature a adds to it.
    for armature in [0.0, 0.25] {
        let xml = format!(
            r#"<mujoco><compiler angle="radian"/><option gravity="0 0 -9.81"/><worldbody>
              <body name="p" pos="0 0 2"><joint name="j" type="hinge" axis="0 1 0" armature="{armature}"/>
                <inertial pos="0 0 -0.5" mass="1" diaginertia="1e-4 1e-4 1e-4"/></body>
            </worldbody></mujoco>"#
        );
        let (mut world, robot) = load(&xml);
        robot.set_joint_positions(&mut world, &[0.05]).unwrap();
        let inertia: Real = 0.25 + 1e-4 + armature;
        let period = 2.0 * kea3d::dynamics::PI_REAL * (inertia / (9.81 * 0.5)).sqrt();
        let h = 1e-3;
        let (mut t, mut last, mut crossings) = (0.0, 0.05, Vec::new());
        while crossings.len() < 3 && t < 10.0 {
            world.step(h).unwrap();
            t += h;
            let q = robot.joint_positions(&world).unwrap()[0];
            if last > 0.0 && q <= 0.0 {
                crossings.push(t - h * q / (q - last));
            }
            last = q;
        }
        let measured = crossings[2] - crossings[1];
        assert!(
            (measured - period).abs() < 0.01 * period,
            "armature {armature}: {measured} s vs {period} s"
        );
    }
}

#[test]
fn a_hopper_like_root_is_one_planar_joint_and_its_coordinates_round_trip() {
    let (mut world, robot) = load(
        r#"<mujoco><compiler angle="degree"/><worldbody>
          <body name="torso" pos="0 0 1.25">
            <joint name="rootx" type="slide" axis="1 0 0" pos="0 0 -1.25"/>
            <joint name="rootz" type="slide" axis="0 0 1" ref="1.25" pos="0 0 -1.25"/>
            <joint name="rooty" type="hinge" axis="0 1 0"/>
            <geom type="capsule" size="0.05 0.2"/>
            <body name="leg" pos="0 0 -0.2"><joint name="knee" type="hinge" axis="0 -1 0" range="-150 0"/>
              <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.04"/></body>
          </body>
          <body name="ball" pos="3 0 1"><joint name="b" type="ball"/><geom size="0.1"/></body>
        </worldbody></mujoco>"#,
    );
    let kinds: Vec<JointType> = robot.joints().iter().map(|j| j.kind).collect();
    assert_eq!(
        kinds,
        [JointType::Planar, JointType::Revolute, JointType::Ball]
    );
    assert_eq!(
        robot.joint("rootz").unwrap().name,
        "rootx",
        "found by any of its parts"
    );
    assert_eq!(robot.position_count(), 3 + 1 + 4);
    let q0 = robot.joint_positions(&world).unwrap();
    assert!(
        (q0[1] - 1.25).abs() < 1e-6,
        "rootz reads its ref at the file pose: {q0:?}"
    );
    let h = (0.3 as Real).sin();
    let q = [0.4, 1.1, 0.3, -1.2, (0.3 as Real).cos(), h, 0.0, 0.0];
    robot.set_joint_positions(&mut world, &q).unwrap();
    let back = robot.joint_positions(&world).unwrap();
    for (a, b) in back.iter().zip(q) {
        assert!((a - b).abs() < 1e-5, "{back:?}");
    }
    // The knee's range reads in degrees.
    let lim = robot.joint("knee").unwrap().limits()[0].unwrap();
    assert!((lim.0 + 150.0f32.to_radians() as Real).abs() < 1e-5);
}

#[test]
fn actuators_drive_their_joints() {
    let xml = r#"<mujoco><compiler angle="radian"/><option gravity="0 0 0"/><worldbody>
          <body name="wheel"><joint name="spin" type="hinge" axis="0 0 1"/>
            <inertial pos="0 0 0" mass="1" diaginertia="0.5 0.5 0.5"/></body>
          <body name="arm" pos="2 0 0"><joint name="turn" type="hinge" axis="0 0 1"/>
            <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/></body>
        </worldbody>
        <actuator>
          <motor joint="spin" gear="10" ctrlrange="-1 1"/>
          <position joint="turn" kp="20" kv="2"/>
        </actuator></mujoco>"#;
    let (mut world, robot) = load(xml);
    assert_eq!(robot.actuators().len(), 2);
    // The control is clamped to its range: 5 → 1, so 10 N·m on 0.5 kg·m² for 0.5 s.
    robot.set_controls(&mut world, &[5.0, 0.8]).unwrap();
    for _ in 0..500 {
        world.step(1e-3).unwrap();
    }
    let v = robot.joint_velocities(&world).unwrap();
    assert!((v[0] - 10.0).abs() < 0.05, "spin rate {}", v[0]);
    for _ in 0..4500 {
        world.step(1e-3).unwrap();
    }
    let q = robot.joint_positions(&world).unwrap();
    assert!((q[1] - 0.8).abs() < 1e-3, "the servo reached {}", q[1]);
    let e = robot.set_controls(&mut world, &[1.0]).unwrap_err();
    assert!(e.to_string().contains("controls"), "{e}");
}

#[test]
fn contype_and_conaffinity_follow_mujocos_rule() {
    // A ball collides with the floor when either's type meets the other's affinity.
    for (contype, conaffinity, rests) in [(1, 0, true), (0, 1, true), (0, 0, false), (2, 2, false)]
    {
        let xml = format!(
            r#"<mujoco><worldbody>
              <geom type="plane" size="5 5 0.1" contype="1" conaffinity="1"/>
              <body name="ball" pos="0 0 0.5"><freejoint/>
                <geom size="0.1" contype="{contype}" conaffinity="{conaffinity}"/></body>
            </worldbody></mujoco>"#
        );
        let (mut world, robot) = load(&xml);
        for _ in 0..120 {
            world.step(1.0 / 60.0).unwrap();
        }
        let z = robot.joint_positions(&world).unwrap()[2];
        if rests {
            assert!(
                (z - 0.1).abs() < 0.01,
                "({contype}, {conaffinity}) rests: z = {z}"
            );
        } else {
            assert!(
                z < -1.0,
                "({contype}, {conaffinity}) falls through: z = {z}"
            );
        }
    }
}

#[test]
fn bad_models_are_refused_naming_line_and_element_and_add_nothing() {
    let cases: [(&str, &[&str]); 6] = [
        (
            "<mujoco><worldbody>\n<body><joint type=\"hinge2\"/><geom size=\"1\"/></body>\n</worldbody></mujoco>",
            &["test.xml:2", "joint", "\"hinge2\""],
        ),
        (
            "<mujoco><worldbody>\n<body pos=\"0 0 x\"><geom size=\"1\"/></body>\n</worldbody></mujoco>",
            &["test.xml:2", "body", "\"x\" is not a finite number"],
        ),
        (
            "<mujoco><asset>\n<mesh name=\"m\" file=\"missing.stl\"/>\n</asset><worldbody/></mujoco>",
            &["test.xml:2", "mesh", "missing.stl", "not found"],
        ),
        (
            "<mujoco><worldbody/>\n<tendon><spatial/></tendon>\n</mujoco>",
            &["test.xml:2", "spatial", "not supported"],
        ),
        (
            "<mujoco><worldbody>\n<body name=\"a\"><geom size=\"1\" class=\"nope\"/></body>\n</worldbody></mujoco>",
            &["test.xml:2", "no default class \"nope\""],
        ),
        (
            "<mujoco><worldbody><body><geom size=\"1\"/>\n<body><joint type=\"free\"/><geom size=\"1\"/></body></body>\n</worldbody></mujoco>",
            &["test.xml:2", "free joint"],
        ),
    ];
    for (text, needles) in cases {
        let mut world = PhysicsWorld::new();
        let (b, c) = (world.body_count(), world.collision().collider_count());
        let gravity = world.gravity();
        let e = world
            .load_mjcf_str(text, "test.xml", &MjcfOptions::default())
            .unwrap_err();
        let msg = e.to_string();
        for n in needles {
            assert!(msg.contains(n), "`{msg}` should contain `{n}`");
        }
        assert_eq!(world.body_count(), b);
        assert_eq!(world.collision().collider_count(), c);
        assert_eq!(world.gravity(), gravity, "not even the gravity changed");
    }
}

#[test]
fn includes_splice_their_children_and_keep_the_lines_of_the_including_file() {
    let dir = std::env::temp_dir().join(format!("kea-mjcf-include-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("common")).unwrap();
    std::fs::write(
        dir.join("common/defaults.xml"),
        "<mujoco>\n  <default><geom density=\"500\"/></default>\n  <option><flag contact=\"disable\"/></option>\n</mujoco>\n",
    )
    .unwrap();
    let main = "<mujoco>\n<include file=\"./common/defaults.xml\"/>\n<worldbody>\n<geom type=\"plane\" size=\"5 5 1\"/>\n<body name=\"b\" pos=\"0 0 1\"><freejoint/><geom size=\"0.1\"/></body>\n</worldbody>\n</mujoco>\n";
    std::fs::write(dir.join("main.xml"), main).unwrap();
    let mut world = PhysicsWorld::new();
    let robot = world
        .load_mjcf(dir.join("main.xml"), &MjcfOptions::default())
        .unwrap();
    let mass = world.body(robot.body("b").unwrap()).unwrap().mass();
    let sphere = 4.0 / 3.0 * kea3d::dynamics::PI_REAL * 0.001;
    assert!(
        (mass - 500.0 * sphere).abs() < 1e-4,
        "the included default applies: {mass}"
    );
    // The included flag turns contacts off: the ball falls through the plane.
    for _ in 0..120 {
        world.step(1.0 / 60.0).unwrap();
    }
    assert!(robot.joint_positions(&world).unwrap()[2] < -1.0);
    // An error after the include keeps its own line; a missing include is named.
    let bad = main.replace("size=\"0.1\"", "size=\"x\"");
    std::fs::write(dir.join("bad.xml"), bad).unwrap();
    let e = world
        .load_mjcf(dir.join("bad.xml"), &MjcfOptions::default())
        .unwrap_err();
    assert!(e.to_string().contains("bad.xml:5"), "{e}");
    std::fs::write(
        dir.join("missing.xml"),
        "<mujoco>\n<include file=\"nope.xml\"/>\n</mujoco>",
    )
    .unwrap();
    let e = world
        .load_mjcf(dir.join("missing.xml"), &MjcfOptions::default())
        .unwrap_err();
    assert!(
        e.to_string().contains("missing.xml:2") && e.to_string().contains("nope.xml"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_planar_roots_coordinates_keep_the_files_sense_for_stops_and_motors() {
    // Slides along x and z and a hinge about +y: Kea's second travel (the turn's axis × the
    // first) runs along −z, against the file's; forces and stops still act as the file says.
    let xml = r#"<mujoco><compiler angle="radian"/><option gravity="0 0 0"/><worldbody>
          <body name="torso" pos="0 0 1">
            <joint name="rootx" type="slide" axis="1 0 0"/>
            <joint name="rootz" type="slide" axis="0 0 1" ref="1" range="0.5 1.2" limited="true"/>
            <joint name="rooty" type="hinge" axis="0 1 0"/>
            <inertial pos="0 0 0" mass="2" diaginertia="0.1 0.1 0.1"/>
          </body></worldbody>
          <actuator><motor joint="rootz" gear="1"/></actuator></mujoco>"#;
    let (mut world, robot) = load(xml);
    robot.set_controls(&mut world, &[1.0]).unwrap();
    for _ in 0..200 {
        world.step(1e-3).unwrap();
    }
    // 1 N on 2 kg for 0.2 s: up 1 cm, from the file's 1.
    let q = robot.joint_positions(&world).unwrap();
    assert!((q[1] - 1.01).abs() < 1e-3, "rootz = {}", q[1]);
    for _ in 0..3000 {
        world.step(1e-3).unwrap();
    }
    let q = robot.joint_positions(&world).unwrap();
    assert!(
        (q[1] - 1.2).abs() < 2e-3,
        "held at its upper stop: rootz = {}",
        q[1]
    );
}

#[test]
fn each_mjcf_geometry_becomes_the_collider_its_size_says() {
    let dir = std::env::temp_dir().join(format!("kea-mjcf-geoms-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A unit tetrahedron, scaled by 2 in the asset.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    std::fs::write(dir.join("tet.obj"), obj).unwrap();
    let xml = r#"<mujoco><compiler angle="radian"/>
      <asset><mesh name="tet" file="tet.obj" scale="2 2 2"/></asset>
      <worldbody>
        <geom type="plane" size="5 5 0.1" pos="0 0 -1"/>
        <body name="b" pos="0 0 0">
          <joint type="free"/>
          <geom type="cylinder" fromto="10 0 0 10 0 2" size="0.5"/>
          <geom type="ellipsoid" pos="20 0 0" size="1 2 3"/>
          <geom type="box" pos="30 0 0" size="1 2 3"/>
          <geom type="mesh" mesh="tet" pos="40 0 0"/>
          <geom type="capsule" pos="50 0 0" size="0.5 1"/>
        </body>
      </worldbody></mujoco>"#;
    let mut world = PhysicsWorld::new();
    world
        .load_mjcf_str(xml, dir.join("g.xml"), &MjcfOptions::default())
        .unwrap();
    let down = Vec3::new(0.0, 0.0, -1.0);
    let ray = |x: Real, y: Real| {
        world
            .collision()
            .cast_ray(
                world.dynamics(),
                &kea_collision::RayCast::new(Vec3::new(x, y, 10.0), down, 100.0),
                kea3d::collision::QueryFilter::default(),
            )
            .unwrap()
            .map(|h| 10.0 - h.distance)
    };
    // The heights of the tops, in order: cylinder (fromto to z = 2), ellipsoid (z radius 3),
    // box (half height 3), the tetrahedron scaled by 2 (its apex at z = 2), capsule (1 + 0.5),
    // and the plane at z = −1 beside them.
    let tops = [
        ray(10.0, 0.0),
        ray(20.0, 0.0),
        ray(30.0, 0.0),
        ray(40.01, 0.01),
        ray(50.0, 0.0),
        ray(-3.0, 3.0),
    ];
    let expected = [2.0, 3.0, 3.0, 1.96, 1.5, -1.0];
    for (k, (t, e)) in tops.iter().zip(expected).enumerate() {
        let t = t.unwrap_or_else(|| panic!("ray {k} missed"));
        assert!(
            (t - e).abs() < 0.05,
            "geometry {k}: top at {t}, expected {e}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn connect_and_weld_equalities_close_loops_as_ball_and_fixed_joints() {
    // Two rods hinged to the world 0.4 m apart, their lower ends held together by a connect,
    // and a block welded to the right rod: a triangle that swings as one.
    let xml = r#"<mujoco><compiler angle="radian"/><worldbody>
        <body name="left" pos="-0.2 0 1"><joint type="hinge" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0.2 0 -0.5" size="0.02"/></body>
        <body name="right" pos="0.2 0 1"><joint type="hinge" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 -0.2 0 -0.5" size="0.02"/></body>
        <body name="block" pos="0.3 0 1"><freejoint/><geom type="box" size="0.05 0.05 0.05"/></body>
      </worldbody>
      <equality>
        <connect body1="left" body2="right" anchor="0.2 0 -0.5"/>
        <weld body1="block" body2="right"/>
      </equality></mujoco>"#;
    let (mut world, robot) = load(xml);
    world
        .add_force(robot.body("block").unwrap(), [20.0, 0.0, 0.0])
        .unwrap();
    for _ in 0..500 {
        world.step(1e-3).unwrap();
    }
    let tip = |name: &str, local: Vec3| {
        let l = robot.links().iter().position(|l| l.name == name).unwrap();
        robot.link_pose(&world, l).unwrap().point(local)
    };
    let (a, b) = (
        tip("left", Vec3::new(0.2, 0.0, -0.5)),
        tip("right", Vec3::new(-0.2, 0.0, -0.5)),
    );
    assert!(
        (a - b).length() < 2e-3,
        "the connect holds the tips together: {a} {b}"
    );
    // A triangle cannot turn about two fixed hinges: everything stays where the file put it.
    let block = world.position(robot.body("block").unwrap()).unwrap();
    assert!(
        (block - Vec3::new(0.3, 0.0, 1.0)).length() < 5e-3,
        "{block}"
    );
    for (bad, needle) in [
        (
            r#"<equality><connect body1="left" body2="nobody" anchor="0 0 0"/></equality>"#,
            "no body named \"nobody\"",
        ),
        (
            r#"<equality><joint joint1="a" joint2="b"/></equality>"#,
            "equality <joint>",
        ),
    ] {
        let text = xml.replace(
            r#"<equality>
        <connect body1="left" body2="right" anchor="0.2 0 -0.5"/>
        <weld body1="block" body2="right"/>
      </equality>"#,
            bad,
        );
        let mut w = PhysicsWorld::new();
        let e = w
            .load_mjcf_str(&text, "test.xml", &MjcfOptions::default())
            .unwrap_err();
        assert!(e.to_string().contains(needle), "{e}");
        assert_eq!(w.body_count(), 0);
    }
}

/// A file whose bodies nest 6,000 deep (which overflowed an 8 MiB stack) is refused by name
/// and the line of the first element past 256 levels (MuJoCo refuses it too).
#[test]
fn bodies_nested_thousands_deep_are_refused_by_line() {
    let err = load_on_stack(nested_bodies(6000), 8 * 1024).unwrap_err();
    assert!(err.contains("deep.xml") && err.contains("nest"), "{err}");
    assert!(
        err.contains("deep.xml:257"),
        "the first element past 256 levels: {err}"
    );
}

/// MJCF text of `depth` bodies nested in one another, each with a hinge and a sphere.
fn nested_bodies(depth: usize) -> String {
    let mut xml = String::from("<mujoco>\n<worldbody>\n");
    for _ in 0..depth {
        xml.push_str("<body><joint type=\"hinge\"/><geom size=\"0.1\"/>\n");
    }
    for _ in 0..depth {
        xml.push_str("</body>");
    }
    xml.push_str("\n</worldbody>\n</mujoco>\n");
    xml
}

/// Loads `xml` on a thread with `kib` KiB of stack.
fn load_on_stack(xml: String, kib: usize) -> Result<(), String> {
    std::thread::Builder::new()
        .stack_size(kib * 1024)
        .spawn(move || {
            let mut world = PhysicsWorld::new();
            world
                .load_mjcf_str(&xml, "deep.xml", &MjcfOptions::default())
                .map(|_| ())
                .map_err(|e| e.to_string())
        })
        .unwrap()
        .join()
        .expect("no overflow")
}

/// Too deep a file is refused before any reader recurses, so on a 96 KiB thread stack too
/// (a PhysicsWorld needs 72 KiB to be made in the test profile; 64 before the reduced path's
/// contacts added to its settings and scratch); a model nested as deep as allowed (250 bodies)
/// loads on 512 KiB (the XML reader and the body reader take about 1 KiB a level each, so the
/// refused files would need 6 MB and 100 MB).
#[test]
fn deep_files_are_refused_on_small_thread_stacks_and_deep_models_load() {
    for depth in [6000, 100_000] {
        let err = load_on_stack(nested_bodies(depth), 96).unwrap_err();
        assert!(err.contains("deep.xml:") && err.contains("nest"), "{err}");
    }
    load_on_stack(nested_bodies(250), 512).unwrap();
}
