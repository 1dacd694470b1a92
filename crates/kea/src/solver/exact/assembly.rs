//! Assembling an island's system: its block graph analysed (or recalled), the system laid out
//! and `A = J M⁻¹ Jᵀ` filled block by block, the diagonal (constraint softness) added, and the
//! right-hand side.

use super::{ExactWorkspace, IslandRow, RowValues};
use crate::constraint::Row;
use crate::math::{to_f64, wide, Real};
use crate::solver::integrate::BodyScratch;
use crate::solver::sparse::factor::Layout;
use crate::solver::sparse::pattern::Pattern;
use crate::solver::sparse::pivoting::Bound;
use crate::solver::SolverParams;

impl ExactWorkspace {
    /// Analyses (or recalls) the island's block graph, lays the system out and fills
    /// `A = J M⁻¹ Jᵀ` (no diagonal terms) for the gathered rows (the caller sizes the vectors).
    /// Blocks that join their bodies without a loop take the tree solve; the others the
    /// general pattern.
    pub(super) fn assemble_matrix(&mut self) {
        self.assemble_matrix_by(None::<fn(usize) -> RowValues>);
    }

    /// [`Self::assemble_matrix`], each row's Jacobian and `M⁻¹Jᵀ` read from `row` when given
    /// (straight into the tree solve's storage, or into the island rows for the general
    /// pattern), else from the island rows.
    pub(super) fn assemble_matrix_by(&mut self, row: Option<impl Fn(usize) -> RowValues>) {
        self.dense_now = false;
        let island_bodies = self.island_bodies.len();
        self.tree_now = self.tree.order.analyse(
            &self.block_key,
            &self.block_first,
            &self.block_size,
            island_bodies,
        );
        if self.tree_now {
            match row {
                Some(row) => self.tree.fill(row),
                None => {
                    let rows = &self.rows;
                    self.tree.fill(|i| (rows[i].jac, rows[i].mj));
                }
            }
            return;
        }
        if let Some(row) = row {
            let n = self.block_first.last().map_or(0, |&f| f as usize)
                + self.block_size.last().map_or(0, |&s| s as usize);
            self.rows.clear();
            self.rows.extend((0..n).map(|i| {
                let (jac, mj) = row(i);
                IslandRow {
                    global: i as u32,
                    bodies: [None; 2],
                    jac,
                    mj,
                }
            }));
        }
        let pattern = self
            .patterns
            .get(&self.block_key, &self.block_size, island_bodies);
        self.layout
            .build(pattern, &self.block_first, &self.block_size);
        self.block_position.clear();
        self.block_position.resize(pattern.len(), 0);
        for (k, &blk) in pattern.order.iter().enumerate() {
            self.block_position[blk as usize] = k as u32;
        }
        self.sys.a.clear();
        self.sys.a.resize(self.layout.values(), 0.0);
        self.stamp += 1;

        // Blocks by body: each body couples every pair of the blocks that touch it.
        self.body_start.clear();
        self.body_start.resize(island_bodies + 1, 0);
        for key in &self.block_key {
            for &b in key.iter().filter(|&&b| b != u32::MAX) {
                self.body_start[b as usize + 1] += 1;
            }
        }
        for i in 0..island_bodies {
            self.body_start[i + 1] += self.body_start[i];
        }
        self.body_entries.clear();
        self.body_entries
            .resize(self.body_start[island_bodies] as usize, (0, 0));
        for (blk, key) in self.block_key.iter().enumerate() {
            for (slot, &b) in key.iter().enumerate() {
                if b != u32::MAX {
                    let at = &mut self.body_start[b as usize];
                    self.body_entries[*at as usize] = (blk as u32, slot as u8);
                    *at += 1;
                }
            }
        }
        // (body_start[b] now holds the end of body b's entries: its start is body_start[b-1].)
        let blocks = BlockRows {
            rows: &self.rows,
            first: &self.block_first,
            size: &self.block_size,
            position: &self.block_position,
        };
        for b in 0..island_bodies {
            let start = if b == 0 { 0 } else { self.body_start[b - 1] } as usize;
            let end = self.body_start[b] as usize;
            for e in start..end {
                for f in start..=e {
                    add_coupling(
                        pattern,
                        &self.layout,
                        &blocks,
                        &mut self.sys.a,
                        self.body_entries[e],
                        self.body_entries[f],
                    );
                }
            }
        }
        // M⁻¹Jᵀ is rounded through `Real`, so J_i·(M⁻¹J_j) and J_j·(M⁻¹J_i) differ in their
        // last bits: mirror each diagonal block's lower triangle so that the matrix the
        // pivoting multiplies by is exactly the one it factorises.
        for k in 0..pattern.len() {
            let (_, s) = self.layout.rows(k);
            let at = self.layout.offset(k);
            for i in 0..s {
                for j in 0..i {
                    self.sys.a[at + j * s + i] = self.sys.a[at + i * s + j];
                }
            }
        }
    }

