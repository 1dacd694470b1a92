//! Rewrites scene files in the canonical form that `Scene::to_json` writes (fixed field order,
//! defaults omitted, two-space indentation), after checking that each one builds.
//!
//! Run: `cargo run -p kea-scene --example canonicalize -- scenes/*.json`

fn main() {
    let mut failed = false;
    for path in std::env::args().skip(1) {
        let result = std::fs::read_to_string(&path)
            .map_err(|e| e.to_string())
            .and_then(|text| kea_scene::Scene::from_json(&text).map_err(|e| e.to_string()))
            .and_then(|scene| {
                kea_scene::build(&scene).map_err(|e| e.to_string())?;
                std::fs::write(&path, scene.to_json()).map_err(|e| e.to_string())
            });
        match result {
            Ok(()) => println!("{path}: ok"),
            Err(e) => {
                eprintln!("{path}: {e}");
                failed = true;
            }
        }
    }
    std::process::exit(i32::from(failed));
}
