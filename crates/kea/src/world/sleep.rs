//! Automatic disabling of resting bodies (the guide's DEM: "disabling bodies"), island by island.
//!
//! A body rests while its speed, spin and last-step accelerations are all under the world's
//! thresholds. When every body of an island (bodies coupled by enabled constraints, as the
//! solver partitions them) has rested for the alive window, the whole island is disabled:
//! its velocities are zeroed, the solver skips it, and constraints see its bodies as fixed.
//! It wakes, whole, when any of its bodies is touched by an awake body through a constraint,
//! is given a force or torque above the wake thresholds, or has its pose or velocity set; when
//! a joint on it is destroyed, enabled or disabled, or a body it is attached to is destroyed;
//! when gravity changes; or on [`World::wake_body`]. Destroying a *contact* does not wake it
//! (collision code remakes contacts every step): wake a body yourself if you take its support
//! away. Disabling a single body inside a moving pile would be wrong, hence
//! islands.

use super::body_constraints::visited;
use super::constraint_index::{EMPTY, NO_BODY};
use super::World;
use crate::error::{check_non_negative, KeaResult};
use crate::handle::BodyHandle;
use crate::math::{Real, Vec3};

/// How the world partitions and disables bodies (the guide's `MdtDEMMode`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum DemMode {
    /// Partition into islands and disable resting islands automatically.
    PartitionAutoDisable,
    /// Partition into islands, never disable automatically (the guide's default).
    #[default]
    PartitionNoAutoDisable,
    /// Solve every coupled body as one problem and never disable (slower; for comparison).
    NoPartition,
}

/// Thresholds for automatic disabling (the guide's `MdtWorldSetDEM*`). Units are SI.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DemSettings {
    /// The mode. Default [`DemMode::PartitionNoAutoDisable`], as in the guide.
    pub mode: DemMode,
    /// Speed below which a body may rest, m/s. Default 0.01.
    pub velocity_threshold: Real,
    /// Spin below which a body may rest, rad/s. Default 0.03 (about 2°/s).
    pub angular_velocity_threshold: Real,
    /// Acceleration over the last step below which a body may rest, m/s². Default 0.5.
    pub acceleration_threshold: Real,
    /// Angular acceleration below which a body may rest, rad/s². Default 1.0.
    pub angular_acceleration_threshold: Real,
    /// Time every body of an island must have rested before it is disabled, s. Default 0.5.
    pub alive_window: Real,
    /// Applied force that wakes a disabled body, N. Default 1e-3.
    pub force_threshold: Real,
    /// Applied torque that wakes a disabled body, N·m. Default 1e-3.
    pub torque_threshold: Real,
}

impl Default for DemSettings {
    fn default() -> Self {
        Self {
            mode: DemMode::default(),
            velocity_threshold: 0.01,
            angular_velocity_threshold: 0.03,
            acceleration_threshold: 0.5,
            angular_acceleration_threshold: 1.0,
            alive_window: 0.5,
            force_threshold: 1.0e-3,
            torque_threshold: 1.0e-3,
        }
    }
}

impl DemSettings {
    /// Checks every threshold (finite, ≥ 0).
    pub fn validate(&self) -> KeaResult<()> {
        check_non_negative("velocity_threshold", self.velocity_threshold)?;
        check_non_negative(
            "angular_velocity_threshold",
            self.angular_velocity_threshold,
        )?;
        check_non_negative("acceleration_threshold", self.acceleration_threshold)?;
        check_non_negative(
            "angular_acceleration_threshold",
            self.angular_acceleration_threshold,
        )?;
        check_non_negative("alive_window", self.alive_window)?;
        check_non_negative("force_threshold", self.force_threshold)?;
        check_non_negative("torque_threshold", self.torque_threshold)?;
        Ok(())
    }
}

impl World {
    /// Wakes a body and, at the next step, its whole island.
    pub fn wake_body(&mut self, h: BodyHandle) -> KeaResult<()> {
        self.bodies.get_mut(h)?.wake();
        self.awake.touch_body(h);
        Ok(())
    }

