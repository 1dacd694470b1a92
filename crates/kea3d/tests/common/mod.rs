//! What the scene tests share: the demo scene files.

/// Every demo scene file in `scenes/`, sorted by name.
pub fn demo_scene_paths() -> Vec<std::path::PathBuf> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .expect("scenes/ exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    files
}
