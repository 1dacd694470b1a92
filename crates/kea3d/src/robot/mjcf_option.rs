//! MJCF's `<option>`: the step the file asks for (`timestep`), its integrator and gravity
//! become the world's defaults on load; every other attribute and `<flag>` that would change
//! the physics and Kea does not model is named in the robot's load report, never dropped
//! silently. A bad value (a step ≤ 0, an unknown integrator, a non-finite gravity) is refused
//! with its file, line and element.

use super::xml::{above, children, Source};
use super::ImportError;
use kea::{Integrator, Real, Vec3};
use roxmltree::Node;

/// What a model's `<option>` elements set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MjcfOption {
    /// Gravity, m/s² (MuJoCo's default: −9.81 along z).
    pub gravity: Vec3,
    /// The file's step, s (MuJoCo's default, 2 ms, when it gives none).
    pub timestep: Option<Real>,
    /// Its integrator (MuJoCo's default: Euler).
    pub integrator: Integrator,
    /// Whether it asked for `implicitfast` (Kea's Euler, but its lone free bodies stay on the
    /// free-body path, whose implicit gyroscopic step keeps a fast spin bounded as MuJoCo's
    /// `implicitfast` does).
    pub implicitfast: bool,
}

/// Attributes Kea reads, or that change nothing it steps.
const MODELLED: [&str; 4] = ["timestep", "integrator", "gravity", "apirate"];

/// `<flag>` settings Kea follows (contacts off: every geometry stops colliding).
const MODELLED_FLAGS: [(&str, &str); 1] = [("contact", "disable")];

/// Reads every `<option>` under `root`, reporting what is not modelled into `skipped`.
pub(crate) fn read(
    src: &Source<'_>,
    root: Node<'_, '_>,
    skipped: &mut Vec<String>,
) -> Result<MjcfOption, ImportError> {
    let mut out = MjcfOption {
        gravity: Vec3::new(0.0, 0.0, -9.81),
        // MuJoCo's defaults where the file names none.
        timestep: Some(0.002),
        integrator: Integrator::Euler,
        implicitfast: false,
    };
    for o in children(root, "option") {
        if let Some(g) = src.vec3(o, "gravity")? {
            out.gravity = g;
        }
        if let Some(t) = src.number(o, "timestep")? {
            if !above(t, 0.0) {
                return Err(src.error(o, format!("`timestep` = {t}: must be > 0")));
            }
            out.timestep = Some(t);
        }
        if let Some(name) = o.attribute("integrator") {
            out.implicitfast = name == "implicitfast";
            out.integrator = Integrator::from_mujoco(name).ok_or_else(|| {
                src.error(
                    o,
                    format!(
                        "`integrator` = {:?}: expected Euler, RK4, implicit or implicitfast",
                        excerpt(name)
                    ),
                )
            })?;
        }
        for a in o.attributes() {
            if !MODELLED.contains(&a.name()) {
                skipped.push(format!(
                    "<option {}=\"{}\"> (line {}): not modelled by Kea",
                    a.name(),
                    excerpt(a.value()),
                    src.line(o)
                ));
            }
        }
        for flag in children(o, "flag") {
            for a in flag.attributes() {
                if !MODELLED_FLAGS.contains(&(a.name(), a.value())) {
                    skipped.push(format!(
                        "<flag {}=\"{}\"> (line {}): not modelled by Kea",
                        a.name(),
                        excerpt(a.value()),
                        src.line(flag)
                    ));
                }
            }
        }
    }
    Ok(out)
}

/// At most 40 characters of a value, for a message.
fn excerpt(value: &str) -> String {
    match value.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &value[..i]),
        None => value.to_string(),
    }
}
