//! One step driven by hand, as a user who brings their own loop writes it: contacts from the
//! geometry, then the world's step. (Applications step through `kea3d::PhysicsWorld`, whose
//! pipeline runs these stages with its drivers around them.)

use kea::{StepSize, StepStats, World};
use kea_collision::{CollisionResult, CollisionWorld};

/// Steps `world` by `dt` with contacts from `collision`. On error nothing has changed.
#[allow(dead_code)] // not every test file steps
pub fn step(
    collision: &mut CollisionWorld,
    world: &mut World,
    dt: kea::Real,
) -> CollisionResult<StepStats> {
    let dt = StepSize::new(dt)?;
    collision.update_contacts_by(world, dt)?;
    let mut stats = world.step_by(dt)?;
    stats.collision = *collision.stats();
    Ok(stats)
}
