//! The world's solver settings, read and changed between steps: gravity, the guide's ε and γ,
//! the contacts' spring, routing, the iterative path's parameters, projection, step timing.
//! Every setter checks its value first and changes nothing when it refuses.

use super::World;
use crate::constraint::Spring;
use crate::error::{check_non_negative, check_vec3, KeaError, KeaResult};
use crate::math::{Real, Vec3};
use crate::solver::{IterativeParams, Routing};

impl World {
    /// Gravity, m/s².
    #[must_use]
    pub fn gravity(&self) -> Vec3 {
        self.gravity
    }

    /// Sets gravity (the guide's `MdtWorldSetGravity`).
    pub fn set_gravity(&mut self, g: Vec3) -> KeaResult<()> {
        self.gravity = check_vec3("gravity", g)?;
        for slot in 0..self.bodies.slot_count() {
            if let Some(b) = self.bodies.at_mut(slot) {
                b.wake();
            }
        }
        Ok(())
    }

    /// Softness ε.
    #[must_use]
    pub fn epsilon(&self) -> Real {
        self.epsilon
    }

    /// Sets softness ε (≥ 0).
    pub fn set_epsilon(&mut self, eps: Real) -> KeaResult<()> {
        self.epsilon = check_non_negative("epsilon", eps)?;
        Ok(())
    }

    /// The default softness of contacts (see [`crate::WorldDef::contact_spring`]).
    #[must_use]
    pub fn contact_spring(&self) -> Spring {
        self.contact_spring
    }

    /// Sets the default softness of contacts (frequency > 0, damping ratio ≥ 0).
    pub fn set_contact_spring(&mut self, spring: Spring) -> KeaResult<()> {
        spring.validate("contact_spring")?;
        self.contact_spring = spring;
        Ok(())
    }

    /// Error reduction γ.
    #[must_use]
    pub fn gamma(&self) -> Real {
        self.gamma
    }

    /// Sets error reduction γ in [0, 1].
    pub fn set_gamma(&mut self, gamma: Real) -> KeaResult<()> {
        check_non_negative("gamma", gamma)?;
        if gamma > 1.0 {
            return Err(KeaError::OutOfRange {
                arg: "gamma",
                value: format!("{gamma}"),
                expected: "must be in [0, 1]",
            });
        }
        self.gamma = gamma;
        Ok(())
    }

    /// Island routing (see [`Routing`]).
    #[must_use]
    pub fn routing(&self) -> &Routing {
        &self.routing
    }

    /// Sets island routing: hybrid (default), or force the exact or iterative path.
    pub fn set_routing(&mut self, routing: Routing) -> KeaResult<()> {
        routing.validate()?;
        self.routing = routing;
        Ok(())
    }

    /// Settings of the iterative path.
    #[must_use]
    pub fn iterative_params(&self) -> &IterativeParams {
        &self.iterative
    }

    /// Sets substeps, iterations and the correction speed cap of the iterative path.
    pub fn set_iterative_params(&mut self, params: IterativeParams) -> KeaResult<()> {
        params.validate()?;
        self.iterative = params;
        Ok(())
    }

    /// Position-projection passes after each step (see [`crate::WorldDef::projection_iterations`]).
    #[must_use]
    pub fn projection_iterations(&self) -> u32 {
        self.projection_iterations
    }

    /// Sets the position-projection passes (0 to 16).
    pub fn set_projection_iterations(&mut self, iterations: u32) -> KeaResult<()> {
        check_projection(iterations)?;
        self.projection_iterations = iterations;
        Ok(())
    }

    /// Substeps of the whole step (see [`crate::WorldDef::world_substeps`]).
    #[must_use]
    pub fn world_substeps(&self) -> u32 {
        self.world_substeps
    }

    /// Sets the substeps per step (1 to 64).
    pub fn set_world_substeps(&mut self, substeps: u32) -> KeaResult<()> {
        check_substeps(substeps)?;
        self.world_substeps = substeps;
        Ok(())
    }

    /// Whether steps time their stages ([`crate::StepStats`]'s `time_*` fields; default true).
    #[must_use]
    pub fn step_timing(&self) -> bool {
        self.step_timing
    }

    /// Turns the stage times of [`crate::StepStats`] on or off. Off, they read zero and no clock is
    /// read: worth it for small worlds stepped many times whose statistics nobody reads (see
    /// [`crate::timing`]). Results are the same bits either way.
    pub fn set_step_timing(&mut self, on: bool) {
        self.step_timing = on;
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
