//! Snapshots (feature `serde`): everything of a world that affects its future, as plain data
//! that serde can write in any format. Restoring one and stepping reproduces the uninterrupted
//! run bit for bit: bodies with their sleep timers, constraints with their joint state, last
//! step's forces (the warm starts), contacts with their points' ids, the free lists that decide
//! the next handles, the quarantine. The solver's workspace is left out; a restored world
//! rebuilds it, which changes no result.

use super::constraint_entry::{ConstraintEntry, ConstraintKind};
use super::{QuarantineEvent, SpeedLimits, World, WorldDef, WorldSettings};
use crate::articulation::Integrator;
use crate::body::Body;
use crate::constraint::Spring;
use crate::error::{KeaError, KeaResult};
use crate::handle::{ArenaState, BodyHandle, ConstraintHandle};
use crate::math::{Real, Vec3};
use crate::solver::{IterativeParams, Reaction, Routing};
use serde::{Deserialize, Serialize};

/// The snapshot format's version: a snapshot of another version is refused by name.
pub const SNAPSHOT_VERSION: u32 = 3;

/// A world's state (see the module docs). Take one with [`World::snapshot`], write it with any
/// serde format, and make a world of it with [`World::restore`].
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct WorldSnapshot {
    /// Format version ([`SNAPSHOT_VERSION`]).
    pub version: u32,
    /// Whether reals are f64 (a snapshot restores only in its own precision).
    pub double_precision: bool,
    id: u32,
    max_bodies: usize,
    max_constraints: usize,
    max_island_rows: usize,
    bodies: ArenaState<Body>,
    constraints: ArenaState<ConstraintEntry>,
    gravity: Vec3,
    epsilon: Real,
    gamma: Real,
    contact_spring: Spring,
    max_lcp_iterations: u32,
    max_friction_passes: u32,
    dem: super::DemSettings,
    routing: Routing,
    iterative: IterativeParams,
    projection_iterations: u32,
    speed_limits: SpeedLimits,
    #[serde(default = "one")]
    world_substeps: u32,
    /// Absent from snapshots made before it existed, which stepped Euler.
    #[serde(default = "euler")]
    integrator: Integrator,
    /// The reduced path's contact model (absent in older snapshots: none).
    #[serde(default)]
    reduced_contacts: Option<crate::SoftLimit>,
    /// Whether floating trees are reduced (absent in older snapshots: no).
    #[serde(default)]
    reduced_free_trees: bool,
    /// Whether lone floating bodies are reduced (absent in older snapshots: no).
    #[serde(default)]
    reduced_lone_bodies: bool,
    quarantine: Vec<QuarantineEvent>,
    /// Last step's λ (joints' warm starts, through each constraint's `last_rows`).
    lambda: Vec<Real>,
    /// Last step's contact forces per row, where they sit, and the broken constraints: what
    /// the read-outs answer until the next step.
    contact_lambda: Vec<Real>,
    contact_rows: Vec<(u32, u32)>,
    contact_reactions: Vec<[Reaction; 2]>,
    broken: Vec<ConstraintHandle>,
    time: f64,
    steps: u64,
    /// The trees the reduced path keeps (their coordinates in `f64`), so that a restored
    /// world steps them on the same bits.
    #[serde(default)]
    reduced_trees: Vec<super::reduced::SavedTree>,
    /// Fixed tendons by index, `None` where removed (absent in older snapshots: none).
    #[serde(default)]
    tendons: Vec<Option<super::FixedTendon>>,
}

