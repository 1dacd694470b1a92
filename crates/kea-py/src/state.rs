//! A world's state as rows of numbers, the same code for a single world and for each world
//! of a batch (so the two agree bit for bit).
//!
//! A body's row: position of its frame origin (3), orientation quaternion `x y z w` (4),
//! linear velocity of its centre of mass (3), angular velocity (3).

use crate::convert::{quat, real};
use kea3d::dynamics::{ConstraintHandle, Hinge, JointHandle, Limit, Prismatic};
use kea3d::{BodyHandle, PhysicsWorld, Result, Vec3};

/// Numbers per body in a state row.
pub const STATE_WIDTH: usize = 13;

/// What a joint is, for reading its coordinate and driving its motor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum JointTag {
    Hinge,
    Prismatic,
    Other,
}

/// A joint as the Python side numbers it.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub struct JointEntry {
    pub raw: ConstraintHandle,
    pub tag: JointTag,
}

/// Writes each body's row into `out` (`bodies.len() × STATE_WIDTH`).
pub fn read_bodies(w: &PhysicsWorld, bodies: &[BodyHandle], out: &mut [f64]) -> Result<()> {
    for (&h, row) in bodies.iter().zip(out.chunks_exact_mut(STATE_WIDTH)) {
        let p = w.position(h)?;
        let q = w.rotation(h)?;
        let v = w.linear_velocity(h)?;
        let om = w.angular_velocity(h)?;
        let values = [
            p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, om.x, om.y, om.z,
        ];
        for (o, x) in row.iter_mut().zip(values) {
            *o = f64::from(x);
        }
    }
    Ok(())
}

/// Sets each body from its row of `src`; checks every row before changing anything.
pub fn write_bodies(w: &mut PhysicsWorld, bodies: &[BodyHandle], src: &[f64]) -> Result<()> {
    for (b, row) in src.chunks_exact(STATE_WIDTH).enumerate() {
        check_row(b, row)?;
    }
    for (&h, row) in bodies.iter().zip(src.chunks_exact(STATE_WIDTH)) {
        let v = |i: usize| Vec3::new(real(row[i]), real(row[i + 1]), real(row[i + 2]));
        w.set_rotation(h, quat([row[3], row[4], row[5], row[6]]))?;
        w.set_position(h, v(0))?;
        w.body_mut(h)?.set_linear_velocity(v(7))?;
        w.body_mut(h)?.set_angular_velocity(v(10))?;
        w.dynamics_mut().wake_body(h)?;
    }
    Ok(())
}

/// Refuses a row that a setter would refuse: non-finite numbers, a position beyond
/// [`kea3d::dynamics::error::MAX_COORDINATE`], a quaternion not of unit length.
fn check_row(body: usize, row: &[f64]) -> Result<()> {
    let bad = |reason: String| kea3d::dynamics::KeaError::OutOfRange {
        arg: "state",
        value: reason,
        expected: "finite rows: position within 1e9 m, unit quaternion x y z w, velocities",
    };
    if let Some(i) = row.iter().position(|x| !x.is_finite()) {
        return Err(bad(format!("body {body} column {i} is {}", row[i])).into());
    }
    let limit = f64::from(kea3d::dynamics::error::MAX_COORDINATE);
    if row[..3].iter().any(|x| x.abs() > limit) {
        return Err(bad(format!("body {body} position {:?}", &row[..3])).into());
    }
    let len = row[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
    if (len - 1.0).abs() > 1e-3 {
        return Err(bad(format!("body {body} quaternion of length {len}")).into());
    }
    Ok(())
}

/// The limit (coordinate, rate, motor) of a hinge or prismatic joint.
pub fn limit(w: &PhysicsWorld, j: JointEntry) -> Result<Option<&Limit>> {
    Ok(match j.tag {
        JointTag::Hinge => Some(JointHandle::<Hinge>::from_raw(j.raw).get(w)?.limit()),
        JointTag::Prismatic => Some(JointHandle::<Prismatic>::from_raw(j.raw).get(w)?.limit()),
        JointTag::Other => None,
    })
}

/// Each joint's coordinate (rad or m) and rate after the last step; 0 for joints without one.
pub fn read_joints(
    w: &PhysicsWorld,
    joints: &[JointEntry],
    positions: &mut [f64],
    velocities: &mut [f64],
) -> Result<()> {
    for (i, &j) in joints.iter().enumerate() {
        let (p, v) = limit(w, j)?.map_or((0.0, 0.0), |l| (l.position(), l.velocity()));
        positions[i] = f64::from(p);
        velocities[i] = f64::from(v);
    }
    Ok(())
}

/// Sets the motor speed of a hinge or prismatic joint, keeping its force limit.
pub fn drive(w: &mut PhysicsWorld, j: JointEntry, velocity: f64) -> Result<()> {
    let max_force = limit(w, j)?.and_then(Limit::motor).map(|m| m.max_force);
    let Some(max_force) = max_force else {
        return Err(kea3d::dynamics::KeaError::InvalidState {
            operation: "set_motor",
            reason: "the joint has no motor: give it one when adding it",
        }
        .into());
    };
    let lim = match j.tag {
        JointTag::Hinge => JointHandle::<Hinge>::from_raw(j.raw).limit_mut(w)?,
        _ => JointHandle::<Prismatic>::from_raw(j.raw).limit_mut(w)?,
    };
    Ok(lim.set_motor(real(velocity), max_force)?)
}
