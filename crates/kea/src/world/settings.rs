//! The world's settings, read and changed between steps as one value: gravity, the guide's ε
//! and γ, the contacts' spring, the pivoting caps, partitioning and auto-disable, routing, the
//! iterative path's parameters, projection, runaway speeds, substeps and step timing. A change
//! is checked whole first and changes nothing when it is refused.

use super::{DemMode, DemSettings, SpeedLimits, World, DEFAULT_CONTACT_SPRING};
use crate::articulation::Integrator;
use crate::constraint::Spring;
use crate::error::{check_vec3, KeaError, KeaResult};
use crate::math::{Real, Vec3};
use crate::solver::{IterativeParams, Routing, SolverParams};

/// Everything a world's step reads that a user may change between steps (the guide's
/// `MdtWorldSet*`), given at creation in [`crate::WorldDef::settings`] and changed with
/// [`World::update_settings`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WorldSettings {
    /// Gravity, m/s². Default (0, −9.81, 0).
    pub gravity: Vec3,
    /// Constraint softness ε ≥ 0 (see [`crate::solver::SolverParams::epsilon`]). Default 0.01.
    pub epsilon: Real,
    /// Error reduction γ in [0, 1] (see [`crate::solver::SolverParams::gamma`]). Default 0.2.
    pub gamma: Real,
    /// Softness of contacts that have none of their own: a mass-independent spring (see
    /// [`Spring`]). Default 30 Hz, damping ratio 10 ([`DEFAULT_CONTACT_SPRING`]).
    pub contact_spring: Spring,
    /// Pivoting iteration cap per LCP. Default 100.
    pub max_lcp_iterations: u32,
    /// Coulomb re-solve cap per island. Default 16.
    pub max_friction_passes: u32,
    /// Partitioning and automatic disabling of resting islands (the guide's DEM). Leaving
    /// auto-disable mode wakes every body.
    pub dem: DemSettings,
    /// Which solver handles each island (default hybrid: small islands exact).
    pub routing: Routing,
    /// Settings of the iterative path.
    pub iterative: IterativeParams,
    /// Most position-projection passes after each step, for the islands the exact path solved
    /// (0 to 16; default 0, only the guide's γ correction). Each pass writes the joints' rows at
    /// the new state and moves bodies (not velocities) so that rigid joints close: a Newton
    /// step, stopping early once every error is below 1 µm. Use it with rigid joints, a small
    /// ε (≤ 1e-4): with the default ε a joint is a spring of stiffness `γ/(ε h²)` whose
    /// stretch the projection would fight. 4 passes keep a 100-link chain whipped at 60 Hz
    /// closed to 1 mm (`tests/chain.rs`).
    pub projection_iterations: u32,
    /// Speeds beyond which an island is quarantined as runaway (see
    /// [`World::quarantine_report`]).
    pub speed_limits: SpeedLimits,
    /// Substeps of the whole step (1 to 64; default 1; the iterative path's own substeps are
    /// [`IterativeParams::substeps`]): [`World::step`] by `h` runs this many steps of
    /// `h / n`, the forces applied for the step acting on each (PyBullet's `numSubSteps`).
    /// The integration error of a swinging arm shrinks as `1/n`, at `n` times the cost: a
    /// chaotic double pendulum that parts from the exact path by 3 cm in 1 s at 1 ms keeps
    /// within 5 mm with 8 (`kea3d/tests/robots_vs_mujoco.rs`).
    pub world_substeps: u32,
    /// How the reduced-coordinate path integrates its trees (default
    /// [`Integrator::RungeKutta4`]: a double pendulum keeps its energy at 60 Hz; an MJCF file's
    /// `<option integrator>` sets it). The maximal-coordinate paths step semi-implicit Euler,
    /// as the guide's solver does.
    pub integrator: Integrator,
    /// Contacts on the reduced-coordinate path (default `None`: a contact on a link sends its
    /// tree to the maximal-coordinate paths for that step). `Some(model)`: a tree's links
    /// touching the static world (or a disabled body) stay in reduced coordinates, their
    /// contacts solved in joint space by MuJoCo's soft contact model with this `solref`,
    /// `solimp` and `margin` and a pyramidal friction cone (`kea::articulation`'s contacts),
    /// with the Euler and Runge–Kutta integrators. Only plain contacts are taken: Coulomb
    /// friction equal both ways (or none), no restitution, own softness, adhesion, slip,
    /// conveyor or primary direction. An MJCF file sets it to its contact parameters.
    #[cfg_attr(feature = "serde", serde(default))]
    pub reduced_contacts: Option<crate::SoftLimit>,
    /// Trees with a free (floating) root on the reduced-coordinate path (default false): a
    /// set of bodies joined by a tree's joints and held to nothing (a legged robot, a
    /// satellite with arms) is stepped in joint coordinates, its root's six (three travels
    /// along the world's axes, three turns about its own axes, their chart centred each step)
    /// first. An MJCF file whose root has a free joint sets it.
    #[cfg_attr(feature = "serde", serde(default))]
    pub reduced_free_trees: bool,
    /// With [`WorldSettings::reduced_free_trees`], a floating body with no joint is a tree of
    /// its own too (default false), stepped by [`WorldSettings::integrator`] and, touching
    /// the static world, with [`WorldSettings::reduced_contacts`] — as MuJoCo steps a free
    /// joint. Under Euler its gyroscopic term is then explicit, as in MuJoCo's Euler (a fast
    /// spin runs away there, and is quarantined); off, the free-body path's is implicit. An
    /// MJCF file sets it unless it asks for `implicitfast`, whose free bodies MuJoCo keeps
    /// bounded.
    #[cfg_attr(feature = "serde", serde(default))]
    pub reduced_lone_bodies: bool,
    /// Whether steps time their stages ([`crate::StepStats`]'s `time_*` fields; default true).
    /// Off, they read zero and no clock is read: worth it for small worlds stepped many times
    /// whose statistics nobody reads (see [`crate::timing`]). Results are the same bits
    /// either way.
    pub step_timing: bool,
}

