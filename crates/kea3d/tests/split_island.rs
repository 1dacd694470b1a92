//! VALIDATION #35: a ragdoll lying across a pile of boxes makes one island of joints and
//! contacts, which the default routing solves split (joints directly inside the substeps, the
//! contacts by the contact solver); every joint stays closed within 1 mm and no box tunnels.

use kea::{IslandList, Real, SolverPath};
use kea3d::PhysicsWorld;
use kea_scene::{build, Scene};

/// A 3 × 2 × 2 pile of 0.2 t unit boxes on the ground and a ragdoll (its bodies prefer the
/// exact solver) lying along x just above it.
const SCENE: &str = r#"{
  "version": 1,
  "world": {"gravity": [0, -9.81, 0], "sleep": false},
  "static": [{"shape": {"plane": {"normal": [0, 1, 0]}}}],
  "groups": [
    {"grid": {"shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "counts": [3, 2, 2],
              "spacing": [1.0, 1.0, 1.0], "density": 200, "origin": [-1.0, 0.5, -0.5]}},
    {"ragdoll": {"origin": [0.0, 2.25, 0.0], "orientation": [0.0, 0.0, -0.70710677, 0.70710677]}}
  ]
}"#;

#[test]
fn a_ragdoll_lying_on_a_pile_of_boxes_is_solved_split_and_its_joints_hold() {
    let mut world = PhysicsWorld::from_scene(build(&Scene::from_json(SCENE).unwrap()).unwrap());
    let pelvis = world.body_by_name("ragdoll1.pelvis").unwrap();
    let boxes: Vec<_> = world
        .named_bodies()
        .iter()
        .filter(|(name, _)| !name.starts_with("ragdoll"))
        .map(|(_, h)| *h)
        .collect();
    assert_eq!(boxes.len(), 12);
    let mut islands = IslandList::default();
    let (mut mixed_steps, mut worst_gap, mut lowest_box): (u32, Real, Real) = (0, 0.0, Real::MAX);
    for _ in 0..300 {
        world.step(1.0 / 60.0).unwrap();
        let w = world.dynamics();
        w.islands(&mut islands);
        let k = islands
            .island_of(pelvis)
            .expect("the ragdoll is in an island");
        let on_pile = boxes.iter().any(|&b| islands.island_of(b) == Some(k));
        if on_pile {
            // One island of the ragdoll and the boxes under it: the step solved it split.
            let n = islands.bodies(k).len() as u32;
            let split: Vec<_> = w
                .island_reports()
                .iter()
                .filter(|r| r.path == SolverPath::Split)
                .collect();
            assert!(
                split.iter().any(|r| r.bodies == n),
                "the mixed island of {n} bodies was not solved split: {:?}",
                w.island_reports()
            );
            mixed_steps += 1;
        }
        worst_gap = worst_gap.max(world.dynamics_mut().joint_error());
        for &b in &boxes {
            lowest_box = lowest_box.min(world.dynamics().body(b).unwrap().position().y);
        }
    }
    eprintln!(
        "ragdoll on the pile for {mixed_steps} of 300 steps; worst joint gap {:.4} mm; lowest box centre {lowest_box:.3} m",
        worst_gap * 1e3
    );
    assert!(
        mixed_steps > 200,
        "the ragdoll lay on the pile for {mixed_steps} steps"
    );
    assert!(worst_gap < 1.0e-3, "a joint opened by {worst_gap} m");
    // A unit box resting on the ground has its centre at 0.5 m: none sinks through.
    assert!(lowest_box > 0.49, "a box sank to {lowest_box} m");
}
