//! A checked step length.

use crate::error::{check_positive, KeaResult};
use crate::math::Real;

/// A step length that has been checked: finite and positive, s. The one check of `dt` in a
/// pipeline that hands the step to several layers ([`crate::World::step_by`], the collision layer's
/// contact update): made once, passed on, never checked again.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct StepSize(Real);

impl StepSize {
    /// `dt` if it is finite and > 0; otherwise an error naming `dt` and its value.
    pub fn new(dt: Real) -> KeaResult<Self> {
        check_positive("dt", dt).map(Self)
    }

    /// The step, s.
    #[must_use]
    pub fn seconds(self) -> Real {
        self.0
    }
}
