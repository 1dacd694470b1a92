//! The tree solve: `A = J M⁻¹ Jᵀ + E` of an island whose blocks join its bodies without a
//! loop, factorised `A = L Lᵀ` with no fill over the order of [`TreeOrder`], and solved leaf
//! to root and back in time linear in the rows (a body's nodes form a clique: quadratic in the
//! nodes on one body, which the order caps).
//!
//! * Fill: each diagonal block is `Σ_b J_b (M⁻¹Jᵀ)_b` over the node's bodies, each
//!   off-diagonal block `J_t,b (M⁻¹Jᵀ)_k,b` over the body `b` two nodes share, written
//!   straight into the blocks in elimination order (values of one position, then its
//!   off-diagonal blocks, next to each other).
//! * Factor, left-looking: position `k`'s diagonal loses `L_kc L_kcᵀ` for each earlier block
//!   `L_kc` aimed at it and is factorised by a dense Cholesky; each of its blocks `L_tk` loses
//!   `L_tc L_kcᵀ` for each earlier pair and is solved against `L_kkᵀ`.
//! * Held rows (pivoting's bound rows): identity rows keeping their diagonal, couplings
//!   cleared. A change of held rows refactorises the positions whose rows changed, the
//!   positions whose blocks aim at them, and their ancestors in the elimination tree only
//!   (the branch to the root); the rest of the factor stands.
//!
//! It is a [`HeldSystem`], so the pivoting of the general system runs on it unchanged.

// Small dense blocks read best with indices.
#![allow(clippy::needless_range_loop)]

use super::pivoting::{self, HeldSystem, LcpReport, Limits};
use super::sets::{Bound, Unknowns};
use super::system::FrictionLink;
pub(crate) use super::tree_order::TreeOrder;
use super::tree_order::{Position, NONE};
use crate::math::DVec3;
use crate::solver::reserve;

/// Values a row of a tree's system is budgeted for when reserving: its node's diagonal block
/// (up to 12 wide in a stack) and a few off-diagonal blocks.
const VALUES_PER_ROW: usize = 48;

/// The tree solve's system and factor (module docs).
#[derive(Debug, Default, Clone)]
pub(crate) struct TreeSystem {
    pub(crate) order: TreeOrder,
    /// `A`'s blocks, and `L`'s, in the order's layout.
    a: Vec<f64>,
    l: Vec<f64>,
    /// `1 / L_ii` per row (position order): substitutions multiply, not divide.
    inv: Vec<f64>,
    /// Per position: its rows up to its last free one (the rest are held).
    active: Vec<u32>,
    /// Which rows (position order) the factor holds, and whether it is of the present values.
    held: Vec<bool>,
    factored: bool,
    /// Per position: refactorise now, and whether its pivots were regularised.
    dirty: Vec<bool>,
    singular: Vec<bool>,
    /// Vectors in position order; scratch for a dense block.
    z: Vec<f64>,
    w: Vec<f64>,
    block: Vec<f64>,
    /// The pivoting's held values.
    bound: Vec<f64>,
    /// Each row's Jacobian and `M⁻¹Jᵀ` by node slot, in position order, while filling.
    jm: Vec<([DVec3; 4], [DVec3; 4])>,
}

