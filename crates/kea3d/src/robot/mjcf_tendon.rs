//! MJCF's `<tendon>`. A fixed tendon is a weighted sum of joint coordinates
//! (`<joint joint="…" coef="…"/>`, hinges and slides); its `stiffness`, `damping`,
//! `springlength` (one length or a dead band of two; MuJoCo's default, the length at the
//! joints' `springref`), and `range` (limited by `limited`, or by `autolimits` where a range is
//! given) with its `solreflimit`, `solimplimit` and `margin` go into the robot as a
//! [`kea::FixedTendon`] (`build.rs`). One with none of these applies no force: it is read, its
//! joints checked, and named in the load report. What Kea does not simulate is refused
//! naming file, line and element: spatial tendons, a tendon's `frictionloss` and `armature`,
//! polynomial stiffness or damping (more than one number).

use super::mjcf_defaults::{Defaults, Element, MAIN};
use super::spec::{RobotSpec, TendonSpec};
use super::xml::{children, Source};
use super::ImportError;
use kea::Real;
use roxmltree::Node;

/// Reads every `<tendon>` under `root` (module docs) into `spec.tendons`, reporting the
/// force-free fixed ones into `spec.skipped`. `auto_limits`: the compiler's `autolimits`.
pub(crate) fn read(
    src: &Source<'_>,
    defaults: &Defaults,
    auto_limits: bool,
    spec: &mut RobotSpec,
    root: Node<'_, '_>,
) -> Result<(), ImportError> {
    for section in children(root, "tendon") {
        for t in section.children().filter(|c| c.is_element()) {
            let mut el = defaults.element(src, t, MAIN)?;
            // `<default><tendon …/>` serves both kinds of tendon.
            el.tag = "tendon";
            let tag = t.tag_name().name();
            if tag != "fixed" {
                return Err(el.error(format!(
                    "<{tag}> tendons are not supported (only fixed tendons)"
                )));
            }
            for attr in ["frictionloss", "armature"] {
                let v = el.non_negative(attr)?;
                if v != 0.0 {
                    return Err(el.error(format!(
                        "fixed tendon with `{attr}` = {v}: a tendon's {attr} is not simulated"
                    )));
                }
            }
            let name = t.attribute("name").unwrap_or("tendon").to_string();
            let tendon = TendonSpec {
                line: src.line(t),
                terms: terms(src, spec, t, &name)?,
                stiffness: polynomial(&el, "stiffness")?,
                damping: polynomial(&el, "damping")?,
                spring_length: spring_length(&el)?,
                range: range(&el, auto_limits)?,
                soft: super::mjcf_soft::soft_limit(&el)?.unwrap_or_default(),
                name,
            };
            let passive = tendon.stiffness == 0.0 && tendon.damping == 0.0;
            if passive && tendon.range.is_none() {
                spec.skipped.push(format!(
                    "{}:{}: fixed tendon \"{}\": no stiffness, damping or range, so it applies no force (read, not stepped)",
                    src.file.display(),
                    tendon.line,
                    tendon.name
                ));
            } else {
                spec.tendons.push(tendon);
            }
        }
    }
    Ok(())
}

/// The tendon's joints and coefficients; a joint that is not a hinge or slide of the file
/// is refused.
fn terms(
    src: &Source<'_>,
    spec: &RobotSpec,
    t: Node<'_, '_>,
    name: &str,
) -> Result<Vec<(String, Real)>, ImportError> {
    let mut out = Vec::new();
    for j in t.children().filter(|c| c.is_element()) {
        let joint = j.attribute("joint").unwrap_or_default();
        let known = spec.joints.iter().any(|s| {
            s.parts.iter().any(|p| p == joint)
                && !matches!(
                    s.kind,
                    super::JointType::Ball | super::JointType::Free | super::JointType::Fixed
                )
        });
        if j.tag_name().name() != "joint" || !known {
            return Err(src.error(
                j,
                format!("tendon \"{name}\": no hinge or slide joint named \"{joint}\""),
            ));
        }
        let coef = match j.attribute("coef") {
            None => 1.0,
            Some(text) => match src.list(j, "coef", text)?.as_slice() {
                [c] => *c,
                _ => return Err(src.error(j, format!("`coef` = \"{text}\": expected one number"))),
            },
        };
        out.push((joint.to_string(), coef));
    }
    if out.is_empty() {
        return Err(src.error(t, format!("tendon \"{name}\" has no joint")));
    }
    Ok(out)
}

/// `stiffness` or `damping`: MuJoCo 4 reads a polynomial; Kea its linear term alone.
fn polynomial(el: &Element<'_>, attr: &str) -> Result<Real, ImportError> {
    let Some((values, n)) = el.up_to::<4>(attr)? else {
        return Ok(0.0);
    };
    if values[1..n].iter().any(|&v| v != 0.0) {
        return Err(el.error(format!(
            "`{attr}` with {n} numbers: a polynomial tendon {attr} is not simulated (one number)"
        )));
    }
    if !(values[0] >= 0.0 && values[0].is_finite()) {
        return Err(el.error(format!("`{attr}` = {}: must be finite and >= 0", values[0])));
    }
    Ok(values[0])
}

/// `springlength`: one length or a dead band; `None` (MuJoCo's default, −1) where unset.
fn spring_length(el: &Element<'_>) -> Result<Option<[Real; 2]>, ImportError> {
    let Some((values, n)) = el.up_to::<2>("springlength")? else {
        return Ok(None);
    };
    let band = if n == 1 { [values[0]; 2] } else { values };
    if band == [-1.0, -1.0] {
        return Ok(None);
    }
    if band[0] > band[1] {
        return Err(el.error(format!(
            "`springlength` = {} {}: the first must not exceed the second",
            band[0], band[1]
        )));
    }
    Ok(Some(band))
}

/// The range, where the tendon is limited (`limited`, or `autolimits` with a range).
fn range(el: &Element<'_>, auto_limits: bool) -> Result<Option<[Real; 2]>, ImportError> {
    let range = el.numbers::<2>("range")?;
    let limited = el
        .flag("limited")?
        .unwrap_or(auto_limits && range.is_some());
    match (limited, range) {
        (true, Some([lo, hi])) if lo < hi => Ok(Some([lo, hi])),
        (true, Some([lo, hi])) => {
            Err(el.error(format!("`range` = {lo} {hi}: lower must be below upper")))
        }
        (true, None) => Err(el.error("limited=\"true\" needs a `range`")),
        (false, _) => Ok(None),
    }
}
