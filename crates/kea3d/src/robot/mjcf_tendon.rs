//! MJCF's `<tendon>`. A fixed tendon is a weighted sum of joint coordinates; one without
//! stiffness, damping, friction loss or a range applies no force (an actuator on a tendon is
//! refused with the actuators), so it changes nothing Kea steps: it is read, its joints
//! checked, and it is named in the load report. Any other fixed tendon, and every spatial
//! tendon, is refused naming its file, line and element.

use super::mjcf_defaults::{Defaults, MAIN};
use super::spec::RobotSpec;
use super::xml::{children, Source};
use super::ImportError;
use roxmltree::Node;

/// Attributes that make a fixed tendon act.
const ACTING: [&str; 5] = [
    "stiffness",
    "damping",
    "frictionloss",
    "range",
    "springlength",
];

/// Reads every `<tendon>` under `root` (module docs), reporting the force-free fixed ones into
/// `spec.skipped`.
pub(crate) fn read(
    src: &Source<'_>,
    defaults: &Defaults,
    spec: &mut RobotSpec,
    root: Node<'_, '_>,
) -> Result<(), ImportError> {
    for section in children(root, "tendon") {
        for t in section.children().filter(|c| c.is_element()) {
            let el = defaults.element(src, t, MAIN)?;
            let tag = t.tag_name().name();
            if tag != "fixed" {
                return Err(el.error(format!(
                    "<{tag}> tendons are not supported (only fixed tendons that apply no force)"
                )));
            }
            for attr in ACTING {
                let value = el.text(attr);
                let zero = value.is_none_or(|v| v.split_whitespace().all(|x| x.parse() == Ok(0.0)));
                // A range acts only where the tendon is limited.
                let unlimited_range = attr == "range" && el.flag("limited")? == Some(false);
                if !(zero || unlimited_range) {
                    return Err(el.error(format!(
                        "fixed tendon with `{attr}` = {:?}: a tendon that applies force is not supported",
                        value.unwrap_or_default()
                    )));
                }
            }
            if el.flag("limited")? == Some(true) {
                return Err(el.error("a limited tendon is not supported"));
            }
            let name = t.attribute("name").unwrap_or("tendon");
            for j in t.children().filter(|c| c.is_element()) {
                let joint = j.attribute("joint").unwrap_or_default();
                if j.tag_name().name() != "joint"
                    || !spec
                        .joints
                        .iter()
                        .any(|s| s.parts.iter().any(|p| p == joint))
                {
                    return Err(
                        src.error(j, format!("tendon \"{name}\": no joint named \"{joint}\""))
                    );
                }
            }
            spec.skipped.push(format!(
                "{}:{}: fixed tendon \"{name}\": no stiffness, damping, friction or range, so it applies no force (read, not stepped)",
                src.file.display(),
                src.line(t)
            ));
        }
    }
    Ok(())
}
