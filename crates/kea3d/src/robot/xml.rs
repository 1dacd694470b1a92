//! Reading attributes of an XML element as numbers, vectors and names, with errors that name
//! the file, the line and the element.

use super::ImportError;
use kea::{Quat, Real, Vec3};
use roxmltree::{Document, Node};
use std::path::Path;

/// A parsed robot file and where it came from.
pub(crate) struct Source<'a> {
    pub file: &'a Path,
    pub doc: &'a Document<'a>,
}

impl<'a> Source<'a> {
    /// The 1-based line of a node.
    pub fn line(&self, node: Node<'_, '_>) -> u32 {
        self.doc.text_pos_at(node.range().start).row
    }

    /// An error at `node`.
    pub fn error(&self, node: Node<'_, '_>, reason: impl Into<String>) -> ImportError {
        ImportError::Element {
            file: self.file.to_path_buf(),
            line: self.line(node),
            element: describe(node),
            reason: reason.into(),
        }
    }

    /// A required attribute's text.
    pub fn required<'n>(&self, node: Node<'n, '_>, attr: &str) -> Result<&'n str, ImportError> {
        node.attribute(attr)
            .ok_or_else(|| self.error(node, format!("the attribute `{attr}` is missing")))
    }

    /// An attribute's numbers, exactly `N` of them, or `None` without the attribute.
    pub fn numbers<const N: usize>(
        &self,
        node: Node<'_, '_>,
        attr: &str,
    ) -> Result<Option<[Real; N]>, ImportError> {
        let Some(text) = node.attribute(attr) else {
            return Ok(None);
        };
        let values = self.list(node, attr, text)?;
        if values.len() != N {
            return Err(self.error(
                node,
                format!(
                    "`{attr}` = \"{text}\": expected {N} numbers, found {}",
                    values.len()
                ),
            ));
        }
        let mut out = [0.0; N];
        out.copy_from_slice(&values);
        Ok(Some(out))
    }

    /// An attribute's numbers, any count (empty without the attribute).
    pub fn list(
        &self,
        node: Node<'_, '_>,
        attr: &str,
        text: &str,
    ) -> Result<Vec<Real>, ImportError> {
        text.split(|c: char| c.is_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
            .map(|t| {
                t.parse::<Real>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        self.error(
                            node,
                            format!("`{attr}` = \"{text}\": \"{t}\" is not a finite number"),
                        )
                    })
            })
            .collect()
    }

    /// One number, or `None` without the attribute.
    pub fn number(&self, node: Node<'_, '_>, attr: &str) -> Result<Option<Real>, ImportError> {
        Ok(self.numbers::<1>(node, attr)?.map(|[v]| v))
    }

    /// One number, ≥ 0.
    pub fn non_negative(
        &self,
        node: Node<'_, '_>,
        attr: &str,
    ) -> Result<Option<Real>, ImportError> {
        let v = self.number(node, attr)?;
        if let Some(x) = v {
            if x < 0.0 {
                return Err(self.error(node, format!("`{attr}` = {x}: must be >= 0")));
            }
        }
        Ok(v)
    }

    /// A vector attribute.
    pub fn vec3(&self, node: Node<'_, '_>, attr: &str) -> Result<Option<Vec3>, ImportError> {
        Ok(self.numbers::<3>(node, attr)?.map(Vec3::from_array))
    }

    /// A unit direction (normalised; zero refused).
    pub fn direction(&self, node: Node<'_, '_>, attr: &str) -> Result<Option<Vec3>, ImportError> {
        let Some(v) = self.vec3(node, attr)? else {
            return Ok(None);
        };
        let len = v.length();
        if !above(len, 1e-9) {
            return Err(self.error(node, format!("`{attr}` = {v}: a direction cannot be zero")));
        }
        Ok(Some(v / len))
    }
}

/// A robot file's text; text that is not UTF-8 is refused at the line of its first bad byte.
pub(crate) fn read_text(file: &Path) -> Result<String, ImportError> {
    let bytes = std::fs::read(file).map_err(|e| ImportError::file(file, e.to_string()))?;
    String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = 1 + good.iter().filter(|&&b| b == b'\n').count();
        let column = 1 + good.iter().rev().take_while(|&&b| b != b'\n').count();
        let bad = e.as_bytes()[good.len()];
        ImportError::Syntax {
            file: file.to_path_buf(),
            line: line as u32,
            reason: format!(
                "not UTF-8 text: byte 0x{bad:02x} at column {column} (XML files are read as UTF-8)"
            ),
        }
    })
}

/// Deepest element nesting a robot file may have (MuJoCo refuses deep files too): the XML
/// reader and the MJCF body and default-class readers recurse once per level; a robot nests
/// tens of levels; 256 levels load on a 512 KiB thread stack, and deeper files are refused
/// before any reader recurses, on any stack (`tests/mjcf.rs`).
pub(crate) const MAX_NESTING: usize = 256;

