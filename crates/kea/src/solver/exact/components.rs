//! The direct solve of split islands' joints, one system per joint-connected component.
//!
//! The joint rows a group of split islands hands to its direct solve
//! (`iterative/rows/direct.rs`) often fall apart into pieces that no joint links: a pile of
//! ragdolls is one island (they touch), but each ragdoll's joints are a tree of their own, and
//! the contacts between them are the contact solver's. Each such component gets its own
//! [`SubstepSystem`]: its analysis, factorisation and pivoting stop when it has converged,
//! whatever the others do, and with the `parallel` feature the components are assembled and
//! solved side by side. The caller sees one system: rows numbered in the order it added them.
//!
//! Components are found by the bodies the blocks join (a body that cannot move joins
//! nothing) and numbered by their first block, so the same blocks give the same components,
//! systems and bits on any number of threads; with one component the system is the one the
//! caller would have built itself.

use super::{LcpReport, Limits, RowValues, SubstepSystem};
use crate::solver::sparse::pivoting::FrictionLink;
use crate::threads::each_side_by_side;
use crate::union_find::UnionFind;

const NONE: u32 = u32::MAX;

/// The split islands' joint rows as one system per component (module docs).
#[derive(Debug, Default, Clone)]
pub(crate) struct ComponentSystems {
    systems: Vec<SubstepSystem>,
    /// Components of the present linearisation.
    used: usize,
    /// Local bodies of the present linearisation.
    bodies: usize,
    /// The blocks as added: their bodies and the end of their rows.
    block_slots: Vec<[u32; 2]>,
    block_end: Vec<u32>,
    /// The rows as added: softness and friction link (an index among all rows).
    row_extra: Vec<f64>,
    row_link: Vec<FrictionLink>,
    /// Each row's component and index in its component's system.
    row_comp: Vec<u32>,
    row_local: Vec<u32>,
    /// The rows of component `c` are `comp_rows[comp_start[c]..comp_start[c + 1]]`.
    comp_rows: Vec<u32>,
    comp_start: Vec<u32>,
    sets: UnionFind,
    comp_of_root: Vec<u32>,
    /// Rows given a right-hand side in the present pass.
    pushed: usize,
    reports: Vec<LcpReport>,
}

