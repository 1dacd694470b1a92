//! The world (the guide's Mdt layer): bodies, constraints and the step, in a retained API.
//!
//! A world is created with capacities ([`WorldDef::max_bodies`], [`WorldDef::max_constraints`],
//! the guide's `MdtWorldCreate`) and reserves all its storage then: within them, creating and
//! destroying bodies and constraints never allocates, and a warm step allocates nothing. A full
//! world doubles its room (allocating once) rather than refuse; [`World::reserve`] grows it
//! ahead of time. Worlds are
//! independent: create as many as you like, and handles of one are rejected by the others.

mod awake;
mod body_constraints;
mod constraint_entry;
mod constraint_index;
mod constraints;
mod gather;
mod held;
mod islands;
mod joint_frames;
mod joint_handle;
mod joint_spec;
mod joints;
mod quarantine;
mod reduced;
mod settings;
mod sketch;
mod sleep;
#[cfg(feature = "serde")]
mod snapshot;
mod state_copy;
mod step;
mod step_size;
mod tendons;
mod write_back;

pub use held::HeldState;
pub use islands::IslandList;
pub use joint_handle::{JointHandle, JointKind, OneCoordinate};
pub use joint_spec::JointSpec;
pub use quarantine::{QuarantineEvent, QuarantineReason, SpeedLimits};
pub use settings::WorldSettings;
pub use sketch::{JointRange, JointSketch};
pub use sleep::{DemMode, DemSettings};
#[cfg(feature = "serde")]
pub(crate) use snapshot::serde_real;
#[cfg(feature = "serde")]
pub use snapshot::{WorldSnapshot, SNAPSHOT_VERSION};
pub use step::{CollisionStats, StepStats, PROJECTION_TOLERANCE};
pub use step_size::StepSize;
pub use tendons::{FixedTendon, TendonHandle, TendonTerm};

use crate::body::{Body, BodyDef};
use crate::constraint::Row;
use crate::error::{KeaError, KeaResult};
use crate::handle::{next_world_id, Arena, BodyHandle, ConstraintHandle};
use crate::math::Real;
use crate::solver::{
    ConstraintBlock, IslandReport, Reaction, Solver, SolverBody, SolverContact,
    DEFAULT_CONTACT_SPRING,
};
use constraint_entry::ConstraintEntry;

/// Parameters of a new world. Every tunable says its unit, normal value and range.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldDef {
    /// Bodies to reserve room for up front (1 to [`MAX_CAPACITY`]). A full world doubles its
    /// capacity (allocating once), so this is the size for which nothing allocates.
    pub max_bodies: usize,
    /// Constraints (joints + contacts) to reserve room for up front (1 to [`MAX_CAPACITY`]);
    /// grows like [`WorldDef::max_bodies`].
    pub max_constraints: usize,
    /// Rows of the largest island to reserve solver memory for up front. The exact solver's
    /// memory grows as rows², so this is a hint, not a limit: bigger islands grow the workspace
    /// once (reported in [`StepStats`]). Default 256.
    pub max_island_rows: usize,
    /// What the step reads, changeable later with [`World::update_settings`].
    pub settings: WorldSettings,
}

impl Default for WorldDef {
    fn default() -> Self {
        Self {
            max_bodies: 1024,
            max_constraints: 4096,
            max_island_rows: 256,
            settings: WorldSettings::default(),
        }
    }
}