    /// Sizes the row vectors for `n` rows without clearing them, for a caller that writes
    /// every entry it reads (the split islands' direct solves, several a substep).
    pub(super) fn fit_vectors(&mut self, n: usize) {
        for v in self.row_vectors() {
            v.resize(n, 0.0);
        }
        self.sys.state.resize(n, Bound::Free);
    }

    /// Sizes `b`, the bounds, `x`, `w` and the sets for `n` rows, cleared.
    pub(super) fn size_vectors(&mut self, n: usize) {
        for v in self.row_vectors() {
            v.clear();
            v.resize(n, 0.0);
        }
        self.sys.state.clear();
        self.sys.state.resize(n, Bound::Free);
    }

    /// Fills `A = J M⁻¹ Jᵀ` (no diagonal terms) for the gathered rows, dense or block-sparse
    /// as [`ExactWorkspace::dense_system`] says, and sizes the vectors.
    pub(super) fn fill_system(&mut self) {
        self.dense_now = self.dense_system();
        if self.dense_now {
            self.dense.fill(&self.rows, &self.sys.links);
            self.size_vectors(self.rows.len());
        } else {
            self.assemble_matrix();
            self.size_vectors(self.rows.len());
        }
    }

    /// The diagonal entry of island row `i` in `A`.
    pub(super) fn diagonal(&self, i: usize) -> f64 {
        if self.dense_now {
            return self.dense.diagonal(i);
        }
        if self.tree_now {
            return self.tree.diagonal(i);
        }
        let (at, stride, r) = self.diagonal_index(i);
        self.sys.a[at + r * stride + r]
    }

    /// Where island row `i`'s diagonal lives: its block's offset, the block's size, and the
    /// row's index in it.
    pub(super) fn diagonal_index(&self, i: usize) -> (usize, usize, usize) {
        // Blocks are contiguous and in gathered order: find the one holding row i.
        let blk = self.block_first.partition_point(|&f| f as usize <= i) - 1;
        let k = self.block_position[blk] as usize;
        let (first, size) = self.layout.rows(k);
        (self.layout.offset(k), size, i - first)
    }

    /// `out = A x` on the block-sparse system as filled (tree or general).
    pub(super) fn multiply(&mut self, x: &[f64], out: &mut [f64]) {
        use crate::solver::sparse::pivoting::HeldSystem;
        if self.tree_now {
            self.tree.multiply(x, out);
        } else {
            crate::solver::sparse::factor::multiply(
                self.patterns.current(),
                &self.layout,
                &self.sys.a,
                x,
                out,
            );
        }
    }

    /// Adds `v` to island row `i`'s diagonal.
    pub(super) fn add_diagonal(&mut self, i: usize, v: f64) {
        if self.dense_now {
            return self.dense.add_diagonal(i, v);
        }
        if self.tree_now {
            return self.tree.add_diagonal(i, v);
        }
        let (at, stride, r) = self.diagonal_index(i);
        self.sys.a[at + r * stride + r] += v;
    }

