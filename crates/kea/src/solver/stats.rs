//! What the solver did in a step.

use crate::math::Real;
use std::time::Duration;

/// What the solver did in one step. Warnings are counts of islands, never aborts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SolverStats {
    /// Islands solved (with at least one row).
    pub islands: u32,
    /// Rows solved in total.
    pub rows: u32,
    /// Rows of the largest island.
    pub largest_island_rows: u32,
    /// LCP pivoting iterations (factorisations) in total.
    pub lcp_iterations: u32,
    /// Index moves between sets in total.
    pub pivots: u32,
    /// Coulomb re-solves in total (one per island without friction).
    pub friction_passes: u32,
    /// Islands whose system was singular and had to be regularised (redundant rows, ε = 0).
    pub singular_islands: u32,
    /// Islands where pivoting revisited a state and did not converge.
    pub cycled_islands: u32,
    /// Islands that hit the pivoting iteration cap.
    pub capped_islands: u32,
    /// Islands whose Coulomb bounds were still moving at the re-solve cap.
    pub friction_unconverged_islands: u32,
    /// Whether the workspace had to grow (allocate) this step.
    pub workspace_grew: bool,
    /// Islands solved by the exact path.
    pub exact_islands: u32,
    /// Islands turned away from the path they were routed to, because it could not hold them
    /// (a warning): islands with contacts whose dense exact system was too big for a step to
    /// afford ([`super::DENSE_EXACT_MAX_ROWS`]), solved on the iterative path (split when
    /// they hold joints); a light chain carrying a body more than
    /// [`super::Routing::mass_ratio`] times heavier, forced exact or iterative, solved split.
    pub rerouted_islands: u32,
    /// Islands solved by the iterative path (split islands not included).
    pub iterative_islands: u32,
    /// Islands split: joints solved directly inside the substeps, contacts iteratively.
    pub split_islands: u32,
    /// Rows of split islands, their contacts' included.
    pub split_rows: u32,
    /// Joint rows of split islands (solved directly).
    pub direct_rows: u32,
    /// Direct solves of split islands' joints (two per substep for each group of islands
    /// solved on its own).
    pub direct_solves: u32,
    /// Factorisations of those solves.
    pub direct_iterations: u32,
    /// Largest joint error of split islands after the substeps, before post-stabilisation
    /// (m, or rad for angular rows).
    pub direct_joint_error: Real,
    /// Rows solved by the exact path.
    pub exact_rows: u32,
    /// Rows solved by the iterative path (split islands not included).
    pub iterative_rows: u32,
    /// Gauss-Seidel sweeps of the iterative path per step (all its islands at once).
    pub iterative_sweeps: u32,
    /// Contacts solved (both paths; those touching no dynamic body excluded).
    pub contacts: u32,
    /// Their points.
    pub contact_points: u32,
    /// Colours the contacts were split into.
    pub colours: u32,
    /// Contacts that found no colour (solved one by one before the colours).
    pub overflow_contacts: u32,
    /// SIMD lanes of the contact solver (8 with AVX2 in `f32`, 4 with SSE2, 1 scalar).
    pub simd_lanes: u32,
    /// Time finding islands and routing them.
    pub time_islands: Duration,
    /// Time assembling and solving exact islands.
    pub time_solve_exact: Duration,
    /// Time in the iterative path (its substep integration included).
    pub time_solve_iterative: Duration,
    /// Time in both solvers.
    pub time_solve: Duration,
    /// Time integrating the bodies.
    pub time_integrate: Duration,
}

impl SolverStats {
    /// True when every island converged without regularisation, each on the path it was
    /// routed to.
    #[must_use]
    pub fn is_clean(&self) -> bool {
        self.singular_islands == 0
            && self.cycled_islands == 0
            && self.capped_islands == 0
            && self.friction_unconverged_islands == 0
            && self.rerouted_islands == 0
    }
}