impl ComponentSystems {
    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        self.systems.iter().map(SubstepSystem::bytes).sum::<usize>()
            + (self.block_slots.capacity() * 2
                + self.block_end.capacity()
                + self.row_comp.capacity()
                + self.row_local.capacity()
                + self.comp_rows.capacity()
                + self.comp_start.capacity()
                + self.comp_of_root.capacity())
                * 4
            + self.row_extra.capacity() * 8
            + self.row_link.capacity() * std::mem::size_of::<FrictionLink>()
            + self.sets.bytes()
            + self.reports.capacity() * std::mem::size_of::<LcpReport>()
    }

    /// Starts over with no rows, for local bodies numbered below `bodies`.
    pub(crate) fn clear(&mut self, bodies: usize) {
        self.bodies = bodies;
        self.block_slots.clear();
        self.block_end.clear();
        self.row_extra.clear();
        self.row_link.clear();
    }

    /// Rows in all the systems.
    pub(crate) fn len(&self) -> usize {
        self.row_extra.len()
    }

    /// Adds one block of rows acting on the bodies in `slots` (`u32::MAX`: none, or a body
    /// that cannot move), each row with its softness and friction link, the link an index
    /// among all rows added (see [`SubstepSystem::add_block`]).
    pub(crate) fn add_block(
        &mut self,
        slots: [u32; 2],
        rows: impl Iterator<Item = (f64, FrictionLink)>,
    ) {
        for (extra, link) in rows {
            self.row_extra.push(extra);
            self.row_link.push(link);
        }
        self.block_slots.push(slots);
        self.block_end.push(self.row_extra.len() as u32);
    }

    /// Builds each component's `A = J M⁻¹ Jᵀ + E`, row `i`'s (among all) Jacobian and
    /// `M⁻¹Jᵀ` read from `row(i)`.
    pub(crate) fn assemble(&mut self, row: impl Fn(usize) -> RowValues + Sync) {
        self.find_components();
        self.fill_components();
        let (rows, start) = (&self.comp_rows, &self.comp_start);
        let build = |c: usize, sys: &mut SubstepSystem| {
            let mine = &rows[start[c] as usize..start[c + 1] as usize];
            sys.assemble(|l| row(mine[l] as usize));
        };
        // `()` per system: a Vec of them holds no memory.
        let mut done = vec![(); self.used];
        each_side_by_side(&mut self.systems[..self.used], &mut done, build);
    }

    /// Numbers the components by their first block and files each row's.
    fn find_components(&mut self) {
        self.sets.reset(self.bodies + 1);
        let lone = self.bodies as u32; // the blocks that move no body: one component
        for &[a, b] in &self.block_slots {
            if a != NONE && b != NONE {
                self.sets.union(a, b);
            }
        }
        self.comp_of_root.clear();
        self.comp_of_root.resize(self.bodies + 1, NONE);
        self.row_comp.clear();
        self.used = 0;
        let mut first = 0;
        for (k, s) in self.block_slots.iter().enumerate() {
            let body = if s[0] != NONE { s[0] } else { s[1] };
            let root = if body == NONE {
                lone
            } else {
                self.sets.find(body)
            } as usize;
            if self.comp_of_root[root] == NONE {
                self.comp_of_root[root] = self.used as u32;
                self.used += 1;
            }
            let c = self.comp_of_root[root];
            let end = self.block_end[k] as usize;
            self.row_comp.extend(std::iter::repeat_n(c, end - first));
            first = end;
        }
    }

    /// Lists each component's rows, numbers them in it, and adds its blocks to its system.
    fn fill_components(&mut self) {
        let used = self.used;
        while self.systems.len() < used {
            self.systems.push(SubstepSystem::default());
        }
        // Counting sort of the rows by component, keeping their order.
        self.comp_start.clear();
        self.comp_start.resize(used + 1, 0);
        for &c in &self.row_comp {
            self.comp_start[c as usize + 1] += 1;
        }
        for c in 0..used {
            self.comp_start[c + 1] += self.comp_start[c];
        }
        self.comp_rows.clear();
        self.comp_rows.resize(self.row_comp.len(), 0);
        self.row_local.clear();
        self.row_local.resize(self.row_comp.len(), 0);
        for sys in &mut self.systems[..used] {
            sys.clear(self.bodies);
        }
        let mut first = 0;
        for (k, &slots) in self.block_slots.iter().enumerate() {
            let end = self.block_end[k] as usize;
            let c = self.row_comp[first] as usize;
            let base = self.systems[c].len();
            for (j, i) in (first..end).enumerate() {
                self.row_local[i] = (base + j) as u32;
                self.comp_rows[self.comp_start[c] as usize + base + j] = i as u32;
            }
            let (local, extra, links) = (&self.row_local, &self.row_extra, &self.row_link);
            self.systems[c].add_block(
                slots,
                (first..end).map(|i| {
                    // A friction row's normal is in its own joint, so in its component.
                    let link = links[i].map(|(normal, mu)| (local[normal as usize], mu));
                    (extra[i], link)
                }),
            );
            first = end;
        }
    }

    /// Starts a pass: no row's right-hand side given yet.
    pub(crate) fn begin_pass(&mut self) {
        self.pushed = 0;
        for sys in &mut self.systems[..self.used] {
            sys.begin_pass();
        }
    }

    /// Gives the next row (in the order they were added) its residual `r`, bounds
    /// `[lo, hi]` and present impulse `y0`.
    pub(crate) fn push(&mut self, r: f64, lo: f64, hi: f64, y0: f64) {
        let c = self.row_comp[self.pushed] as usize;
        self.systems[c].push(r, lo, hi, y0);
        self.pushed += 1;
    }

    /// Row `i`'s impulse: as pushed, or as solved after [`ComponentSystems::solve`].
    pub(crate) fn impulse(&self, i: usize) -> f64 {
        self.systems[self.row_comp[i] as usize].impulse(self.row_local[i] as usize)
    }

    /// Solves every component (see [`SubstepSystem::solve`]); the report sums their work and
    /// holds any trouble one met.
    pub(crate) fn solve(&mut self, limits: Limits) -> LcpReport {
        let used = self.used;
        self.reports.clear();
        self.reports.resize(used, LcpReport::default());
        let systems = &mut self.systems[..used];
        each_side_by_side(systems, &mut self.reports, |_, sys| sys.solve(limits));
        merge(&self.reports)
    }
}

/// The components' reports as one.
fn merge(reports: &[LcpReport]) -> LcpReport {
    let mut all = LcpReport {
        converged: true,
        ..LcpReport::default()
    };
    for r in reports {
        all.iterations += r.iterations;
        all.pivots += r.pivots;
        all.bound_updates += r.bound_updates;
        all.converged &= r.converged;
        all.singular |= r.singular;
        all.cycled |= r.cycled;
        all.capped |= r.capped;
        all.bounds_moving |= r.bounds_moving;
    }
    all
}