    pub(super) fn assemble(
        &mut self,
        rows: &[Row],
        scratch: &BodyScratch,
        params: &SolverParams,
        h: f64,
        guess: &[Real],
    ) {
        self.fill_system();
        let n = self.rows.len();
        for i in 0..n {
            let ri = self.rows[i];
            let row = &rows[ri.global as usize];
            // A spring row's ε is relative to its own effective mass: the diagonal just built.
            let diag = self.diagonal(i);
            let (eps, gamma) = match row.spring.and_then(|sp| sp.relative_softness(h as Real)) {
                Some((relative, g)) => (wide(relative) * diag, wide(row.gamma.unwrap_or(g))),
                None => (
                    wide(row.softness.unwrap_or(params.epsilon)),
                    wide(row.gamma.unwrap_or(params.gamma)),
                ),
            };
            self.add_diagonal(i, eps + wide(row.slip) / h);
            let mut jv = 0.0;
            for s in 0..2 {
                if let Some(b) = ri.bodies[s] {
                    jv += ri.jac[2 * s].dot(to_f64(scratch.free_linear[b as usize]))
                        + ri.jac[2 * s + 1].dot(to_f64(scratch.free_angular[b as usize]));
                }
            }
            // No chord here (`Row::curvature`): one linearisation a step and the chord turned
            // a 30° pendulum's slow loss (1% in 10 s) into a gain (3%).
            self.sys.b[i] = (wide(row.c) - gamma * wide(row.xi) / h - jv) / h;
            self.sys.lo[i] = wide(row.lo);
            self.sys.hi[i] = wide(row.hi);
        }
        // Warm start: each row at the set its last force puts it in; friction bounded by the
        // last normal force, or unbounded (the sticking guess) without one.
        for i in 0..n {
            let g = |j: usize| wide(guess[self.rows[j].global as usize]);
            if let Some((normal, mu)) = self.sys.links[i] {
                let bound = mu * g(normal as usize).max(0.0);
                (self.sys.lo[i], self.sys.hi[i]) = if bound > 0.0 {
                    (-bound, bound)
                } else {
                    (f64::NEG_INFINITY, f64::INFINITY)
                };
            }
            self.sys.state[i] = crate::solver::sparse::pivoting::state_from_guess(
                self.sys.lo[i],
                self.sys.hi[i],
                g(i),
            );
            let ri = self.rows[i].global;
            if self.contact_rows_from.is_some_and(|f| ri >= f) && g(i) == 0.0 {
                let row = &rows[ri as usize];
                if row.lo == 0.0 && row.hi == Real::INFINITY && row.friction.is_none() {
                    self.sys.state[i] = Bound::Free;
                }
            }
        }
    }
}

/// An island's rows grouped by block, with each block's place in the elimination order.
struct BlockRows<'a> {
    rows: &'a [IslandRow],
    first: &'a [u32],
    size: &'a [u32],
    position: &'a [u32],
}

/// Adds, to `a`, the coupling through one body of block `p` (touching it in slot `sp`) and
/// block `q` (slot `sq`).
fn add_coupling(
    pattern: &Pattern,
    layout: &Layout,
    blocks: &BlockRows<'_>,
    a: &mut [f64],
    (p, sp): (u32, u8),
    (q, sq): (u32, u8),
) {
    let (p, q) = (p as usize, q as usize);
    let (pa, pb) = (blocks.position[p] as usize, blocks.position[q] as usize);
    let (fp, sp_rows) = (blocks.first[p] as usize, blocks.size[p] as usize);
    let (fq, sq_rows) = (blocks.first[q] as usize, blocks.size[q] as usize);
    let at = layout.offset(
        pattern
            .slot(pa, pb)
            .expect("coupled blocks are in the pattern"),
    );
    let (sp, sq) = (2 * sp as usize, 2 * sq as usize);
    for i in 0..sp_rows {
        let ri = &blocks.rows[fp + i];
        for j in 0..sq_rows {
            let rj = &blocks.rows[fq + j];
            let v = ri.jac[sp].dot(rj.mj[sq]) + ri.jac[sp + 1].dot(rj.mj[sq + 1]);
            if pa == pb {
                // The same block through its two slots (a block on one body twice) adds the
                // mirrored term too.
                a[at + i * sp_rows + j] += v;
                if sp != sq {
                    a[at + j * sp_rows + i] += v;
                }
            } else if pa > pb {
                a[at + i * sq_rows + j] += v;
            } else {
                a[at + j * sp_rows + i] += v;
            }
        }
    }
}
