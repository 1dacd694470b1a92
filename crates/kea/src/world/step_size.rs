//! A checked step length.

use crate::error::{check_finite, KeaError, KeaResult};
use crate::math::Real;

/// A step length that has been checked: finite and at least [`StepSize::MIN_SECONDS`], s. The
/// one check of `dt` in a pipeline that hands the step to several layers
/// ([`crate::World::step_by`], the collision layer's contact update): made once, passed on,
/// never checked again.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct StepSize(Real);

impl StepSize {
    /// The shortest step, s: a nanosecond. A step divides `dt` into substeps and squares
    /// them, and reads subnormal numbers as zero (`crate::float_mode`); below this a step's
    /// `h²` could vanish in single precision.
    pub const MIN_SECONDS: Real = 1e-9;

    /// `dt` if it is finite and at least [`StepSize::MIN_SECONDS`]; otherwise an error naming
    /// `dt` and its value.
    pub fn new(dt: Real) -> KeaResult<Self> {
        check_finite("dt", dt)?;
        if dt >= Self::MIN_SECONDS {
            Ok(Self(dt))
        } else {
            Err(KeaError::OutOfRange {
                arg: "dt",
                value: crate::error::format_real(dt),
                expected: "must be at least 1e-9 s",
            })
        }
    }

    /// The step, s.
    #[must_use]
    pub fn seconds(self) -> Real {
        self.0
    }
}
