//! The Kea solver (the guide's MdtKea): bodies and rows in, new body states and constraint forces
//! out. Usable without a world (the guide's KeaOnly example, `examples/kea_only.rs`).
//!
//! # One step of size h
//!
//! 1. **Free velocities.** Damping is applied implicitly (`v ← v/(1 + h·d/m)`,
//!    `ω ← (I + h·d_ω)⁻¹ I ω`), then gravity and applied forces:
//!    `v_f = v + h(g + f/m)`, `ω_f = ω + h I⁻¹τ` (world-frame inertia at the current orientation).
//! 2. **Islands.** Bodies coupled by constraints are grouped (`island`); each island is solved
//!    on its own, by the path [`Routing`] chooses: by structure (hybrid, the default, with
//!    hysteresis: piles iterative, joints with contacts split, small joint islands exact, big
//!    ones split), or all one way. [`Solver::island_reports`] says
//!    which path solved each island, its size and its effort.
//! 3. **Exact path** per island (`exact`): `(A + εI)λ = b` as a boxed LCP with
//!    `A = J M⁻¹ Jᵀ` and `b = (c − γ·xi/h − J v_f)/h`, λ in force units, by block principal
//!    pivoting in `f64`. Islands of joints use a block-sparse factorisation whose elimination
//!    order keeps trees free of fill (a chain costs time linear in its rows), warm started
//!    from last step's forces; islands with contacts use the dense system, with the Coulomb
//!    bounds `±μλₙ` iterated: solve, update the bounds from the new normal forces, re-solve
//!    while they move. The reference answer.
//! 4. **Iterative path** per island (`iterative`): warm-started projected Gauss-Seidel with
//!    substeps (Box2D v3's soft step over the same rows): per substep integrate velocities,
//!    warm start, solve with error correction, integrate positions, relax without it;
//!    restitution once afterwards. A row's own softness is the same spring as in the exact
//!    path, re-discretised at the substep; rows without one are rigid and use γ as their rate
//!    of error reduction. Cost linear in rows.
//! 5. **Split islands** (joints among contacts, or big joint islands): in the iterative
//!    pass, but their joint rows are solved directly every substep (the exact path's
//!    block-sparse system over rows re-linearised at the present poses), after the contacts, so
//!    that joints hold exactly what the contacts did; after the substeps, post-stabilisation
//!    moves the bodies (not their velocities) so that rigid joints close.
//! 6. **Integrate** (`integrate`, exact islands and free bodies): `v⁺ = v_f + h M⁻¹ Jᵀλ`,
//!    `x⁺ = x + h v⁺` (semi-implicit first order), orientation by the exact rotation
//!    `exp(h ω⁺)` (the fast-spin component as its own exact rotation about the body-fixed axis),
//!    then `ω` is re-expressed at the new orientation so that the angular momentum `I ω` is
//!    unchanged by the rotation: the gyroscopic effect, with `|L|` conserved exactly for a
//!    torque-free body. The iterative path does the same per substep.
//!
//! After a step, [`Solver::project`] can move the bodies of exact islands so that rigid joints
//! close at the position level (Newton passes on the rows written at the new state); the world
//! does it when asked (`WorldDef::projection_iterations`).
//!
//! # Units and conventions
//! λ is a force (N, or N·m for angular rows). ε is added to the diagonal of `A`, so it has the
//! units of inverse mass; a row with ε behaves as a spring of stiffness `γ/(ε h²)` and damping
//! `(1 − γ)/(ε h)` ([`crate::constraint::Softness::from_spring`] goes the other way). ODE's CFM
//! equals `ε·h`. Slip `s` (velocity per force) adds `s/h` to the diagonal.
//!
//! # Memory
//! A [`Solver`] owns a workspace that grows to the largest problem seen and is reused; after
//! warm-up a step with the same counts performs no heap allocation, in either path. A logger
//! installed for the `log` crate may allocate when the solver warns (singular system, cycle,
//! cap reached); with no logger, warnings cost nothing. [`memory_required`] gives
//! the size needed for given island sizes (the guide's `MdtKeaMemoryRequired`).

