//! Scene files: every demo scene loads, builds and saves back to the same text; malformed files
//! get errors that say where and what. (Scenes stepped: `kea3d`'s `scene_runs` test.)

mod common;

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
fn every_demo_scene_loads_builds_and_saves_back_to_the_same_file() {
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
        "pyramid_struck",
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
        build(&scene).unwrap_or_else(|e| panic!("{path}: {e}"));
    }
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
/// A scene with every field and joint type (also stepped by `kea3d`'s `scene_runs` test).
const EVERYTHING: &str = include_str!("fixtures/everything.json");

#[test]
fn every_field_and_joint_type_builds_and_round_trips() {
    let scene = Scene::from_json(EVERYTHING).unwrap();
    let text = scene.to_json();
    assert_eq!(Scene::from_json(&text).unwrap(), scene);
    assert_eq!(Scene::from_json(&text).unwrap().to_json(), text);
    let built = build(&scene).unwrap();
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
    let kind = built.world.constraint_kind(path).unwrap();
    assert_eq!(kind, "fixed-path-fixed-orientation joint");
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
