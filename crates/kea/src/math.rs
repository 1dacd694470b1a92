//! Numbers and vectors: the guide's `MePrecision.h`.
//!
//! Every real number in the crate is a [`Real`]: `f32` by default, `f64` with the cargo feature
//! `f64`. The vector types are glam's, chosen to match. The exact LCP solver always works in `f64`
//! whatever `Real` is (see [`crate::solver`]).

/// The precision's aliases: `$real` with glam's vector, quaternion and matrix types of it.
macro_rules! precision {
    ($real:ident, $vec3:ty, $quat:ty, $mat3:ty, $mat4:ty, $which:literal) => {
        #[doc = concat!("The crate's real number type (the guide's `MeReal`): `", stringify!($real), "` ", $which, ".")]
        pub type Real = $real;
        /// A 3-vector of [`Real`] (the guide's `MeVector3`).
        pub type Vec3 = $vec3;
        /// A unit quaternion of [`Real`] describing an orientation.
        pub type Quat = $quat;
        /// A 3×3 matrix of [`Real`] (the guide's `MeMatrix3`), column-major.
        pub type Mat3 = $mat3;
        /// A 4×4 matrix of [`Real`] (the guide's `MeMatrix4`), column-major, as renderers expect.
        pub type Mat4 = $mat4;
        /// π in [`Real`].
        pub const PI: Real = std::$real::consts::PI;
    };
}

#[cfg(not(feature = "f64"))]
mod precision {
    precision!(
        f32,
        glam::Vec3,
        glam::Quat,
        glam::Mat3,
        glam::Mat4,
        "by default"
    );
}

#[cfg(feature = "f64")]
mod precision {
    precision!(
        f64,
        glam::DVec3,
        glam::DQuat,
        glam::DMat3,
        glam::DMat4,
        "with the `f64` feature"
    );
}

pub use precision::*;

/// Machine epsilon of [`Real`].
pub const REAL_EPSILON: Real = Real::EPSILON;

/// Tolerance on the length of vectors and quaternions that the API requires to be unit length.
///
/// Inputs within this distance of length 1 are accepted and renormalised; farther ones are an
/// error, because a far-from-unit normal or quaternion is almost always a bug in the caller.
pub const UNIT_TOLERANCE: Real = 1.0e-3;

/// A 3-vector in `f64`, used by the exact solver.
pub type DVec3 = glam::DVec3;

/// Widens a [`Real`] to `f64` (a no-op with the `f64` feature).
#[inline]
#[must_use]
#[allow(clippy::unnecessary_cast)]
pub fn wide(x: Real) -> f64 {
    x as f64
}

/// Converts a [`Vec3`] to `f64` for the exact solver.
#[inline]
#[must_use]
#[allow(clippy::unnecessary_cast)]
pub fn to_f64(v: Vec3) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

/// Converts an `f64` vector back to a [`Vec3`].
#[inline]
#[must_use]
#[allow(clippy::unnecessary_cast)]
pub fn from_f64(v: DVec3) -> Vec3 {
    Vec3::new(v.x as Real, v.y as Real, v.z as Real)
}

/// The skew-symmetric matrix `[a]×` such that `[a]× b = a × b`.
#[inline]
#[must_use]
pub fn cross_matrix(a: Vec3) -> Mat3 {
    Mat3::from_cols(
        Vec3::new(0.0, a.z, -a.y),
        Vec3::new(-a.z, 0.0, a.x),
        Vec3::new(a.y, -a.x, 0.0),
    )
}

/// Two unit vectors that complete `n` (unit) to a right-handed orthonormal basis `(t1, t2, n)`
/// with `t1 × t2 = n`. Continuous away from `n ≈ -z` (the branch of Frisvad / Duff et al.).
#[must_use]
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t1 = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let t2 = Vec3::new(b, sign + n.y * n.y * a, -n.y);
    (t1, t2)
}

