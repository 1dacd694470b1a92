//! MuJoCo as the reference: runs `mujoco_reference.py` with the Python that has `mujoco`,
//! `pybullet` (for `pybullet_data`) and `gymnasium` installed — `KEA_PYTHON`, else `python3`.
//! Without them a test prints SKIPPED and passes, unless `KEA_REQUIRE_REFERENCES=1` (CI sets
//! it), when it fails.

use std::io::Write;
use std::path::PathBuf;
use std::process::Command;

/// Parsed JSON from the script.
pub type Json = serde_json::Value;

fn python() -> String {
    std::env::var("KEA_PYTHON").unwrap_or_else(|_| "python3".to_string())
}

fn script() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/reference/mujoco_reference.py")
}

/// Runs the script with these arguments; `None` (after printing SKIPPED) when the packages
/// are missing and not required.
pub fn run(args: &[&str]) -> Option<Json> {
    let probe = Command::new(python())
        .args(["-c", "import mujoco, pybullet_data, gymnasium"])
        .output();
    let ready = matches!(&probe, Ok(o) if o.status.success());
    if !ready {
        let why = match probe {
            Ok(o) => String::from_utf8_lossy(&o.stderr).into_owned(),
            Err(e) => e.to_string(),
        };
        if std::env::var("KEA_REQUIRE_REFERENCES").is_ok_and(|v| v == "1") {
            panic!("KEA_REQUIRE_REFERENCES=1 but {} cannot import mujoco, pybullet_data and gymnasium: {why}", python());
        }
        // Past the test harness's capture, so that a plain `cargo test` shows it.
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED (no reference engine): {} lacks mujoco, pybullet or gymnasium ({}); \
             `pip install mujoco pybullet gymnasium` or set KEA_PYTHON to a Python that has them",
            python(),
            why.trim().lines().last().unwrap_or("")
        );
        return None;
    }
    let out = Command::new(python())
        .arg(script())
        .args(args)
        .output()
        .expect("the reference script runs");
    assert!(
        out.status.success(),
        "mujoco_reference.py {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(serde_json::from_slice(&out.stdout).expect("the script prints JSON"))
}

/// The installed models' folders.
pub fn model_dirs() -> Option<Json> {
    run(&["paths"])
}

/// Numbers of a JSON array.
pub fn numbers(v: &Json) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}
