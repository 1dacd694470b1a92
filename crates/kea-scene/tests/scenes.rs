//! Scene files: every demo scene loads, runs 5 s without NaN or explosion, and saves back to the
//! same text; malformed files get errors that say where and what.

mod common;

use kea::Real;
use kea_scene::{build, Scene, SceneError};

fn demo_scenes() -> Vec<(String, String)> {
    common::demo_scene_paths()
        .into_iter()
        .map(|p| {
            (
                p.display().to_string(),
                std::fs::read_to_string(&p).unwrap(),
            )
        })
        .collect()
}

#[test]
fn every_demo_scene_loads_runs_and_saves_back_to_the_same_file() {
    let scenes = demo_scenes();
    for name in [
        "animated_hand",
        "ball_pit",
        "bounce",
        "car",
        "chain",
        "conveyor",
        "drop",
        "hinge",
        "newtons_cradle",
        "pendulum",
        "pyramid",
        "ragdoll",
    ] {
        let file = format!("/{name}.json");
        assert!(
            scenes.iter().any(|(p, _)| p.ends_with(&file)),
            "scenes/{name}.json is missing"
        );
    }
    for (path, text) in scenes {
        let scene = Scene::from_json(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
        assert_eq!(
            scene.to_json(),
            text,
            "{path} does not save back to the same text"
        );
        let mut built = build(&scene).unwrap_or_else(|e| panic!("{path}: {e}"));
        let start_energy = mechanical_energy(&built);
        for _ in 0..300 {
            built
                .step(1.0 / 60.0)
                .unwrap_or_else(|e| panic!("{path}: {e}"));
        }
        for (name, h) in &built.bodies {
            let b = built.world.body(*h).unwrap();
            let (p, v) = (b.position(), b.linear_velocity());
            assert!(
                p.is_finite() && v.is_finite(),
                "{path}: {name} went non-finite"
            );
            assert!(
                p.length() < 100.0 && v.length() < 50.0,
                "{path}: {name} exploded: {p} {v}"
            );
        }
        let energy = mechanical_energy(&built);
        eprintln!(
            "{path}: {} bodies, kinetic + potential energy {start_energy:.2} → {energy:.2} J after 5 s",
            built.bodies.len()
        );
        // Scenes with nothing driving them (no motor, moving path or belt) may only lose
        // energy: to contacts, friction, restitution below 1 and stabilisation.
        let driven = ["animated_hand", "car", "conveyor", "hinge"];
        if !driven.iter().any(|d| path.ends_with(&format!("/{d}.json"))) {
            assert!(
                energy <= start_energy + 0.01 * start_energy.abs() + 1.0,
                "{path}: energy grew from {start_energy} J to {energy} J"
            );
        }
    }
}

#[test]
fn the_bounce_scene_bounces_with_its_material_restitution() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/bounce.json"
    ))
    .unwrap();
    let mut built = build(&Scene::from_json(&text).unwrap()).unwrap();
    let ball = built.body("ball").unwrap();
    let mut ratio = None;
    for _ in 0..240 {
        let v_in = built.world.body(ball).unwrap().linear_velocity().y;
        built.step(1.0 / 240.0).unwrap();
        let v = built.world.body(ball).unwrap().linear_velocity().y;
        if v_in < -1.0 && v > 0.0 {
            ratio = Some(v / -v_in);
            break;
        }
    }
    let ratio = ratio.expect("it bounced");
    assert!((ratio - 0.6).abs() < 0.01, "ratio {ratio}");
}

