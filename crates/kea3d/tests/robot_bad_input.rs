//! Robot files as a hostile user writes them (issue 35's bad input): every refusal names the
//! file, the line and the element, quotes at most a short excerpt of a bad value, says what
//! was expected, and leaves the world as it was; what loads but needs saying is in the load
//! report (`Robot::skipped`).

use kea3d::prelude::*;
use kea3d::robot::{MjcfOptions, UrdfOptions};
use std::path::PathBuf;

/// A fresh folder for this test's files.
fn folder(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kea-bad-input-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A one-link URDF robot whose link carries `inertial` and whose geometry is `geometry`.
fn urdf(inertial: &str, geometry: &str) -> String {
    format!(
        r#"<robot name="r">
  <link name="base">
    {inertial}
    <collision><geometry>{geometry}</geometry></collision>
  </link>
</robot>
"#
    )
}

const SPHERE: &str = r#"<sphere radius="0.1"/>"#;

fn load_urdf(text: &str) -> (PhysicsWorld, Result<kea3d::robot::Robot, String>) {
    let mut w = PhysicsWorld::new();
    let r = w
        .load_urdf_str(text, "bad.urdf", &UrdfOptions::default())
        .map_err(|e| e.to_string());
    (w, r)
}

fn load_mjcf(text: &str) -> (PhysicsWorld, Result<kea3d::robot::Robot, String>) {
    let mut w = PhysicsWorld::new();
    let r = w
        .load_mjcf_str(text, "bad.xml", &MjcfOptions::default())
        .map_err(|e| e.to_string());
    (w, r)
}

/// The refusal, checked to name `file:line`, and the world left empty.
fn refused(
    (w, r): (PhysicsWorld, Result<kea3d::robot::Robot, String>),
    at: &str,
    says: &str,
) -> String {
    let e = r
        .err()
        .unwrap_or_else(|| panic!("loaded; expected a refusal at {at}"));
    assert!(e.contains(at) && e.contains(says), "{e}");
    assert!(
        !e.contains("argument `"),
        "a file's values are not arguments: {e}"
    );
    assert!(e.len() < 400, "a short message: {e}");
    assert_eq!(w.dynamics().body_count(), 0, "nothing was built: {e}");
    e
}

#[test]
fn inertias_no_body_can_have_are_refused_or_reported() {
    // Not positive semi-definite: refused in both formats.
    let bad = r#"<inertial><mass value="1"/>
    <inertia ixx="1" ixy="2" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>"#;
    refused(load_urdf(&urdf(bad, SPHERE)), "bad.urdf:4:", "negative");
    // Breaking only the triangle inequality: PyBullet loads it, and so does Kea, saying so.
    let thin = r#"<inertial><mass value="1"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="1"/></inertial>"#;
    let (_, robot) = load_urdf(&urdf(thin, SPHERE));
    let robot = robot.unwrap();
    let note = robot.skipped().join("\n");
    assert!(
        note.contains("bad.urdf:4:") && note.contains("A + B >= C"),
        "{note}"
    );
    // MuJoCo refuses both; Kea too.
    for inertia in [r#"diaginertia="0.1 0.1 1""#, r#"fullinertia="1 1 1 2 0 0""#] {
        let mjcf = format!(
            r#"<mujoco>
<worldbody>
  <body>
    <freejoint/>
    <inertial pos="0 0 0" mass="1" {inertia}/>
    <geom size="0.1"/>
  </body>
</worldbody>
</mujoco>"#
        );
        refused(load_mjcf(&mjcf), "bad.xml:5:", "inertial");
    }
}

#[test]
fn a_mass_without_its_value_is_refused_by_line() {
    refused(
        load_urdf(&urdf(r#"<inertial><mass/></inertial>"#, SPHERE)),
        "bad.urdf:3:",
        "`value` is missing",
    );
    let mjcf = r#"<mujoco>
<worldbody>
  <body>
    <freejoint/>
    <inertial pos="0 0 0" diaginertia="1 1 1"/>
    <geom size="0.1"/>
  </body>
</worldbody>
</mujoco>"#;
    refused(load_mjcf(mjcf), "bad.xml:5:", "`mass` is missing");
}

#[test]
fn a_massless_moving_link_is_refused_by_line_without_api_wording() {
    let text = r#"<robot name="r">
  <link name="base"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="arm"/>
  <joint name="j" type="revolute">
    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>"#;
    let e = refused(load_urdf(text), "bad.urdf:3:", "link \"arm\"");
    assert!(e.contains("`mass`") && e.contains("> 0"), "{e}");
}

#[test]
fn two_mjcf_joints_with_one_name_are_refused() {
    let mjcf = r#"<mujoco>
<worldbody>
  <body>
    <joint name="elbow" type="hinge"/>
    <geom size="0.1"/>
    <body pos="0 0 1">
      <joint name="elbow" type="hinge"/>
      <geom size="0.1"/>
    </body>
  </body>
</worldbody>
</mujoco>"#;
    refused(
        load_mjcf(mjcf),
        "bad.xml:7:",
        "a second joint named \"elbow\"",
    );
}

#[test]
fn urdf_limits_with_lower_not_below_upper_leave_the_joint_free_and_say_so() {
    let text = r#"<robot name="r">
  <link name="base"/>
  <link name="arm"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j" type="revolute">
    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="1" upper="-1" effort="1" velocity="1"/>
  </joint>
</robot>"#;
    let mut w = PhysicsWorld::new();
    let robot = w
        .load_urdf_str(
            text,
            "bad.urdf",
            &UrdfOptions {
                fixed_base: true,
                ..UrdfOptions::default()
            },
        )
        .unwrap();
    let note = robot.skipped().join("\n");
    assert!(
        note.contains("bad.urdf:6:") && note.contains("unlimited"),
        "{note}"
    );
    let j = robot.joints().iter().find(|j| j.name == "j").unwrap();
    assert_eq!(j.limits(), vec![None]);
}

#[test]
fn a_huge_attribute_is_quoted_as_a_short_excerpt() {
    let huge = "7".repeat(2 << 20) + "x";
    let text = format!(
        r#"<robot name="r"><link name="base"><inertial><origin xyz="{huge} 0 0"/><mass value="1"/></inertial></link></robot>"#
    );
    let e = refused(load_urdf(&text), "bad.urdf:1:", "bytes");
    assert!(e.contains("\"7777"), "{e}");
    // A huge name, too.
    let text = format!(
        r#"<robot name="r"><link name="base"/><link name="arm"/><joint name="j" type="fixed"><parent link="{huge}"/><child link="arm"/></joint></robot>"#
    );
    refused(load_urdf(&text), "bad.urdf:1:", "no link named \"7777");
}

#[test]
fn broken_stl_files_say_what_is_wrong_with_each() {
    let dir = folder("stl");
    let truncated = {
        let mut b = vec![0u8; 80];
        b.extend_from_slice(&10u32.to_le_bytes());
        b.extend_from_slice(&[0u8; 100]);
        b
    };
    let cases: [(&str, Vec<u8>, &str); 4] = [
        ("empty.stl", Vec::new(), "0 bytes: too short"),
        ("short.stl", vec![1u8; 40], "40 bytes: too short"),
        (
            "cut.stl",
            truncated,
            "declaring 10 triangles needs 584 bytes, this one has 184",
        ),
        (
            "ascii.stl",
            b"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 zero\n".to_vec(),
            "not a readable ASCII STL file",
        ),
    ];
    let mut messages = Vec::new();
    for (name, bytes, says) in cases {
        std::fs::write(dir.join(name), bytes).unwrap();
        let robot = dir.join("robot.urdf");
        std::fs::write(
            &robot,
            urdf(
                r#"<inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>"#,
                &format!(r#"<mesh filename="{name}"/>"#),
            ),
        )
        .unwrap();
        let mut w = PhysicsWorld::new();
        let e = w
            .load_urdf(&robot, &UrdfOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains(name) && e.contains(says), "{name}: {e}");
        assert!(!e.contains("fill whole buffer"), "{e}");
        assert_eq!(w.dynamics().body_count(), 0);
        messages.push(e);
    }
    messages.dedup();
    assert_eq!(messages.len(), 4, "each says its own fault");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn xml_that_is_cut_short_or_not_utf8_is_refused_by_line() {
    let text = "<mujoco>\n<worldbody>\n  <body>\n    <geom size=\"0.1\"/>\n";
    refused(load_mjcf(text), "bad.xml:4:", "not well-formed XML");
    let dir = folder("utf8");
    let path = dir.join("bad.urdf");
    let mut bytes = b"<robot name=\"r\">\n  <link name=\"base\"/>\n  <link name=\"".to_vec();
    bytes.extend_from_slice(&[0xff, 0xfe]);
    bytes.extend_from_slice(b"\"/>\n</robot>\n");
    std::fs::write(&path, bytes).unwrap();
    let mut w = PhysicsWorld::new();
    let e = w
        .load_urdf(&path, &UrdfOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bad.urdf:3:") && e.contains("not UTF-8") && e.contains("0xff"),
        "{e}"
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bad_option_values_are_refused_by_line_and_nothing_is_built() {
    for (option, says) in [
        (r#"timestep="-0.01""#, "`timestep` = -0.01: must be > 0"),
        (r#"timestep="nan""#, "not a finite number"),
        (r#"gravity="0 0 nan""#, "not a finite number"),
        (
            r#"integrator="Verlet""#,
            "expected Euler, RK4, implicit or implicitfast",
        ),
    ] {
        let mjcf = format!(
            r#"<mujoco>
<option {option}/>
<worldbody>
  <body><freejoint/><geom size="0.1"/></body>
</worldbody>
</mujoco>"#
        );
        let (w, r) = load_mjcf(&mjcf);
        refused((w.clone(), r), "bad.xml:2:", says);
        assert_eq!(w.gravity(), PhysicsWorld::new().gravity(), "{option}");
    }
}

/// A two-hinge MJCF arm whose tendon section is `tendon`, on line 5.
fn tendon_arm(tendon: &str) -> String {
    format!(
        r#"<mujoco><worldbody>
<body name="a"><joint name="j1" type="hinge"/><geom size="0.1"/>
<body name="b" pos="0 0 -0.3"><joint name="j2" type="hinge"/><geom size="0.1"/><body pos="0 0 -0.3"><joint name="ball" type="ball"/><geom size="0.1"/></body></body>
</body></worldbody><tendon>
{tendon}
</tendon></mujoco>"#
    )
}

#[test]
fn tendons_kea_does_not_simulate_or_with_bad_values_are_refused_by_element() {
    let j = r#"<joint joint="j1" coef="1"/><joint joint="j2" coef="-1"/>"#;
    for (tendon, says) in [
        (
            format!(r#"<spatial name="s">{j}</spatial>"#),
            "<spatial> tendons are not supported",
        ),
        (
            format!(r#"<fixed frictionloss="0.5">{j}</fixed>"#),
            "frictionloss",
        ),
        (format!(r#"<fixed armature="0.1">{j}</fixed>"#), "armature"),
        (
            format!(r#"<fixed stiffness="1 2">{j}</fixed>"#),
            "polynomial",
        ),
        (format!(r#"<fixed stiffness="-1">{j}</fixed>"#), "stiffness"),
        (format!(r#"<fixed damping="nan">{j}</fixed>"#), "damping"),
        (format!(r#"<fixed range="0.5 -0.5">{j}</fixed>"#), "range"),
        (
            format!(r#"<fixed limited="true">{j}</fixed>"#),
            "needs a `range`",
        ),
        (
            format!(r#"<fixed springlength="1 0" stiffness="1">{j}</fixed>"#),
            "springlength",
        ),
        (
            format!(r#"<fixed range="-1 1" solreflimit="nan 1">{j}</fixed>"#),
            "solreflimit",
        ),
        (
            format!(r#"<fixed range="-1 1" solimplimit="0.9 0.95 -1">{j}</fixed>"#),
            "width",
        ),
        (
            r#"<fixed stiffness="1"><joint joint="nope"/></fixed>"#.to_string(),
            "\"nope\"",
        ),
        (
            r#"<fixed stiffness="1"><joint joint="ball"/></fixed>"#.to_string(),
            "\"ball\"",
        ),
        (
            r#"<fixed stiffness="1"><joint joint="j1" coef="x"/></fixed>"#.to_string(),
            "coef",
        ),
        (r#"<fixed stiffness="1"/>"#.to_string(), "has no joint"),
    ] {
        refused(load_mjcf(&tendon_arm(&tendon)), "bad.xml:5", says);
    }
    // One that applies no force loads, and says so; one that acts loads as a tendon.
    let (_, robot) = load_mjcf(&tendon_arm(&format!(r#"<fixed name="idle">{j}</fixed>"#)));
    let robot = robot.unwrap();
    assert!(robot.tendons().is_empty());
    assert!(robot
        .skipped()
        .join("\n")
        .contains("bad.xml:5: fixed tendon \"idle\""));
    let (_, robot) = load_mjcf(&tendon_arm(&format!(
        r#"<fixed name="on" damping="1">{j}</fixed>"#
    )));
    assert_eq!(robot.unwrap().tendons()[0].name, "on");
}