    /// Groups enabled bodies by enabled constraints and marks (in scratch, without changing any
    /// body yet) every sleeping body whose island has an awake member or a member pushed harder
    /// than the wake thresholds. [`World::apply_wake`] commits it once the step succeeds.
    pub(super) fn plan_wake(&mut self) {
        let n = self.bodies.slot_count();
        let s = &mut self.scratch;
        let (ft, tt) = (
            self.settings.dem.force_threshold,
            self.settings.dem.torque_threshold,
        );
        let active = |b: &crate::body::Body| {
            let pushed = b.force.length() > ft || b.torque.length() > tt;
            // A kinematic body set moving wakes itself and what it touches.
            let driven = b.kinematic
                && (b.linear_velocity != Vec3::ZERO || b.angular_velocity != Vec3::ZERO);
            b.enabled && (!b.sleeping || pushed || driven)
        };
        // Only awake bodies and bodies touched since the last step can be active: a body
        // asleep and untouched has no velocity (sleeping zeroes it) and no force.
        let any_active = !self.awake.slots().is_empty()
            || self
                .awake
                .touched()
                .iter()
                .any(|&slot| self.bodies.at(slot as usize).is_some_and(active));
        if !any_active {
            // All asleep and unpushed: nothing wakes, nothing to group (a sleeping pile costs
            // nothing per body).
            s.wake.clear();
            return;
        }
        // Read from the dense index of constraints' bodies and the awake set's flags, not
        // from the constraints' and bodies' records: a sleeping pile beside anything awake
        // has every one of its contacts looked at here, every step.
        s.sleep_sets.reset(n);
        let awake = &self.awake;
        // Disabled constraints (`EMPTY`), the static world (`NO_BODY`) and disabled bodies
        // join nothing.
        let joins = |x: u32| x != EMPTY && x != NO_BODY && awake.is_enabled(x);
        // A sleeping body wakes only through an active one: itself pushed, or a constraint
        // to an awake body (the frontier). Without either, the edges among sleeping bodies
        // join nothing this step needs — it wakes none, and the islands put to sleep after
        // it are of awake bodies — and are not joined (a sleeping pile costs its index).
        let bodies = &self.bodies;
        let mut frontier = awake
            .touched()
            .iter()
            .any(|&slot| awake.is_asleep(slot) && bodies.at(slot as usize).is_some_and(active));
        // A constraint with no awake body joins two asleep, or nothing: the listed ones
        // (`list_awake_constraints`) are all this pass needs.
        let listed = s.awake_constraints_listed;
        let listing = &s.awake_constraints;
        for slot in visited(listed, listing, self.constraint_bodies.len()) {
            let [a, b] = self.constraint_bodies[slot];
            if joins(a) && joins(b) {
                match (awake.is_asleep(a), awake.is_asleep(b)) {
                    (false, false) => s.sleep_sets.union(a, b),
                    (true, true) => {}
                    _ => frontier = true,
                }
            }
        }
        // Nothing wakes without a frontier: the flags stay empty (read as false), so that
        // passes over them cost nothing.
        s.wake.clear();
        if !frontier {
            return;
        }
        s.wake.resize(n, false);
        // Sleeping bodies may wake: this step's passes look at every constraint slot.
        s.awake_constraints_listed = false;
        for &[a, b] in &self.constraint_bodies {
            if joins(a) && joins(b) && (awake.is_asleep(a) || awake.is_asleep(b)) {
                s.sleep_sets.union(a, b);
            }
        }
        s.island_flag.clear();
        s.island_flag.resize(n, 0.0);
        // Only awake bodies and bodies touched since the last step can be active.
        for &slot in awake.slots().iter().chain(awake.touched()) {
            if bodies.at(slot as usize).is_some_and(active) {
                let r = s.sleep_sets.find(slot) as usize;
                s.island_flag[r] = 1.0;
            }
        }
        for slot in 0..n as u32 {
            if awake.is_asleep(slot) {
                let r = s.sleep_sets.find(slot) as usize;
                s.wake[slot as usize] = s.island_flag[r] > 0.0;
            }
        }
    }

    /// Wakes the bodies [`World::plan_wake`] marked.
    pub(super) fn apply_wake(&mut self) {
        for slot in 0..self.scratch.wake.len() {
            if self.scratch.wake[slot] {
                if let Some(b) = self.bodies.at_mut(slot) {
                    b.wake();
                    self.awake.touch(slot as u32);
                }
            }
        }
    }

    /// Wakes every body attached to `h` by a constraint (a support or a joint changed).
    pub(super) fn wake_neighbours(&mut self, h: BodyHandle) {
        for i in 0..self.constraints.slot_count() {
            let Some(c) = self.constraints.at(i) else {
                continue;
            };
            if c.bodies.contains(&Some(h)) {
                for b in c.bodies.into_iter().flatten() {
                    if let Ok(body) = self.bodies.get_mut(b) {
                        body.wake();
                        self.awake.touch_body(b);
                    }
                }
            }
        }
    }

    /// After a step: accumulates each awake body's resting time and disables islands whose
    /// every body has rested for the alive window. Uses the grouping of [`World::wake_islands`].
    pub(super) fn disable_resting_islands(&mut self, dt: Real) {
        // The bodies this step woke are awake now.
        self.awake.refresh(&self.bodies);
        if self.awake.slots().is_empty() {
            return; // nothing awake, nothing to put to sleep
        }
        let n = self.bodies.slot_count();
        let d = self.settings.dem;
        let s = &mut self.scratch;
        // island_flag now holds the smallest resting time of each island's awake bodies.
        s.island_flag.clear();
        s.island_flag.resize(n, Real::INFINITY);
        for &slot in self.awake.slots() {
            let slot = slot as usize;
            let Some(b) = self.bodies.at_mut(slot) else {
                continue;
            };
            let resting = b.linear_velocity.length() < d.velocity_threshold
                && b.angular_velocity.length() < d.angular_velocity_threshold
                && b.linear_acceleration.length() < d.acceleration_threshold
                && b.angular_acceleration.length() < d.angular_acceleration_threshold;
            b.rest_time = if resting { b.rest_time + dt } else { 0.0 };
            let r = s.sleep_sets.find(slot as u32) as usize;
            s.island_flag[r] = s.island_flag[r].min(b.rest_time);
        }
        for k in 0..self.awake.slots().len() {
            let slot = self.awake.slots()[k];
            let r = s.sleep_sets.find(slot) as usize;
            let island_rest = s.island_flag[r];
            let Some(b) = self.bodies.at_mut(slot as usize) else {
                continue;
            };
            if island_rest >= d.alive_window {
                b.sleep();
                self.awake.touch(slot);
            }
        }
    }
}
