//! What a run did, added up step by step, and printed at the end.

use kea::{Real, StepStats};
use kea3d::PhysicsWorld;
use std::time::Duration;

/// Totals over a run.
pub struct Summary {
    start_energy: Real,
    wall: Duration,
    collect: Duration,
    gather: Duration,
    solve_exact: Duration,
    solve_iterative: Duration,
    integrate: Duration,
    dynamics: Duration,
    /// Time spent measuring joint error, left out of the step timings.
    measuring: Duration,
    max_joint_error: Real,
    warnings: u32,
    broken: u32,
    quarantined: u32,
    last: Option<StepStats>,
    started: std::time::Instant,
}

/// Kinetic plus gravitational potential energy of every body, J.
pub fn energy(built: &PhysicsWorld) -> Real {
    let g = built.dynamics().settings().gravity;
    built
        .dynamics()
        .bodies()
        .map(|(_, b)| b.kinetic_energy() - b.mass() * g.dot(b.position()))
        .sum()
}

fn ms(d: Duration, steps: u32) -> f64 {
    d.as_secs_f64() * 1000.0 / f64::from(steps)
}

impl Summary {
    /// Starts counting, with the scene's energy now.
    pub fn new(built: &PhysicsWorld) -> Self {
        Self {
            start_energy: energy(built),
            wall: Duration::ZERO,
            collect: Duration::ZERO,
            gather: Duration::ZERO,
            solve_exact: Duration::ZERO,
            solve_iterative: Duration::ZERO,
            integrate: Duration::ZERO,
            dynamics: Duration::ZERO,
            measuring: Duration::ZERO,
            max_joint_error: 0.0,
            warnings: 0,
            broken: 0,
            quarantined: 0,
            last: None,
            started: std::time::Instant::now(),
        }
    }

    /// Adds one step's statistics.
    pub fn add(&mut self, s: &StepStats) {
        self.collect += s.time_collect;
        self.gather += s.time_gather;
        self.solve_exact += s.solver.time_solve_exact;
        self.solve_iterative += s.solver.time_solve_iterative;
        self.integrate += s.solver.time_integrate;
        self.dynamics += s.time_total;
        self.warnings += u32::from(!s.solver.is_clean());
        self.broken += s.broken_joints;
        self.quarantined += s.quarantined_bodies;
        self.last = Some(*s);
        self.wall = self.started.elapsed().saturating_sub(self.measuring);
    }

    /// Measures how far the joints have come apart after a step (`World::joint_error`),
    /// keeping the largest; its time is left out of the step timings.
    pub fn measure_joints(&mut self, built: &mut PhysicsWorld) {
        let start = std::time::Instant::now();
        self.max_joint_error = self.max_joint_error.max(built.dynamics_mut().joint_error());
        self.measuring += start.elapsed();
    }

    /// Prints the human summary of `kea run`.
    pub fn print(&self, name: &str, built: &PhysicsWorld, steps: u32, dt: Real) {
        let seconds = self.wall.as_secs_f64();
        let last = self.last.unwrap_or_default();
        println!(
            "{name}: {steps} steps of {dt} s ({:.2} s simulated)",
            f64::from(steps) * kea::math::wide(dt)
        );
        println!(
            "  speed      {:.0} steps/s, {:.3} ms/step (collision and dynamics)",
            f64::from(steps) / seconds.max(1e-9),
            seconds * 1000.0 / f64::from(steps)
        );
        println!(
            "  collision  {:.3} ms/step (broad and narrow phase, contact updates)",
            ms(self.wall.saturating_sub(self.dynamics), steps)
        );
        println!(
            "  dynamics   collect {:.3}, rows {:.3}, exact {:.3}, iterative {:.3}, integrate {:.3} ms/step",
            ms(self.collect, steps),
            ms(self.gather, steps),
            ms(self.solve_exact, steps),
            ms(self.solve_iterative, steps),
            ms(self.integrate, steps)
        );
        println!(
            "  bodies     {} awake, {} asleep; {} constraints, {} rows in the last step",
            last.bodies, last.sleeping_bodies, last.constraints, last.rows
        );
        println!(
            "  energy     {:.3} J at the start, {:.3} J at the end",
            self.start_energy,
            energy(built)
        );
        println!(
            "  solver     {} steps with warnings, {} joints broken, {} bodies quarantined, largest joint error {:.2e} m, deepest contact {:.2e} m",
            self.warnings,
            self.broken,
            self.quarantined,
            self.max_joint_error,
            built.collision().deepest_penetration(built.dynamics())
        );
    }

    /// The counts of `kea bench`'s line: bodies, constraints of the last step, steps with
    /// solver warnings.
    pub fn bench_counts(&self, built: &PhysicsWorld) -> String {
        let last = self.last.unwrap_or_default();
        format!(
            "bodies={} constraints={} warnings={}",
            built.named_bodies().len(),
            last.constraints,
            self.warnings
        )
    }
}

/// The quarantined islands of a run, by body name: "2 bodies quarantined (runaway at
/// 2.1e4 m/s): ragdoll1.torso, ragdoll1.head".
pub fn quarantine_report(built: &PhysicsWorld) -> String {
    let mut parts = Vec::new();
    for event in built.dynamics().quarantine_report() {
        let names: Vec<&str> = event
            .bodies
            .iter()
            .map(|h| {
                built
                    .named_bodies()
                    .iter()
                    .find(|(_, b)| b == h)
                    .map_or("(unnamed)", |(n, _)| n.as_str())
            })
            .collect();
        let why = match event.reason {
            kea::QuarantineReason::NonFinite => "non-finite state".to_string(),
            kea::QuarantineReason::Runaway { linear, angular } => {
                format!("runaway at {linear:.3e} m/s, {angular:.3e} rad/s")
            }
        };
        let shown = names.len().min(10);
        let more = if names.len() > shown {
            format!(" and {} more", names.len() - shown)
        } else {
            String::new()
        };
        parts.push(format!(
            "{} bodies quarantined at step {} ({why}): {}{more}",
            names.len(),
            event.step + 1,
            names[..shown].join(", ")
        ));
    }
    parts.join("; ")
}