/// Reused per-step buffers, sized from the capacities.
#[derive(Default, Clone)]
#[repr(C)]
struct StepScratch {
    // `repr(C)`: the state a held world trades first (see `World`).
    lambda: Vec<Real>,
    /// Each contact's per-row forces (normal, friction 1, friction 2 per point), where they
    /// sit in `contact_lambda`, and its reactions, from the last step.
    contact_lambda: Vec<Real>,
    contact_rows: Vec<(u32, u32)>,
    contact_reactions: Vec<[Reaction; 2]>,
    /// Constraints that broke in the last step.
    broken: Vec<ConstraintHandle>,
    /// Slots of the constraints whose read-outs (rows, reactions) the last step wrote: the
    /// only ones the next step must clear (a sleeping pile's contacts are not visited).
    written: Vec<u32>,
    /// The reduced-coordinate path's buffers.
    reduced: reduced::ReducedScratch,
    solver_bodies: Vec<SolverBody>,
    /// Body slot → solver body index (`u32::MAX` if not simulated this step).
    slot_to_solver: Vec<u32>,
    /// Solver body index → body slot.
    solver_to_slot: Vec<u32>,
    rows: Vec<Row>,
    blocks: Vec<ConstraintBlock>,
    /// Block index → constraint slot.
    block_constraint: Vec<u32>,
    /// The enabled contacts of the step, as the solver takes them, and their constraint slots.
    contacts: Vec<SolverContact>,
    contact_constraint: Vec<u32>,
    /// The previous step's λ, for warm starting the iterative path.
    prev_lambda: Vec<Real>,
    reactions: Vec<[Reaction; 2]>,
    /// Body slots grouped by enabled constraints, for auto-disable.
    sleep_sets: crate::union_find::UnionFind,
    /// Per island root: awake flag, then smallest resting time.
    island_flag: Vec<Real>,
    /// The slots, ascending, of the enabled constraints with an awake body, when
    /// `awake_constraints_listed` (`World::list_awake_constraints`): the constraints this
    /// step's passes visit while no sleeping body wakes; else they scan every slot.
    awake_constraints: Vec<u32>,
    awake_constraints_listed: bool,
    /// Sleeping bodies (by slot) that this step wakes, committed when it succeeds.
    wake: Vec<bool>,
    /// Per tendon: stepped by the reduced path this step.
    tendon_reduced: Vec<bool>,
    /// Joint slots whose rows came out non-finite in this step's gather.
    unwritable: Vec<u32>,
    /// Per constraint of the step: (slot, first row, row count), for projection.
    step_layout: Vec<(u32, u32, u32)>,
    /// The step's λ lined up with the rows a projection pass gathers.
    projection_lambda: Vec<Real>,
    /// Islands of the step's solver bodies, and which roots are bad, for quarantine.
    quarantine_sets: crate::union_find::UnionFind,
    quarantine_root: Vec<bool>,
}

/// A simulated world.
///
/// A clone is the same world at the same instant (it accepts the same handles): stepping both
/// alike gives bit-identical results.
///
/// ```
/// use kea::{BodyDef, JointSpec, Vec3, World};
///
/// let mut world = World::with_capacity(16, 64)?; // room for 16 bodies, 64 constraints
/// world.update_settings(|s| s.gravity = Vec3::new(0.0, -9.81, 0.0))?;
/// let bob = world.create_body(&BodyDef {
///     position: Vec3::new(1.0, 0.0, 0.0),
///     ..BodyDef::default()
/// })?;
/// world.create_joint(bob, None, JointSpec::ball(Vec3::ZERO))?; // a 1 m pendulum from the origin
/// for _ in 0..30 {
///     world.step(1.0 / 60.0)?;
/// }
/// let p = world.body(bob)?.position();
/// assert!((p.length() - 1.0).abs() < 0.01, "the rod keeps its length: {p}");
/// assert!(p.y < -0.5, "and the bob swings down: {p}");
/// # Ok::<(), kea::KeaError>(())
/// ```
#[derive(Clone)]
#[repr(C)]
pub struct World {
    // `repr(C)`, the state first (what a batch's worker trades with a held world,
    // `state_copy.rs`), its scratch's state at the head of `scratch`: the trade reads and
    // writes a few contiguous cache lines of the held world, not lines across its 4 KB.
    id: u32,
    /// Changes whenever a joint is made, destroyed, enabled, disabled or re-bodied.
    joint_revision: u64,
    time: f64,
    steps: u64,
    /// Rows the solver's workspace was reserved for ([`WorldDef::max_island_rows`]).
    #[cfg_attr(not(feature = "serde"), allow(dead_code))] // kept for snapshots
    max_island_rows: usize,
    /// Per constraint slot, the slots of its two bodies (`NO_BODY` for the static world), or
    /// `[EMPTY; 2]` for an empty or disabled slot: what a step scans to pass constraints of
    /// sleeping bodies without reading their entries (`constraint_index.rs`).
    constraint_bodies: Vec<[u32; 2]>,
    /// Per constraint slot: a hinge or a prismatic joint (what the reduced path may take), so
    /// that its search passes contacts without reading their entries.
    tree_joint_slots: Vec<bool>,
    /// Per body slot, the enabled constraints that touch it (`body_constraints.rs`), kept
    /// with `constraint_bodies`.
    body_constraints: body_constraints::BodyConstraints,
    /// Islands quarantined and not yet cleared.
    quarantine: Vec<QuarantineEvent>,
    /// While quarantining: each new event's island root, and whether it has its reason.
    quarantine_roots: Vec<(u32, bool)>,
    /// Fixed tendons by index (`None`: removed; `tendons.rs`).
    tendons: Vec<Option<FixedTendon>>,
    /// The awake bodies' slots, kept as bodies change (`awake.rs`).
    awake: awake::AwakeSet,
    settings: WorldSettings,
    scratch: StepScratch,
    bodies: Arena<Body, BodyHandle>,
    constraints: Arena<ConstraintEntry, ConstraintHandle>,
    solver: Solver,
}

