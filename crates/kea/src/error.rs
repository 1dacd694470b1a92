//! Errors returned for bad input. Every fallible call validates before it changes anything, so an
//! `Err` always means the world is exactly as it was before the call.

use thiserror::Error;

/// What went wrong with a call. Each variant names the argument and shows the bad value.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum KeaError {
    /// A number was NaN or infinite.
    #[error("argument `{arg}` must be finite, got {value}")]
    NonFinite {
        /// The argument's name.
        arg: &'static str,
        /// The offending value, formatted.
        value: String,
    },
    /// A number was outside its allowed range.
    #[error("argument `{arg}` = {value} is out of range: {expected}")]
    OutOfRange {
        /// The argument's name.
        arg: &'static str,
        /// The offending value, formatted.
        value: String,
        /// What the argument must satisfy.
        expected: &'static str,
    },
    /// A vector or quaternion that must be unit length was not (or was zero).
    #[error("argument `{arg}` must be unit length (within 1e-3), got {value} of length {length}")]
    NotUnit {
        /// The argument's name.
        arg: &'static str,
        /// The offending value, formatted.
        value: String,
        /// Its length.
        length: f64,
    },
    /// An inertia tensor that is not symmetric positive definite.
    #[error("argument `{arg}` must be a symmetric positive-definite inertia tensor, got {value}: {reason}")]
    BadInertia {
        /// The argument's name.
        arg: &'static str,
        /// The offending matrix, formatted.
        value: String,
        /// Why it was rejected.
        reason: &'static str,
    },
    /// A handle whose object was destroyed (its generation is stale) or never existed.
    #[error(
        "{kind} handle {index}v{generation} is stale: the {kind} was destroyed or never existed"
    )]
    StaleHandle {
        /// "body" or "constraint".
        kind: &'static str,
        /// The handle's slot index.
        index: u32,
        /// The handle's generation.
        generation: u32,
    },
    /// A handle that belongs to another world.
    #[error("{kind} handle {index}v{generation} belongs to world {handle_world}, not to this world {world}")]
    ForeignHandle {
        /// "body" or "constraint".
        kind: &'static str,
        /// The handle's slot index.
        index: u32,
        /// The handle's generation.
        generation: u32,
        /// The world the handle came from.
        handle_world: u32,
        /// The world it was given to.
        world: u32,
    },
    /// Creating the object would take a world past [`crate::MAX_CAPACITY`] of its kind.
    #[error("capacity exceeded: the world holds at most {capacity} {what}")]
    CapacityExceeded {
        /// "bodies" or "constraints".
        what: &'static str,
        /// The capacity.
        capacity: usize,
    },
    /// The constraint exists but is not of the kind the call needs (e.g. a joint given to a
    /// contact accessor).
    #[error("constraint {index}v{generation} is a {actual}, not a {expected}")]
    WrongConstraintKind {
        /// The handle's slot index.
        index: u32,
        /// The handle's generation.
        generation: u32,
        /// The kind the call needs.
        expected: &'static str,
        /// The kind the constraint is.
        actual: &'static str,
    },
    /// A call that is only allowed in some state (e.g. changing bodies of an enabled constraint).
    #[error("invalid state for `{operation}`: {reason}")]
    InvalidState {
        /// The operation attempted.
        operation: &'static str,
        /// Why it is not allowed now.
        reason: &'static str,
    },
    /// The immediate-mode solver was given inconsistent arrays.
    #[error("argument `{arg}` is inconsistent: {reason}")]
    Inconsistent {
        /// The argument's name.
        arg: &'static str,
        /// What is wrong.
        reason: String,
    },
}

/// A number as an error message shows it: plain in the everyday range, in scientific notation
/// beyond it (`1e-40`, not forty zeros).
#[must_use]
pub fn format_real(x: Real) -> String {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1.0e-4..1.0e7).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A vector as an error message shows it (see [`format_real`]).
#[must_use]
pub fn format_vec3(v: Vec3) -> String {
    format!(
        "[{}, {}, {}]",
        format_real(v.x),
        format_real(v.y),
        format_real(v.z)
    )
}

