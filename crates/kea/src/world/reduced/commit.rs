//! Committing a step's trees once the solver has accepted the rest of the world: their bodies
//! and joints written, their coordinates kept, and the marks a kept tree is checked against
//! next step (a floating tree's chart re-centred past `CHART_LIMIT` by building it again).

use super::{mark, CachedTree, CHART_LIMIT, FREE_ROOT};
use crate::world::constraint_entry::ConstraintKind;
use crate::world::World;

impl World {
    /// Writes the trees' new states to their bodies and joints (after the solver succeeded),
    /// keeps their coordinates, and clears the marks so that read-outs between steps see
    /// every body.
    pub(in crate::world) fn commit_reduced_trees(&mut self) {
        let r = &mut self.scratch.reduced;
        for t in r.trees.iter_mut().filter(|t| t.stepped) {
            std::mem::swap(&mut t.q, &mut t.q_next);
            std::mem::swap(&mut t.qd, &mut t.qd_next);
            if t.rebuilt_each_step || !chart_centred(t) {
                // Built again, centred again, from the bodies next step.
                t.revision = 0;
            }
            t.marks.clear();
            for x in &r.results[t.first..t.first + t.plan.len()] {
                if let Some(b) = self.bodies.at_mut(x.body as usize) {
                    b.take_motion(&x.motion);
                    let coordinates = if x.joint == FREE_ROOT {
                        [0.0; 3] // no joint: the body is the whole mark
                    } else {
                        [x.coordinate, x.more[0].0, x.more[1].0]
                    };
                    t.marks.push(mark(b, coordinates));
                }
                if let Some(e) = self.constraints.at_mut(x.joint as usize) {
                    match &mut e.kind {
                        ConstraintKind::Hinge(j) => {
                            j.angle = x.coordinate;
                            j.limit.record(x.coordinate, x.rate);
                        }
                        ConstraintKind::Prismatic(j) => {
                            j.limit.record(x.coordinate, x.rate);
                        }
                        ConstraintKind::Planar(j) => {
                            j.record([(x.coordinate, x.rate), x.more[0], x.more[1]]);
                        }
                        _ => {}
                    }
                    e.last_rows = None;
                    e.reaction = x.reaction;
                }
                if x.joint != FREE_ROOT {
                    self.scratch.written.push(x.joint);
                }
            }
            t.stepped = false;
        }
        r.results.clear();
        r.contacts.write_back(&mut self.constraints);
        r.reduced.iter_mut().for_each(|x| *x = false);
    }
}

/// Whether a kept tree's floating root (if any) is still within `CHART_LIMIT` of where its
/// chart was centred.
fn chart_centred(t: &CachedTree) -> bool {
    match t.plan.first() {
        Some(p) if p.free => {
            let turns = t.first_link[0] + 3..t.first_link[0] + 6;
            t.q[turns].iter().all(|a| a.abs() < CHART_LIMIT)
        }
        _ => true,
    }
}
