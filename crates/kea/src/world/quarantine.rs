//! Quarantine: after the solver, before anything is committed, each island is checked. An island
//! with a non-finite state or force, or a body faster than the world's limits, is put back to
//! its state before the step and frozen (disabled), and reported by body handles; the other
//! islands step on. The user reads the report and clears the quarantine when ready.

use super::constraint_entry::ConstraintKind;
use super::World;
use crate::error::{check_positive, KeaResult, MAX_COORDINATE};
use crate::handle::BodyHandle;
use crate::math::{is_finite3, Real, Vec3};
use crate::solver::SolverBody;
use crate::union_find::UnionFind;

/// The speeds beyond which a body counts as runaway (see [`crate::WorldSettings::speed_limits`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpeedLimits {
    /// Largest linear speed, m/s. Default 1e4 (thirty times the speed of sound).
    pub linear: Real,
    /// Largest angular speed, rad/s. Default 1e4.
    pub angular: Real,
}

impl Default for SpeedLimits {
    fn default() -> Self {
        Self {
            linear: 1.0e4,
            angular: 1.0e4,
        }
    }
}

impl SpeedLimits {
    pub(crate) fn validate(&self) -> KeaResult<()> {
        check_positive("speed_limits.linear", self.linear)?;
        check_positive("speed_limits.angular", self.angular)?;
        Ok(())
    }
}

/// Why an island was quarantined.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum QuarantineReason {
    /// A body's state, or a constraint's force, became NaN or infinite.
    NonFinite,
    /// A body went faster than [`SpeedLimits`], or beyond [`MAX_COORDINATE`] of the origin:
    /// its linear (m/s) and angular (rad/s) speed.
    Runaway {
        /// Linear speed the step would have given, m/s.
        linear: Real,
        /// Angular speed the step would have given, rad/s.
        angular: Real,
    },
}

/// One island taken out of the simulation by a step.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct QuarantineEvent {
    /// The step that failed (the world's step count before it).
    pub step: u64,
    /// What was wrong with the first bad body found.
    pub reason: QuarantineReason,
    /// Every body of the island, now disabled at its state before that step.
    pub bodies: Vec<BodyHandle>,
}

impl World {
    /// The islands quarantined since the last [`World::clear_quarantine`], oldest first.
    #[must_use]
    pub fn quarantine_report(&self) -> &[QuarantineEvent] {
        &self.quarantine
    }

    /// Releases every quarantined body (enables it again, at the state it was frozen in, which
    /// is the state before the step that failed) and empties the report. Returns how many bodies
    /// were released. Bodies destroyed meanwhile are skipped.
    pub fn clear_quarantine(&mut self) -> usize {
        let mut released = 0;
        for event in std::mem::take(&mut self.quarantine) {
            for h in event.bodies {
                if let Ok(b) = self.bodies.get_mut(h) {
                    if b.quarantined {
                        b.quarantined = false;
                        b.enabled = true;
                        b.wake();
                        self.awake.touch_body(h);
                        released += 1;
                    }
                }
            }
        }
        released
    }

    /// Checks the solver's results island by island; quarantines the bad ones (their solver
    /// bodies get their state before the step back; their joints no force, their contacts
    /// their forces of the last step). Returns how many bodies it quarantined. Costs one pass
    /// over the bodies when all is well.
    pub(super) fn quarantine_bad_islands(&mut self) -> u32 {
        let limits = self.settings.speed_limits;
        let s = &self.scratch;
        let all_well = s
            .solver_bodies
            .iter()
            .all(|b| body_trouble(b, &limits).is_none())
            && s.lambda.iter().all(|l| l.is_finite())
            && s.contacts.iter().all(|c| c.contact.forces_finite());
        if all_well {
            return 0;
        }
        self.mark_bad_islands();
        self.restore_bad_constraints();
        let first_event = self.quarantine.len();
        let quarantined = self.freeze_bad_bodies();
        for e in &self.quarantine[first_event..] {
            let shown = &e.bodies[..e.bodies.len().min(4)];
            let more = e.bodies.len() - shown.len();
            log::warn!(
                "kea: step {}: island of {} bodies quarantined ({:?}): {:?}{}",
                e.step,
                e.bodies.len(),
                e.reason,
                shown,
                if more > 0 { " and more" } else { "" }
            );
        }
        quarantined
    }