impl World {
    /// The world's state now, for saving. Refused for a world holding custom constraints
    /// (their code cannot be saved).
    pub fn snapshot(&self) -> KeaResult<WorldSnapshot> {
        let custom = self
            .constraints
            .iter()
            .any(|(_, e)| matches!(e.kind, ConstraintKind::Custom(_)));
        if custom {
            return Err(KeaError::InvalidState {
                operation: "snapshot",
                reason: "the world holds a custom constraint, whose code cannot be saved",
            });
        }
        let s = &self.scratch;
        Ok(WorldSnapshot {
            version: SNAPSHOT_VERSION,
            double_precision: cfg!(feature = "f64"),
            id: self.id,
            max_bodies: self.bodies.capacity(),
            max_constraints: self.constraints.capacity(),
            max_island_rows: self.max_island_rows,
            bodies: self.bodies.state(),
            constraints: self.constraints.state(),
            gravity: self.settings.gravity,
            epsilon: self.settings.epsilon,
            gamma: self.settings.gamma,
            contact_spring: self.settings.contact_spring,
            max_lcp_iterations: self.settings.max_lcp_iterations,
            max_friction_passes: self.settings.max_friction_passes,
            dem: self.settings.dem,
            routing: self.settings.routing,
            iterative: self.settings.iterative,
            projection_iterations: self.settings.projection_iterations,
            speed_limits: self.settings.speed_limits,
            world_substeps: self.settings.world_substeps,
            integrator: self.settings.integrator,
            reduced_contacts: self.settings.reduced_contacts,
            reduced_free_trees: self.settings.reduced_free_trees,
            reduced_lone_bodies: self.settings.reduced_lone_bodies,
            quarantine: self.quarantine.clone(),
            lambda: s.lambda.clone(),
            contact_lambda: s.contact_lambda.clone(),
            contact_rows: s.contact_rows.clone(),
            contact_reactions: s.contact_reactions.clone(),
            broken: s.broken.clone(),
            time: self.time,
            steps: self.steps,
            reduced_trees: self.saved_trees(),
            tendons: self.tendons.clone(),
        })
    }

    /// The world a snapshot was taken of, at the instant it was taken. It keeps that world's
    /// id, so the handles held for it work in the restored one. A snapshot of another version
    /// or precision, or one whose parts do not fit together, is refused by name.
    pub fn restore(snapshot: WorldSnapshot) -> KeaResult<World> {
        let bad = |reason: String| KeaError::Inconsistent {
            arg: "snapshot",
            reason,
        };
        if snapshot.version != SNAPSHOT_VERSION {
            return Err(bad(format!(
                "version {} (this Kea reads version {SNAPSHOT_VERSION})",
                snapshot.version
            )));
        }
        if snapshot.double_precision != cfg!(feature = "f64") {
            return Err(bad("it was taken in the other precision (f32 / f64)".into()));
        }
        let mut world = World::new(WorldDef {
            max_bodies: snapshot.max_bodies,
            max_constraints: snapshot.max_constraints,
            max_island_rows: snapshot.max_island_rows,
            settings: WorldSettings {
                gravity: snapshot.gravity,
                epsilon: snapshot.epsilon,
                gamma: snapshot.gamma,
                contact_spring: snapshot.contact_spring,
                max_lcp_iterations: snapshot.max_lcp_iterations,
                max_friction_passes: snapshot.max_friction_passes,
                dem: snapshot.dem,
                routing: snapshot.routing,
                iterative: snapshot.iterative,
                projection_iterations: snapshot.projection_iterations,
                speed_limits: snapshot.speed_limits,
                world_substeps: snapshot.world_substeps,
                integrator: snapshot.integrator,
                reduced_contacts: snapshot.reduced_contacts,
                reduced_free_trees: snapshot.reduced_free_trees,
                reduced_lone_bodies: snapshot.reduced_lone_bodies,
                step_timing: true,
            },
        })?;
        let id = snapshot.id;
        world.id = id;
        world.bodies =
            crate::handle::Arena::from_state(id, snapshot.max_bodies, "bodies", snapshot.bodies)?;
        world.constraints = crate::handle::Arena::from_state(
            id,
            snapshot.max_constraints,
            "constraints",
            snapshot.constraints,
        )?;
        check_bodies(&world)?;
        check_constraints(&world, snapshot.lambda.len(), snapshot.contact_lambda.len())?;
        world.reindex_constraints();
        crate::handle::reserve_world_id(id);
        world.quarantine = snapshot.quarantine;
        let s = &mut world.scratch;
        s.lambda.extend_from_slice(&snapshot.lambda);
        s.contact_lambda.extend_from_slice(&snapshot.contact_lambda);
        s.contact_rows.extend_from_slice(&snapshot.contact_rows);
        s.contact_reactions
            .extend_from_slice(&snapshot.contact_reactions);
        s.broken.extend_from_slice(&snapshot.broken);
        // The constraints the last step wrote read-outs to: the next step clears them.
        for (h, e) in world.constraints.iter() {
            if e.last_rows.is_some() || e.reaction != [Reaction::default(); 2] {
                s.written.push(h.index());
            }
        }
        world.time = snapshot.time;
        world.steps = snapshot.steps;
        world.restore_trees(snapshot.reduced_trees)?;
        for t in snapshot.tendons.iter().flatten() {
            world.check_tendon(t)?;
        }
        world.tendons = snapshot.tendons;
        Ok(world)
    }
}

