//! Storing a step's contact forces: each lane's impulses back to its contact (the mean force
//! over the step, and the last substep's as the next step's warm start, the manifold's
//! friction spread back over its points), then summed into its bodies' constraint forces.

use super::super::super::integrate::BodyScratch;
use super::super::super::wide::FloatW;
use super::super::super::SolverContact;
use super::super::bodies::BodyStates;
use super::super::disjoint::Disjoint;
use super::batch::ContactBatch;
use super::kernel;
use crate::constraint::PointForce;
use crate::math::{to_f64, Real};

/// Writes the forces of a chunk of batches back to their contacts (each contact sits in one
/// lane of one batch, so chunks may run on several threads).
pub(super) fn write_chunk<F: FloatW>(
    chunk: &[ContactBatch<F>],
    contacts: &Disjoint<'_, SolverContact>,
    h: Real,
    hs: Real,
) {
    for batch in chunk {
        for (l, &index) in batch.contact.as_ref().iter().enumerate() {
            // SAFETY: every contact was filed once, into one lane of one batch.
            unsafe { contacts.with(index as usize, |sc| write_back(batch, l, sc, h, hs)) };
        }
    }
}

/// Adds the stored forces of `batches`' contacts to their bodies' constraint forces (on one
/// thread: bodies are shared between batches).
pub(super) fn add_body_forces<F: FloatW>(
    batches: &[ContactBatch<F>],
    contacts: &[SolverContact],
    states: &BodyStates,
    scratch: &mut BodyScratch,
) {
    for batch in batches {
        let n = batch.normal;
        for l in 0..F::LANES {
            let Some(sc) = contacts.get(batch.contact.as_ref()[l] as usize) else {
                continue; // an empty lane
            };
            let a = batch.body_a.as_ref()[l] as usize;
            let b = batch.body_b.as_ref()[l] as usize;
            for (p, mean) in batch.p.iter().zip(sc.contact.forces()) {
                let f = n.lane(l) * mean.normal + mean.friction;
                for (slot, r, sign) in [(a, p.r_a.lane(l), 1.0), (b, p.r_b.lane(l), -1.0)] {
                    if states.writable[slot] {
                        let g = states.global[slot] as usize;
                        scratch.constraint_force[g] += to_f64(f * sign);
                        scratch.constraint_torque[g] += to_f64(r.cross(f) * sign);
                    }
                }
            }
        }
    }
}

/// Writes lane `l`'s forces to its contact: the mean over the step, and the last substep's as
/// the next warm start.
#[inline(always)]
fn write_back<F: FloatW>(
    batch: &ContactBatch<F>,
    l: usize,
    sc: &mut SolverContact,
    h: Real,
    hs: Real,
) {
    let t = [batch.tangent[0].lane(l), batch.tangent[1].lane(l)];
    let (now_f, total_f) = kernel::lane_friction(batch, l);
    let mean_friction = (t[0] * total_f[0] + t[1] * total_f[1]) / h;
    let end_friction = (t[0] * now_f[0] + t[1] * now_f[1]) / hs;
    let (mean_twist, end_twist) = (total_f[2] / h, now_f[2] / hs);
    let frame = sc.contact.friction_frame();
    let mean_shares = sc
        .contact
        .spread_friction(&frame, mean_friction, mean_twist);
    let end_shares = sc.contact.spread_friction(&frame, end_friction, end_twist);
    for (j, p) in batch.p.iter().enumerate().take(sc.contact.points().len()) {
        let (now, total) = kernel::lane_normal(p, l);
        let mean = PointForce {
            normal: total / h,
            friction: mean_shares[j],
        };
        let end = PointForce {
            normal: now / hs,
            friction: end_shares[j],
        };
        sc.contact.set_point_force(j, mean, end);
    }
}