impl std::fmt::Debug for World {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("World")
            .field("id", &self.id)
            .field("bodies", &self.bodies.len())
            .field("constraints", &self.constraints.len())
            .field("settings", &self.settings)
            .field("time", &self.time)
            .finish()
    }
}

/// Grows `v`'s capacity to hold at least `n` items in all.
fn reserve_total<T>(v: &mut Vec<T>, n: usize) {
    if v.capacity() < n {
        v.reserve(n - v.len());
    }
}

/// Upper bound on rows one constraint writes, used to size the row buffer up front.
const ROWS_PER_CONSTRAINT: usize = 6;

impl World {
    /// Creates a world, reserving storage for its capacities (the guide's `MdtWorldCreate`).
    pub fn new(def: WorldDef) -> KeaResult<Self> {
        check_capacity("max_bodies", def.max_bodies)?;
        check_capacity("max_constraints", def.max_constraints)?;
        def.settings.validate()?;
        let id = next_world_id();
        let rows = def.max_constraints * ROWS_PER_CONSTRAINT;
        let island_rows = def.max_island_rows.min(rows);
        let mut sleep_sets = crate::union_find::UnionFind::default();
        sleep_sets.reserve(def.max_bodies);
        let mut quarantine_sets = crate::union_find::UnionFind::default();
        quarantine_sets.reserve(def.max_bodies);
        let scratch = StepScratch {
            solver_bodies: Vec::with_capacity(def.max_bodies),
            slot_to_solver: Vec::with_capacity(def.max_bodies),
            solver_to_slot: Vec::with_capacity(def.max_bodies),
            rows: Vec::with_capacity(rows),
            blocks: Vec::with_capacity(def.max_constraints),
            block_constraint: Vec::with_capacity(def.max_constraints),
            contacts: Vec::with_capacity(def.max_constraints),
            contact_constraint: Vec::with_capacity(def.max_constraints),
            contact_lambda: Vec::with_capacity(def.max_constraints * 3),
            contact_rows: Vec::with_capacity(def.max_constraints),
            contact_reactions: Vec::with_capacity(def.max_constraints),
            lambda: Vec::with_capacity(rows),
            prev_lambda: Vec::with_capacity(rows),
            reactions: Vec::with_capacity(def.max_constraints),
            sleep_sets,
            island_flag: Vec::with_capacity(def.max_bodies),
            wake: Vec::with_capacity(def.max_bodies),
            awake_constraints: Vec::with_capacity(def.max_constraints),
            awake_constraints_listed: false,
            broken: Vec::with_capacity(def.max_constraints),
            written: Vec::with_capacity(def.max_constraints),
            unwritable: Vec::with_capacity(def.max_constraints),
            step_layout: Vec::with_capacity(def.max_constraints),
            projection_lambda: Vec::with_capacity(rows),
            quarantine_sets,
            quarantine_root: Vec::with_capacity(def.max_bodies),
            reduced: reduced::ReducedScratch::default(),
            tendon_reduced: Vec::new(),
        };
        Ok(Self {
            id,
            bodies: Arena::new(id, def.max_bodies, "bodies"),
            constraints: Arena::new(id, def.max_constraints, "constraints"),
            constraint_bodies: Vec::with_capacity(def.max_constraints),
            tree_joint_slots: Vec::with_capacity(def.max_constraints),
            body_constraints: body_constraints::BodyConstraints::with_capacity(
                def.max_bodies,
                def.max_constraints,
            ),
            joint_revision: constraint_index::next_joint_revision(),
            settings: def.settings,
            max_island_rows: def.max_island_rows,
            quarantine: Vec::new(),
            quarantine_roots: Vec::new(),
            solver: Solver::with_capacity(
                def.max_bodies,
                def.max_constraints,
                rows,
                def.max_constraints,
                island_rows,
            ),
            scratch,
            tendons: Vec::new(),
            time: 0.0,
            steps: 0,
            awake: awake::AwakeSet::stale(),
        })
    }