mod exact;
mod inputs;
mod integrate;
mod island;
mod iterative;
mod params;
mod routing;
pub(crate) mod sparse;
mod stats;
mod validate;
mod wide;

pub use inputs::{ConstraintBlock, Reaction, RowSource, SolverBody, SolverContact};
pub use iterative::IterativeParams;
pub use params::{SolverParams, DEFAULT_CONTACT_SPRING, EXACT_CONTACT_STIFFENING};
pub use routing::{IslandReport, Routing, SolverMode, SolverPath, DENSE_EXACT_MAX_ROWS};
pub use stats::SolverStats;
pub use wide::SimdLevel;

use crate::constraint::{PointForce, Row, MAX_CONTACT_POINTS};
use crate::error::{KeaError, KeaResult};
use crate::math::{from_f64, rotate_by_vector, DVec3, Real, Vec3};
use crate::timing::Stamp;
use validate::{validate_inputs, validate_row_values, validate_rows};

/// The exact solver and its reusable workspace.
#[derive(Debug, Default, Clone)]
pub struct Solver {
    islands: island::Islands,
    exact: exact::ExactWorkspace,
    iterative: iterative::IterativePass,
    integ: integrate::BodyScratch,
    reports: Vec<IslandReport>,
    /// The most workspace a step has needed so far (`memory_high_water`).
    peak_needed: usize,
    /// Islands routed to the iterative path this step, and whether each is split.
    iterative_islands: Vec<u32>,
    split: Vec<bool>,
}

/// Bytes of workspace the solver needs for islands of the given row counts, with `bodies` and
/// `rows` in total (the guide's `MdtKeaMemoryRequired`); contacts count as three rows a point.
#[must_use]
pub fn memory_required(rows_per_island: &[usize], bodies: usize) -> usize {
    let rows: usize = rows_per_island.iter().sum();
    let largest = rows_per_island.iter().copied().max().unwrap_or(0);
    required_bytes(rows, largest, rows_per_island.len(), bodies)
}

/// [`memory_required`] from the totals: all rows, the largest island's, islands, bodies.
fn required_bytes(rows: usize, largest: usize, islands: usize, bodies: usize) -> usize {
    exact::ExactWorkspace::bytes_for(largest, rows)
        + iterative::IterativeWorkspace::bytes_for(bodies, rows, rows / 3)
        + integrate::BodyScratch::bytes_for(bodies)
        + std::mem::size_of::<IslandReport>() * islands
        + 16 * (bodies + rows)
}

impl Solver {
    /// An empty solver; its workspace grows on first use.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// A solver with workspace reserved for `bodies` bodies, `blocks` constraints, `rows` rows
    /// in total, `contacts` contacts and islands of up to `island_rows` rows.
    #[must_use]
    pub fn with_capacity(
        bodies: usize,
        blocks: usize,
        rows: usize,
        contacts: usize,
        island_rows: usize,
    ) -> Self {
        let mut s = Self::default();
        s.reserve(bodies, blocks, rows, contacts, island_rows);
        s
    }

    /// Reserves workspace (see [`Solver::with_capacity`]).
    pub fn reserve(
        &mut self,
        bodies: usize,
        blocks: usize,
        rows: usize,
        contacts: usize,
        island_rows: usize,
    ) {
        self.islands.reserve(bodies, blocks, contacts);
        self.exact.reserve(rows, island_rows);
        self.exact.reserve_mixed(island_rows);
        self.iterative.reserve(bodies, rows, contacts);
        self.integ.reserve(bodies);
        reserve(&mut self.reports, bodies);
        reserve(&mut self.iterative_islands, bodies);
        reserve(&mut self.split, bodies);
    }

    /// The most workspace any step so far has needed, by its islands' sizes
    /// ([`memory_required`]); 0 before the first step whatever was reserved (the guide's
    /// `MdtWorldGetMemoryPoolSize`).
    #[must_use]
    pub fn memory_high_water(&self) -> usize {
        self.peak_needed
    }