fn format_mat3(m: &Mat3) -> String {
    format!(
        "[{}, {}, {}]",
        format_vec3(m.x_axis),
        format_vec3(m.y_axis),
        format_vec3(m.z_axis)
    )
}

/// Shorthand for results of this crate.
pub type KeaResult<T> = Result<T, KeaError>;

use crate::math::{is_finite3, is_finite_mat3, Mat3, Quat, Real, Vec3, UNIT_TOLERANCE};

/// Checks that a real number is finite.
pub(crate) fn check_finite(arg: &'static str, x: Real) -> KeaResult<Real> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(KeaError::NonFinite {
            arg,
            value: format_real(x),
        })
    }
}

/// Checks that a real number is finite and ≥ 0.
pub(crate) fn check_non_negative(arg: &'static str, x: Real) -> KeaResult<Real> {
    check_finite(arg, x)?;
    if x >= 0.0 {
        Ok(x)
    } else {
        Err(KeaError::OutOfRange {
            arg,
            value: format_real(x),
            expected: "must be >= 0",
        })
    }
}

/// Checks that a real number is finite and > 0: at least the smallest normal number, since a
/// step reads subnormal numbers as zero (`crate::float_mode`).
pub(crate) fn check_positive(arg: &'static str, x: Real) -> KeaResult<Real> {
    check_finite(arg, x)?;
    if x >= Real::MIN_POSITIVE {
        Ok(x)
    } else {
        Err(KeaError::OutOfRange {
            arg,
            value: format_real(x),
            expected: "must be > 0 (and not subnormal: at least the smallest normal number)",
        })
    }
}

/// Checks that a vector is finite.
pub(crate) fn check_vec3(arg: &'static str, v: Vec3) -> KeaResult<Vec3> {
    if is_finite3(v) {
        Ok(v)
    } else {
        Err(KeaError::NonFinite {
            arg,
            value: format_vec3(v),
        })
    }
}

/// Checks that a vector is finite and unit length (within [`UNIT_TOLERANCE`]); returns it
/// renormalised.
pub(crate) fn check_unit(arg: &'static str, v: Vec3) -> KeaResult<Vec3> {
    check_vec3(arg, v)?;
    let len = v.length();
    if (len - 1.0).abs() <= UNIT_TOLERANCE {
        Ok(v / len)
    } else {
        Err(KeaError::NotUnit {
            arg,
            value: format_vec3(v),
            length: crate::math::wide(len),
        })
    }
}

/// Checks that a quaternion is finite and unit length; returns it renormalised.
pub(crate) fn check_quat(arg: &'static str, q: Quat) -> KeaResult<Quat> {
    let finite = q.x.is_finite() && q.y.is_finite() && q.z.is_finite() && q.w.is_finite();
    if !finite {
        return Err(KeaError::NonFinite {
            arg,
            value: format!("{q}"),
        });
    }
    let len = q.length();
    if (len - 1.0).abs() <= UNIT_TOLERANCE {
        Ok(q / len)
    } else {
        Err(KeaError::NotUnit {
            arg,
            value: format!("{q}"),
            length: crate::math::wide(len),
        })
    }
}

/// Smallest and largest body mass accepted, kg. Outside this range `1/m`, or the products the
/// solver forms from it (`m v²`, `J M⁻¹ Jᵀ`), leave the range of f32.
pub const MASS_RANGE: (Real, Real) = (1.0e-9, 1.0e12);

/// Smallest and largest diagonal entry accepted in an inertia tensor, kg·m² (see
/// [`MASS_RANGE`]).
pub const INERTIA_RANGE: (Real, Real) = (1.0e-20, 1.0e20);

/// Largest coordinate accepted for a position or an anchor, m: a million kilometres. Lever
/// arms and their products in the rows stay well inside f32 there.
pub const MAX_COORDINATE: Real = 1.0e9;

