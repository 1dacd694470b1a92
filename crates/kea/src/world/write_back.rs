//! Write-back, the last stage of a step: the solver's new states to the bodies, its forces to
//! the constraints (each contact's per-row forces and reactions for the read-outs), force
//! accumulators cleared.

use super::constraint_entry::ConstraintKind;
use super::World;
use crate::solver::Reaction;

impl World {
    /// Copies the solver's new states to the bodies and forces to the constraints, and clears
    /// the force accumulators.
    pub(super) fn write_back(&mut self, clear_forces: bool) {
        self.write_back_contacts();
        let s = &self.scratch;
        for (i, sb) in s.solver_bodies.iter().enumerate() {
            let slot = s.solver_to_slot[i] as usize;
            let b = self.bodies.at_mut(slot).expect("simulated bodies are live");
            b.take_motion(&crate::body::Motion {
                position: sb.position,
                orientation: sb.orientation,
                linear_velocity: sb.linear_velocity,
                angular_velocity: sb.angular_velocity,
                linear_acceleration: sb.linear_acceleration,
                angular_acceleration: sb.angular_acceleration,
            });
            b.last_path = sb.last_path;
        }
        // Accumulators are cleared for every body, simulated or not (the guide's rule), after
        // the step's last substep: only awake and touched bodies can hold any.
        if clear_forces {
            // The step's own changes (waking, quarantine) taken in before the touched list
            // goes.
            self.awake.refresh(&self.bodies);
            let awake = &mut self.awake;
            for &slot in awake.slots().iter().chain(awake.touched()) {
                if let Some(b) = self.bodies.at_mut(slot as usize) {
                    b.clear_forces();
                }
            }
            awake.forget_touched();
        }
        // Last step's read-outs go; only the constraints it solved hold any.
        for &slot in &s.written {
            if let Some(e) = self.constraints.at_mut(slot as usize) {
                e.last_rows = None;
                e.reaction = [Reaction::default(); 2];
            }
        }
        for (k, blk) in s.blocks.iter().enumerate() {
            let slot = s.block_constraint[k] as usize;
            let e = self
                .constraints
                .at_mut(slot)
                .expect("solved constraints are live");
            e.last_rows = Some((blk.first_row, blk.row_count));
            e.reaction = s.reactions[k];
        }
        for (k, &slot) in s.contact_constraint.iter().enumerate() {
            let e = self
                .constraints
                .at_mut(slot as usize)
                .expect("solved contacts are live");
            e.last_rows = Some(s.contact_rows[k]);
            e.reaction = s.contact_reactions[k];
        }
        let s = &mut self.scratch;
        s.written.clear();
        s.written.extend_from_slice(&s.block_constraint);
        s.written.extend_from_slice(&s.contact_constraint);
    }

    /// Hands each contact its forces, and records its reactions and its per-row forces for
    /// [`World::constraint_lambdas`] (normal, then the two friction directions of
    /// [`crate::Contact::tangent_basis`], point by point), before the bodies move.
    fn write_back_contacts(&mut self) {
        let s = &mut self.scratch;
        s.contact_lambda.clear();
        s.contact_rows.clear();
        s.contact_reactions.clear();
        for (sc, &slot) in s.contacts.iter().zip(&s.contact_constraint) {
            let Some(e) = self.constraints.at_mut(slot as usize) else {
                continue;
            };
            let ConstraintKind::Contact(c) = &mut e.kind else {
                continue;
            };
            c.take_forces(&sc.contact);
            let (t1, t2) = c.tangent_basis();
            let first = s.contact_lambda.len() as u32;
            let mut reaction = [Reaction::default(); 2];
            let centres = e.bodies.map(|b| {
                b.and_then(|h| self.bodies.get(h).ok())
                    .map(|x| x.position())
            });
            for (p, f) in c.points().iter().zip(c.forces()) {
                s.contact_lambda.extend_from_slice(&[
                    f.normal,
                    f.friction.dot(t1),
                    f.friction.dot(t2),
                ]);
                let force = c.normal() * f.normal + f.friction;
                for (side, centre) in centres.iter().enumerate() {
                    let Some(x) = centre else {
                        continue;
                    };
                    let sign = if side == 0 { 1.0 } else { -1.0 };
                    reaction[side].force += force * sign;
                    reaction[side].torque += (p.position - *x).cross(force) * sign;
                }
            }
            s.contact_rows
                .push((first, s.contact_lambda.len() as u32 - first));
            s.contact_reactions.push(reaction);
        }
    }
}
