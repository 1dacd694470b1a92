//! Issue 12: determinism and replay, on every demo scene, stepped through the pipeline.
//!
//! - A clone taken mid-run (dynamics, collision layer and drivers) and stepped on gives the
//!   bits of the uninterrupted run: warm starts, contact ids, manifolds, sleep timers and joint
//!   state all travel with it.
//! - Each scene's state hash after 120 steps equals the one in `tests/golden/` for this precision:
//!   the same across runs and processes (each test run is a new process), with the `parallel`
//!   feature on and off (both builds check the same file), and for 1, 2 and 4 threads.
//!
//! - A snapshot saved mid-run, in the binary and the JSON form, restores to a world that steps
//!   on with the same bits, on every demo scene.
//!
//! After a change that moves the physics on purpose, write the new hashes with
//! `KEA_BLESS=1 cargo test -p kea3d --test determinism` (and again with
//! `--features kea-collision/f64`).

mod common;
use common::{HOPPER, QUADRUPED};

use kea::Real;
use kea3d::PhysicsWorld;
use kea_scene::{build, Scene, SceneSnapshot};
use std::io::Write;

const STEPS: usize = 120;
const DT: Real = 1.0 / 60.0;

fn demo_scenes() -> Vec<(String, Scene)> {
    common::demo_scene_paths()
        .into_iter()
        .map(|p| {
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            let scene = Scene::from_json(&std::fs::read_to_string(&p).unwrap()).unwrap();
            (name, scene)
        })
        .collect()
}

/// The bits of a real, widened (in f32 and f64 alike).
#[allow(clippy::unnecessary_cast)] // a no-op in f64
fn bits(x: kea::Real) -> u64 {
    x.to_bits() as u64
}

/// FNV-1a over the bits of every body's pose and velocities, in slot order.
fn state_hash(scene: &PhysicsWorld) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bits: u64| {
        for byte in bits.to_le_bytes() {
            h ^= u64::from(byte);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    };
    for (handle, body) in scene.dynamics().bodies() {
        eat(u64::from(handle.index()));
        let (p, q) = (body.position(), body.orientation());
        let (v, w) = (body.linear_velocity(), body.angular_velocity());
        for x in [
            p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z,
        ] {
            eat(bits(x));
        }
    }
    h
}

/// The bits of every joint's reactions on its two bodies, in the robot's joint order.
fn reaction_bits(robot: &kea3d::robot::Robot, w: &PhysicsWorld) -> Vec<u64> {
    robot
        .joints()
        .iter()
        .filter_map(|j| j.raw)
        .flat_map(|j| w.dynamics().constraint_reaction(j).unwrap())
        .flat_map(|r| [r.force, r.torque])
        .flat_map(|v| v.to_array())
        .map(bits)
        .collect()
}

/// The scene's islands as lists of body handles, asleep or not.
fn island_lists(scene: &PhysicsWorld) -> Vec<(bool, Vec<kea::BodyHandle>)> {
    let mut list = kea::IslandList::default();
    scene.dynamics().islands(&mut list);
    (0..list.len())
        .map(|k| (list.is_asleep(k), list.bodies(k).to_vec()))
        .collect()
}

fn run(scene: &mut PhysicsWorld, steps: usize) {
    for _ in 0..steps {
        scene.step(DT).unwrap();
    }
}

#[test]
fn every_demo_scene_replays_bit_for_bit_from_a_clone_taken_mid_run() {
    for (name, scene) in demo_scenes() {
        let mut original = PhysicsWorld::from_scene(build(&scene).unwrap());
        run(&mut original, STEPS / 2);
        let mut copy = original.clone();
        run(&mut original, STEPS / 2);
        run(&mut copy, STEPS / 2);
        assert_eq!(
            state_hash(&copy),
            state_hash(&original),
            "{name}: the clone went its own way"
        );
        // And the clone's contacts are the same contacts, with the same forces.
        assert_eq!(
            copy.dynamics().constraint_count(),
            original.dynamics().constraint_count(),
            "{name}"
        );
    }
}