/// True when every component of the vector is finite.
#[inline]
#[must_use]
pub fn is_finite3(v: Vec3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

/// True when every entry of the matrix is finite.
#[inline]
#[must_use]
pub fn is_finite_mat3(m: &Mat3) -> bool {
    is_finite3(m.x_axis) && is_finite3(m.y_axis) && is_finite3(m.z_axis)
}

/// Rotates orientation `q` by the finite rotation vector `phi` (axis × angle, world frame):
/// `q' = exp(phi / 2) ⊗ q`, exact for any angle (no small-angle approximation).
#[must_use]
pub fn rotate_by_vector(q: Quat, phi: Vec3) -> Quat {
    let angle = phi.length();
    if angle < 1.0e-12 {
        // Second-order expansion avoids 0/0 and is exact to round-off at this size.
        let dq = Quat::from_xyzw(0.5 * phi.x, 0.5 * phi.y, 0.5 * phi.z, 1.0);
        return (dq * q).normalize();
    }
    (Quat::from_axis_angle(phi / angle, angle) * q).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_right_handed_and_orthonormal() {
        for n in [
            Vec3::Y,
            -Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.3, -0.4, 0.866).normalize(),
        ] {
            let (t1, t2) = orthonormal_basis(n);
            assert!((t1.length() - 1.0).abs() < 1e-5);
            assert!((t2.length() - 1.0).abs() < 1e-5);
            assert!(t1.dot(n).abs() < 1e-5 && t2.dot(n).abs() < 1e-5);
            assert!((t1.cross(t2) - n).length() < 1e-5);
        }
    }

    #[test]
    fn cross_matrix_matches_cross_product() {
        let a = Vec3::new(1.0, -2.0, 3.0);
        let b = Vec3::new(0.5, 4.0, -1.0);
        assert!((cross_matrix(a) * b - a.cross(b)).length() < 1e-5);
    }

    #[test]
    fn rotation_by_vector_is_exact() {
        let q = rotate_by_vector(Quat::IDENTITY, Vec3::new(0.0, 0.0, PI / 2.0));
        assert!((q * Vec3::X - Vec3::Y).length() < 1e-5);
    }
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations (in `f64`):
/// returns the rotation `P` (as a quaternion) and eigenvalues `d` with `m = P diag(d) Pᵀ`.
/// A diagonal input returns the identity at once.
#[must_use]
#[allow(clippy::unnecessary_cast, clippy::needless_range_loop)]
pub fn symmetric_eigen(m: Mat3) -> (Quat, Vec3) {
    let off = m.x_axis.y.abs() + m.x_axis.z.abs() + m.y_axis.z.abs();
    if off == 0.0 {
        return (
            Quat::IDENTITY,
            Vec3::new(m.x_axis.x, m.y_axis.y, m.z_axis.z),
        );
    }
    let mut a = [[0.0f64; 3]; 3];
    for (c, col) in [m.x_axis, m.y_axis, m.z_axis].iter().enumerate() {
        a[0][c] = col.x as f64;
        a[1][c] = col.y as f64;
        a[2][c] = col.z as f64;
    }
    let mut v = [[1.0f64, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..32 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let scale = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1.0e-15 * scale {
            break;
        }
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    // Columns of v are eigenvectors; make the frame right-handed.
    let col = |j: usize| glam::DVec3::new(v[0][j], v[1][j], v[2][j]);
    let (c0, c1) = (col(0), col(1));
    let c2 = c0.cross(c1);
    let rot = glam::DMat3::from_cols(c0, c1, c2);
    let q = glam::DQuat::from_mat3(&rot).normalize();
    (
        Quat::from_xyzw(q.x as Real, q.y as Real, q.z as Real, q.w as Real),
        Vec3::new(a[0][0] as Real, a[1][1] as Real, a[2][2] as Real),
    )
}

#[cfg(test)]
mod eigen_tests {
    use super::*;

    #[test]
    fn eigen_decomposition_reconstructs_the_matrix() {
        let r = Mat3::from_quat(Quat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1));
        let d = Vec3::new(1.0, 2.5, 4.0);
        let m = r * Mat3::from_diagonal(d) * r.transpose();
        let (p, e) = symmetric_eigen(m);
        let pm = Mat3::from_quat(p);
        let back = pm * Mat3::from_diagonal(e) * pm.transpose();
        for (a, b) in [
            (back.x_axis, m.x_axis),
            (back.y_axis, m.y_axis),
            (back.z_axis, m.z_axis),
        ] {
            assert!((a - b).length() < 1e-5, "{back} vs {m}");
        }
    }
}