    /// Bytes of workspace currently held: what steps have grown it to, and any reservation.
    #[must_use]
    pub fn memory_used(&self) -> usize {
        self.islands.bytes()
            + self.exact.bytes()
            + self.iterative.bytes()
            + self.integ.bytes()
            + self.reports.capacity() * std::mem::size_of::<IslandReport>()
            + self.iterative_islands.capacity() * 4
            + self.split.capacity()
    }

    /// One report per island of the last step: which path solved it, its size and effort.
    #[must_use]
    pub fn island_reports(&self) -> &[IslandReport] {
        &self.reports
    }

    /// Advances `bodies` by one step under the constraints (`blocks` over `rows`) and the
    /// contacts.
    ///
    /// On input `lambda[i]` is a warm-start guess of row i's force for the iterative path (0 when
    /// unknown; the exact path needs none), and each contact carries its points' forces of the
    /// last step. On return `lambda[i]` is row i's force, `reactions[k]` the force and torque of
    /// constraint k on its two bodies, and each contact holds its points' forces. Each body's
    /// `last_path` is set to the path that solved its island. Everything is checked first: on
    /// `Err` nothing changed.
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        bodies: &mut [SolverBody],
        blocks: &[ConstraintBlock],
        rows: &[Row],
        contacts: &mut [SolverContact],
        params: &SolverParams,
        lambda: &mut [Real],
        reactions: &mut [[Reaction; 2]],
    ) -> KeaResult<SolverStats> {
        self.step_arrays(StepArrays {
            bodies,
            blocks,
            rows,
            contacts,
            params,
            lambda,
            reactions,
            source: None,
        })
    }

    /// [`Solver::step`] on one step's arrays, checked first.
    pub(crate) fn step_arrays(&mut self, step: StepArrays<'_>) -> KeaResult<SolverStats> {
        validate_inputs(&step)?;
        self.step_valid_arrays(step)
    }

    /// [`Solver::step`] on a world's own arrays, with their row source. The world made them
    /// from what its API and scene files checked when it came in, and a step leaves nothing
    /// non-finite behind (an island that blew up is put back and frozen), so a release build
    /// checks only the rows' numbers (forces the step works out become bounds) and not the
    /// bodies, blocks, contacts and parameters again in every substep; debug builds (the
    /// tests, the fuzzer) check everything and refuse as [`Solver::step`] would.
    pub(crate) fn step_world_arrays(&mut self, step: StepArrays<'_>) -> KeaResult<SolverStats> {
        if cfg!(debug_assertions) {
            validate_inputs(&step)?;
        } else {
            validate_row_values(step.rows)?;
        }
        self.step_valid_arrays(step)
    }

    /// The step, its arrays valid.
    fn step_valid_arrays(&mut self, mut step: StepArrays<'_>) -> KeaResult<SolverStats> {
        let params = step.params;
        let mut stats = SolverStats::default();
        if step.bodies.is_empty() {
            // Nothing to solve (every body asleep, static or stepped in reduced coordinates).
            self.reports.clear();
            return Ok(stats);
        }
        let before = self.memory_used();
        let t0 = Stamp::now(params.timing);
        let bodies = &*step.bodies;
        self.integ.prepare(bodies, params);
        self.islands.build(
            bodies.len(),
            |i| !bodies[i].is_fixed(),
            step.blocks,
            step.contacts,
            params.partition,
        );
        let t1 = Stamp::now(params.timing);
        stats.time_islands = t0.until(t1);
        self.clear_unsolved(&mut step, &mut stats);
        self.solve_routed(&mut step, &mut stats);
        if !self.iterative_islands.is_empty() {
            self.solve_iterative(&mut step, &mut stats);
        }
        let t2 = Stamp::now(params.timing);
        stats.time_solve = t1.until(t2);
        self.integ.integrate(step.bodies, params.dt);
        stats.time_integrate = t2.elapsed();
        self.record_after_step(&mut step);
        stats.workspace_grew = self.memory_used() > before;
        Ok(stats)
    }

    /// Zeroes the reactions, and the forces of the constraints and contacts that touch no
    /// dynamic body (they carry none); counts the contacts that take part.
    fn clear_unsolved(&self, step: &mut StepArrays<'_>, stats: &mut SolverStats) {
        for r in step.reactions.iter_mut() {
            *r = [Reaction::default(); 2];
        }
        for (k, blk) in step.blocks.iter().enumerate() {
            if self.islands.block_island[k] == u32::MAX {
                let range = blk.first_row as usize..(blk.first_row + blk.row_count) as usize;
                step.lambda[range].fill(0.0);
            }
        }
        for (c, sc) in step.contacts.iter_mut().enumerate() {
            let n = sc.contact.points().len();
            if self.islands.contact_island[c] == u32::MAX {
                sc.contact
                    .set_forces(&[PointForce::default(); MAX_CONTACT_POINTS][..n]);
            } else {
                stats.contacts += 1;
                stats.contact_points += n as u32;
            }
        }
    }

    /// Routes each island to its path and solves the exact ones; the others are listed for
    /// the iterative pass (`iterative_islands`, `split`).
    fn solve_routed(&mut self, step: &mut StepArrays<'_>, stats: &mut SolverStats) {
        let params = step.params;
        self.reports.clear();
        reserve(&mut self.reports, self.islands.count());
        self.iterative_islands.clear();
        self.split.clear();
        for k in 0..self.islands.count() {
            let island = routing::IslandView {
                islands: &self.islands,
                k,
                blocks: step.blocks,
                contacts: step.contacts,
                bodies: step.bodies,
            };
            let choice = routing::choose(&params.routing, &island, params.gravity);
            let mut report = IslandReport {
                path: choice.path,
                bodies: self.islands.island_bodies[k],
                rows: island.rows(),
                iterations: 0,
                pivots: 0,
            };
            if choice.rerouted {
                stats.rerouted_islands += 1;
            }
            let exact = choice.path == SolverPath::Exact;
            if !(exact && self.solve_exact(k, step, stats, &mut report)) {
                self.iterative_islands.push(k as u32);
                self.split.push(report.path == SolverPath::Split);
            }
            self.reports.push(report);
        }
        if stats.rerouted_islands > 0 {
            log::warn!(
                "kea: {} islands turned away from the path they were routed to (contacts past the dense exact LCP's {DENSE_EXACT_MAX_ROWS} rows, or a light chain carrying a heavy end forced exact or iterative)",
                stats.rerouted_islands
            );
        }
    }

    /// Island `k` on the exact path; false (its report turned iterative) when it was a stack
    /// the exact path did not settle (sliding): the contact solver takes it this step, with a
    /// warning only where the world forced exact.
    fn solve_exact(
        &mut self,
        k: usize,
        step: &mut StepArrays<'_>,
        stats: &mut SolverStats,
        report: &mut IslandReport,
    ) -> bool {
        let t = Stamp::now(step.params.timing);
        let before = *stats;
        let island = (self.islands.blocks(k), self.islands.contacts(k));
        let solved = self
            .exact
            .solve_island_with_contacts(island, step, &mut self.integ, stats);
        stats.time_solve_exact += t.elapsed();
        if solved {
            stats.exact_islands += 1;
            stats.exact_rows += stats.rows - before.rows;
            report.iterations = stats.lcp_iterations - before.lcp_iterations;
            report.pivots = stats.pivots - before.pivots;
        } else {
            report.path = SolverPath::Iterative;
            if step.params.routing.mode == SolverMode::Exact {
                stats.rerouted_islands += 1;
            }
        }
        solved
    }

    /// The iterative and split islands, in one pass of the soft step.
    fn solve_iterative(&mut self, step: &mut StepArrays<'_>, stats: &mut SolverStats) {
        let t = Stamp::now(step.params.timing);
        let islands = (&self.iterative_islands[..], &self.split[..], &self.islands);
        let done = self.iterative.solve(islands, step, &mut self.integ);
        for (&k, &split) in self.iterative_islands.iter().zip(&self.split) {
            let r = &mut self.reports[k as usize];
            r.iterations = done.sweeps;
            if split {
                stats.split_rows += r.rows;
            } else {
                stats.iterative_rows += r.rows;
            }
            stats.rows += r.rows;
            stats.largest_island_rows = stats.largest_island_rows.max(r.rows);
        }
        stats.islands += self.iterative_islands.len() as u32;
        stats.split_islands = self.split.iter().filter(|&&s| s).count() as u32;
        stats.iterative_islands = self.iterative_islands.len() as u32 - stats.split_islands;
        record_direct(stats, &done.direct);
        stats.iterative_sweeps = done.sweeps;
        stats.colours = done.colours;
        stats.overflow_contacts = done.overflow;
        stats.simd_lanes = done.lanes;
        stats.time_solve_iterative = t.elapsed();
    }

    /// After the step: each body's path, each contact's sliding state from the bodies' new
    /// velocities (static or kinetic friction next step), and the workspace this step needed
    /// by its sizes (the reservation made ahead not counted).
    fn record_after_step(&mut self, step: &mut StepArrays<'_>) {
        for (i, b) in step.bodies.iter_mut().enumerate() {
            let k = self.islands.body_island[i];
            b.last_path = if k == u32::MAX {
                SolverPath::None
            } else {
                self.reports
                    .get(k as usize)
                    .map_or(SolverPath::None, |r| r.path)
            };
        }
        let bodies = &*step.bodies;
        for sc in step.contacts.iter_mut() {
            let ids = sc.bodies;
            let point_velocity = |side: usize, p: Vec3| {
                ids[side]
                    .and_then(|i| bodies.get(i as usize))
                    .map_or(Vec3::ZERO, |b| {
                        b.linear_velocity + b.angular_velocity.cross(p - b.position)
                    })
            };
            let relative = |p: Vec3| point_velocity(0, p) - point_velocity(1, p);
            sc.contact.record_sliding(relative);
        }
        let rows = self.reports.iter().map(|r| r.rows as usize);
        let needed = required_bytes(
            rows.clone().sum(),
            rows.max().unwrap_or(0),
            self.reports.len(),
            bodies.len(),
        );
        self.peak_needed = self.peak_needed.max(needed);
    }
}