/// Each malformed scene, with words its error must contain.
const MALFORMED: &[(&str, &str, &[&str])] = &[
    ("not json", "this is not a scene", &["line 1", "expected"]),
    ("empty object", "{}", &["missing field `version`"]),
    (
        "bad version",
        r#"{"version": 7}"#,
        &["version 7", "version 1"],
    ),
    (
        "version as text",
        r#"{"version": "one"}"#,
        &["line 1", "invalid type"],
    ),
    (
        "unknown top field",
        "{\"version\": 1,\n \"bodys\": []}",
        &["line 2", "unknown field `bodys`"],
    ),
    (
        "gravity of two numbers",
        r#"{"version": 1, "world": {"gravity": [0, -9.8]}}"#,
        &["invalid length 2"],
    ),
    (
        "unknown solver",
        r#"{"version": 1, "world": {"solver": "magic"}}"#,
        &["unknown variant `magic`"],
    ),
    (
        "unknown shape",
        r#"{"version": 1, "static": [{"shape": {"torus": {"r": 1}}}]}"#,
        &["unknown variant `torus`"],
    ),
    (
        "unknown joint",
        r#"{"version": 1, "joints": [{"type": "rope", "body1": "a"}]}"#,
        &["unknown variant `rope`"],
    ),
    (
        "body without position",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1}]}"#,
        &["missing field `position`"],
    ),
    (
        "negative mass",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": -2, "position": [0,0,0]}]}"#,
        &["bodies[0].mass", "-2"],
    ),
    (
        "zero radius",
        r#"{"version": 1, "bodies": [{"name": "a", "position": [0,0,0], "shapes": [{"shape": {"sphere": {"radius": 0}}}]}]}"#,
        &["bodies[0].shapes[0].shape", "radius"],
    ),
    (
        "no shapes and no mass",
        r#"{"version": 1, "bodies": [{"name": "a", "position": [0,0,0]}]}"#,
        &["bodies[0]", "shapes or a mass"],
    ),
    (
        "same name twice",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0]}, {"name": "a", "mass": 1, "position": [1,0,0]}]}"#,
        &["bodies[1].name", "already exists"],
    ),
    (
        "missing body",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0]}], "joints": [{"type": "ball", "body1": "a", "body2": "b", "anchor": [0,0,0]}]}"#,
        &["joints[0].body2", "no body named \"b\""],
    ),
    (
        "missing material",
        r#"{"version": 1, "static": [{"shape": {"plane": {"normal": [0,1,0]}}, "material": "ice"}]}"#,
        &["static[0].material", "ice"],
    ),
    (
        "joint on one body twice",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0]}], "joints": [{"type": "fixed", "body1": "a", "body2": "a", "anchor": [0,0,0]}]}"#,
        &["joints[0].body2", "twice"],
    ),
    (
        "zero hinge axis",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0]}], "joints": [{"type": "hinge", "body1": "a", "anchor": [0,0,0], "axis": [0,0,0]}]}"#,
        &["joints[0].axis", "axis"],
    ),
    (
        "limits reversed",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0]}], "joints": [{"type": "hinge", "body1": "a", "anchor": [0,0,0], "axis": [0,1,0], "limits": [1, -1]}]}"#,
        &["joints[0].limits"],
    ),
    (
        "material twice",
        r#"{"version": 1, "materials": [{"name": "ice"}, {"name": "ice"}]}"#,
        &["materials[1]", "defined twice"],
    ),
    (
        "negative friction",
        r#"{"version": 1, "materials": [{"name": "ice", "friction": -1}]}"#,
        &["materials[0]", "friction"],
    ),
    (
        "unknown material in a pair",
        r#"{"version": 1, "material_pairs": [{"a": "default", "b": "ice", "friction": 0.1}]}"#,
        &["material_pairs[0].b", "no material named \"ice\""],
    ),
    (
        "zero slide direction",
        r#"{"version": 1, "materials": [{"name": "belt"}], "material_pairs": [{"a": "default", "b": "belt", "slide": [1, 0], "slide_direction": [0, 0, 0]}]}"#,
        &["material_pairs[0].slide_direction", "non-zero"],
    ),
    (
        "negative pair friction",
        r#"{"version": 1, "material_pairs": [{"a": "default", "b": "default", "friction": -0.5}]}"#,
        &["material_pairs[0].friction", "-0.5"],
    ),
    (
        "car wheel with a zero axle",
        r#"{"version": 1, "bodies": [{"name": "c", "mass": 1, "position": [0,0,0]}, {"name": "w", "mass": 1, "position": [1,0,0]}], "joints": [{"type": "car_wheel", "body1": "c", "body2": "w", "steering_axis": [0,1,0], "axle": [0,0,0], "suspension": [1000, 10]}]}"#,
        &["joints[0].axle"],
    ),
    (
        "car wheel without a wheel",
        r#"{"version": 1, "bodies": [{"name": "c", "mass": 1, "position": [0,0,0]}], "joints": [{"type": "car_wheel", "body1": "c", "steering_axis": [0,1,0], "axle": [0,0,1], "suspension": [1000, 10]}]}"#,
        &["joints[0].body2", "wheel"],
    ),
    (
        "car wheel with zero suspension stiffness",
        r#"{"version": 1, "bodies": [{"name": "c", "mass": 1, "position": [0,0,0]}, {"name": "w", "mass": 1, "position": [1,0,0]}], "joints": [{"type": "car_wheel", "body1": "c", "body2": "w", "steering_axis": [0,1,0], "axle": [0,0,1], "suspension": [0, 10]}]}"#,
        &["joints[0].suspension"],
    ),
    (
        "steering limits on a locked wheel",
        r#"{"version": 1, "bodies": [{"name": "c", "mass": 1, "position": [0,0,0]}, {"name": "w", "mass": 1, "position": [1,0,0]}], "joints": [{"type": "car_wheel", "body1": "c", "body2": "w", "steering_axis": [0,1,0], "axle": [0,0,1], "suspension": [1000, 10], "steering_limits": [-0.5, 0.5]}]}"#,
        &["joints[0].steerable"],
    ),
    (
        "path keyframes not increasing in t",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0]}], "joints": [{"type": "fixed_path", "body1": "a", "anchor": [0,0,0], "path": [[0, 0,0,0], [1, 1,0,0], [1, 2,0,0]]}]}"#,
        &["joints[0].path[2]", "increase"],
    ),
    (
        "path keyframe of three numbers",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0]}], "joints": [{"type": "fixed_path", "body1": "a", "anchor": [0,0,0], "path": [[0, 0, 0]]}]}"#,
        &["invalid length 3"],
    ),
    (
        "negative break force",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0]}], "joints": [{"type": "ball", "body1": "a", "anchor": [0,0,0], "break_force": -5}]}"#,
        &["joints[0].break_force", "-5"],
    ),
    (
        "two joints of one name",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0]}], "joints": [{"type": "ball", "name": "j", "body1": "a", "anchor": [0,0,0]}, {"type": "ball", "name": "j", "body1": "a", "anchor": [1,0,0]}]}"#,
        &["joints[1].name", "already exists"],
    ),
    (
        "misspelt joint field",
        r#"{"version": 1, "joints": [{"type": "hinge", "body1": "a", "anchor": [0,0,0], "axis": [0,1,0], "limit": [0, 1]}]}"#,
        &["unknown field `limit`"],
    ),
    (
        "universal axes not perpendicular",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0]}], "joints": [{"type": "universal", "body1": "a", "anchor": [0,0,0], "axis1": [1,0,0], "axis2": [1,0,0]}]}"#,
        &["joints[0].axis2", "perpendicular"],
    ),
    (
        "negative cone",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,-1,0]}], "joints": [{"type": "ball", "body1": "a", "anchor": [0,0,0], "cone": -0.5}]}"#,
        &["joints[0].cone", "-0.5"],
    ),
    (
        "soft limit with negative stiffness",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0]}], "joints": [{"type": "prismatic", "body1": "a", "anchor": [0,0,0], "axis": [1,0,0], "limits": {"lower": -1, "upper": 1, "stiffness": -10}}]}"#,
        &["joints[0].limits", "stiffness"],
    ),
    (
        "negative sleep threshold",
        r#"{"version": 1, "world": {"sleep": true, "sleep_thresholds": {"velocity": -1}}}"#,
        &["world.sleep_thresholds", "velocity_threshold"],
    ),
    (
        "inertia not positive definite",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0], "inertia": [1, -1, 1]}]}"#,
        &["bodies[0].inertia"],
    ),
    (
        "a mesh triangle naming a missing vertex",
        r#"{"version": 1, "static": [{"shape": {"mesh": {"vertices": [[0,0,0],[1,0,0],[0,0,1]], "triangles": [[0,1,3]]}}}]}"#,
        &["static[0].shape", "vertex 3"],
    ),
    (
        "a body of meshes with no inertia to weigh it by",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0], "shapes": [{"shape": {"mesh": {"vertices": [[0,0,0],[1,0,0],[0,0,1]], "triangles": [[0,2,1]]}}}]}]}"#,
        &["bodies[0].shapes", "no volume"],
    ),
    (
        "a collider orientation that is not a unit quaternion",
        r#"{"version": 1, "static": [{"shape": {"box": {"half_extents": [1,1,1]}}, "orientation": [0, 0, 0, 2]}]}"#,
        &["static[0].orientation", "unit quaternion"],
    ),
    (
        "a pyramid of zero-sized cubes",
        r#"{"version": 1, "groups": [{"pyramid": {"base": 3, "half_extent": 0, "density": 1000, "origin": [0,0,0]}}]}"#,
        &["groups[0].pyramid.half_extent", "half_extents"],
    ),
    (
        "a grid of negative density",
        r#"{"version": 1, "groups": [{"grid": {"shape": {"sphere": {"radius": 0.1}}, "counts": [2,2,2], "spacing": [1,1,1], "density": -5, "origin": [0,0,0]}}]}"#,
        &["groups[0].grid.density", "-5"],
    ),
    (
        "zero fast-spin axis",
        r#"{"version": 1, "bodies": [{"name": "a", "mass": 1, "position": [0,0,0], "fast_spin_axis": [0,0,0]}]}"#,
        &["bodies[0].fast_spin_axis"],
    ),
    (
        "a grid too big to build",
        r#"{"version": 1, "groups": [{"grid": {"shape": {"sphere": {"radius": 0.1}}, "counts": [4000000000, 4000000000, 4000000000], "spacing": [1,1,1], "density": 1000, "origin": [0,0,0]}}]}"#,
        &["groups[0]", "more than"],
    ),
    (
        "ragdoll of scale zero",
        r#"{"version": 1, "groups": [{"ragdoll": {"origin": [0,1,0], "scale": 0}}]}"#,
        &["groups[0].ragdoll.scale"],
    ),
];