#[test]
fn every_demo_scene_replays_bit_for_bit_from_a_saved_snapshot() {
    for (name, scene) in demo_scenes() {
        let mut original = PhysicsWorld::from_scene(build(&scene).unwrap());
        run(&mut original, STEPS / 2);
        let binary = original.snapshot().unwrap().to_binary().unwrap();
        let json = original.snapshot().unwrap().to_json().unwrap();
        let mut from_binary = SceneSnapshot::from_binary(&binary)
            .and_then(PhysicsWorld::restore)
            .unwrap_or_else(|e| panic!("{name}: binary: {e}"));
        let mut from_json = SceneSnapshot::from_json(&json)
            .and_then(PhysicsWorld::restore)
            .unwrap_or_else(|e| panic!("{name}: JSON: {e}"));
        // The restored worlds hold the same islands (the guide's partition lists).
        let expected = island_lists(&original);
        assert_eq!(
            island_lists(&from_binary),
            expected,
            "{name}: binary islands"
        );
        assert_eq!(island_lists(&from_json), expected, "{name}: JSON islands");
        run(&mut original, STEPS / 2);
        run(&mut from_binary, STEPS / 2);
        run(&mut from_json, STEPS / 2);
        let expected = state_hash(&original);
        assert_eq!(state_hash(&from_binary), expected, "{name}: binary");
        assert_eq!(state_hash(&from_json), expected, "{name}: JSON");
        let expected = island_lists(&original);
        assert_eq!(
            island_lists(&from_binary),
            expected,
            "{name}: binary islands"
        );
        // The restored scene answers to the same handles.
        let (body_name, body) = &original.named_bodies()[0];
        assert_eq!(from_binary.body_by_name(body_name), Some(*body));
        assert!(from_binary.dynamics().body(*body).is_ok());
        // And keeps the clock.
        assert_eq!(from_binary.time(), original.time());
    }
}

#[test]
fn a_bad_snapshot_is_refused_by_name() {
    let (_, scene) = demo_scenes().remove(0);
    let built = PhysicsWorld::from_scene(build(&scene).unwrap());
    let snapshot = built.snapshot().unwrap();
    let mut binary = snapshot.to_binary().unwrap();
    let e = SceneSnapshot::from_binary(b"not a snapshot").err().unwrap();
    assert!(e.to_string().contains("KEASNAP"), "{e}");
    binary[8] = 99; // the version
    let e = SceneSnapshot::from_binary(&binary).err().unwrap();
    assert!(e.to_string().contains("version 99"), "{e}");
    // A snapshot of the first format (its clock was the scene's, not the world's).
    let json = snapshot.to_json().unwrap();
    assert!(json.starts_with("{\"version\":4,"), "{json:.40}");
    let json = json.replacen("\"version\":4", "\"version\":1", 1);
    let e = SceneSnapshot::from_json(&json)
        .and_then(PhysicsWorld::restore)
        .err()
        .unwrap();
    assert!(e.to_string().contains("version 1"), "{e}");
    let e = SceneSnapshot::from_json("{}").err().unwrap();
    assert!(e.to_string().contains("snapshot"), "{e}");
}

