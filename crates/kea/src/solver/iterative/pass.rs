//! The iterative pass over a step's islands, in groups.
//!
//! The islands routed to the iterative path are packed, in their order, into groups of at
//! least [`GROUP_WORK`] bodies, constraints and contacts (an island is never cut), and each
//! group is solved in a workspace of its own that only reads the step's arrays; then the
//! groups write their results back, one after another. Groups share no body, so with the
//! `parallel` feature they run side by side on the pool's threads (32 ragdolls are 32 islands:
//! a step's solve no longer runs them one after the other).
//!
//! Which islands share a group depends on the islands alone, never on the number of threads,
//! so a step gives the same bits on any number of them. Inside a group the islands are solved
//! together as before: one contact solver and one direct system for their joints, whose
//! pivoting and post-stabilisation iterate over the group.

use super::{DirectReport, IterativeReport, IterativeWorkspace};
use crate::solver::integrate::BodyScratch;
use crate::solver::island::Islands;
use crate::solver::StepArrays;

/// Bodies, constraints and contacts from which a group is closed and the next one begins: big
/// enough that a group's fixed costs (and its contact lanes) stay small beside its work, small
/// enough that a few ragdolls make a group (one is about 30).
const GROUP_WORK: u32 = 64;

/// The iterative path's workspaces, one per group of islands (module docs).
#[derive(Debug, Default, Clone)]
pub(crate) struct IterativePass {
    workspaces: Vec<IterativeWorkspace>,
    /// Group `g` holds the routed islands `starts[g]..starts[g + 1]`.
    starts: Vec<u32>,
    reports: Vec<IterativeReport>,
}

impl IterativePass {
    /// Reserves the first group's workspace for `bodies`, `rows` and `contacts`.
    pub(crate) fn reserve(&mut self, bodies: usize, rows: usize, contacts: usize) {
        if self.workspaces.is_empty() {
            self.workspaces.push(IterativeWorkspace::default());
        }
        self.workspaces[0].reserve(bodies, rows, contacts);
        super::super::reserve(&mut self.starts, 2);
    }

    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        self.workspaces
            .iter()
            .map(IterativeWorkspace::bytes)
            .sum::<usize>()
            + self.starts.capacity() * 4
            + self.reports.capacity() * std::mem::size_of::<IterativeReport>()
    }

    /// Solves the islands `islands` (ids in `all`; those marked in `split` have their joints
    /// solved directly) and integrates their bodies: `step.lambda` holds the rows' warm-start
    /// forces on input and their forces on output; contacts carry their warm start and get
    /// their forces.
    pub(crate) fn solve(
        &mut self,
        (islands, split, all): (&[u32], &[bool], &Islands),
        step: &mut StepArrays<'_>,
        scratch: &mut BodyScratch,
    ) -> IterativeReport {
        self.group(islands, all);
        let groups = self.starts.len() - 1;
        while self.workspaces.len() < groups {
            self.workspaces.push(IterativeWorkspace::default());
        }
        self.reports.clear();
        self.reports.resize(groups, IterativeReport::default());
        let (inputs, starts) = (step.inputs(), &self.starts);
        let shared: &BodyScratch = scratch;
        let run = |g: usize, ws: &mut IterativeWorkspace| {
            let range = starts[g] as usize..starts[g + 1] as usize;
            let mine = (&islands[range.clone()], &split[range], all);
            ws.solve(mine, &inputs, shared)
        };
        let workspaces = &mut self.workspaces[..groups];
        crate::threads::each_side_by_side(workspaces, &mut self.reports, run);
        for ws in &mut self.workspaces[..groups] {
            ws.write_out(step, scratch);
        }
        merge(&self.reports)
    }

    /// Packs the routed islands, in order, into groups of at least [`GROUP_WORK`].
    fn group(&mut self, islands: &[u32], all: &Islands) {
        self.starts.clear();
        self.starts.push(0);
        let mut work = 0;
        for (i, &k) in islands.iter().enumerate() {
            let k = k as usize;
            work += all.island_bodies[k] + (all.blocks(k).len() + all.contacts(k).len()) as u32;
            if work >= GROUP_WORK && i + 1 < islands.len() {
                self.starts.push(i as u32 + 1);
                work = 0;
            }
        }
        self.starts.push(islands.len() as u32);
    }
}

/// The groups' reports as one: counts added, colours and the worst joint error the largest.
fn merge(reports: &[IterativeReport]) -> IterativeReport {
    let mut all = IterativeReport::default();
    let mut direct = DirectReport::default();
    for r in reports {
        all.sweeps = all.sweeps.max(r.sweeps);
        all.colours = all.colours.max(r.colours);
        all.overflow += r.overflow;
        all.lanes = all.lanes.max(r.lanes);
        direct.absorb(&r.direct);
    }
    all.direct = direct;
    all
}
