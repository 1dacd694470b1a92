//! Whether a file's inertia tensor can belong to a body: finite, symmetric positive
//! semi-definite, and its principal moments `A ≤ B ≤ C` meeting the triangle inequality
//! `A + B ≥ C` (every real mass distribution does; MuJoCo refuses tensors that do not).

use kea::{Mat3, Real};

/// Relative slack on both tests, for tensors rounded in the file.
const SLACK: f64 = 1e-6;

/// What is wrong with `inertia`, if anything: `Err(reason)` for a tensor no body can have
/// (not positive semi-definite), `Ok(Some(note))` for one breaking only the triangle
/// inequality, `Ok(None)` for a good one.
pub(crate) fn check(inertia: Mat3) -> Result<Option<String>, String> {
    let [a, b, c] = principal_moments(inertia);
    let scale = c.abs().max(f64::MIN_POSITIVE);
    if a < -SLACK * scale {
        return Err(format!(
            "the inertia's principal moments are {a:.6e}, {b:.6e}, {c:.6e}: a negative one \
             (the tensor is not positive semi-definite)"
        ));
    }
    if a + b < c * (1.0 - SLACK) {
        return Ok(Some(format!(
            "the inertia's principal moments {a:.6e} + {b:.6e} < {c:.6e}: no mass distribution \
             has them (A + B >= C)"
        )));
    }
    Ok(None)
}

/// The eigenvalues of symmetric `m`, ascending (the closed form for 3×3 symmetric matrices,
/// in f64).
pub(crate) fn principal_moments(m: Mat3) -> [f64; 3] {
    let e = |c: usize, r: usize| wide(m.col(c)[r]);
    let (a11, a22, a33) = (e(0, 0), e(1, 1), e(2, 2));
    // Symmetrised off-diagonals.
    let a12 = 0.5 * (e(1, 0) + e(0, 1));
    let a13 = 0.5 * (e(2, 0) + e(0, 2));
    let a23 = 0.5 * (e(2, 1) + e(1, 2));
    let p1 = a12 * a12 + a13 * a13 + a23 * a23;
    let mut out = if p1 == 0.0 {
        [a11, a22, a33]
    } else {
        let q = (a11 + a22 + a33) / 3.0;
        let p2 = (a11 - q).powi(2) + (a22 - q).powi(2) + (a33 - q).powi(2) + 2.0 * p1;
        let p = (p2 / 6.0).sqrt();
        let (b11, b22, b33) = ((a11 - q) / p, (a22 - q) / p, (a33 - q) / p);
        let (b12, b13, b23) = (a12 / p, a13 / p, a23 / p);
        let det = b11 * (b22 * b33 - b23 * b23) - b12 * (b12 * b33 - b23 * b13)
            + b13 * (b12 * b23 - b22 * b13);
        let phi = (det / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
        let big = q + 2.0 * p * phi.cos();
        let small = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
        [small, 3.0 * q - big - small, big]
    };
    out.sort_by(f64::total_cmp);
    out
}

#[allow(clippy::unnecessary_cast)] // a no-op in f64
fn wide(x: Real) -> f64 {
    x as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use kea::{Quat, Vec3};

    #[test]
    fn principal_moments_of_a_turned_tensor_are_its_diagonal() {
        let r = Mat3::from_quat(Quat::from_axis_angle(
            Vec3::new(1.0, 2.0, 3.0).normalize(),
            0.8,
        ));
        let m = r * Mat3::from_diagonal(Vec3::new(0.5, 1.0, 1.25)) * r.transpose();
        let [a, b, c] = principal_moments(m);
        assert!((a - 0.5).abs() < 1e-5 && (b - 1.0).abs() < 1e-5 && (c - 1.25).abs() < 1e-5);
        assert_eq!(check(m), Ok(None));
        let bad = r * Mat3::from_diagonal(Vec3::new(0.1, 0.2, 1.0)) * r.transpose();
        assert!(check(bad).unwrap().unwrap().contains("A + B >= C"));
        let negative = Mat3::from_diagonal(Vec3::new(-0.1, 1.0, 1.0));
        assert!(check(negative).unwrap_err().contains("negative"));
        assert_eq!(check(Mat3::ZERO), Ok(None));
    }
}
