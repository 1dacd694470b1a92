//! Records the Cargo profile this benchmark was built with (the folder under `target/`), so
//! that its output says whether both engines got the fair build (`bench-lto`).

fn main() {
    let out = std::env::var("OUT_DIR").unwrap_or_default();
    // OUT_DIR is target/[triple/]<profile>/build/<crate>-<hash>/out.
    let parts: Vec<&str> = out.split(std::path::MAIN_SEPARATOR).collect();
    let profile = parts
        .iter()
        .rposition(|p| *p == "build")
        .and_then(|i| i.checked_sub(1))
        .map_or("unknown", |i| parts[i]);
    println!("cargo:rustc-env=KEA_BENCH_PROFILE={profile}");
    println!("cargo:rerun-if-changed=build.rs");
}
