//! A joint's limits and motor from the scene's form, and kea's errors placed on the scene
//! field they are about.

use crate::error::SceneError;
use crate::joint_format::LimitSpec;
use kea::{KeaError, Limit, Real, SingleLimit};

/// The scene field a kea argument error is about, if it names one.
fn field_of(e: &KeaError) -> Option<&'static str> {
    let arg = match e {
        KeaError::NonFinite { arg, .. }
        | KeaError::OutOfRange { arg, .. }
        | KeaError::NotUnit { arg, .. } => *arg,
        _ => return None,
    };
    Some(match arg {
        "k" | "d" => "suspension",
        "max_force" => "break_force",
        "max_torque" => "break_torque",
        "primary" => "limit_axis",
        other => other,
    })
}

/// A kea error at `place`, or at the field it names.
pub(crate) fn placed(place: &str, e: KeaError) -> SceneError {
    match field_of(&e) {
        Some(f) => SceneError::at(format!("{place}.{f}"), e),
        None => SceneError::at(place, e),
    }
}

/// Sets a [`Limit`]'s stops from the scene's form.
pub(crate) fn set_limits(
    limit: &mut Limit,
    spec: &LimitSpec,
    place: &str,
) -> Result<(), SceneError> {
    let (lower, upper) = match spec {
        LimitSpec::Hard([lo, hi]) => (SingleLimit::hard(*lo, 0.0), SingleLimit::hard(*hi, 0.0)),
        LimitSpec::Stops(s) => match s.stiffness {
            Some(k) => (
                SingleLimit::soft(s.lower, k, s.damping),
                SingleLimit::soft(s.upper, k, s.damping),
            ),
            None => (
                SingleLimit::hard(s.lower, s.restitution),
                SingleLimit::hard(s.upper, s.restitution),
            ),
        },
    };
    limit
        .set_limits(lower, upper)
        .map_err(|e| SceneError::at(place, e))
}

/// Sets a [`Limit`]'s motor `[speed, max force]` if given.
pub(crate) fn set_motor(
    limit: &mut Limit,
    motor: Option<[Real; 2]>,
    place: &str,
) -> Result<(), SceneError> {
    if let Some([speed, force]) = motor {
        limit
            .set_motor(speed, force)
            .map_err(|e| SceneError::at(place, e))?;
    }
    Ok(())
}
