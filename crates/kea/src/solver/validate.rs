//! Checks on the immediate-mode inputs: every array consistent, every number finite, every
//! body physical. The solver changes nothing before these pass.

use super::{ConstraintBlock, SolverBody, StepArrays};
use crate::constraint::Row;
use crate::error::{KeaError, KeaResult};
use crate::math::{is_finite3, Mat3, Real};

pub(super) fn validate_inputs(step: &StepArrays<'_>) -> KeaResult<()> {
    let (bodies, blocks, rows) = (&*step.bodies, step.blocks, step.rows);
    let (contacts, params) = (&*step.contacts, step.params);
    let (lambda, reactions) = (&*step.lambda, &*step.reactions);
    params.validate()?;
    for (i, c) in contacts.iter().enumerate() {
        let [a, b] = c.bodies;
        for x in [a, b].into_iter().flatten() {
            if x as usize >= bodies.len() {
                return Err(KeaError::Inconsistent {
                    arg: "contacts",
                    reason: format!("contact {i} names body {x} of {}", bodies.len()),
                });
            }
        }
        if a.is_some() && a == b {
            return Err(KeaError::Inconsistent {
                arg: "contacts",
                reason: format!("contact {i} joins body {} to itself", a.unwrap_or(0)),
            });
        }
    }
    let inconsistent = |arg, reason: String| Err(KeaError::Inconsistent { arg, reason });
    if lambda.len() != rows.len() {
        return inconsistent(
            "lambda",
            format!("has {} entries for {} rows", lambda.len(), rows.len()),
        );
    }
    if reactions.len() != blocks.len() {
        return inconsistent(
            "reactions",
            format!(
                "has {} entries for {} constraints",
                reactions.len(),
                blocks.len()
            ),
        );
    }
    validate_rows(bodies, blocks, rows)
}

/// Checks bodies, blocks and rows for consistency and finiteness.
pub(super) fn validate_rows(
    bodies: &[SolverBody],
    blocks: &[ConstraintBlock],
    rows: &[Row],
) -> KeaResult<()> {
    let inconsistent = |arg, reason: String| Err(KeaError::Inconsistent { arg, reason });
    for (i, b) in bodies.iter().enumerate() {
        let unit = |q: Real| (q - 1.0).abs() <= crate::math::UNIT_TOLERANCE;
        let diag_ok = |m: &Mat3, strict: bool| {
            let d = [m.x_axis.x, m.y_axis.y, m.z_axis.z];
            m.is_finite() && d.iter().all(|&x| if strict { x > 0.0 } else { x >= 0.0 })
        };
        let ok = is_finite3(b.position)
            && is_finite3(b.linear_velocity)
            && is_finite3(b.angular_velocity)
            && is_finite3(b.force)
            && is_finite3(b.torque)
            && b.orientation.is_finite()
            && unit(b.orientation.length())
            && b.inv_mass.is_finite()
            && b.inv_mass >= 0.0
            && diag_ok(&b.inv_inertia, false)
            && (b.is_fixed() || diag_ok(&b.inertia, true))
            && b.fast_spin_axis
                .is_none_or(|a| a.is_finite() && unit(a.length()))
            && b.linear_damping >= 0.0
            && b.angular_damping >= 0.0;
        if !ok {
            return inconsistent(
                "bodies",
                format!(
                    "body {i} has a NaN, infinite or negative field, a non-unit orientation or \
                     fast-spin axis, or a non-positive inertia: {b:?}"
                ),
            );
        }
    }
    for (k, blk) in blocks.iter().enumerate() {
        for b in blk.bodies.iter().flatten() {
            if *b as usize >= bodies.len() {
                return inconsistent(
                    "blocks",
                    format!("constraint {k} names body {b} of {}", bodies.len()),
                );
            }
        }
        if blk.row_count > u32::from(u16::MAX) {
            return inconsistent(
                "blocks",
                format!("constraint {k} has {} rows (at most 65535)", blk.row_count),
            );
        }
        let end = blk.first_row as usize + blk.row_count as usize;
        if end > rows.len() {
            return inconsistent(
                "blocks",
                format!("constraint {k} uses rows up to {end} of {}", rows.len()),
            );
        }
        for r in &rows[blk.first_row as usize..end] {
            if let Some(f) = r.friction {
                if u32::from(f.normal_row) >= blk.row_count {
                    return inconsistent(
                        "rows",
                        format!(
                            "constraint {k} links friction to its row {} of {}",
                            f.normal_row, blk.row_count
                        ),
                    );
                }
            }
        }
    }
    validate_row_values(rows)
}

/// Checks every row's numbers (finite, bounds in order): the part of the check a world's own
/// arrays keep in release builds, since a row's bounds come from forces the step works out
/// (a tendon's, a motor's) and a NaN bound would reach a `clamp` that panics.
pub(super) fn validate_row_values(rows: &[Row]) -> KeaResult<()> {
    for (i, r) in rows.iter().enumerate() {
        if let Some(field) = r.invalid_field() {
            return Err(KeaError::Inconsistent {
                arg: "rows",
                reason: format!("row {i} has a bad `{field}`: {r:?}"),
            });
        }
    }
    Ok(())
}
