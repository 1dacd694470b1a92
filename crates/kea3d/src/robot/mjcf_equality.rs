//! MJCF's `<equality>` constraints that Kea's joints express: `connect` (a point of one body
//! held on another, or on the world) as a ball joint, `weld` (two bodies held as the file
//! poses them) as a fixed joint. They close loops the body tree cannot (a four-bar linkage, a
//! gripper's parallel fingers). `joint`, `tendon` and `flex` equalities, a weld with its own
//! `relpose`, and inactive ones are refused or skipped by name.

use super::model::Robot;
use super::xml::{children, Source};
use super::ImportError;
use crate::{Joint, PhysicsWorld};
use kea::Vec3;
use roxmltree::Node;
use std::path::Path;

/// One equality as the file gives it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct EqualitySpec {
    /// `Some(anchor in body1's frame)` for a connect; `None` for a weld.
    pub anchor: Option<Vec3>,
    pub body1: String,
    /// `None`: the world.
    pub body2: Option<String>,
    /// The element, for errors: `connect` on line 12.
    pub line: u32,
    pub tag: &'static str,
}

/// The file's `<equality>` elements.
pub(crate) fn read(
    src: &Source<'_>,
    root: Node<'_, '_>,
    skipped: &mut Vec<String>,
) -> Result<Vec<EqualitySpec>, ImportError> {
    let mut out = Vec::new();
    for section in children(root, "equality") {
        for e in section.children().filter(|c| c.is_element()) {
            let tag: &'static str = match e.tag_name().name() {
                "connect" => "connect",
                "weld" => "weld",
                other => {
                    return Err(src.error(
                        e,
                        format!("equality <{other}> is not supported (connect and weld are)"),
                    ))
                }
            };
            if e.attribute("active") == Some("false") {
                skipped.push(format!(
                    "{}:{}: inactive <{tag}>: left out",
                    src.file.display(),
                    src.line(e)
                ));
                continue;
            }
            if e.attribute("site1").is_some() || e.attribute("site2").is_some() {
                return Err(src.error(e, "equalities between sites are not supported (bodies are)"));
            }
            let anchor = if tag == "connect" {
                src.required(e, "anchor")?;
                src.vec3(e, "anchor")?
            } else {
                if let Some(r) = e.attribute("relpose") {
                    let values = src.list(e, "relpose", r)?;
                    if values != [0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0] {
                        return Err(src.error(e, "a weld's own `relpose` is not supported: it holds the bodies as the file poses them"));
                    }
                }
                None
            };
            out.push(EqualitySpec {
                anchor,
                body1: src.required(e, "body1")?.to_string(),
                body2: e.attribute("body2").map(str::to_string),
                line: src.line(e),
                tag,
            });
        }
    }
    Ok(out)
}

/// Adds the equalities to `world` as joints between `robot`'s bodies.
pub(crate) fn build(
    world: &mut PhysicsWorld,
    robot: &Robot,
    equalities: &[EqualitySpec],
    file: &Path,
) -> Result<(), ImportError> {
    for e in equalities {
        let element = || format!("{} (line {})", e.tag, e.line);
        let fail = |reason: String| ImportError::Element {
            file: file.to_path_buf(),
            line: e.line,
            element: e.tag.into(),
            reason,
        };
        let index = |name: &str| {
            robot
                .links()
                .iter()
                .position(|l| l.name == name)
                .ok_or_else(|| fail(format!("no body named \"{name}\"")))
        };
        let i1 = index(&e.body1)?;
        let b1 = robot.links()[i1].body;
        let b2 = match &e.body2 {
            Some(name) => Some(robot.links()[index(name)?].body).filter(|_| name != "world"),
            None => None,
        };
        if Some(b1) == b2 {
            return Err(fail(
                "body1 and body2 are one body (welded together)".into(),
            ));
        }
        let wrap = |source: crate::Error| ImportError::World {
            file: file.to_path_buf(),
            line: e.line,
            element: element(),
            source,
        };
        let frame = robot.link_pose(world, i1).map_err(wrap)?;
        match e.anchor {
            Some(a) => world
                .insert_joint(b1, b2, Joint::ball(frame.point(a)))
                .map(|_| ()),
            None => world
                .insert_joint(b1, b2, Joint::fixed(frame.translation))
                .map(|_| ()),
        }
        .map_err(wrap)?;
    }
    Ok(())
}
