//! MJCF actuators on joints: `motor`, `position` and `velocity`, with their gear, control
//! range and force range, as the file gives them (a `Robot` feeds them in `set_controls`).

use super::mjcf_defaults::{Defaults, MAIN};
use super::spec::RobotSpec;
use super::xml::{children, Source};
use super::ImportError;
use kea::Real;
use roxmltree::Node;

/// What an actuator does with its control.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ActuatorKind {
    /// Force = gear · control.
    Motor,
    /// A servo to position `control`, stiffness `kp`, damping `kv`.
    Position {
        /// Stiffness.
        kp: Real,
        /// Damping.
        kv: Real,
    },
    /// A servo to velocity `control`, gain `kv`.
    Velocity {
        /// Gain.
        kv: Real,
    },
}

/// An actuator as the file gives it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ActuatorSpec {
    /// Its name (or `actuator<N>`).
    pub name: String,
    /// The joint it drives, by the file's name.
    pub joint: String,
    /// What it does.
    pub kind: ActuatorKind,
    /// Gear ratio (the first entry of `gear`).
    pub gear: Real,
    /// The control's range, where limited.
    pub ctrl_range: Option<(Real, Real)>,
    /// The force's range, where limited.
    pub force_range: Option<(Real, Real)>,
}

/// The file's `<actuator>` elements on joints of `spec`.
pub(crate) fn read(
    src: &Source<'_>,
    defaults: &Defaults,
    spec: &RobotSpec,
    root: Node<'_, '_>,
) -> Result<Vec<ActuatorSpec>, ImportError> {
    let mut out = Vec::new();
    for section in children(root, "actuator") {
        for a in section.children().filter(|c| c.is_element()) {
            let el = defaults.element(src, a, MAIN)?;
            let tag = a.tag_name().name();
            let kind = match tag {
                "motor" => ActuatorKind::Motor,
                "position" => ActuatorKind::Position {
                    kp: el.number("kp")?.unwrap_or(1.0),
                    kv: el.number("kv")?.unwrap_or(0.0),
                },
                "velocity" => ActuatorKind::Velocity {
                    kv: el.number("kv")?.unwrap_or(1.0),
                },
                other => {
                    return Err(el.error(format!(
                        "actuator <{other}> is not supported (motor, position, velocity)"
                    )))
                }
            };
            let Some(joint) = a.attribute("joint") else {
                return Err(el.error("only actuators on a `joint` are supported"));
            };
            if !spec
                .joints
                .iter()
                .any(|j| j.parts.iter().any(|p| p == joint))
            {
                return Err(el.error(format!("no joint named \"{joint}\"")));
            }
            let range = |attr: &str, flag: &str| -> Result<Option<(Real, Real)>, ImportError> {
                let r = el.numbers::<2>(attr)?;
                let on = el.flag(flag)?.unwrap_or(r.is_some());
                match (on, r) {
                    (true, Some([lo, hi])) if lo <= hi => Ok(Some((lo, hi))),
                    (true, Some([lo, hi])) => {
                        Err(el.error(format!("`{attr}` = {lo} {hi}: lower must not exceed upper")))
                    }
                    (true, None) => Err(el.error(format!("{flag}=\"true\" needs `{attr}`"))),
                    (false, _) => Ok(None),
                }
            };
            let gear = el.up_to::<6>("gear")?.map(|(g, _)| g[0]).unwrap_or(1.0);
            if gear == 0.0 {
                return Err(el.error("`gear` = 0 drives nothing"));
            }
            out.push(ActuatorSpec {
                name: a
                    .attribute("name")
                    .map(str::to_string)
                    .unwrap_or_else(|| format!("actuator{}", out.len())),
                joint: joint.to_string(),
                kind,
                gear,
                ctrl_range: range("ctrlrange", "ctrllimited")?,
                force_range: range("forcerange", "forcelimited")?,
            });
        }
    }
    Ok(out)
}