    /// Groups the step's solver bodies into islands (`quarantine_sets`) and flags the root of
    /// each island with a bad body, a non-finite joint force or contact force
    /// (`quarantine_root`).
    fn mark_bad_islands(&mut self) {
        let limits = self.settings.speed_limits;
        let s = &mut self.scratch;
        let n = s.solver_bodies.len();
        let sets = &mut s.quarantine_sets;
        sets.reset(n);
        let joined = s
            .blocks
            .iter()
            .map(|b| b.bodies)
            .chain(s.contacts.iter().map(|c| c.bodies));
        for bodies in joined {
            if let [Some(a), Some(b)] = bodies {
                sets.union(a, b);
            }
        }
        let roots = &mut s.quarantine_root;
        roots.clear();
        roots.resize(n, false);
        let mut mark = |bodies: [Option<u32>; 2], sets: &mut UnionFind| {
            for &i in bodies.iter().flatten() {
                roots[sets.find(i) as usize] = true;
            }
        };
        for i in 0..n as u32 {
            if body_trouble(&s.solver_bodies[i as usize], &limits).is_some() {
                mark([Some(i), None], sets);
            }
        }
        for b in &s.blocks {
            let rows = b.first_row as usize..(b.first_row + b.row_count) as usize;
            if s.lambda[rows].iter().any(|l| !l.is_finite()) {
                mark(b.bodies, sets);
            }
        }
        for c in &s.contacts {
            if !c.contact.forces_finite() {
                mark(c.bodies, sets);
            }
        }
    }

    /// The constraints of bad islands: joints get no force, contacts their last step's.
    fn restore_bad_constraints(&mut self) {
        let s = &mut self.scratch;
        let (sets, roots) = (&mut s.quarantine_sets, &s.quarantine_root);
        let mut bad = |bodies: [Option<u32>; 2]| {
            bodies
                .iter()
                .flatten()
                .any(|&i| roots[sets.find(i) as usize])
        };
        for (k, b) in s.blocks.iter().enumerate() {
            if bad(b.bodies) {
                let rows = b.first_row as usize..(b.first_row + b.row_count) as usize;
                s.lambda[rows].fill(0.0);
                s.reactions[k] = Default::default();
            }
        }
        for (c, &slot) in s.contacts.iter_mut().zip(&s.contact_constraint) {
            if bad(c.bodies) {
                if let Some(ConstraintKind::Contact(old)) =
                    self.constraints.at(slot as usize).map(|e| &e.kind)
                {
                    c.contact = *old;
                }
            }
        }
    }

    /// The bodies of bad islands: their state before the step (in the solver array, which
    /// write-back copies), frozen; one event per island. Returns how many.
    fn freeze_bad_bodies(&mut self) -> u32 {
        let limits = self.settings.speed_limits;
        let s = &mut self.scratch;
        let (sets, roots) = (&mut s.quarantine_sets, &s.quarantine_root);
        let first_event = self.quarantine.len();
        let mut quarantined = 0;
        for i in 0..s.solver_bodies.len() as u32 {
            let root = sets.find(i);
            if !roots[root as usize] {
                continue;
            }
            let sb = &mut s.solver_bodies[i as usize];
            let trouble = body_trouble(sb, &limits);
            let slot = s.solver_to_slot[i as usize] as usize;
            let body = self.bodies.at_mut(slot).expect("simulated bodies are live");
            sb.position = body.position;
            sb.orientation = body.orientation;
            sb.linear_velocity = body.linear_velocity;
            sb.angular_velocity = body.angular_velocity;
            sb.linear_acceleration = Vec3::ZERO;
            sb.angular_acceleration = Vec3::ZERO;
            body.enabled = false;
            body.quarantined = true;
            self.awake.touch(slot as u32);
            quarantined += 1;
            let handle = self.bodies.handle_at(slot).expect("occupied slot");
            // The island's reason is its first troubled body's (NonFinite when only a force
            // was bad).
            let event = self.quarantine[first_event..]
                .iter_mut()
                .zip(&mut self.quarantine_roots)
                .find(|(_, (r, _))| *r == root);
            match event {
                Some((e, (_, reasoned))) => {
                    e.bodies.push(handle);
                    if let (false, Some(t)) = (*reasoned, trouble) {
                        e.reason = t;
                        *reasoned = true;
                    }
                }
                None => {
                    self.quarantine.push(QuarantineEvent {
                        step: self.steps,
                        reason: trouble.unwrap_or(QuarantineReason::NonFinite),
                        bodies: vec![handle],
                    });
                    self.quarantine_roots.push((root, trouble.is_some()));
                }
            }
        }
        self.quarantine_roots.clear();
        quarantined
    }
}

/// What is wrong with a solved body, if anything: a non-finite state, a speed past the limits,
/// or a position past [`MAX_COORDINATE`].
fn body_trouble(b: &SolverBody, limits: &SpeedLimits) -> Option<QuarantineReason> {
    let finite = is_finite3(b.position)
        && b.orientation.is_finite()
        && is_finite3(b.linear_velocity)
        && is_finite3(b.angular_velocity);
    if !finite {
        return Some(QuarantineReason::NonFinite);
    }
    let (linear, angular) = (b.linear_velocity.length(), b.angular_velocity.length());
    let far = b.position.abs().max_element() > MAX_COORDINATE;
    (linear > limits.linear || angular > limits.angular || far)
        .then_some(QuarantineReason::Runaway { linear, angular })
}