impl TreeSystem {
    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        self.order.bytes()
            + 8 * (self.a.capacity()
                + self.l.capacity()
                + self.inv.capacity()
                + self.z.capacity()
                + self.w.capacity()
                + self.block.capacity()
                + self.bound.capacity())
            + self.jm.capacity() * std::mem::size_of::<([DVec3; 4], [DVec3; 4])>()
            + self.held.capacity()
            + self.active.capacity() * 4
            + self.dirty.capacity()
            + self.singular.capacity()
    }

    /// Makes room for systems of `rows` rows (a tree's values are budgeted at
    /// [`VALUES_PER_ROW`] a row), so that a step allocates nothing when one first reaches it.
    pub(crate) fn reserve(&mut self, rows: usize) {
        self.order.reserve(rows);
        for v in [&mut self.a, &mut self.l] {
            reserve(v, rows * VALUES_PER_ROW);
        }
        for v in [&mut self.inv, &mut self.z, &mut self.w, &mut self.bound] {
            reserve(v, rows);
        }
        reserve(&mut self.active, rows);
        reserve(&mut self.held, rows);
        reserve(&mut self.dirty, rows);
        reserve(&mut self.singular, rows);
        reserve(&mut self.jm, rows);
    }

    /// Rows.
    pub(crate) fn rows(&self) -> usize {
        self.order.row_of.len()
    }

    /// Fills `A = J M⁻¹ Jᵀ` (no diagonal terms) from each caller row's Jacobian and `M⁻¹Jᵀ`
    /// (linear then angular, per block slot), after [`TreeOrder::analyse`] took the blocks.
    pub(crate) fn fill(&mut self, row: impl Fn(usize) -> ([DVec3; 4], [DVec3; 4])) {
        let o = &self.order;
        // Every value is written below: no clearing.
        self.a.resize(o.values, 0.0);
        self.factored = false;
        // Each row's Jacobian and M⁻¹Jᵀ by node slot (a swapped block's slots exchanged).
        self.jm.clear();
        self.jm
            .extend(o.row_of.iter().zip(&o.row_swapped).map(|(&r, &swapped)| {
                let (jac, mj) = row(r as usize);
                if swapped {
                    (
                        [jac[2], jac[3], jac[0], jac[1]],
                        [mj[2], mj[3], mj[0], mj[1]],
                    )
                } else {
                    (jac, mj)
                }
            }));
        let jm = &self.jm;
        let dot = |j: &[DVec3; 4], m: &[DVec3; 4], s: usize, t: usize| {
            j[2 * s].dot(m[2 * t]) + j[2 * s + 1].dot(m[2 * t + 1])
        };
        for (k, p) in o.position.iter().enumerate() {
            let (first, size, at) = (p.row as usize, p.size as usize, p.value as usize);
            let bodies = o.position_bodies[k];
            let rows = &jm[first..first + size];
            for r in 0..size {
                for c in 0..=r {
                    let mut v = 0.0;
                    for s in 0..2 {
                        if bodies[s] != NONE {
                            v += dot(&rows[r].0, &rows[c].1, s, s);
                        }
                    }
                    // Mirrored, so that the matrix multiplied by is the one factorised.
                    self.a[at + r * size + c] = v;
                    self.a[at + c * size + r] = v;
                }
            }
            for b in o.blocks_of(p) {
                let [sk, st] = b.slots.map(usize::from);
                let (tf, ts, at) = (
                    b.target_row as usize,
                    b.target_size as usize,
                    b.value as usize,
                );
                let out = &mut self.a[at..at + ts * size];
                for (r, target) in jm[tf..tf + ts].iter().enumerate() {
                    for (c, source) in rows.iter().enumerate() {
                        out[r * size + c] = dot(&target.0, &source.1, st, sk);
                    }
                }
            }
        }
    }

    /// The index in `a` of caller row `i`'s diagonal.
    fn diagonal_index(&self, i: usize) -> usize {
        let o = &self.order;
        let pr = o.position_of_row[i] as usize;
        let p = &o.position[o.row_position[pr] as usize];
        p.value as usize + (pr - p.row as usize) * (p.size as usize + 1)
    }

    /// Caller row `i`'s diagonal in `A`.
    pub(crate) fn diagonal(&self, i: usize) -> f64 {
        self.a[self.diagonal_index(i)]
    }

    /// Adds `v` to caller row `i`'s diagonal.
    pub(crate) fn add_diagonal(&mut self, i: usize, v: f64) {
        let at = self.diagonal_index(i);
        self.a[at] += v;
        self.factored = false;
    }

    /// Block principal pivoting (see [`pivoting`]) on this system.
    pub(crate) fn pivot(
        &mut self,
        (b, links): (&[f64], &[FrictionLink]),
        u: &mut Unknowns<'_>,
        limits: Limits,
    ) -> LcpReport {
        let mut bound = std::mem::take(&mut self.bound);
        let report = pivoting::solve_on(self, (b, links), u, &mut bound, limits);
        self.bound = bound;
        report
    }

    /// Refactorises position `k` (module docs); returns whether a pivot was regularised.
    /// Rows past a position's last free row (a joint's open stops, written after its
    /// equalities) are identity rows: the products skip them.
    fn factor_position(&mut self, k: usize, tiny: f64, floor: f64) -> bool {
        match self.order.position[k].size {
            3 => self.factor_position_of::<3>(k, tiny, floor),
            4 => self.factor_position_of::<4>(k, tiny, floor),
            5 => self.factor_position_of::<5>(k, tiny, floor),
            6 => self.factor_position_of::<6>(k, tiny, floor),
            7 => self.factor_position_of::<7>(k, tiny, floor),
            8 => self.factor_position_of::<8>(k, tiny, floor),
            _ => self.factor_position_of::<0>(k, tiny, floor),
        }
    }

    /// [`Self::factor_position`] for a position of `S` rows, so that its loops unroll (0: any
    /// size, read from the position).
    #[inline(always)]
    fn factor_position_of<const S: usize>(&mut self, k: usize, tiny: f64, floor: f64) -> bool {
        let o = &self.order;
        let p = o.position[k];
        let size = if S == 0 { p.size as usize } else { S };
        let (first, at) = (p.row as usize, p.value as usize);
        let (held, act) = (&self.held[..], &self.active[..]);
        let m = act[k] as usize;
        let own_held = held[first..first + m].iter().any(|&h| h);
        // Everything of earlier positions lies before this position's values.
        let (done, rest) = self.l.split_at_mut(at);
        let a = &self.a[at..];
        // The diagonal (lower triangle), held rows as identity rows.
        let diag = &mut rest[..size * size];
        diag.fill(0.0);
        for r in 0..size {
            if r >= m {
                diag[r * size + r] = a[r * size + r];
                continue;
            }
            for c in 0..=r {
                let keep = !own_held || r == c || !(held[first + r] || held[first + c]);
                if keep {
                    diag[r * size + c] = a[r * size + c];
                }
            }
        }
        let [u0, u1] = p.diag_updates.map(|x| x as usize);
        for u in &o.diag_update[u0..u1] {
            let (cs, lq) = (u.columns as usize, u.value as usize);
            let mc = act[u.source as usize] as usize;
            let block = &done[lq..lq + size * cs];
            for r in 0..m {
                let lr = &block[r * cs..];
                for c in 0..=r {
                    diag[r * size + c] -= dot_n(lr, &block[c * cs..], mc);
                }
            }
        }
        let singular = cholesky(diag, size, m, (tiny, floor));
        let (diag, blocks) = rest.split_at_mut(size * size);
        let inv = &mut self.inv[first..first + size];
        for r in 0..size {
            inv[r] = 1.0 / diag[r * size + r];
        }
        let inv = &self.inv[first..first + size];
        // Each off-diagonal block: A_tk − Σ L_tc L_kcᵀ, then solved against L_kkᵀ.
        for b in o.blocks_of(&p) {
            let (tf, ts) = (b.target_row as usize, b.target_size as usize);
            let mt = act[b.target as usize] as usize;
            let off = b.value as usize - at;
            let out = &mut blocks[off - size * size..off - size * size + ts * size];
            let a = &self.a[b.value as usize..b.value as usize + ts * size];
            out.fill(0.0);
            let target_held = held[tf..tf + mt].iter().any(|&h| h);
            for r in 0..mt {
                let (o_row, a_row) = (&mut out[r * size..r * size + m], &a[r * size..r * size + m]);
                if own_held || target_held {
                    for c in 0..m {
                        if !(held[tf + r] || held[first + c]) {
                            o_row[c] = a_row[c];
                        }
                    }
                } else {
                    o_row.copy_from_slice(a_row);
                }
            }
            let [q0, q1] = b.pairs.map(|x| x as usize);
            for pu in &o.pair_update[q0..q1] {
                let cs = pu.columns as usize;
                let mc = act[pu.source as usize] as usize;
                let lt = &done[pu.target_side as usize..pu.target_side as usize + ts * cs];
                let lk = &done[pu.source_side as usize..pu.source_side as usize + size * cs];
                for r in 0..mt {
                    let lr = &lt[r * cs..];
                    for c in 0..m {
                        out[r * size + c] -= dot_n(lr, &lk[c * cs..], mc);
                    }
                }
            }
            // Row r of L_tk solves L_kk x = (row r)ᵀ.
            for r in 0..mt {
                let row = &mut out[r * size..r * size + m];
                for c in 0..m {
                    let v = row[c] - dot_n(&diag[c * size..], row, c);
                    row[c] = v * inv[c];
                }
            }
        }
        singular
    }

    /// Permutes caller-ordered `x` into `z` (position order).
    fn gather(order: &TreeOrder, x: &[f64], z: &mut Vec<f64>) {
        z.clear();
        z.extend(order.row_of.iter().map(|&r| x[r as usize]));
    }
}