/// Checks that a point is finite and each coordinate within [`MAX_COORDINATE`] of the origin.
pub fn check_coordinate(arg: &'static str, v: Vec3) -> KeaResult<Vec3> {
    check_vec3(arg, v)?;
    if v.abs().max_element() > MAX_COORDINATE {
        return Err(KeaError::OutOfRange {
            arg,
            value: format_vec3(v),
            expected:
                "each coordinate must be within 1e9 m of the origin (kea::error::MAX_COORDINATE)",
        });
    }
    Ok(v)
}

/// Checks that a mass is finite and within [`MASS_RANGE`].
pub(crate) fn check_mass(arg: &'static str, mass: Real) -> KeaResult<Real> {
    check_positive(arg, mass)?;
    if !(MASS_RANGE.0..=MASS_RANGE.1).contains(&mass) {
        return Err(KeaError::OutOfRange {
            arg,
            value: format_real(mass),
            expected: "must be in [1e-9, 1e12] kg (kea::error::MASS_RANGE)",
        });
    }
    Ok(mass)
}

/// Checks that an inertia tensor is finite, symmetric, positive definite and of a size within
/// [`INERTIA_RANGE`]; returns its symmetric part and that part's inverse (finite).
pub(crate) fn check_inertia(arg: &'static str, m: Mat3) -> KeaResult<(Mat3, Mat3)> {
    let bad = |reason| KeaError::BadInertia {
        arg,
        value: format_mat3(&m),
        reason,
    };
    if !is_finite_mat3(&m) {
        return Err(bad("it has a NaN or infinite entry"));
    }
    let diagonal = Vec3::new(m.x_axis.x, m.y_axis.y, m.z_axis.z);
    if diagonal.min_element() <= 0.0 {
        return Err(bad("it is not positive definite"));
    }
    let scale = diagonal.max_element();
    if !(INERTIA_RANGE.0..=INERTIA_RANGE.1).contains(&scale) {
        return Err(bad(
            "its largest diagonal entry must be in [1e-20, 1e20] kg·m² (kea::error::INERTIA_RANGE)",
        ));
    }
    // Work on the tensor scaled to a unit diagonal, so that neither the determinant nor the
    // inverse overflows or underflows at the ends of the range.
    let unit = m * (1.0 / scale);
    let asym = (unit.x_axis.y - unit.y_axis.x)
        .abs()
        .max((unit.x_axis.z - unit.z_axis.x).abs())
        .max((unit.y_axis.z - unit.z_axis.y).abs());
    if asym > 1.0e-4 {
        return Err(bad("it is not symmetric"));
    }
    let unit = (unit + unit.transpose()) * 0.5;
    // Sylvester's criterion: every leading principal minor is positive.
    let m1 = unit.x_axis.x;
    let m2 = unit.x_axis.x * unit.y_axis.y - unit.x_axis.y * unit.y_axis.x;
    let m3 = unit.determinant();
    if !(m1 > 0.0 && m2 > 0.0 && m3 > 0.0) {
        return Err(bad("it is not positive definite"));
    }
    let symmetric = (m + m.transpose()) * 0.5;
    // The plain inverse where the determinant is a normal number (as the immediate-mode
    // solver computes it, so both agree bit for bit); the scaled one near the range's ends.
    let inverse = if symmetric.determinant().is_normal() {
        symmetric.inverse()
    } else {
        unit.inverse() * (1.0 / scale)
    };
    if !is_finite_mat3(&inverse) {
        return Err(bad("its inverse is not finite (too nearly singular)"));
    }
    Ok((symmetric, inverse))
}

/// Checks that the unit vector `v` (argument `arg`) is perpendicular, within 1e-3, to `w`;
/// `expected` names `w` in the error.
pub(crate) fn check_perpendicular(
    arg: &'static str,
    v: Vec3,
    w: Vec3,
    expected: &'static str,
) -> KeaResult<()> {
    if v.dot(w).abs() > 1.0e-3 {
        return Err(KeaError::OutOfRange {
            arg,
            value: format!("{v}"),
            expected,
        });
    }
    Ok(())
}
