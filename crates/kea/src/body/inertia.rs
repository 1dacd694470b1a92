//! Inertia tensors of common solids, about their centre of mass, in their own frame.
//!
//! The guide (chapter 3) calls a wrong inertia "the most common cause of unrealistic behaviour";
//! these helpers make the right one a single call. Cylinders and capsules have their axis along
//! the body's local **y** axis.

use crate::error::{check_positive, KeaResult};
use crate::math::{Mat3, Real, Vec3, PI};

/// Inertia of a solid box of `mass` with half-extents `half_extents`: `I_xx = m(b² + c²)/3` with
/// half-sizes a, b, c.
pub fn solid_box(mass: Real, half_extents: Vec3) -> KeaResult<Mat3> {
    check_positive("mass", mass)?;
    check_positive("half_extents.x", half_extents.x)?;
    check_positive("half_extents.y", half_extents.y)?;
    check_positive("half_extents.z", half_extents.z)?;
    let s = half_extents * half_extents;
    Ok(Mat3::from_diagonal(
        Vec3::new(s.y + s.z, s.x + s.z, s.x + s.y) * (mass / 3.0),
    ))
}

/// Inertia of a solid sphere: `I = 2/5 m r²` about any axis.
pub fn solid_sphere(mass: Real, radius: Real) -> KeaResult<Mat3> {
    check_positive("mass", mass)?;
    check_positive("radius", radius)?;
    Ok(Mat3::from_diagonal(Vec3::splat(
        0.4 * mass * radius * radius,
    )))
}

/// Inertia of a solid cylinder along local y with `radius` and `half_height`:
/// `I_yy = m r²/2`, `I_xx = I_zz = m(3r² + h²)/12` with full height `h`.
pub fn solid_cylinder(mass: Real, radius: Real, half_height: Real) -> KeaResult<Mat3> {
    check_positive("mass", mass)?;
    check_positive("radius", radius)?;
    check_positive("half_height", half_height)?;
    let h = 2.0 * half_height;
    let side = mass * (3.0 * radius * radius + h * h) / 12.0;
    Ok(Mat3::from_diagonal(Vec3::new(
        side,
        0.5 * mass * radius * radius,
        side,
    )))
}

/// Inertia of a solid capsule along local y: a cylinder of `radius` and `half_height` closed by
/// two hemispheres of the same radius, uniform density, total `mass`.
pub fn solid_capsule(mass: Real, radius: Real, half_height: Real) -> KeaResult<Mat3> {
    check_positive("mass", mass)?;
    check_positive("radius", radius)?;
    check_positive("half_height", half_height)?;
    let r = radius;
    let h = 2.0 * half_height;
    let v_cyl = PI * r * r * h;
    let v_sph = 4.0 / 3.0 * PI * r * r * r;
    let m_cyl = mass * v_cyl / (v_cyl + v_sph);
    let m_sph = mass - m_cyl; // both hemispheres together
    let axial = m_cyl * r * r / 2.0 + m_sph * 2.0 * r * r / 5.0;
    // Each hemisphere's centroid is 3r/8 from the flat face; parallel-axis to the capsule centre.
    let side = m_cyl * (r * r / 4.0 + h * h / 12.0)
        + m_sph * (2.0 * r * r / 5.0 + h * h / 4.0 + 3.0 * h * r / 8.0);
    Ok(Mat3::from_diagonal(Vec3::new(side, axial, side)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capsule_of_zero_length_is_a_sphere() {
        let c = solid_capsule(2.0, 0.5, 1e-6).unwrap();
        let s = solid_sphere(2.0, 0.5).unwrap();
        assert!((c.x_axis.x - s.x_axis.x).abs() < 1e-4);
        assert!((c.y_axis.y - s.y_axis.y).abs() < 1e-4);
    }

    #[test]
    fn cube_inertia() {
        let i = solid_box(6.0, Vec3::splat(0.5)).unwrap();
        assert!((i.x_axis.x - 1.0).abs() < 1e-6); // m s²/6 with side 1
    }

    #[test]
    fn bad_arguments_are_named() {
        let e = solid_sphere(-1.0, 1.0).unwrap_err().to_string();
        assert!(e.contains("mass") && e.contains("-1"), "{e}");
        let e = solid_box(1.0, Vec3::new(1.0, 0.0, 1.0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("half_extents.y"), "{e}");
    }
}
