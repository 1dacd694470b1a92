//! The synchronising pass of the joint rows (`substep` module docs): after the step's poses
//! are final, the last half kick of the islands without contacts is projected on their joints,
//! written at those poses. Only what acts at an instant takes part — rigid rows, and motors
//! (dampers with a force limit) with half their budget — and a stop pushes at most half of
//! what it pushed in the last substep, so that it holds a resting load but never takes an
//! impact. The pass's impulses start from zero and join the step's totals.

use super::super::bodies::{BodyStates, NONE};
use super::{JointRows, SyncRows, BOUNCE, HARD, SYNCHRONISED, UNILATERAL};
use crate::math::Real;

impl JointRows {
    /// Whether a pass skips row `i`: the synchronising pass solves only the synchronised
    /// rows that act on velocity at an instant (hard rows, and motors: dampers with a force
    /// limit); a spring is a force spread over the substeps, and a Coulomb row has no contact
    /// in such an island to lean on.
    #[inline]
    pub(super) fn skipped(&self, i: usize) -> bool {
        if !self.synchronising {
            return false;
        }
        let force_limited = self.lo[i].is_finite() && self.hi[i].is_finite();
        self.flags[i] & SYNCHRONISED == 0
            || !self.acts_at_an_instant(i)
            || self.link[i] != NONE
            || match self.sync_rows {
                SyncRows::All => false,
                SyncRows::Motors => !force_limited,
                SyncRows::Hard => force_limited,
            }
    }

    /// A rigid row, or a soft one without a spring (a damper).
    #[inline]
    fn acts_at_an_instant(&self, i: usize) -> bool {
        self.rigid(i) || self.rate[i] == 0.0
    }

    /// Whether row `i` is solved as rigid in this pass: a hard row, and in the synchronising
    /// pass also a row whose softness only regularises (a motor's or a hard stop's, a
    /// compliance under a millionth of its effective inverse mass), which acts at an instant
    /// rather than as a spring through the substeps.
    #[inline]
    pub(super) fn rigid(&self, i: usize) -> bool {
        self.flags[i] & HARD != 0 || (self.synchronising && self.extra[i] <= 1.0e-6 * self.diag[i])
    }

    /// Row `i`'s own impulse bounds in this pass: a bounded row of a synchronised island that
    /// takes part in the synchronising pass (a motor's force limit) has half a substep's
    /// budget in the first substep and in that pass, the two half kicks, so that a step's
    /// budget stays `h·f`.
    #[inline]
    pub(super) fn own_bounds(&self, i: usize) -> (Real, Real) {
        if self.half_budget && self.flags[i] & SYNCHRONISED != 0 && self.acts_at_an_instant(i) {
            let hi = 0.5 * self.hi[i];
            let hi = if self.synchronising {
                hi.min(self.sync_cap[i])
            } else {
                hi
            };
            (0.5 * self.lo[i], hi)
        } else {
            (self.lo[i], self.hi[i])
        }
    }

    /// Gives the synchronised rows half their budget (see [`Self::own_bounds`]) or all of it.
    pub(crate) fn halve_budget(&mut self, half: bool) {
        self.half_budget = half;
    }

    /// The synchronising pass of the Gauss–Seidel rows (`substep` module docs): one unbiased
    /// sweep over the synchronised rows that makes their velocities tangent to the poses
    /// reached.
    pub(crate) fn synchronise(&mut self, states: &mut BodyStates, hs: Real, max_speed: Real) {
        // Motors first, then the hard rows, so that what a single sweep leaves is a motor a
        // little off its speed rather than a stop or a joint pushed open (a door driven into
        // its stop rested at 0.36 rad/s with the order of the rows).
        self.sync_rows = SyncRows::Motors;
        self.sweep(states, hs, false, max_speed);
        self.sync_rows = SyncRows::Hard;
        self.sweep(states, hs, false, max_speed);
        self.sync_rows = SyncRows::All;
    }

    /// Starts the synchronising pass: the synchronised rows' impulses start from zero (the
    /// pass's impulse is its own, bounded alone), a stop that bounced this step aims at its
    /// rebound, and a stop may push at most half of what it pushed in the last substep: it
    /// holds the half kick of what rests on it, but an impact is not the pass's to take (a
    /// body reaching its stop as the step ends would be stopped dead, its restitution lost).
    pub(crate) fn begin_synchronising(&mut self) {
        self.synchronising = true;
        self.half_budget = true;
        self.sync_cap.clear();
        for i in 0..self.len() {
            let cap = if self.flags[i] & UNILATERAL != 0 {
                0.5 * self.impulse[i].max(0.0)
            } else {
                Real::INFINITY
            };
            self.sync_cap.push(cap);
            if self.flags[i] & SYNCHRONISED != 0 {
                self.impulse[i] = 0.0;
            }
        }
    }

    /// Ends the synchronising pass: its impulses join the step's totals.
    pub(crate) fn end_synchronising(&mut self) {
        self.synchronising = false;
        self.half_budget = false;
        for i in 0..self.len() {
            if self.flags[i] & SYNCHRONISED != 0 {
                self.total[i] += self.impulse[i];
            }
        }
    }

    /// Row `i`'s velocity target in this pass: a stop that bounced this step keeps its rebound
    /// in the synchronising pass.
    #[inline]
    pub(super) fn target_for(&self, i: usize) -> Real {
        if self.synchronising && self.flags[i] & BOUNCE != 0 && self.total[i] > 0.0 {
            self.bounce_target[i]
        } else {
            self.target[i]
        }
    }
}