#[test]
fn malformed_scenes_are_refused_with_where_and_what() {
    assert!(MALFORMED.len() >= 35);
    for (case, text, words) in MALFORMED {
        let e: SceneError = match Scene::from_json(text) {
            Err(e) => e,
            Ok(scene) => match build(&scene) {
                Err(e) => e,
                Ok(_) => panic!("{case}: accepted"),
            },
        };
        let message = e.to_string();
        for w in *words {
            assert!(message.contains(w), "{case}: expected {w:?} in {message:?}");
        }
    }
}

/// A scene using every field and joint type of the format.
const EVERYTHING: &str = r#"{"version": 1,
  "world": {"sleep": true, "sleep_thresholds": {"velocity": 0.02, "time": 1.0},
            "projection_iterations": 2, "max_lcp_iterations": 80, "max_friction_passes": 8,
            "max_island_rows": 128, "routing": {"max_exact_rows": 96},
            "iterative": {"substeps": 2}},
  "materials": [{"name": "belt", "friction": 0.9, "softness": 0.001, "slip": 0.0001, "adhesion": 1}],
  "material_pairs": [{"a": "default", "b": "belt", "friction": 0.7, "restitution": 0.1,
                      "restitution_threshold": 0.5, "softness": 0.0001, "slip": [0, 0],
                      "adhesion": 0, "slide": [1, 0], "slide_direction": [2, 0, 0]}],
  "static": [{"shape": {"plane": {"normal": [0, 1, 0]}}, "material": "belt"},
             {"shape": {"mesh": {"vertices": [[4, 0, 0], [6, 0, 0], [5, 1, -1]], "triangles": [[0, 1, 2]]}}},
             {"shape": {"box": {"half_extents": [1, 0.1, 1]}}, "offset": [8, 0.5, 0], "orientation": [0, 0, 0.2588190, 0.9659258]}],
  "bodies": [
    {"name": "a", "mass": 2, "position": [0, 1, 0], "inertia": [0.1, 0.2, 0.3], "prefer_exact": true,
     "shapes": [{"shape": {"box": {"half_extents": [0.2, 0.2, 0.2]}}}]},
    {"name": "b", "mass": 1, "position": [1, 1, 0], "inertia": [[0.1, 0.01, 0], [0.01, 0.1, 0], [0, 0, 0.1]],
     "fast_spin_axis": [0, 2, 0], "shapes": [{"shape": {"sphere": {"radius": 0.2}}}]},
    {"name": "c", "mass": 1, "position": [2, 1, 0], "enabled": false},
    {"name": "sheet", "mass": 1, "inertia": [0.1, 0.1, 0.1], "position": [-2, 3, 0],
     "shapes": [{"shape": {"mesh": {"vertices": [[0, 0, 0], [1, 0, 0], [0, 0, 1]], "triangles": [[0, 2, 1]]}}}]}],
  "joints": [
    {"type": "ball", "name": "shoulder", "body1": "b", "body2": "a", "anchor": [0.5, 1, 0], "cone": 0.5,
     "twist": {"lower": -0.2, "upper": 0.2, "restitution": 0.3}, "limit_axis": [1, 0, 0]},
    {"type": "hinge", "body1": "a", "anchor": [0, 1.5, 0], "axis": [0, 0, 1],
     "limits": {"lower": -1, "upper": 1, "stiffness": 100, "damping": 5}, "motor": [0.5, 10],
     "break_force": 1000, "break_torque": 500},
    {"type": "prismatic", "body1": "b", "anchor": [1, 1, 0], "axis": [0, 1, 0], "limits": [-0.5, 0.5], "motor": [0, 5]},
    {"type": "fixed", "body1": "a", "body2": "c", "anchor": [1, 1, 0]},
    {"type": "fixed_path", "body1": "c", "anchor": [2, 1, 0], "fixed_orientation": true,
     "path": [[0, 2, 1, 0], [1, 2, 2, 0]]},
    {"type": "universal", "body1": "a", "body2": "b", "anchor": [0.5, 1, 0], "axis1": [1, 0, 0], "axis2": [0, 1, 0]},
    {"type": "linear1", "body1": "b", "anchor": [1, 1, 0], "normal": [0, 0, 1]},
    {"type": "linear2", "body1": "a", "anchor": [0, 1, 0], "direction": [1, 0, 0]},
    {"type": "car_wheel", "name": "wheel", "body1": "a", "body2": "b", "steering_axis": [0, 1, 0],
     "axle": [0, 0, 1], "suspension": [1000, 50], "suspension_limits": [-0.1, 0.1], "steerable": true,
     "steering_limits": [-0.4, 0.4], "steering_motor": [0, 10], "drive": [-5, 20]}],
  "groups": [{"ragdoll": {"origin": [5, 2, 0], "scale": 0.5, "density": 900}},
             {"chain": {"links": 2, "spacing": 0.3, "radius": 0.1, "density": 1000, "origin": [-3, 3, 0]}}]
}"#;