/// One step's arrays, as [`Solver::step`] takes them, and where the rows come from.
pub(crate) struct StepArrays<'a> {
    pub(crate) bodies: &'a mut [SolverBody],
    pub(crate) blocks: &'a [ConstraintBlock],
    pub(crate) rows: &'a [Row],
    pub(crate) contacts: &'a mut [SolverContact],
    pub(crate) params: &'a SolverParams,
    pub(crate) lambda: &'a mut [Real],
    pub(crate) reactions: &'a mut [[Reaction; 2]],
    /// Writes the blocks' rows again at each substep of the iterative path (joints
    /// re-linearised at the present poses, so fast rotation inside a step does not tear
    /// them). Row counts and kinds must not depend on the poses for a block to be re-written;
    /// one whose rows change keeps those of the step's start.
    pub(crate) source: Option<&'a dyn RowSource>,
}

/// The step's arrays read only: what the iterative pass's groups of islands share while each
/// solves its own (`iterative::IterativePass`).
#[derive(Clone, Copy)]
pub(crate) struct StepInputs<'a> {
    pub(crate) bodies: &'a [SolverBody],
    pub(crate) blocks: &'a [ConstraintBlock],
    pub(crate) rows: &'a [Row],
    pub(crate) contacts: &'a [SolverContact],
    pub(crate) params: &'a SolverParams,
    pub(crate) lambda: &'a [Real],
    pub(crate) source: Option<&'a dyn RowSource>,
}