/// Parses robot-file text as XML, after checking without recursion that its elements nest
/// at most [`MAX_NESTING`] deep. Errors name the file and the line.
pub(crate) fn parse_document<'a>(text: &'a str, file: &Path) -> Result<Document<'a>, ImportError> {
    check_depth(text, file)?;
    Document::parse(text).map_err(|e| {
        let (line, why) = match e {
            // Where the text ended.
            roxmltree::Error::UnexpectedEndOfStream | roxmltree::Error::UnclosedRootNode => (
                text.lines().count().max(1) as u32,
                " (the text ends inside an element: cut short?)",
            ),
            _ => (e.pos().row, ""),
        };
        ImportError::Syntax {
            file: file.to_path_buf(),
            line,
            reason: format!("not well-formed XML: {e}{why}"),
        }
    })
}

/// Refuses text whose elements nest deeper than [`MAX_NESTING`], at the first element past
/// it, by one pass over the text (comments, CDATA, declarations and quoted attribute values
/// skipped). Malformed text passes here and fails in the reader.
fn check_depth(text: &str, file: &Path) -> Result<(), ImportError> {
    let bytes = text.as_bytes();
    let (mut at, mut depth, mut line) = (0, 0usize, 1u32);
    // Moves `at` past the first `end` from it, counting lines; to the end if there is none.
    let skip_to = |at: &mut usize, line: &mut u32, end: &[u8]| {
        while *at < bytes.len() && !bytes[*at..].starts_with(end) {
            *line += u32::from(bytes[*at] == b'\n');
            *at += 1;
        }
        *at = (*at + end.len()).min(bytes.len());
    };
    while at < bytes.len() {
        let b = bytes[at];
        if b == b'\n' {
            line += 1;
        }
        if b != b'<' {
            at += 1;
            continue;
        }
        let rest = &bytes[at..];
        if rest.starts_with(b"<!--") {
            skip_to(&mut at, &mut line, b"-->");
        } else if rest.starts_with(b"<![CDATA[") {
            skip_to(&mut at, &mut line, b"]]>");
        } else if rest.starts_with(b"<?") {
            skip_to(&mut at, &mut line, b"?>");
        } else if rest.starts_with(b"<!") {
            skip_to(&mut at, &mut line, b">");
        } else if rest.starts_with(b"</") {
            depth = depth.saturating_sub(1);
            skip_to(&mut at, &mut line, b">");
        } else {
            let start = line;
            at += 1;
            let mut quote = None;
            let mut closed = false;
            while at < bytes.len() {
                let c = bytes[at];
                line += u32::from(c == b'\n');
                at += 1;
                match (quote, c) {
                    (Some(q), _) if c == q => quote = None,
                    (Some(_), _) => {}
                    (None, b'"' | b'\'') => quote = Some(c),
                    (None, b'>') => {
                        closed = bytes[at - 2] == b'/';
                        break;
                    }
                    _ => {}
                }
            }
            if !closed {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(ImportError::Syntax {
                        file: file.to_path_buf(),
                        line: start,
                        reason: format!(
                            "elements nest more than {MAX_NESTING} deep: the file is refused"
                        ),
                    });
                }
            }
        }
    }
    Ok(())
}

/// Text as XML readers take it from files written by hand and by tools: an XML declaration
/// that does not open the file (blank lines or a comment before it) blanked out, trailing NUL
/// bytes dropped. Every line keeps its number.
pub(crate) fn tidy(text: &str) -> String {
    let mut out = text.trim_end_matches('\0').to_string();
    if let Some(at) = out.find("<?xml") {
        if at > 0 {
            if let Some(len) = out[at..].find("?>") {
                let blank: String = out[at..at + len + 2]
                    .chars()
                    .map(|c| if c == '\n' { '\n' } else { ' ' })
                    .collect();
                out.replace_range(at..at + len + 2, &blank);
            }
        }
    }
    out
}

/// `tag "name"`, or just `tag`.
pub(crate) fn describe(node: Node<'_, '_>) -> String {
    let tag = node.tag_name().name();
    match node.attribute("name") {
        Some(name) => format!("{tag} \"{name}\""),
        None => tag.to_string(),
    }
}

/// The element children of `node` with this tag.
pub(crate) fn children<'a, 'i>(
    node: Node<'a, 'i>,
    tag: &'static str,
) -> impl Iterator<Item = Node<'a, 'i>> {
    node.children()
        .filter(move |c| c.is_element() && c.tag_name().name() == tag)
}

/// The first element child of `node` with this tag.
pub(crate) fn child<'a, 'i>(node: Node<'a, 'i>, tag: &'static str) -> Option<Node<'a, 'i>> {
    children(node, tag).next()
}

/// Roll, pitch, yaw (fixed axes x, then y, then z: URDF's `rpy`) as a rotation.
pub(crate) fn rpy(r: Real, p: Real, y: Real) -> Quat {
    Quat::from_rotation_z(y) * Quat::from_rotation_y(p) * Quat::from_rotation_x(r)
}

/// `x > floor`, false for NaN: the test every "must be positive" check makes.
pub(crate) fn above(x: Real, floor: Real) -> bool {
    x > floor
}