fn golden_path() -> String {
    // (By the real type: CI switches precision through `kea-collision/f64`.)
    let precision = if std::mem::size_of::<Real>() == 8 {
        "f64"
    } else {
        "f32"
    };
    format!(
        "{}/tests/golden/hashes_{precision}.txt",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// Each scene's hash after [`STEPS`] steps, as `name hash` lines.
fn hashes() -> String {
    hashes_at(kea::SimdLevel::Auto)
}

/// [`hashes`] with the contact solver's lane width forced to `simd`.
fn hashes_at(simd: kea::SimdLevel) -> String {
    let mut out = String::new();
    for (name, scene) in demo_scenes() {
        let mut built = PhysicsWorld::from_scene(build(&scene).unwrap());
        built
            .dynamics_mut()
            .update_settings(|s| s.iterative.simd = simd)
            .unwrap();
        run(&mut built, STEPS);
        out.push_str(&format!("{name} {:016x}\n", state_hash(&built)));
    }
    out
}

fn check_against_golden(found: &str, how: &str) {
    let path = golden_path();
    if std::env::var_os("KEA_BLESS").is_some() {
        std::fs::write(&path, found).unwrap();
        return;
    }
    let golden = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{path}: {e} (write it with KEA_BLESS=1)"));
    assert_eq!(found, golden, "{how}: the state hashes differ from {path}");
}

#[test]
fn demo_scene_hashes_match_the_golden_file() {
    let found = hashes();
    // Twice in one process: nothing carried over between runs.
    assert_eq!(hashes(), found, "a second run in this process differs");
    check_against_golden(&found, "one thread");
}

/// ARCHITECTURE's "same bits on every machine": the contact kernels at 1 lane (scalar), 4
/// (SSE2 in f32, 2 in f64) and 8 (AVX2 and FMA in f32, 4 in f64) give the golden bits. A width
/// this processor lacks falls back to the next narrower one, and the test says so; Kea has no
/// wider kernels (AVX-512), so 16 lanes are not a case.
#[test]
fn demo_scene_hashes_are_the_same_for_every_simd_width() {
    use kea::SimdLevel;
    for level in [SimdLevel::Scalar, SimdLevel::Narrow, SimdLevel::Wide] {
        let ran = level.detect();
        if ran != level {
            writeln!(
                std::io::stderr(),
                "SKIPPED ({level:?} lanes: this processor runs {ran:?}, already checked)"
            )
            .unwrap();
            continue;
        }
        let found = hashes_at(level);
        check_against_golden(&found, &format!("{} lanes", level.lanes()));
    }
}

#[cfg(feature = "parallel")]
#[test]
fn demo_scene_hashes_are_the_same_for_every_thread_count() {
    for threads in [1, 2, 4] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let found = pool.install(hashes);
        check_against_golden(&found, &format!("{threads} threads"));
    }
}

#[test]
fn a_world_saved_with_a_quarantined_island_restores_its_report_and_replays() {
    use kea::{BodyDef, Mat3, Routing, SolverMode, Vec3, World};
    let mut w = World::with_capacity(8, 8).unwrap();
    // Gauss-Seidel forced, with no mass ratio turning the island away to split islands.
    w.update_settings(|s| {
        s.routing = Routing {
            mode: SolverMode::Iterative,
            mass_ratio: Real::INFINITY,
            ..Routing::default()
        }
    })
    .unwrap();
    // A redundant pair of ball joints between 1e-9 kg and 1e12 kg bodies blows up there; a
    // ball elsewhere falls.
    let body = |w: &mut World, mass: Real, inertia: Real, x: Real| {
        w.create_body(&BodyDef {
            mass,
            inertia: Mat3::from_diagonal(Vec3::splat(inertia)),
            position: Vec3::new(x, 0.0, 0.0),
            angular_velocity: Vec3::new(3.0, 1.0, 2.0),
            ..BodyDef::default()
        })
        .unwrap()
    };
    let light = body(&mut w, 1.0e-9, 1.0e-19, 1.0);
    let heavy = body(&mut w, 1.0e12, 1.0e19, 2.0);
    w.create_joint(
        light,
        Some(heavy),
        kea::JointSpec::ball(Vec3::new(1.5, 0.0, 0.0)),
    )
    .unwrap();
    w.create_joint(
        light,
        Some(heavy),
        kea::JointSpec::ball(Vec3::new(1.0, 1.0, 0.0)),
    )
    .unwrap();
    w.create_joint(light, None, kea::JointSpec::ball(Vec3::ZERO))
        .unwrap();
    let ball = body(&mut w, 1.0, 1.0, 50.0);
    while w.quarantine_report().is_empty() {
        assert!(w.step_count() < 120, "the island never blew up");
        w.step(DT).unwrap();
    }
    let mut restored = World::restore(w.snapshot().unwrap()).unwrap();
    assert_eq!(restored.quarantine_report(), w.quarantine_report());
    assert!(restored.body(light).unwrap().is_quarantined());
    for world in [&mut w, &mut restored] {
        for _ in 0..30 {
            world.step(DT).unwrap();
        }
        assert_eq!(world.clear_quarantine(), 2);
        for _ in 0..30 {
            world.step(DT).unwrap();
        }
    }
    for h in [light, heavy, ball] {
        let (a, b) = (w.body(h).unwrap(), restored.body(h).unwrap());
        assert_eq!(a.position(), b.position());
        assert_eq!(a.linear_velocity(), b.linear_velocity());
    }
}

#[test]
fn a_chain_of_ball_joints_in_reduced_coordinates_replays_from_a_snapshot_and_a_clone() {
    use kea::{BodyDef, Vec3, World};
    let mut w = World::with_capacity(4, 4).unwrap();
    let mut parent = None;
    for k in 0..3 {
        let x = 0.5 * k as Real;
        let b = w
            .create_body(&BodyDef {
                position: Vec3::new(x + 0.5, 0.0, 0.1 * k as Real),
                angular_velocity: Vec3::new(0.0, 1.0, 0.0),
                ..BodyDef::default()
            })
            .unwrap();
        w.create_joint(b, parent, kea::JointSpec::ball(Vec3::new(x, 0.0, 0.0)))
            .unwrap();
        parent = Some(b);
    }
    for _ in 0..60 {
        assert_eq!(w.step(DT).unwrap().reduced_trees, 1);
    }
    let mut restored = World::restore(w.snapshot().unwrap()).unwrap();
    let mut copy = w.clone();
    let state = |w: &World| -> Vec<u64> {
        w.bodies()
            .flat_map(|(_, b)| {
                let (p, q, v) = (b.position(), b.orientation(), b.angular_velocity());
                [p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z].map(bits)
            })
            .collect()
    };
    for _ in 0..60 {
        for world in [&mut w, &mut restored, &mut copy] {
            world.step(DT).unwrap();
        }
    }
    assert_eq!(state(&restored), state(&w));
    assert_eq!(state(&copy), state(&w));
}

/// A robot standing on the ground in reduced coordinates, its contacts solved in joint space
/// (an MJCF hopper-like model: planar root, hip and knee with stops and springs, a capsule
/// foot on a plane), replays bit for bit from a saved snapshot (binary and JSON) and a clone.
#[test]
fn a_robot_on_the_ground_in_reduced_coordinates_replays_from_a_snapshot_and_a_clone() {
    let xml = r#"<mujoco><compiler angle="degree"/>
      <default><joint armature="0.1" damping="0.5" limited="true"/></default>
      <worldbody>
        <geom type="plane" size="5 5 0.1"/>
        <body name="torso" pos="0 0 1">
          <joint name="x" type="slide" axis="1 0 0" limited="false" armature="0" damping="0"/>
          <joint name="z" type="slide" axis="0 0 1" limited="false" armature="0" damping="0"/>
          <joint name="pitch" type="hinge" axis="0 1 0" limited="false" armature="0" damping="0"/>
          <geom type="capsule" size="0.05 0.2"/>
          <body name="thigh" pos="0 0 -0.2">
            <joint name="hip" type="hinge" axis="0 -1 0" range="-150 0" stiffness="5"/>
            <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.05"/>
            <body name="shin" pos="0 0 -0.4">
              <joint name="knee" type="hinge" axis="0 -1 0" range="-150 0"/>
              <geom type="capsule" fromto="0 0 0 0.1 0 -0.4" size="0.04"/>
            </body>
          </body>
        </body>
      </worldbody></mujoco>"#;
    let mut w = PhysicsWorld::new();
    w.load_mjcf_str(xml, "hopper.xml", &kea3d::robot::MjcfOptions::default())
        .unwrap();
    let h = 1.0 / 240.0;
    let mut touched = false;
    for _ in 0..240 {
        assert_eq!(w.step(h).unwrap().reduced_trees, 1);
        touched |= w.dynamics().contacts().count() > 0;
    }
    assert!(touched, "it lands");
    let binary = w.snapshot().unwrap().to_binary().unwrap();
    let json = w.snapshot().unwrap().to_json().unwrap();
    let mut from_binary = SceneSnapshot::from_binary(&binary)
        .and_then(PhysicsWorld::restore)
        .unwrap();
    let mut from_json = SceneSnapshot::from_json(&json)
        .and_then(PhysicsWorld::restore)
        .unwrap();
    let mut copy = w.clone();
    let state = |w: &PhysicsWorld| -> Vec<u64> {
        w.dynamics()
            .bodies()
            .flat_map(|(_, b)| {
                let (p, q, v) = (b.position(), b.orientation(), b.linear_velocity());
                [p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z].map(bits)
            })
            .collect()
    };
    for _ in 0..240 {
        for world in [&mut w, &mut from_binary, &mut from_json, &mut copy] {
            assert_eq!(world.step(h).unwrap().reduced_trees, 1);
        }
    }
    assert_eq!(state(&from_binary), state(&w));
    assert_eq!(state(&from_json), state(&w));
    assert_eq!(state(&copy), state(&w));
}

#[test]
fn a_legged_robot_on_the_ground_replays_bit_for_bit_from_a_snapshot_and_a_clone() {
    let mut original = PhysicsWorld::new();
    let robot = original
        .load_mjcf_str(
            QUADRUPED,
            "quadruped.xml",
            &kea3d::robot::MjcfOptions::default(),
        )
        .unwrap();
    let h = robot.timestep().unwrap();
    // Kicking legs: contacts that come and go, stops that push and let go.
    let controls = |k: usize| -> Vec<Real> {
        (0..8)
            .map(|j| (0.7 * (k as Real * 0.05 + j as Real)).sin())
            .collect()
    };
    let step = |w: &mut PhysicsWorld, k: usize| {
        robot.set_controls(w, &controls(k)).unwrap();
        w.step(h).unwrap();
    };
    let mut touching = 0;
    for k in 0..150 {
        step(&mut original, k);
        touching += usize::from(original.dynamics().contacts().count() > 0);
    }
    assert!(
        touching > 50,
        "the robot hops on the floor: touching in {touching} of 150 steps"
    );
    let binary = original.snapshot().unwrap().to_binary().unwrap();
    let mut restored = SceneSnapshot::from_binary(&binary)
        .and_then(PhysicsWorld::restore)
        .unwrap();
    let mut cloned = original.clone();
    for k in 150..450 {
        step(&mut original, k);
        step(&mut restored, k);
        step(&mut cloned, k);
        let expected = state_hash(&original);
        assert_eq!(state_hash(&restored), expected, "snapshot: step {k}");
        assert_eq!(state_hash(&cloned), expected, "clone: step {k}");
    }
}

/// `step_many` (what Python's `World.step(dt, steps)` and `Batch.step` run) gives the bits of
/// as many single steps, the joints' reactions after it included, on the legged robot above
/// with its contacts, stops, actuators and world substeps.
#[test]
fn many_steps_at_once_give_the_bits_of_single_steps_reactions_included() {
    let mut one = PhysicsWorld::new();
    let robot = one
        .load_mjcf_str(
            QUADRUPED,
            "quadruped.xml",
            &kea3d::robot::MjcfOptions::default(),
        )
        .unwrap();
    one.dynamics_mut()
        .update_settings(|s| s.world_substeps = 2)
        .unwrap();
    let h = robot.timestep().unwrap();
    let mut many = one.clone();
    let reactions = |w: &PhysicsWorld| reaction_bits(&robot, w);
    let mut touching = 0;
    for k in 0..40 {
        let u: Vec<Real> = (0..8)
            .map(|j| (0.7 * (k as Real * 0.3 + j as Real)).sin())
            .collect();
        robot.set_controls(&mut one, &u).unwrap();
        robot.set_controls(&mut many, &u).unwrap();
        for _ in 0..5 {
            one.step(h).unwrap();
        }
        many.step_many(h, 5).unwrap();
        assert_eq!(state_hash(&many), state_hash(&one), "after call {k}");
        assert_eq!(
            reactions(&many),
            reactions(&one),
            "reactions after call {k}"
        );
        touching += usize::from(one.dynamics().contacts().count() > 0);
    }
    assert!(
        touching > 10,
        "it touches the floor ({touching} of 40 calls)"
    );
    assert!(
        reactions(&one).iter().any(|&b| b != 0),
        "the joints carry load"
    );
    assert!(many
        .step_many(h, 0)
        .unwrap_err()
        .to_string()
        .contains("steps"));
}

/// The model/data split of batches: one worker world steps several worlds' states in turn
/// (each taken in, stepped, given back to a world that only holds it), and each comes out on
/// the bits of the same world stepped on its own — bodies, joints' reactions and contacts —
/// on the hopping quadruped (contacts coming and going, a floating tree kept and re-centred)
/// and a planar hopper, with their controls set on the held states between calls.
///
/// Twice: the worker copying each state in and out (`copy_state_from`), and trading states
/// with each world (`swap_state`, what `kea.Batch` does); after the trades, each held world
/// also steps on its own (its kept trees size the scratch they gave away) on the same bits.
#[test]
fn a_worker_world_steps_other_worlds_states_on_their_bits() {
    let options = kea3d::robot::MjcfOptions::default();
    let cases = [(QUADRUPED, "quadruped.xml", 8), (HOPPER, "hopper.xml", 1)];
    for ((xml, name, n), swap) in cases.into_iter().flat_map(|c| [(c, false), (c, true)]) {
        let mut base = PhysicsWorld::new();
        let robot = base.load_mjcf_str(xml, name, &options).unwrap();
        let h = robot.timestep().unwrap_or(0.005);
        let mut alone: Vec<PhysicsWorld> = (0..3).map(|_| base.clone()).collect();
        let mut held: Vec<PhysicsWorld> = (0..3)
            .map(|_| {
                let mut w = PhysicsWorld::new();
                w.copy_state_only(&base);
                w
            })
            .collect();
        let mut worker = PhysicsWorld::new();
        let reactions = |w: &PhysicsWorld| reaction_bits(&robot, w);
        let mut touching = 0;
        for call in 0..60 {
            for i in 0..3 {
                let u: Vec<Real> = (0..n)
                    .map(|j| (0.5 * (call as Real * 0.2 + (i + j) as Real)).sin())
                    .collect();
                robot.set_controls(&mut alone[i], &u).unwrap();
                alone[i].step_many(h, 5).unwrap();
                robot.set_controls(&mut held[i], &u).unwrap();
                if swap {
                    worker.swap_state(&mut held[i]);
                    worker.step_many(h, 5).unwrap();
                    worker.swap_state(&mut held[i]);
                } else {
                    worker.copy_state_from(&held[i]);
                    worker.step_many(h, 5).unwrap();
                    held[i].copy_state_only(&worker);
                }
                let what = format!("{name}, world {i}, call {call}, swap {swap}");
                assert_eq!(state_hash(&held[i]), state_hash(&alone[i]), "{what}");
                assert_eq!(reactions(&held[i]), reactions(&alone[i]), "{what}");
                let contacts = |w: &PhysicsWorld| w.dynamics().contacts().count();
                assert_eq!(contacts(&held[i]), contacts(&alone[i]), "{what}");
                touching += usize::from(contacts(&alone[i]) > 0);
            }
        }
        assert!(
            touching > 30,
            "{name}: they touch the floor ({touching} of 180)"
        );
        for (i, (own, alone)) in held.iter_mut().zip(&mut alone).enumerate() {
            own.step_many(h, 5).unwrap();
            alone.step_many(h, 5).unwrap();
            let what = format!("{name}, world {i} on its own, swap {swap}");
            assert_eq!(state_hash(own), state_hash(alone), "{what}");
            assert_eq!(reactions(own), reactions(alone), "{what}");
        }
    }
}

/// A clone steps on the original's bits after a mesh pair goes away: a box resting on one
/// triangle of a mesh (its pair in a slot made with room for several manifolds, holding one)
/// is lifted off after the clone, and a ball lands on the mesh. The freed slot must go back
/// to the same free list in both (it went by the slot's heap room, which a clone of a
/// one-manifold pair does not carry, so the ball's pair took another slot in the clone), so
/// their snapshots agree byte for byte.
#[test]
fn a_clone_reuses_pair_slots_as_the_original_after_a_mesh_pair_goes() {
    use kea3d::prelude::{Body, Collider, Vec3};
    let mut world = PhysicsWorld::new();
    world.set_gravity([0.0, -9.81, 0.0]).unwrap();
    let ground = Collider::trimesh(
        vec![
            Vec3::new(-4.0, 0.0, -4.0),
            Vec3::new(4.0, 0.0, -4.0),
            Vec3::new(4.0, 0.0, 4.0),
            Vec3::new(-4.0, 0.0, 4.0),
        ],
        vec![[0, 2, 1], [0, 3, 2]],
    );
    world.insert_collider(ground, None).unwrap();
    let block = world
        .insert_body(Body::dynamic().position([2.0, 0.3, -2.0]))
        .unwrap();
    world
        .insert_collider(Collider::cuboid([0.5, 0.25, 0.5]), Some(block))
        .unwrap();
    for _ in 0..30 {
        world.step(1.0 / 60.0).unwrap();
    }
    let manifolds = world.dynamics().contacts().count();
    assert_eq!(manifolds, 1, "the block rests on one triangle");
    let mut copy = world.clone();
    for w in [&mut world, &mut copy] {
        w.set_position(block, [0.0, 20.0, 0.0]).unwrap();
        w.step(1.0 / 60.0).unwrap();
        let ball = w
            .insert_body(Body::dynamic().position([-2.0, 0.5, 2.0]))
            .unwrap();
        w.insert_collider(Collider::ball(0.25), Some(ball)).unwrap();
        for _ in 0..20 {
            w.step(1.0 / 60.0).unwrap();
        }
    }
    let bytes = |w: &PhysicsWorld| w.snapshot().unwrap().to_binary().unwrap();
    assert!(
        bytes(&world) == bytes(&copy),
        "the clone parted from the original"
    );
    assert_eq!(state_hash(&world), state_hash(&copy));
}

/// A batch's way across different worlds: one worker steps every demo scene's held states
/// in turn (two of each, the second pushed apart from the first at every step), trading
/// states with each, and every world comes out on the bits of the same world stepped alone
/// at every step: nothing the worker keeps from one world's step (the solver's orders and
/// factors, the narrow phase's caches, kept trees) changes another's.
#[test]
fn one_worker_steps_every_demo_scenes_states_in_turn_on_their_bits() {
    let mut alone = Vec::new();
    let mut names = Vec::new();
    for (name, scene) in demo_scenes() {
        let world = PhysicsWorld::from_scene(build(&scene).unwrap());
        for copy in 0..2 {
            alone.push(world.clone());
            names.push(format!("{name} #{copy}"));
        }
    }
    let mut held: Vec<PhysicsWorld> = alone
        .iter()
        .map(|w| {
            let mut h = w.clone();
            h.trim_to_state();
            h
        })
        .collect();
    let mut worker = PhysicsWorld::new();
    for step in 0..STEPS {
        for i in 0..alone.len() {
            // The second copy of each scene is pushed: the worlds a worker steps part ways.
            let push = |w: &mut PhysicsWorld| {
                let body = w.body_handles().nth(step % 3);
                if let Some(h) = body {
                    let f = 0.5 * (step as Real * 0.7 + i as Real).sin();
                    w.add_force(h, [f, 0.3 * f, -f]).unwrap();
                }
            };
            if i % 2 == 1 {
                push(&mut alone[i]);
                push(&mut held[i]);
            }
            alone[i].step(DT).unwrap();
            worker.swap_state(&mut held[i]);
            worker.step(DT).unwrap();
            worker.swap_state(&mut held[i]);
            assert_eq!(
                state_hash(&held[i]),
                state_hash(&alone[i]),
                "{} at step {step}",
                names[i]
            );
        }
    }
}
