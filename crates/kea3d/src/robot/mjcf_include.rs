//! MJCF's `<include file="…"/>`: the included file's `<mujoco>` children spliced in where the
//! element stood (dm_control's suite includes its skybox, visual and materials files this
//! way). The included text is joined onto the include's own line, so that every line of the
//! including file keeps its number in errors; an error inside included text names the line of
//! the include. Includes nest up to [`MAX_DEPTH`] deep; a file including itself is refused.

use super::ImportError;
use std::path::{Path, PathBuf};

/// How deep includes may nest.
const MAX_DEPTH: usize = 8;

/// `text` (of `file`) with every `<include>` replaced by what it includes.
pub(crate) fn expand(text: &str, file: &Path) -> Result<String, ImportError> {
    expand_at(text, file, &mut vec![file.to_path_buf()])
}

fn expand_at(text: &str, file: &Path, chain: &mut Vec<PathBuf>) -> Result<String, ImportError> {
    if !text.contains("<include") {
        return Ok(text.to_string());
    }
    let doc = super::xml::parse_document(text, file)?;
    let mut out = String::with_capacity(text.len());
    let mut at = 0;
    for node in doc
        .descendants()
        .filter(|n| n.is_element() && n.tag_name().name() == "include")
    {
        let line = doc.text_pos_at(node.range().start).row;
        let fail = |reason: String| ImportError::Element {
            file: file.to_path_buf(),
            line,
            element: "include".into(),
            reason,
        };
        let name = node
            .attribute("file")
            .ok_or_else(|| fail("the attribute `file` is missing".into()))?;
        let path = file.parent().unwrap_or(Path::new(".")).join(name);
        if chain.iter().any(|p| p == &path) || chain.len() > MAX_DEPTH {
            return Err(fail(format!(
                "\"{name}\" includes itself, or includes nest past {MAX_DEPTH}"
            )));
        }
        if let Err(e) = std::fs::metadata(&path) {
            return Err(fail(format!("\"{name}\" cannot be read: {e}")));
        }
        let included = super::xml::read_text(&path)?;
        chain.push(path.clone());
        let included = expand_at(&included, &path, chain)?;
        chain.pop();
        let inner = children_of_root(&included).ok_or_else(|| {
            fail(format!(
                "\"{name}\" is not an MJCF file (its root element is not <mujoco>)"
            ))
        })?;
        out.push_str(&text[at..node.range().start]);
        out.push_str(&inner.replace(['\n', '\r'], " "));
        at = node.range().end;
    }
    out.push_str(&text[at..]);
    Ok(out)
}

/// The text between an MJCF file's `<mujoco …>` and `</mujoco>`.
fn children_of_root(text: &str) -> Option<String> {
    let doc = super::xml::parse_document(text, Path::new("")).ok()?;
    let root = doc.root_element();
    if root.tag_name().name() != "mujoco" {
        return None;
    }
    let first = root.first_child()?.range().start;
    let last = root.last_child()?.range().end;
    Some(text[first..last].to_string())
}
