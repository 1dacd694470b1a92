//! One scene, every way in: `kea run`, `kea3d`'s `PhysicsWorld` stepped from Rust (what
//! Python's `kea.World.from_scene` steps), and the same world saved halfway to a binary
//! snapshot and restored, end on the same bits: they all step through the one pipeline. The final
//! states' fingerprints are kept in `tests/golden/pipeline_<precision>.txt`, which the Python
//! suite also checks its own run against (`crates/kea-py/tests/test_pipeline.py`).
//!
//! After a deliberate change of results: `KEA_BLESS=1 cargo test -p kea-cli --test pipeline`,
//! and `KEA_BLESS=1 cargo test --workspace --features kea-collision/f64 --test pipeline`.

use kea::Real;
use kea3d::PhysicsWorld;
use kea_scene::{build, Scene, SceneSnapshot};
use std::process::Command;

/// Scenes of every kind the front ends meet: a pile, joints with contacts, keyframed paths,
/// slide contacts, car wheels, hinged balls.
const SCENES: [&str; 6] = [
    "pyramid.json",
    "ragdoll.json",
    "animated_hand.json",
    "conveyor.json",
    "car.json",
    "newtons_cradle.json",
];
const STEPS: usize = 60;
const DT: Real = 1.0 / 60.0;

fn scene_path(name: &str) -> String {
    format!("{}/../../scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// FNV-1a over the bits of each body's position, orientation (x, y, z, w) and velocity as
/// `f64`, bodies in scene order: the same fingerprint Python computes from `World.state()`.
fn fingerprint(rows: &[[f64; 10]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for x in rows.iter().flatten() {
        for byte in x.to_bits().to_le_bytes() {
            h ^= u64::from(byte);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

fn row(p: kea::Vec3, q: kea::Quat, v: kea::Vec3) -> [f64; 10] {
    #[allow(clippy::useless_conversion)]
    let f = |x: Real| f64::from(x);
    [
        f(p.x),
        f(p.y),
        f(p.z),
        f(q.x),
        f(q.y),
        f(q.z),
        f(q.w),
        f(v.x),
        f(v.y),
        f(v.z),
    ]
}

fn load(name: &str) -> PhysicsWorld {
    let text = std::fs::read_to_string(scene_path(name)).unwrap();
    PhysicsWorld::from_scene(build(&Scene::from_json(&text).unwrap()).unwrap())
}

/// Every body's state, in scene order.
fn rows(world: &PhysicsWorld) -> Vec<[f64; 10]> {
    world
        .named_bodies()
        .iter()
        .map(|(_, h)| {
            let b = world.dynamics().body(*h).unwrap();
            row(b.position(), b.orientation(), b.linear_velocity())
        })
        .collect()
}

/// The scene stepped from Rust.
fn from_rust(name: &str) -> Vec<[f64; 10]> {
    let mut world = load(name);
    for _ in 0..STEPS {
        world.step(DT).unwrap();
    }
    rows(&world)
}

/// The scene stepped halfway, saved to the binary snapshot form, restored, and stepped on.
fn from_snapshot(name: &str) -> Vec<[f64; 10]> {
    let mut world = load(name);
    for _ in 0..STEPS / 2 {
        world.step(DT).unwrap();
    }
    let bytes = world.snapshot().unwrap().to_binary().unwrap();
    drop(world);
    let mut world = PhysicsWorld::restore(SceneSnapshot::from_binary(&bytes).unwrap()).unwrap();
    for _ in STEPS / 2..STEPS {
        world.step(DT).unwrap();
    }
    rows(&world)
}

/// The scene run by `kea run --json`: the last sample of every body.
fn from_cli(name: &str) -> Vec<[f64; 10]> {
    let dir = std::env::temp_dir().join(format!("kea-pipeline-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join(name);
    let status = Command::new(env!("CARGO_BIN_EXE_kea"))
        .args(["run", &scene_path(name), "--steps", &STEPS.to_string()])
        .args(["--dt", &DT.to_string(), "--json"])
        .arg(&out)
        .output()
        .expect("kea runs");
    assert!(status.status.success(), "{name}: {status:?}");
    let text = std::fs::read_to_string(&out).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let samples: Vec<serde_json::Value> = serde_json::from_str(&text).unwrap();
    let last_t = samples.last().unwrap()["t"].as_f64().unwrap();
    let number = |v: &serde_json::Value| {
        // Printed from `Real`: read back as `Real`, then widened as the other routes widen.
        #[allow(clippy::useless_conversion, clippy::unnecessary_cast)]
        f64::from(v.as_f64().unwrap() as Real)
    };
    samples
        .iter()
        .filter(|s| s["t"].as_f64() == Some(last_t))
        .map(|s| {
            let mut r = [0.0; 10];
            let fields = ["position", "orientation", "velocity"];
            let values = fields
                .iter()
                .flat_map(|f| s[f].as_array().unwrap().iter().map(number));
            for (x, v) in r.iter_mut().zip(values) {
                *x = v;
            }
            r
        })
        .collect()
}

fn golden_path() -> String {
    let precision = if std::mem::size_of::<Real>() == 8 {
        "f64"
    } else {
        "f32"
    };
    format!(
        "{}/tests/golden/pipeline_{precision}.txt",
        env!("CARGO_MANIFEST_DIR")
    )
}

#[test]
fn a_scene_ends_on_the_same_bits_from_kea_run_from_rust_and_from_a_snapshot() {
    let mut found = String::new();
    for name in SCENES {
        let rust = from_rust(name);
        let restored = from_snapshot(name);
        let cli = from_cli(name);
        assert_eq!(rust.len(), cli.len(), "{name}: bodies");
        assert_eq!(
            fingerprint(&restored),
            fingerprint(&rust),
            "{name}: the restored run and the straight one differ"
        );
        assert_eq!(
            fingerprint(&cli),
            fingerprint(&rust),
            "{name}: `kea run` and Rust differ"
        );
        found.push_str(&format!("{name} {:016x}\n", fingerprint(&rust)));
    }
    let path = golden_path();
    if std::env::var_os("KEA_BLESS").is_some() {
        std::fs::write(&path, &found).unwrap();
    }
    let want = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{path}: {e} (write it with KEA_BLESS=1)"));
    assert_eq!(found, want, "fingerprints changed ({path})");
}