#[test]
fn every_field_and_joint_type_builds_steps_and_round_trips() {
    let scene = Scene::from_json(EVERYTHING).unwrap();
    let text = scene.to_json();
    assert_eq!(Scene::from_json(&text).unwrap(), scene);
    assert_eq!(Scene::from_json(&text).unwrap().to_json(), text);
    let mut built = build(&scene).unwrap();
    let names: Vec<&str> = built.joints.iter().map(|(n, _)| n.as_str()).collect();
    for name in [
        "shoulder",
        "joint1",
        "joint7",
        "wheel",
        "ragdoll0.left_knee",
        "chain1.1",
    ] {
        assert!(names.contains(&name), "{name} missing from {names:?}");
    }
    assert_eq!(built.bodies.len(), 4 + 11 + 2);
    let path = built.joint("joint4").unwrap();
    let c = built.body("c").unwrap();
    for _ in 0..30 {
        built.step(1.0 / 60.0).unwrap();
    }
    assert!((built.time() - 0.5).abs() < 1e-4);
    let kind = built.world.constraint_kind(path).unwrap();
    assert_eq!(kind, "fixed-path-fixed-orientation joint");
    // Body c is disabled: it stays put even though its path moves.
    let p = built.world.body(c).unwrap().position();
    assert!((p - kea::Vec3::new(2.0, 1.0, 0.0)).length() < 1e-6, "{p}");
}

