//! Kea's `Real` vectors, quaternions and matrices to the tree's `f64` ones and back.

use crate::math::{Mat3, Quat, Real, Vec3};
use glam::{DMat3, DQuat, DVec3};

#[allow(clippy::unnecessary_cast)]
pub(super) fn d3(v: Vec3) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

#[allow(clippy::unnecessary_cast)]
pub(super) fn v3(v: DVec3) -> Vec3 {
    Vec3::new(v.x as Real, v.y as Real, v.z as Real)
}

#[allow(clippy::unnecessary_cast)]
pub(super) fn dq(q: Quat) -> DQuat {
    DQuat::from_xyzw(q.x as f64, q.y as f64, q.z as f64, q.w as f64).normalize()
}

#[allow(clippy::unnecessary_cast)]
pub(super) fn rq(q: DQuat) -> Quat {
    Quat::from_xyzw(q.x as Real, q.y as Real, q.z as Real, q.w as Real).normalize()
}

pub(super) fn dm(m: Mat3) -> DMat3 {
    DMat3::from_cols(d3(m.x_axis), d3(m.y_axis), d3(m.z_axis))
}
