//! `docs/api-map.md` stays true: every `Type::name` it names in code spans is a method,
//! associated function or public field of that type (or a method of that trait) somewhere in
//! the workspace's sources, found by parsing them (`syn`). glam's types (`Vec3::normalize`)
//! are left to glam.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Every `.rs` file's text under `dir`.
fn sources(dir: &Path, out: &mut Vec<String>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            if !path.ends_with("target") {
                sources(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(std::fs::read_to_string(&path).unwrap());
        }
    }
}

/// The last segment of a type's path (`kea::World` → `World`).
fn type_name(ty: &syn::Type) -> Option<String> {
    match ty {
        syn::Type::Path(p) => p.path.segments.last().map(|s| s.ident.to_string()),
        _ => None,
    }
}

/// The renames of `use … as …` items: (new name, original name).
fn renames(tree: &syn::UseTree, out: &mut Vec<(String, String)>) {
    match tree {
        syn::UseTree::Path(p) => renames(&p.tree, out),
        syn::UseTree::Rename(r) => out.push((r.rename.to_string(), r.ident.to_string())),
        syn::UseTree::Group(g) => g.items.iter().for_each(|t| renames(t, out)),
        _ => {}
    }
}

/// Each type's (and trait's) methods, associated functions and public fields, and the
/// renames of `use` items.
fn collect_members(
    items: &[syn::Item],
    out: &mut BTreeMap<String, BTreeSet<String>>,
    aliases: &mut Vec<(String, String)>,
) {
    for item in items {
        match item {
            syn::Item::Use(u) => renames(&u.tree, aliases),
            syn::Item::Impl(i) => {
                let Some(owner) = type_name(&i.self_ty) else {
                    continue;
                };
                for member in &i.items {
                    if let syn::ImplItem::Fn(f) = member {
                        out.entry(owner.clone())
                            .or_default()
                            .insert(f.sig.ident.to_string());
                    }
                }
            }
            syn::Item::Struct(s) => {
                for field in &s.fields {
                    if let (Some(name), syn::Visibility::Public(_)) = (&field.ident, &field.vis) {
                        out.entry(s.ident.to_string())
                            .or_default()
                            .insert(name.to_string());
                    }
                }
            }
            syn::Item::Trait(t) => {
                for member in &t.items {
                    if let syn::TraitItem::Fn(f) = member {
                        out.entry(t.ident.to_string())
                            .or_default()
                            .insert(f.sig.ident.to_string());
                    }
                }
            }
            syn::Item::Mod(m) => {
                if let Some((_, inner)) = &m.content {
                    collect_members(inner, out, aliases);
                }
            }
            _ => {}
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
fn every_function_and_field_the_api_map_names_exists_on_its_type() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let map = std::fs::read_to_string(root.join("docs/api-map.md")).unwrap();
    let mut files = Vec::new();
    sources(&root.join("crates"), &mut files);
    let (mut members, mut aliases) = (BTreeMap::new(), Vec::new());
    for text in &files {
        let file = syn::parse_file(text).expect("the workspace's sources parse");
        collect_members(&file.items, &mut members, &mut aliases);
    }
    // A type re-exported under another name (`pub use kea::JointSpec as Joint`) has its
    // members under both.
    for (alias, original) in aliases {
        let of_original = members.get(&original).cloned().unwrap_or_default();
        members.entry(alias).or_default().extend(of_original);
    }
    let names = named_functions(&map);
    assert!(
        names.len() > 50,
        "only {} names found: {names:?}",
        names.len()
    );
    let missing: Vec<&String> = names
        .iter()
        .filter(|name| {
            let (owner, f) = name.split_once("::").unwrap();
            let glam = ["Vec3", "Quat", "Mat3", "Mat4", "DVec3", "DQuat"].contains(&owner);
            !(glam || members.get(owner).is_some_and(|m| m.contains(f)))
        })
        .collect();
    assert!(
        missing.is_empty(),
        "docs/api-map.md names {} functions or fields that are not on the type it names: \
         {missing:?}",
        missing.len()
    );
}