impl StepArrays<'_> {
    /// The arrays to read.
    pub(crate) fn inputs(&self) -> StepInputs<'_> {
        StepInputs {
            bodies: self.bodies,
            blocks: self.blocks,
            rows: self.rows,
            contacts: self.contacts,
            params: self.params,
            lambda: self.lambda,
            source: self.source,
        }
    }
}

impl Solver {
    /// Position projection after a step, for the islands the exact path solved: moves bodies so
    /// that rigid equality rows (joints without their own softness) have zero error, leaving
    /// velocities alone (see `exact::ExactWorkspace::project_island`). `rows` must have been
    /// written at the bodies' new state, by the same constraints in the same order as the
    /// step's, and `lambda` is the step's output. Returns the largest joint error found before
    /// projecting. Allocation-free after warm-up, like [`Solver::step`].
    pub fn project(
        &mut self,
        bodies: &mut [SolverBody],
        blocks: &[ConstraintBlock],
        rows: &[Row],
        lambda: &[Real],
        params: &SolverParams,
    ) -> KeaResult<f64> {
        params.validate()?;
        validate_rows(bodies, blocks, rows)?;
        if lambda.len() != rows.len() {
            return Err(KeaError::Inconsistent {
                arg: "lambda",
                reason: format!("has {} entries for {} rows", lambda.len(), rows.len()),
            });
        }
        self.integ.prepare(bodies, params);
        self.islands.build(
            bodies.len(),
            |i| !bodies[i].is_fixed(),
            blocks,
            &[],
            params.partition,
        );
        let mut stats = SolverStats::default();
        let mut worst = 0.0f64;
        for k in 0..self.islands.count() {
            // Joints only here: an island is projected if the step solved its bodies exactly.
            let exact = self
                .islands
                .blocks(k)
                .iter()
                .flat_map(|&b| blocks[b as usize].bodies.into_iter().flatten())
                .any(|i| bodies[i as usize].last_path == SolverPath::Exact);
            if !exact {
                continue;
            }
            let input = exact::IslandInputs {
                blocks,
                rows,
                bodies,
                params,
            };
            let e = self.exact.project_island(
                self.islands.blocks(k),
                input,
                &mut self.integ,
                lambda,
                &mut stats,
            );
            worst = worst.max(e);
        }
        for (i, b) in bodies.iter_mut().enumerate() {
            let dx = self.integ.constraint_force[i];
            let dtheta = self.integ.constraint_torque[i];
            if dx != DVec3::ZERO || dtheta != DVec3::ZERO {
                b.position += from_f64(dx);
                b.orientation = rotate_by_vector(b.orientation, from_f64(dtheta));
            }
        }
        Ok(worst)
    }
}

