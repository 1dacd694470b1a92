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
