//! Errors of the collision layer. Like Kea's, each names the argument and the bad value, and a
//! call that returns one has changed nothing.

use thiserror::Error;

/// What went wrong with a collision call.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CollisionError {
    /// An error from the dynamics world (stale body handle, capacity, …).
    #[error(transparent)]
    Kea(#[from] kea::KeaError),
    /// A shape that encloses no volume or is otherwise unusable.
    #[error("degenerate shape: {0}")]
    DegenerateShape(String),
    /// A material id with no entry in the material table.
    #[error("unknown material id {0}: add it to the MaterialTable first")]
    UnknownMaterial(u32),
    /// A collider handle that was removed or never existed.
    #[error(
        "collider handle {index}v{generation} is stale: the collider was removed or never existed"
    )]
    StaleCollider {
        /// The handle's slot index.
        index: u32,
        /// The handle's generation.
        generation: u32,
    },
}

/// Result of a collision call.
pub type CollisionResult<T> = Result<T, CollisionError>;

/// Checks that a number is finite, naming the argument.
pub(crate) fn check_finite(arg: &'static str, v: kea::Real) -> CollisionResult<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(kea::KeaError::NonFinite {
            arg,
            value: format!("{v}"),
        }
        .into())
    }
}

/// Checks that a number is finite and strictly positive, naming the argument.
pub(crate) fn check_positive(arg: &'static str, v: kea::Real) -> CollisionResult<()> {
    check_finite(arg, v)?;
    if v > 0.0 {
        Ok(())
    } else {
        Err(kea::KeaError::OutOfRange {
            arg,
            value: format!("{v}"),
            expected: "must be > 0",
        }
        .into())
    }
}

/// Checks that a number is finite and not negative, naming the argument.
pub(crate) fn check_non_negative(arg: &'static str, v: kea::Real) -> CollisionResult<()> {
    check_finite(arg, v)?;
    if v >= 0.0 {
        Ok(())
    } else {
        Err(kea::KeaError::OutOfRange {
            arg,
            value: format!("{v}"),
            expected: "must be >= 0",
        }
        .into())
    }
}

/// Checks that every component of a vector is finite, naming the argument.
pub(crate) fn check_vec3(arg: &'static str, v: kea::Vec3) -> CollisionResult<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(kea::KeaError::NonFinite {
            arg,
            value: format!("{v}"),
        }
        .into())
    }
}

/// Checks that a quaternion is finite and of unit length (within 1e-3), and normalises it.
pub(crate) fn check_unit_quat(arg: &'static str, q: kea::Quat) -> CollisionResult<kea::Quat> {
    let len = q.length();
    if !q.is_finite() || (len - 1.0).abs() > 1.0e-3 {
        return Err(kea::KeaError::NotUnit {
            arg,
            value: format!("{q}"),
            length: kea::math::wide(len),
        }
        .into());
    }
    Ok(q.normalize())
}