#[test]
fn a_keyframed_path_carries_its_body_along_the_keyframes() {
    let text = r#"{"version": 1, "world": {"gravity": [0, 0, 0]},
      "bodies": [{"name": "hand", "mass": 1, "position": [0, 1, 0]}],
      "joints": [{"type": "fixed_path", "body1": "hand", "anchor": [0, 1, 0],
                  "path": [[0, 0, 1, 0], [1, 2, 1, 0], [2, 2, 3, 0]]}]}"#;
    let mut built = build(&Scene::from_json(text).unwrap()).unwrap();
    let hand = built.body("hand").unwrap();
    for (steps, expected) in [
        (30, [1.0, 1.0]),
        (30, [2.0, 1.0]),
        (30, [2.0, 2.0]),
        (60, [2.0, 3.0]),
    ] {
        for _ in 0..steps {
            built.step(1.0 / 60.0).unwrap();
        }
        let p = built.world.body(hand).unwrap().position();
        eprintln!("t = {:.2}: hand at {p}", built.time());
        assert!(
            (p.x - expected[0]).abs() < 1e-3 && (p.y - expected[1]).abs() < 1e-3,
            "{p}"
        );
    }
}

/// Kinetic plus gravitational potential energy of every body, J.
fn mechanical_energy(built: &kea_scene::BuiltScene) -> Real {
    let g = built.world.gravity();
    built
        .world
        .bodies()
        .map(|(_, b)| b.kinetic_energy() - b.mass() * g.dot(b.position()))
        .sum()
}

#[test]
fn a_body_given_only_a_mass_gets_that_mass_times_unit_inertia() {
    let scene = Scene::from_json(
        r#"{"version": 1, "world": {"gravity": [0, 0, 0]},
            "bodies": [{"name": "point", "mass": 2.5, "position": [0, 0, 0]}]}"#,
    )
    .unwrap();
    let built = build(&scene).unwrap();
    let b = built.world.body(built.body("point").unwrap()).unwrap();
    assert_eq!(b.mass(), 2.5);
    assert_eq!(b.inertia(), kea::Mat3::from_diagonal(kea::Vec3::splat(2.5)));
}