impl Default for WorldSettings {
    fn default() -> Self {
        Self {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            epsilon: 0.01,
            gamma: 0.2,
            contact_spring: DEFAULT_CONTACT_SPRING,
            max_lcp_iterations: 100,
            max_friction_passes: 16,
            dem: DemSettings::default(),
            routing: Routing::default(),
            iterative: IterativeParams::default(),
            projection_iterations: 0,
            speed_limits: SpeedLimits::default(),
            world_substeps: 1,
            integrator: Integrator::RungeKutta4,
            reduced_contacts: None,
            reduced_free_trees: false,
            reduced_lone_bodies: false,
            step_timing: true,
        }
    }
}

impl WorldSettings {
    /// Checks every setting; the error names the first one out of range and its value.
    pub fn validate(&self) -> KeaResult<()> {
        check_vec3("gravity", self.gravity)?;
        self.solver_params(1.0).validate()?;
        self.dem.validate()?;
        check_projection(self.projection_iterations)?;
        check_substeps(self.world_substeps)?;
        if let Some(model) = &self.reduced_contacts {
            model.validate()?;
        }
        self.speed_limits.validate()
    }

    /// The solver's parameters for a step of `dt`.
    pub(crate) fn solver_params(&self, dt: Real) -> SolverParams {
        SolverParams {
            dt,
            epsilon: self.epsilon,
            gamma: self.gamma,
            gravity: self.gravity,
            contact_spring: self.contact_spring,
            max_lcp_iterations: self.max_lcp_iterations,
            max_friction_passes: self.max_friction_passes,
            partition: self.dem.mode != DemMode::NoPartition,
            routing: self.routing,
            iterative: self.iterative,
            timing: self.step_timing,
            body_forces: false,
        }
    }
}

impl World {
    /// The world's settings.
    #[must_use]
    pub fn settings(&self) -> &WorldSettings {
        &self.settings
    }

    /// Changes settings between steps: `change` edits a copy, which is checked whole and then
    /// kept, or refused with nothing changed. A new gravity wakes every body, as does leaving
    /// auto-disable mode.
    ///
    /// ```
    /// use kea::{Vec3, World};
    ///
    /// let mut world = World::with_capacity(4, 4)?;
    /// world.update_settings(|s| s.gravity = Vec3::new(0.0, -1.62, 0.0))?; // the Moon
    /// assert_eq!(world.settings().gravity.y, -1.62);
    /// let refused = world.update_settings(|s| s.gamma = 2.0);
    /// assert!(refused.is_err(), "γ must be in [0, 1]");
    /// assert_eq!(world.settings().gamma, 0.2, "and nothing changed");
    /// # Ok::<(), kea::KeaError>(())
    /// ```
    pub fn update_settings(&mut self, change: impl FnOnce(&mut WorldSettings)) -> KeaResult<()> {
        let mut next = self.settings;
        change(&mut next);
        next.validate()?;
        let wake_all = next.gravity != self.settings.gravity
            || (next.dem.mode != DemMode::PartitionAutoDisable
                && self.settings.dem.mode == DemMode::PartitionAutoDisable);
        self.settings = next;
        if wake_all {
            for slot in 0..self.bodies.slot_count() {
                if let Some(b) = self.bodies.at_mut(slot) {
                    b.wake();
                }
            }
            self.awake.touch_all();
        }
        Ok(())
    }
}

/// Checks a count of projection passes (0 to 16).
pub(super) fn check_projection(iterations: u32) -> KeaResult<()> {
    if iterations > 16 {
        return Err(KeaError::OutOfRange {
            arg: "projection_iterations",
            value: iterations.to_string(),
            expected: "must be in 0..=16",
        });
    }
    Ok(())
}

/// Substeps must be 1 to 64.
pub(crate) fn check_substeps(substeps: u32) -> KeaResult<()> {
    if !(1..=64).contains(&substeps) {
        return Err(KeaError::OutOfRange {
            arg: "world_substeps",
            value: format!("{substeps}"),
            expected: "1 to 64",
        });
    }
    Ok(())
}
