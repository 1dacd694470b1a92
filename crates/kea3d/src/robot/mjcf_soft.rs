//! MuJoCo's soft-constraint parameters as an MJCF file gives them: a joint's stops
//! (`solreflimit`, `solimplimit`, `margin`) and a geom's contacts (`solref`, `solimp`), read
//! into a [`kea::SoftLimit`], MuJoCo's defaults where absent, a bad value refused by element.

use super::mjcf_defaults::Element;
use super::ImportError;
use kea::{Real, SoftLimit};

/// A joint's stops as MuJoCo makes them: soft, by its `solreflimit`, `solimplimit` (3 or 5
/// numbers) and `margin`, MuJoCo's defaults where absent.
pub(crate) fn soft_limit(el: &Element<'_>) -> Result<Option<SoftLimit>, ImportError> {
    let mut s = SoftLimit::default();
    if let Some(r) = solref(el, "solreflimit")? {
        s.solref = r;
    }
    if let Some(i) = solimp(el, "solimplimit")? {
        s.solimp = i;
    }
    s.margin = el.non_negative("margin")?;
    s.validate()
        .map_err(|e| refused(el, e, ["solreflimit", "solimplimit"]))?;
    Ok(Some(s))
}

/// A geom's contact parameters (`solref`, `solimp`), `None` when it gives neither.
pub(crate) fn contact_model(el: &Element<'_>) -> Result<Option<SoftLimit>, ImportError> {
    let (r, i) = (solref(el, "solref")?, solimp(el, "solimp")?);
    if r.is_none() && i.is_none() {
        return Ok(None);
    }
    let mut s = SoftLimit::default();
    if let Some(r) = r {
        s.solref = r;
    }
    if let Some(i) = i {
        s.solimp = i;
    }
    s.validate()
        .map_err(|e| refused(el, e, ["solref", "solimp"]))?;
    Ok(Some(s))
}

/// A `solref`-like attribute in MuJoCo's positive (time constant, damping ratio) form.
fn solref(el: &Element<'_>, attr: &str) -> Result<Option<[Real; 2]>, ImportError> {
    match el.numbers::<2>(attr)? {
        Some(r) if r[0] <= 0.0 => Err(el.error(format!(
            "`{attr}` = {} {}: Kea reads MuJoCo's positive (time constant, damping ratio) form",
            r[0], r[1]
        ))),
        r => Ok(r),
    }
}

/// A `solimp`-like attribute (3 or 5 numbers), its impedances clamped into (0, 1) as MuJoCo
/// clamps them.
fn solimp(el: &Element<'_>, attr: &str) -> Result<Option<[Real; 5]>, ImportError> {
    let imp = match el.numbers::<5>(attr) {
        Ok(v) => v,
        Err(five) => match el.numbers::<3>(attr) {
            Ok(v) => v.map(|[a, b, c]| [a, b, c, 0.5, 2.0]),
            Err(_) => return Err(five),
        },
    };
    Ok(imp.map(|i| {
        [
            i[0].clamp(1e-4, 0.9999),
            i[1].clamp(1e-4, 0.9999),
            i[2],
            i[3],
            i[4],
        ]
    }))
}

/// A soft model's refusal in the file's terms: the attribute (`names`: the element's `solref`
/// and `solimp` names) and which of its numbers, rather than the API's argument.
fn refused(el: &Element<'_>, e: kea::KeaError, [solref, solimp]: [&str; 2]) -> ImportError {
    match e {
        kea::KeaError::OutOfRange {
            arg,
            value,
            expected,
        } => {
            let (attr, part) = match arg.split_once('[') {
                Some(("solref", rest)) => (solref, rest.trim_end_matches(']')),
                Some(("solimp", rest)) => (solimp, rest.trim_end_matches(']')),
                _ => (arg, ""),
            };
            let which = if part.is_empty() {
                String::new()
            } else {
                format!(" (number {part})")
            };
            el.error(format!("`{attr}`{which} = {value}: {expected}"))
        }
        other => el.error(other.to_string()),
    }
}