/// `a · b` over the shorter of the two.
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `a · b` over their first `n` entries, summed as [`dot`] sums (from −0.0, in order, so the
/// bits are the same), unrolled for the sizes joints' blocks have: the products of a tree's
/// 3×3 and 6×6 blocks are dots of 0 to 6 terms, where a general loop's set-up and bounds
/// checks cost more than the arithmetic.
#[inline(always)]
fn dot_n(a: &[f64], b: &[f64], n: usize) -> f64 {
    #[inline(always)]
    fn fixed<const N: usize>(a: &[f64], b: &[f64]) -> f64 {
        let (a, b) = (&a[..N], &b[..N]);
        let mut s = -0.0;
        for i in 0..N {
            s += a[i] * b[i];
        }
        s
    }
    match n {
        0 => -0.0,
        1 => fixed::<1>(a, b),
        2 => fixed::<2>(a, b),
        3 => fixed::<3>(a, b),
        4 => fixed::<4>(a, b),
        5 => fixed::<5>(a, b),
        6 => fixed::<6>(a, b),
        _ => dot(&a[..n], &b[..n]),
    }
}

impl HeldSystem for TreeSystem {
    fn len(&self) -> usize {
        self.rows()
    }

    fn diagonal_max(&self) -> f64 {
        let mut m = 0.0f64;
        for p in &self.order.position {
            let (size, at) = (p.size as usize, p.value as usize);
            for r in 0..size {
                m = m.max(self.a[at + r * (size + 1)].abs());
            }
        }
        m
    }

    fn multiply(&mut self, x: &[f64], out: &mut [f64]) {
        let o = &self.order;
        Self::gather(o, x, &mut self.z);
        let (z, w) = (&self.z, &mut self.w);
        w.clear();
        w.resize(z.len(), 0.0);
        for p in &o.position {
            let (first, size, at) = (p.row as usize, p.size as usize, p.value as usize);
            let zk = &z[first..first + size];
            for r in 0..size {
                w[first + r] += dot_n(&self.a[at + r * size..], zk, size);
            }
            for b in o.blocks_of(p) {
                let (tf, ts, aq) = (
                    b.target_row as usize,
                    b.target_size as usize,
                    b.value as usize,
                );
                for r in 0..ts {
                    let row = &self.a[aq + r * size..aq + r * size + size];
                    w[tf + r] += dot(row, zk);
                    let zt = z[tf + r];
                    for (wc, e) in w[first..first + size].iter_mut().zip(row) {
                        *wc += e * zt;
                    }
                }
            }
        }
        for (p, &r) in o.row_of.iter().enumerate() {
            out[r as usize] = w[p];
        }
    }

    fn slack(&mut self, x: &[f64], b: &[f64], state: &[Bound], w: &mut [f64]) {
        // Only the rows not free (a joint's stops, most of them open and held at zero): each
        // from its own block, the blocks its position sends and the blocks aimed at it, in
        // that order (the order of a full product's sums, so the bits are the same).
        let o = &self.order;
        Self::gather(o, x, &mut self.z);
        let z = &self.z;
        w.fill(0.0);
        for p in &o.position {
            let (first, size, at) = (p.row as usize, p.size as usize, p.value as usize);
            let rows = &o.row_of[first..first + size];
            let mut held = [0u8; 32];
            let mut count = 0;
            for (r, &caller) in rows.iter().enumerate() {
                if state[caller as usize] != Bound::Free {
                    held[count] = r as u8;
                    count += 1;
                }
            }
            if count == 0 {
                continue;
            }
            let held = &held[..count];
            let mut wk = [0.0f64; 32];
            for &r in held {
                let r = usize::from(r);
                wk[r] = dot_n(&self.a[at + r * size..], &z[first..], size);
            }
            for bq in o.blocks_of(p) {
                let (tf, ts, aq) = (
                    bq.target_row as usize,
                    bq.target_size as usize,
                    bq.value as usize,
                );
                for t in 0..ts {
                    let zt = z[tf + t];
                    let row = &self.a[aq + t * size..aq + t * size + size];
                    for &r in held {
                        let r = usize::from(r);
                        wk[r] += row[r] * zt;
                    }
                }
            }
            let [u0, u1] = p.diag_updates.map(|x| x as usize);
            for u in &o.diag_update[u0..u1] {
                let (cs, aq) = (u.columns as usize, u.value as usize);
                let sf = o.position[u.source as usize].row as usize;
                for &r in held {
                    let r = usize::from(r);
                    wk[r] += dot_n(&self.a[aq + r * cs..], &z[sf..], cs);
                }
            }
            for &r in held {
                let r = usize::from(r);
                let i = rows[r] as usize;
                w[i] = wk[r] - b[i];
            }
        }
    }

    fn held_diagonal(&self, state: &[Bound], held: &[f64], x: &mut [f64]) {
        for i in 0..self.rows() {
            if state[i] != Bound::Free {
                x[i] = self.diagonal(i) * held[i];
            }
        }
    }

    fn factor(&mut self, state: &[Bound], tiny: f64, floor: f64) -> bool {
        let positions = self.order.positions();
        let rows = self.rows();
        let fresh = !self.factored;
        if fresh {
            // Every position is factorised (each writes all its values, reciprocals and
            // flag), and a held flag left over is rewritten below where it differs: sized,
            // not cleared.
            self.l.resize(self.order.values, 0.0);
            self.inv.resize(rows, 0.0);
            self.held.resize(rows, false);
            self.singular.resize(positions, false);
        }
        self.dirty.clear();
        self.dirty.resize(positions, fresh);
        for p in 0..rows {
            let h = state[self.order.row_of[p] as usize] != Bound::Free;
            if h != self.held[p] {
                self.held[p] = h;
                let o = &self.order;
                let k = o.row_position[p] as usize;
                self.dirty[k] = true;
                // The blocks aimed at k clear the held row: their sources change too.
                let [u0, u1] = o.position[k].diag_updates.map(|x| x as usize);
                for u in &o.diag_update[u0..u1] {
                    self.dirty[u.source as usize] = true;
                }
            }
        }
        self.active.clear();
        self.active.extend(self.order.position.iter().map(|p| {
            let rows = &self.held[p.row as usize..(p.row + p.size) as usize];
            rows.iter().rposition(|&h| !h).map_or(0, |r| r as u32 + 1)
        }));
        for k in 0..positions {
            if !self.dirty[k] {
                continue;
            }
            self.singular[k] = self.factor_position(k, tiny, floor);
            let parent = self.order.position[k].parent;
            if parent != NONE {
                self.dirty[parent as usize] = true;
            }
        }
        self.factored = true;
        self.singular.iter().any(|&s| s)
    }

    fn solve(&mut self, x: &mut [f64]) {
        let o = &self.order;
        Self::gather(o, x, &mut self.z);
        let z = &mut self.z;
        let (l, inv, act) = (&self.l[..], &self.inv[..], &self.active[..]);
        for (k, p) in o.position.iter().enumerate() {
            let parts = (l, inv, act[k] as usize);
            match p.size {
                3 => forward::<3>(o, p, parts, act, z),
                4 => forward::<4>(o, p, parts, act, z),
                5 => forward::<5>(o, p, parts, act, z),
                6 => forward::<6>(o, p, parts, act, z),
                7 => forward::<7>(o, p, parts, act, z),
                8 => forward::<8>(o, p, parts, act, z),
                _ => forward::<0>(o, p, parts, act, z),
            }
        }
        for (k, p) in o.position.iter().enumerate().rev() {
            let parts = (l, inv, act[k] as usize);
            match p.size {
                3 => backward::<3>(o, p, parts, act, z),
                4 => backward::<4>(o, p, parts, act, z),
                5 => backward::<5>(o, p, parts, act, z),
                6 => backward::<6>(o, p, parts, act, z),
                7 => backward::<7>(o, p, parts, act, z),
                8 => backward::<8>(o, p, parts, act, z),
                _ => backward::<0>(o, p, parts, act, z),
            }
        }
        for (p, &r) in o.row_of.iter().enumerate() {
            x[r as usize] = z[p];
        }
    }
}

/// The solve's forward pass over position `p` (its active rows `m`): `z_k ← L_kk⁻¹ z_k`, then
/// the blocks it sends take their share off their targets. `S` is the position's size when it
/// is one joints have (3 to 8 rows: a joint and its stops), so that the loops unroll; 0 for any
/// other (read from `p`).
#[inline(always)]
fn forward<const S: usize>(
    o: &TreeOrder,
    p: &Position,
    (l, inv, m): (&[f64], &[f64], usize),
    act: &[u32],
    z: &mut [f64],
) {
    let (first, at) = (p.row as usize, p.value as usize);
    let size = if S == 0 { p.size as usize } else { S };
    for r in 0..size {
        let v = if r < m {
            z[first + r] - dot_n(&l[at + r * size..], &z[first..], r)
        } else {
            z[first + r]
        };
        z[first + r] = v * inv[first + r];
    }
    for b in o.blocks_of(p) {
        let (tf, lq) = (b.target_row as usize, b.value as usize);
        for r in 0..act[b.target as usize] as usize {
            let v = dot_n(&l[lq + r * size..], &z[first..], m);
            z[tf + r] -= v;
        }
    }
}

/// The solve's backward pass over position `p`: the blocks it sent give back their targets'
/// share, then `z_k ← L_kkᵀ⁻¹ z_k` (see [`forward`] for `S`).
#[inline(always)]
fn backward<const S: usize>(
    o: &TreeOrder,
    p: &Position,
    (l, inv, m): (&[f64], &[f64], usize),
    act: &[u32],
    z: &mut [f64],
) {
    let (first, at) = (p.row as usize, p.value as usize);
    let size = if S == 0 { p.size as usize } else { S };
    for b in o.blocks_of(p) {
        let (tf, lq) = (b.target_row as usize, b.value as usize);
        for r in 0..act[b.target as usize] as usize {
            let zt = z[tf + r];
            let row = &l[lq + r * size..lq + r * size + m];
            for (zc, e) in z[first..first + m].iter_mut().zip(row) {
                *zc -= e * zt;
            }
        }
    }
    for r in (0..size).rev() {
        let mut v = z[first + r];
        for c in r + 1..m {
            v -= l[at + c * size + r] * z[first + c];
        }
        z[first + r] = v * inv[first + r];
    }
}

/// Dense Cholesky of the `n × n` lower triangle of `m` (row-major) in place, of which the
/// rows from `active` on are identity rows (their diagonal only); pivots not above `tiny`
/// become `floor`. Returns whether one did.
fn cholesky(m: &mut [f64], n: usize, active: usize, (tiny, floor): (f64, f64)) -> bool {
    let mut singular = false;
    for j in 0..n {
        let mut d = m[j * n + j];
        if j < active {
            d -= dot_n(&m[j * n..], &m[j * n..], j);
        }
        if d.is_nan() || d <= tiny {
            d = floor;
            singular = true;
        }
        let d = d.sqrt();
        m[j * n + j] = d;
        let inv = 1.0 / d;
        for i in j + 1..active {
            let v = m[i * n + j] - dot_n(&m[i * n..], &m[j * n..], j);
            m[i * n + j] = v * inv;
        }
    }
    singular
}

#[cfg(test)]
#[path = "tree_tests.rs"]
mod tests;