    /// A world with capacities for `max_bodies` bodies and `max_constraints` constraints and
    /// default parameters. The capacities are reserved now and grow when full:
    ///
    /// ```
    /// use kea::{BodyDef, World};
    ///
    /// let mut world = World::with_capacity(1, 1)?;
    /// for _ in 0..3 {
    ///     world.create_body(&BodyDef::default())?; // past the capacity: it grows
    /// }
    /// assert!(world.max_bodies() >= 3);
    /// # Ok::<(), kea::KeaError>(())
    /// ```
    pub fn with_capacity(max_bodies: usize, max_constraints: usize) -> KeaResult<Self> {
        Self::new(WorldDef {
            max_bodies,
            max_constraints,
            ..WorldDef::default()
        })
    }

    /// This world's id (handles carry it).
    #[must_use]
    pub fn id(&self) -> u32 {
        self.id
    }
    /// Simulated time, s.
    #[must_use]
    pub fn time(&self) -> f64 {
        self.time
    }
    /// Steps taken.
    #[must_use]
    pub fn step_count(&self) -> u64 {
        self.steps
    }
    /// Creates a body (the guide's `MdtBodyCreate` + setters). Errors name the bad field.
    pub fn create_body(&mut self, def: &BodyDef) -> KeaResult<BodyHandle> {
        let body = Body::from_def(def)?;
        let h = self.bodies.insert(body)?;
        self.awake.touch_body(h);
        Ok(h)
    }

    /// Destroys a body and every constraint attached to it.
    pub fn destroy_body(&mut self, h: BodyHandle) -> KeaResult<()> {
        self.bodies.check(h)?;
        self.wake_neighbours(h);
        for i in 0..self.constraints.slot_count() {
            let attached = self
                .constraints
                .at(i)
                .is_some_and(|c| c.bodies.contains(&Some(h)));
            if attached {
                let joint = self.is_joint_slot(i);
                let ch = self.constraints.handle_at(i).expect("occupied slot");
                self.constraints.remove(ch)?;
                self.index_constraint(i, joint);
            }
        }
        self.bodies.remove(h)?;
        self.awake.touch_body(h);
        Ok(())
    }

    /// A body, read-only.
    pub fn body(&self, h: BodyHandle) -> KeaResult<&Body> {
        self.bodies.get(h)
    }

