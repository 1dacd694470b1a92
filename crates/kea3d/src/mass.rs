//! A body's mass properties from its colliders: each one's own (by density or mass), summed
//! about their common centre of mass with the parallel-axis theorem.

use crate::collider::ColliderMass;
use kea::{Mat3, Quat, Real, Vec3};
use kea_collision::{CollisionError, CollisionResult, MassProperties, Shape};

/// One collider as it weighs: its placement in the body's frame, shape and mass rule.
pub(crate) struct Part<'a> {
    pub offset: Vec3,
    pub rotation: Quat,
    pub shape: &'a Shape,
    pub mass: ColliderMass,
}

/// The combined mass properties of the parts that have volume, in the body's frame; `None`
/// if none has.
pub(crate) fn combine(parts: &[Part<'_>]) -> CollisionResult<Option<MassProperties>> {
    let mut weighed: Vec<MassProperties> = Vec::with_capacity(parts.len());
    for p in parts.iter().filter(|p| p.shape.has_volume()) {
        let placed = [(p.offset, p.rotation, p.shape.clone())];
        let mp = match p.mass {
            ColliderMass::Density(rho) => MassProperties::of_shapes(&placed, rho)?,
            ColliderMass::Mass(m) => {
                check_mass(m)?;
                let unit = MassProperties::of_shapes(&placed, 1.0)?;
                let scale = m / unit.mass;
                MassProperties {
                    mass: m,
                    center_of_mass: unit.center_of_mass,
                    inertia: unit.inertia * scale,
                }
            }
        };
        weighed.push(mp);
    }
    if weighed.is_empty() {
        return Ok(None);
    }
    let mass: Real = weighed.iter().map(|m| m.mass).sum();
    let com = weighed
        .iter()
        .map(|m| m.center_of_mass * m.mass)
        .sum::<Vec3>()
        / mass;
    let inertia = weighed.iter().fold(Mat3::ZERO, |acc, m| {
        acc + m.inertia + parallel_axis(m.mass, m.center_of_mass - com)
    });
    Ok(Some(MassProperties {
        mass,
        center_of_mass: com,
        inertia,
    }))
}

/// The inertia a point mass `m` at `d` from the centre adds: m (|d|² 1 − d dᵀ).
fn parallel_axis(m: Real, d: Vec3) -> Mat3 {
    let outer = Mat3::from_cols(d * d.x, d * d.y, d * d.z);
    (Mat3::IDENTITY * d.length_squared() - outer) * m
}

fn check_mass(m: Real) -> CollisionResult<()> {
    if !(m.is_finite() && m > 0.0) {
        return Err(CollisionError::Kea(kea::KeaError::OutOfRange {
            arg: "mass",
            value: kea::error::format_real(m),
            expected: "a positive finite mass, kg",
        }));
    }
    Ok(())
}
