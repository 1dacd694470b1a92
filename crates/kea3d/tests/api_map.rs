//! `docs/api-map.md` stays true: every `Type::name` it names in code spans is a function or a
//! public field defined somewhere in the workspace's sources (a cheap textual check: `fn name`
//! or `pub name:` exists). glam's types (`Vec3::normalize`) are left to glam.

use std::collections::BTreeSet;
use std::path::Path;

/// Every `.rs` file's text under `dir`.
fn sources(dir: &Path, out: &mut String) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            if !path.ends_with("target") {
                sources(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push_str(&std::fs::read_to_string(&path).unwrap());
        }
    }
}

/// `Type::function` names inside code spans: a capitalised path segment, then a lower-case
/// function name.
fn named_functions(map: &str) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    for (i, span) in map.split('`').enumerate() {
        if i % 2 == 0 {
            continue; // outside a code span
        }
        let cleaned: String = span
            .chars()
            .map(|c| {
                if c.is_alphanumeric() || c == '_' || c == ':' {
                    c
                } else {
                    ' '
                }
            })
            .collect();
        for word in cleaned.split_whitespace() {
            let parts: Vec<&str> = word.split("::").collect();
            if parts.len() < 2 {
                continue;
            }
            let (owner, f) = (parts[parts.len() - 2], parts[parts.len() - 1]);
            let is_type = owner.chars().next().is_some_and(char::is_uppercase);
            let is_fn = f
                .chars()
                .next()
                .is_some_and(|c| c.is_lowercase() || c == '_')
                && f.chars()
                    .all(|c| c.is_lowercase() || c.is_ascii_digit() || c == '_');
            if is_type && is_fn && !f.ends_with('_') {
                names.insert(format!("{owner}::{f}"));
            }
        }
    }
    names
}

#[test]
fn every_function_and_field_the_api_map_names_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let map = std::fs::read_to_string(root.join("docs/api-map.md")).unwrap();
    let mut code = String::new();
    sources(&root.join("crates"), &mut code);
    let names = named_functions(&map);
    assert!(
        names.len() > 50,
        "only {} names found: {names:?}",
        names.len()
    );
    let missing: Vec<&String> = names
        .iter()
        .filter(|name| {
            let f = name.rsplit("::").next().unwrap();
            let glam = ["Vec3", "Quat", "Mat3", "Mat4", "DVec3", "DQuat"]
                .contains(&name.split("::").next().unwrap());
            !(glam
                || code.contains(&format!("fn {f}("))
                || code.contains(&format!("fn {f}<"))
                || code.contains(&format!("pub {f}:")))
        })
        .collect();
    assert!(
        missing.is_empty(),
        "docs/api-map.md names {} functions or fields that do not exist: {missing:?}",
        missing.len()
    );
}
