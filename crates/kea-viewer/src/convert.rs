//! Between Kea's numbers (`Real`, f32 or f64, glam 0.33) and macroquad's (f32, its own glam).

use kea::{Real, Vec3};
use macroquad::math as mq;

/// Seconds as f64.
#[allow(clippy::unnecessary_cast)] // Real is f64 in the double-precision build
pub fn to_f64(x: Real) -> f64 {
    x as f64
}

/// An f64 as Real.
#[allow(clippy::unnecessary_cast)]
pub fn to_real(x: f64) -> Real {
    x as Real
}

/// A Kea vector for drawing.
#[allow(clippy::unnecessary_cast)]
pub fn to_mq(v: Vec3) -> mq::Vec3 {
    mq::vec3(v.x as f32, v.y as f32, v.z as f32)
}