/// Every body's state finite, with a unit orientation and a mass in range.
fn check_bodies(world: &World) -> KeaResult<()> {
    for (h, b) in world.bodies.iter() {
        let finite = b.position.is_finite()
            && b.orientation.is_finite()
            && (b.orientation.length() - 1.0).abs() <= crate::math::UNIT_TOLERANCE
            && b.linear_velocity.is_finite()
            && b.angular_velocity.is_finite()
            && b.inv_inertia.is_finite();
        if !finite || crate::error::check_mass("mass", b.mass).is_err() {
            return Err(KeaError::Inconsistent {
                arg: "snapshot",
                reason: format!("body {h:?} has a bad state"),
            });
        }
    }
    Ok(())
}

/// Every constraint's bodies live in this world, and its last rows inside last step's λ (a
/// contact's inside the contact forces).
fn check_constraints(world: &World, lambda: usize, contact_lambda: usize) -> KeaResult<()> {
    for (h, e) in world.constraints.iter() {
        let bodies_live = e
            .bodies
            .iter()
            .flatten()
            .all(|b: &BodyHandle| world.bodies.check(*b).is_ok());
        let len = match e.kind {
            ConstraintKind::Contact(_) => contact_lambda,
            _ => lambda,
        };
        let rows_inside = e
            .last_rows
            .is_none_or(|(first, count)| (first as usize + count as usize) <= len);
        if !bodies_live || !rows_inside {
            return Err(KeaError::Inconsistent {
                arg: "snapshot",
                reason: format!("constraint {h:?} names a missing body or rows"),
            });
        }
    }
    Ok(())
}

/// `#[serde(with = "crate::world::serde_real")]` for a real that may be infinite (a hard
/// stop's stiffness): in a text form, a number when finite and `"inf"` or `"-inf"` otherwise,
/// since JSON has no infinity; in a binary form, the number as it is.
pub(crate) mod serde_real {
    use crate::math::Real;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    #[serde(untagged)]
    enum Text {
        Number(Real),
        Word(String),
    }

    pub(crate) fn serialize<S: Serializer>(x: &Real, s: S) -> Result<S::Ok, S::Error> {
        if !s.is_human_readable() {
            return x.serialize(s); // binary forms carry infinities as they are
        }
        match *x {
            x if x.is_finite() => Text::Number(x),
            x if x > 0.0 => Text::Word("inf".into()),
            x if x < 0.0 => Text::Word("-inf".into()),
            _ => Text::Word("NaN".into()),
        }
        .serialize(s)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Real, D::Error> {
        if !d.is_human_readable() {
            return Real::deserialize(d);
        }
        match Text::deserialize(d)? {
            Text::Number(x) => Ok(x),
            Text::Word(w) => match w.as_str() {
                "inf" => Ok(Real::INFINITY),
                "-inf" => Ok(Real::NEG_INFINITY),
                "NaN" => Ok(Real::NAN),
                other => Err(serde::de::Error::custom(format!(
                    "expected a number, \"inf\" or \"-inf\", got \"{other}\""
                ))),
            },
        }
    }
}

/// Snapshots from before substeps step once.
fn one() -> u32 {
    1
}

fn euler() -> Integrator {
    Integrator::Euler
}