/// The direct solves of split islands in the step's stats, with a warning for each kind of
/// trouble they met (counted per solve).
fn record_direct(stats: &mut SolverStats, d: &iterative::DirectReport) {
    stats.direct_rows = d.rows;
    stats.direct_solves = d.solves;
    stats.direct_iterations = d.iterations;
    stats.direct_joint_error = d.worst_error;
    stats.lcp_iterations += d.iterations;
    stats.pivots += d.pivots;
    stats.singular_islands += d.singular;
    stats.cycled_islands += d.cycled;
    stats.capped_islands += d.capped;
    stats.friction_unconverged_islands += d.bounds_moving;
    if d.singular > 0 {
        log::warn!(
            "kea: singular joint system of split islands ({} rows) regularised in {} solves",
            d.rows,
            d.singular
        );
    }
    if d.cycled + d.capped + d.bounds_moving > 0 {
        log::warn!(
            "kea: direct joint solves of split islands unconverged ({} cycled, {} capped, {} with moving bounds)",
            d.cycled,
            d.capped,
            d.bounds_moving
        );
    }
}

/// Each constraint's force and torque on its two bodies, from its rows' λ.
pub(crate) fn block_reactions(
    island_blocks: &[u32],
    blocks: &[ConstraintBlock],
    rows: &[Row],
    lambda: &[Real],
    reactions: &mut [[Reaction; 2]],
) {
    for &k in island_blocks {
        let blk = &blocks[k as usize];
        let mut out = [Reaction::default(); 2];
        for g in blk.first_row..blk.first_row + blk.row_count {
            let row = &rows[g as usize];
            let l = lambda[g as usize];
            for (s, o) in out.iter_mut().enumerate() {
                if blk.bodies[s].is_some() {
                    o.force += row.jacobian[s].linear * l;
                    o.torque += row.jacobian[s].angular * l;
                }
            }
        }
        reactions[k as usize] = out;
    }
}

/// Grows `v`'s capacity to at least `n` (no-op when it is already enough).
pub(crate) fn reserve<T>(v: &mut Vec<T>, n: usize) {
    if v.capacity() < n {
        v.reserve(n - v.len());
    }
}
