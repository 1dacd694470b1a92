//! The step pipeline: the one place a world is stepped. [`PhysicsWorld::step`] checks `dt` once
//! and runs the stages in order, on one thread of the pool at most one hop away:
//!
//! ```text
//! PhysicsWorld::step(dt)            dt checked once (StepSize), one hop onto the pool,
//!                                   the collision settings checked; then n = the world's
//!                                   `world_substeps` times, with h = dt / n:
//!   drive                           scene paths at the world's clock, kinematic targets
//!   CollisionWorld::update_contacts_by    broad phase, narrow phase → the world's contacts
//!   World::substep_by               islands and routing, solve, integrate, sleep, clock + h
//! ```
//!
//! Read-outs derived from the contacts' forces (pair impulses) are computed when asked, not
//! by a stage.
//!
//! The clock is the dynamics world's ([`kea::World::time`]): one clock, saved in its snapshot.

use super::PhysicsWorld;
use crate::Result;
use kea::{Real, StepSize, StepStats, Vec3};

impl PhysicsWorld {
    /// Steps the world by `dt` seconds: drives scene paths and kinematic bodies, finds contacts,
    /// and solves. The statistics include the collision stage's ([`StepStats::collision`]). A
    /// bad `dt` is refused, naming it, before anything changes.
    ///
    /// With the `parallel` feature, a big world's step called from outside rayon's pool runs
    /// on one of its threads (so its parallel sections do not each wait to be handed over);
    /// see [`kea::threads`].
    pub fn step(&mut self, dt: Real) -> Result<StepStats> {
        let dt = StepSize::new(dt)?;
        kea::threads::on_pool(self.dynamics.awake_body_count(), || {
            self.run_stages(dt, true)
        })
    }

    /// `steps` steps of `dt` (at least one), bit for bit as many calls of
    /// [`PhysicsWorld::step`]; only the last works out the joint reactions of trees on the
    /// reduced path, which each step overwrites (see [`kea::World::step_many`]). Returns the
    /// last step's statistics; on an `Err` the steps before it stand.
    pub fn step_many(&mut self, dt: Real, steps: u32) -> Result<StepStats> {
        let dt = StepSize::new(dt)?;
        if steps == 0 {
            return Err(kea::KeaError::OutOfRange {
                arg: "steps",
                value: "0".into(),
                expected: "at least one step",
            }
            .into());
        }
        kea::threads::on_pool(self.dynamics.awake_body_count(), || {
            for _ in 1..steps {
                self.run_stages(dt, false)?;
            }
            self.run_stages(dt, true)
        })
    }

    /// The stages of one step, on the calling thread (the reduced trees' joint reactions
    /// worked out on its last substep when `reactions`). Every input is checked before the
    /// first stage changes anything: `dt` by the caller, the collision settings here, targets
    /// and paths when they were set.
    fn run_stages(&mut self, dt: StepSize, reactions: bool) -> Result<StepStats> {
        // Set once for the substeps' collision and dynamics, whose own guards then only read
        // the mode (`kea::float_mode`).
        let _flush = kea::float_mode::FlushSubnormals::new();
        self.collision.check_settings()?;
        let n = self.dynamics.settings().world_substeps;
        let h = if n == 1 {
            dt
        } else {
            StepSize::new(dt.seconds() / n as Real)?
        };
        let mut stats = StepStats::default();
        for k in 0..n {
            let remaining = dt.seconds() - k as Real * h.seconds();
            self.drive(h, remaining)?;
            self.collision.update_contacts_by(&mut self.dynamics, h)?;
            let last = k + 1 == n;
            stats = self.dynamics.substep_with(h, last, reactions && last)?;
        }
        stats.collision = *self.collision.stats();
        for &h in &self.driven {
            if let Some(Some(m)) = self.meta.get_mut(h.index() as usize) {
                m.target = None;
            }
        }
        Ok(stats)
    }

    /// The drivers: each keyframed path set to where it is at the world's clock, with the
    /// velocity that reaches its next point at the end of the (sub)step `dt`; each
    /// position-driven kinematic body given the velocity that takes it to its target in the
    /// `remaining` time of the step (none without a target). Targets were checked when set, so
    /// nothing here fails on user input.
    fn drive(&mut self, dt: StepSize, remaining: Real) -> Result<()> {
        let time = self.dynamics.time() as Real;
        let h = dt.seconds();
        for (joint, position, velocity) in self.paths.samples(time, h) {
            joint.set_path(&mut self.dynamics, position, velocity)?;
        }
        for i in 0..self.driven.len() {
            let body = self.driven[i];
            let (target, com) = {
                let m = self.meta(body)?;
                (m.target, m.local_com)
            };
            let b = self.dynamics.body_mut(body)?;
            let (v, w) = match target {
                Some((p, q)) => {
                    let v = (p + q * com - b.position()) / remaining;
                    let dq = (q * b.orientation().inverse()).normalize();
                    let dq = if dq.w < 0.0 { -dq } else { dq };
                    let (axis, angle) = dq.to_axis_angle();
                    (v, axis * (angle / remaining))
                }
                None => (Vec3::ZERO, Vec3::ZERO),
            };
            b.set_linear_velocity(v)?;
            b.set_angular_velocity(w)?;
        }
        Ok(())
    }

    /// Time simulated, s: the dynamics world's clock.
    #[must_use]
    pub fn time(&self) -> Real {
        self.dynamics.time() as Real
    }
}
