//! Scene files stepped through the pipeline: every demo scene runs 5 s without NaN, explosion
//! or (undriven) energy gain; the bounce scene bounces with its material's restitution; a
//! scene with every field and joint type steps with its clock and keyframed paths right; a
//! keyframed path carries its body along the keyframes.

mod common;

use kea::Real;
use kea3d::PhysicsWorld;
use kea_scene::{build, Scene};

fn world_of(text: &str) -> PhysicsWorld {
    PhysicsWorld::from_scene(build(&Scene::from_json(text).unwrap()).unwrap())
}

/// Kinetic plus gravitational potential energy of every body, J.
fn mechanical_energy(world: &PhysicsWorld) -> Real {
    let g = world.gravity();
    world
        .dynamics()
        .bodies()
        .map(|(_, b)| b.kinetic_energy() - b.mass() * g.dot(b.position()))
        .sum()
}

#[test]
fn every_demo_scene_runs_5_s_without_nan_explosion_or_energy_gain() {
    for path in common::demo_scene_paths() {
        let path = path.display().to_string();
        let mut world = world_of(&std::fs::read_to_string(&path).unwrap());
        let start_energy = mechanical_energy(&world);
        for _ in 0..300 {
            world
                .step(1.0 / 60.0)
                .unwrap_or_else(|e| panic!("{path}: {e}"));
        }
        for (name, h) in world.named_bodies() {
            let b = world.dynamics().body(*h).unwrap();
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
        let energy = mechanical_energy(&world);
        eprintln!(
            "{path}: {} bodies, kinetic + potential energy {start_energy:.2} → {energy:.2} J after 5 s",
            world.named_bodies().len()
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
    let mut world = world_of(&text);
    let ball = world.body_by_name("ball").unwrap();
    let mut ratio = None;
    for _ in 0..240 {
        let v_in = world.dynamics().body(ball).unwrap().linear_velocity().y;
        world.step(1.0 / 240.0).unwrap();
        let v = world.dynamics().body(ball).unwrap().linear_velocity().y;
        if v_in < -1.0 && v > 0.0 {
            ratio = Some(v / -v_in);
            break;
        }
    }
    let ratio = ratio.expect("it bounced");
    assert!((ratio - 0.6).abs() < 0.01, "ratio {ratio}");
}

#[test]
fn a_scene_with_every_field_and_joint_type_steps_on_the_worlds_clock() {
    let text = include_str!("../../kea-scene/tests/fixtures/everything.json");
    let mut world = world_of(text);
    let c = world.body_by_name("c").unwrap();
    for _ in 0..30 {
        world.step(1.0 / 60.0).unwrap();
    }
    // One clock: the dynamics world's.
    assert!((world.time() - 0.5).abs() < 1e-4, "{}", world.time());
    assert_eq!(world.time(), world.dynamics().time() as Real);
    // Body c is disabled: it stays put even though its path moves.
    let p = world.dynamics().body(c).unwrap().position();
    assert!((p - kea::Vec3::new(2.0, 1.0, 0.0)).length() < 1e-6, "{p}");
}

#[test]
fn a_keyframed_path_carries_its_body_along_the_keyframes() {
    let text = r#"{"version": 1, "world": {"gravity": [0, 0, 0]},
      "bodies": [{"name": "hand", "mass": 1, "position": [0, 1, 0]}],
      "joints": [{"type": "fixed_path", "body1": "hand", "anchor": [0, 1, 0],
                  "path": [[0, 0, 1, 0], [1, 2, 1, 0], [2, 2, 3, 0]]}]}"#;
    let mut world = world_of(text);
    let hand = world.body_by_name("hand").unwrap();
    for (steps, expected) in [
        (30, [1.0, 1.0]),
        (30, [2.0, 1.0]),
        (30, [2.0, 2.0]),
        (60, [2.0, 3.0]),
    ] {
        for _ in 0..steps {
            world.step(1.0 / 60.0).unwrap();
        }
        let p = world.dynamics().body(hand).unwrap().position();
        eprintln!("t = {:.2}: hand at {p}", world.time());
        assert!(
            (p.x - expected[0]).abs() < 1e-3 && (p.y - expected[1]).abs() < 1e-3,
            "{p}"
        );
    }
}
