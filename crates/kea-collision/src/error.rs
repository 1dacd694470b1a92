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
    /// parry panicked inside a query: the query is refused (nothing changed).
    #[error("`{operation}` failed inside parry on collider {collider}: {message}")]
    Dependency {
        /// The query.
        operation: &'static str,
        /// The collider being tested (slot index and generation).
        collider: String,
        /// parry's panic message.
        message: String,
    },
    /// A query whose work would not be bounded: too many height-field cells along its path.
    #[error("`{operation}` is too long: {reason}")]
    QueryTooLong {
        /// The query.
        operation: &'static str,
        /// What makes it too long.
        reason: String,
    },
}

/// Result of a collision call.
pub type CollisionResult<T> = Result<T, CollisionError>;

/// Smallest and largest size of a shape accepted, m: a radius, a half extent, a half height,
/// a height field's span. Outside it parry's iterative queries lose their footing (segments of
/// zero length, supports beyond f32). Points of hulls and meshes, offsets and heights must lie
/// within the largest size of the origin.
pub const SIZE_RANGE: (kea::Real, kea::Real) = (1.0e-4, 1.0e5);

/// Largest ratio between the largest and smallest size of one primitive shape.
pub const MAX_ASPECT: kea::Real = 1.0e6;

/// Checks that a shape size is finite and within [`SIZE_RANGE`], naming the argument.
pub(crate) fn check_size(arg: &'static str, v: kea::Real) -> CollisionResult<kea::Real> {
    check_finite(arg, v)?;
    if (SIZE_RANGE.0..=SIZE_RANGE.1).contains(&v) {
        Ok(v)
    } else {
        Err(kea::KeaError::OutOfRange {
            arg,
            value: kea::error::format_real(v),
            expected: "must be in [1e-4, 1e5] m (kea_collision::SIZE_RANGE)",
        }
        .into())
    }
}

/// Checks that one primitive's sizes are within [`MAX_ASPECT`] of each other.
pub(crate) fn check_aspect(arg: &'static str, sizes: &[kea::Real]) -> CollisionResult<()> {
    let max = sizes.iter().copied().fold(0.0, kea::Real::max);
    let min = sizes.iter().copied().fold(kea::Real::MAX, kea::Real::min);
    if max <= min * MAX_ASPECT {
        Ok(())
    } else {
        Err(kea::KeaError::OutOfRange {
            arg,
            value: format!("{sizes:?}"),
            expected: "the largest size must be within 1e6 times the smallest (kea_collision::MAX_ASPECT)",
        }
        .into())
    }
}

/// Checks that a point of a shape (or an offset, or a distance setting) is finite and within
/// the largest size of [`SIZE_RANGE`] of the origin, per component.
pub(crate) fn check_extent(arg: &'static str, v: kea::Vec3) -> CollisionResult<()> {
    check_vec3(arg, v)?;
    if v.abs().max_element() <= SIZE_RANGE.1 {
        Ok(())
    } else {
        Err(kea::KeaError::OutOfRange {
            arg,
            value: kea::error::format_vec3(v),
            expected:
                "every component must be within 1e5 m of the origin (kea_collision::SIZE_RANGE)",
        }
        .into())
    }
}

/// Checks that a distance setting (margin, touch distance) is finite, not negative and at most
/// the largest size of [`SIZE_RANGE`].
pub(crate) fn check_distance(arg: &'static str, v: kea::Real) -> CollisionResult<()> {
    check_non_negative(arg, v)?;
    if v <= SIZE_RANGE.1 {
        Ok(())
    } else {
        Err(kea::KeaError::OutOfRange {
            arg,
            value: kea::error::format_real(v),
            expected: "must be in [0, 1e5] m",
        }
        .into())
    }
}

/// Checks that a number is finite, naming the argument.
pub(crate) fn check_finite(arg: &'static str, v: kea::Real) -> CollisionResult<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(kea::KeaError::NonFinite {
            arg,
            value: kea::error::format_real(v),
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
            value: kea::error::format_real(v),
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
            value: kea::error::format_real(v),
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
            value: kea::error::format_vec3(v),
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