    /// A body, to change through its validating setters.
    pub fn body_mut(&mut self, h: BodyHandle) -> KeaResult<&mut Body> {
        let body = self.bodies.get_mut(h)?;
        // Its flags or forces may change: the awake set looks at it again.
        self.awake.touch_body(h);
        Ok(body)
    }

    /// Number of bodies.
    #[must_use]
    pub fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Bodies the last step simulated (enabled and awake; all bodies before the first step):
    /// the work a coming step is likely to have, which decides whether it is worth handing to
    /// the thread pool (`threads::on_pool`).
    #[must_use]
    pub fn awake_body_count(&self) -> usize {
        if self.steps == 0 {
            self.bodies.len()
        } else {
            self.scratch.solver_bodies.len()
        }
    }

    /// Steps completed so far (each clears the applied forces), for
    /// [`World::bodies_changed_since`].
    #[must_use]
    pub fn completed_steps(&self) -> u64 {
        self.awake.clears()
    }

    /// The slots of every body that may have moved or changed (flags, pose, velocity, forces,
    /// or destroyed) since [`World::completed_steps`] read `since`: the awake bodies and the
    /// bodies touched since. Every other body is asleep, disabled or gone, and untouched. A
    /// collision layer that updates before each step visits only these bodies' colliders.
    /// `None` when that cannot be told (more than one step since, or a world just restored):
    /// then every body must be looked at. Slots may repeat.
    pub fn bodies_changed_since(&self, since: u64) -> Option<impl Iterator<Item = u32> + '_> {
        self.awake.changed_since(since)
    }

    /// Every body with its handle, in slot order.
    pub fn bodies(&self) -> impl Iterator<Item = (BodyHandle, &Body)> + '_ {
        self.bodies.iter()
    }

    /// Grows the room reserved for bodies and constraints to at least `bodies` and
    /// `constraints` (each capped at [`MAX_CAPACITY`]), with the step's buffers, so that
    /// adding up to that many and stepping allocate nothing more. Never shrinks.
    pub fn reserve(&mut self, bodies: usize, constraints: usize) {
        self.bodies.reserve_total(bodies);
        self.constraints.reserve_total(constraints);
        let (nb, nc) = (self.bodies.capacity(), self.constraints.capacity());
        let rows = nc * ROWS_PER_CONSTRAINT;
        let s = &mut self.scratch;
        for v in [&mut s.slot_to_solver, &mut s.solver_to_slot] {
            reserve_total(v, nb);
        }
        reserve_total(&mut s.solver_bodies, nb);
        reserve_total(&mut s.island_flag, nb);
        reserve_total(&mut s.wake, nb);
        reserve_total(&mut s.awake_constraints, nc);
        self.body_constraints.reserve(nb, nc);
        reserve_total(&mut s.quarantine_root, nb);
        s.sleep_sets.reserve(nb);
        s.quarantine_sets.reserve(nb);
        reserve_total(&mut s.rows, rows);
        reserve_total(&mut s.lambda, rows);
        reserve_total(&mut s.prev_lambda, rows);
        reserve_total(&mut s.projection_lambda, rows);
        reserve_total(&mut s.blocks, nc);
        reserve_total(&mut s.block_constraint, nc);
        reserve_total(&mut s.contacts, nc);
        reserve_total(&mut s.contact_constraint, nc);
        reserve_total(&mut s.written, nc);
        reserve_total(&mut s.contact_lambda, nc * 3);
        reserve_total(&mut s.contact_rows, nc);
        reserve_total(&mut s.contact_reactions, nc);
        reserve_total(&mut s.reactions, nc);
        reserve_total(&mut s.broken, nc);
        reserve_total(&mut s.unwritable, nc);
        reserve_total(&mut s.step_layout, nc);
    }

    /// Room for bodies now reserved (grows when full, see [`World::reserve`]).
    #[must_use]
    pub fn max_bodies(&self) -> usize {
        self.bodies.capacity()
    }

    /// Room for constraints now reserved (grows when full, see [`World::reserve`]).
    #[must_use]
    pub fn max_constraints(&self) -> usize {
        self.constraints.capacity()
    }

    /// The most solver workspace any step so far has needed, bytes: a high-water mark by the
    /// steps' island sizes ([`crate::solver::memory_required`]), 0 before the first step
    /// whatever was reserved (the guide's `MdtWorldGetMemoryPoolSize`). What the world's
    /// buffers hold, reservations included, is [`World::reserved_bytes`].
    ///
    /// ```
    /// use kea::{BodyDef, Vec3, World};
    ///
    /// let mut world = World::with_capacity(64, 64)?; // reserved, not used
    /// // The solver's path (the default routing steps a lone pendulum in reduced coordinates).
    /// world.update_settings(|s| s.routing.mode = kea::SolverMode::Exact)?;
    /// assert_eq!(world.memory_pool_size(), 0);
    /// let bob = world.create_body(&BodyDef { position: Vec3::X, ..BodyDef::default() })?;
    /// world.create_joint(bob, None, kea::JointSpec::ball(Vec3::ZERO))?;
    /// world.step(0.01)?;
    /// let used = world.memory_pool_size();
    /// assert!(used > 0 && used <= kea::solver::memory_required(&[3], 1));
    /// # Ok::<(), kea::KeaError>(())
    /// ```
    #[must_use]
    pub fn memory_pool_size(&self) -> usize {
        self.solver.memory_high_water()
    }

    /// Bytes reserved for bodies, constraints and per-step buffers (excluding the solver pool).
    #[must_use]
    pub fn reserved_bytes(&self) -> usize {
        let s = &self.scratch;
        self.bodies.reserved_bytes()
            + self.constraints.reserved_bytes()
            + s.solver_bodies.capacity() * std::mem::size_of::<SolverBody>()
            + (s.slot_to_solver.capacity() + s.solver_to_slot.capacity()) * 4
            + s.rows.capacity() * std::mem::size_of::<Row>()
            + s.blocks.capacity() * std::mem::size_of::<ConstraintBlock>()
            + s.block_constraint.capacity() * 4
            + s.contacts.capacity() * std::mem::size_of::<SolverContact>()
            + s.contact_constraint.capacity() * 4
            + s.written.capacity() * 4
            + s.contact_lambda.capacity() * std::mem::size_of::<Real>()
            + s.contact_rows.capacity() * 8
            + s.contact_reactions.capacity() * std::mem::size_of::<[Reaction; 2]>()
            + (s.lambda.capacity() + s.prev_lambda.capacity()) * std::mem::size_of::<Real>()
            + s.reactions.capacity() * std::mem::size_of::<[Reaction; 2]>()
            + s.sleep_sets.bytes()
            + s.island_flag.capacity() * std::mem::size_of::<Real>()
            + s.wake.capacity()
            + s.step_layout.capacity() * 12
            + s.projection_lambda.capacity() * std::mem::size_of::<Real>()
    }

    /// The breakable constraints that broke (and were disabled) in the last step.
    #[must_use]
    pub fn broken_last_step(&self) -> &[ConstraintHandle] {
        &self.scratch.broken
    }

    /// One report per island of the last step: path, bodies, rows, iterations or pivots.
    #[must_use]
    pub fn island_reports(&self) -> &[IslandReport] {
        self.solver.island_reports()
    }

    /// Total kinetic energy of enabled bodies.
    #[must_use]
    pub fn kinetic_energy(&self) -> Real {
        self.bodies
            .iter()
            .filter(|(_, b)| b.enabled)
            .map(|(_, b)| b.kinetic_energy())
            .sum()
    }
}

pub use crate::handle::MAX_CAPACITY;

fn check_capacity(arg: &'static str, capacity: usize) -> KeaResult<()> {
    if !(1..=MAX_CAPACITY).contains(&capacity) {
        return Err(KeaError::OutOfRange {
            arg,
            value: capacity.to_string(),
            expected: "must be in 1..=1048576 (kea::world::MAX_CAPACITY)",
        });
    }
    Ok(())
}
