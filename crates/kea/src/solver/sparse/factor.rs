//! The numbers of an island's block-sparse system: its blocks laid out over a [`Pattern`], the
//! product `A x`, and an in-place block Cholesky factorisation `A = L Lᵀ` with its solve.
//!
//! Position `k` of the pattern owns a dense diagonal block (its rows by its rows) and one dense
//! block per later position `a` below it (the rows of `a` by the rows of `k`). Eliminating `k`
//! factors its diagonal block, turns the blocks below it into `L_ak = A_ak L_kk⁻ᵀ`, and
//! subtracts `L_ak L_bkᵀ` from every later pair `(a, b)`; the pattern already holds a slot for
//! each such pair, so the factor never needs memory the analysis did not plan. A pivot that is
//! not clearly positive (redundant rows without softness) is replaced by a small positive one
//! and reported: the solve stays finite and the redundant direction carries no force.

// Dense kernels over row and block indices read clearest as index loops.
#![allow(clippy::needless_range_loop)]

use super::pattern::Pattern;

/// Where the blocks of one island's system live.
#[derive(Debug, Default, Clone)]
pub(crate) struct Layout {
    /// Per position: its first row in the island's row order, and its row count.
    first: Vec<u32>,
    size: Vec<u32>,
    /// Per slot: offset of its values.
    offset: Vec<u32>,
    /// Values in all.
    values: usize,
}

impl Layout {
    /// Lays out `pattern` for blocks whose rows start at `block_first[b]` and number
    /// `block_size[b]` (indexed by block, not position).
    pub(crate) fn build(&mut self, pattern: &Pattern, block_first: &[u32], block_size: &[u32]) {
        let n = pattern.len();
        self.first.clear();
        self.size.clear();
        for &b in &pattern.order {
            self.first.push(block_first[b as usize]);
            self.size.push(block_size[b as usize]);
        }
        self.offset.clear();
        self.offset.resize(pattern.slot_count(), 0);
        let mut at = 0usize;
        for k in 0..n {
            self.offset[k] = at as u32;
            at += (self.size[k] * self.size[k]) as usize;
        }
        for k in 0..n {
            for (i, &a) in pattern.later(k).iter().enumerate() {
                self.offset[pattern.off_slot(k, i)] = at as u32;
                at += (self.size[a as usize] * self.size[k]) as usize;
            }
        }
        self.values = at;
    }

    /// Values the system needs.
    pub(crate) fn values(&self) -> usize {
        self.values
    }

    /// Rows of position `k`: first and count.
    pub(crate) fn rows(&self, k: usize) -> (usize, usize) {
        (self.first[k] as usize, self.size[k] as usize)
    }

    /// Offset of slot `s`.
    pub(crate) fn offset(&self, s: usize) -> usize {
        self.offset[s] as usize
    }
}

/// `out = A x` for the system `values` laid out by `layout` over `pattern`.
pub(crate) fn multiply(
    pattern: &Pattern,
    layout: &Layout,
    values: &[f64],
    x: &[f64],
    out: &mut [f64],
) {
    out.fill(0.0);
    for k in 0..pattern.len() {
        let (fk, sk) = layout.rows(k);
        let d = &values[layout.offset(k)..];
        for r in 0..sk {
            let mut s = 0.0;
            for c in 0..sk {
                s += d[r * sk + c] * x[fk + c];
            }
            out[fk + r] += s;
        }
        for (i, &a) in pattern.later(k).iter().enumerate() {
            let (fa, sa) = layout.rows(a as usize);
            let blk = &values[layout.offset(pattern.off_slot(k, i))..];
            for r in 0..sa {
                let row = &blk[r * sk..r * sk + sk];
                let xa = x[fa + r];
                let mut s = 0.0;
                for c in 0..sk {
                    s += row[c] * x[fk + c];
                    out[fk + c] += row[c] * xa;
                }
                out[fa + r] += s;
            }
        }
    }
}

/// Factors `values` (the system, over `pattern` and `layout`) in place into `L`. Pivots not
/// above `tiny` are replaced by `floor`; returns whether any was. With `only`, just the
/// positions it marks are factorised: it must mark whole connected components (elimination
/// never leaves one), whose values are then as if the whole were factorised.
pub(crate) fn factorise(
    pattern: &Pattern,
    layout: &Layout,
    values: &mut [f64],
    tiny: f64,
    floor: f64,
    only: Option<&[bool]>,
) -> bool {
    let mut regularised = false;
    for k in 0..pattern.len() {
        if only.is_some_and(|o| !o[k]) {
            continue;
        }
        let (_, sk) = layout.rows(k);
        let dk = layout.offset(k);
        regularised |= cholesky_in_place(&mut values[dk..dk + sk * sk], sk, tiny, floor);
        let later = pattern.later(k);
        // L_ak = A_ak L_kk⁻ᵀ: each row of the block solved against L_kk.
        for (i, &a) in later.iter().enumerate() {
            let (_, sa) = layout.rows(a as usize);
            let at = layout.offset(pattern.off_slot(k, i));
            let (head, tail) = values.split_at_mut(at);
            let l = &head[dk..dk + sk * sk];
            for r in 0..sa {
                forward_solve(l, sk, &mut tail[r * sk..r * sk + sk]);
            }
        }
        // Schur complement onto the later pairs.
        let mut u = pattern.updates(k).iter();
        for ia in 0..later.len() {
            let (_, sa) = layout.rows(later[ia] as usize);
            let la = layout.offset(pattern.off_slot(k, ia));
            for ib in 0..=ia {
                let (_, sb) = layout.rows(later[ib] as usize);
                let lb = layout.offset(pattern.off_slot(k, ib));
                let target = layout.offset(*u.next().expect("one update per pair") as usize);
                let update = Update {
                    la,
                    lb,
                    target,
                    sa,
                    sb,
                    diagonal: ia == ib,
                };
                // Specialised per eliminated block size so that the dot unrolls (a ball
                // joint's 3 rows, a hinge's 5, a fixed joint's 6); same sums, same bits.
                match sk {
                    1 => update.apply::<1>(values),
                    2 => update.apply::<2>(values),
                    3 => update.apply::<3>(values),
                    4 => update.apply::<4>(values),
                    5 => update.apply::<5>(values),
                    6 => update.apply::<6>(values),
                    _ => update.apply_sized(values, sk),
                }
            }
        }
    }
    regularised
}

/// One Schur-complement update of the factorisation: `target −= L_a L_bᵀ`, the blocks `L_a`
/// (sa rows) and `L_b` (sb rows) at offsets `la`, `lb`, both of the eliminated block's width;
/// a diagonal target gets only its lower triangle.
struct Update {
    la: usize,
    lb: usize,
    target: usize,
    sa: usize,
    sb: usize,
    diagonal: bool,
}

impl Update {
    /// The update for an eliminated block of `S` rows.
    #[inline(always)]
    fn apply<const S: usize>(&self, values: &mut [f64]) {
        for r in 0..self.sa {
            let cols = if self.diagonal { r + 1 } else { self.sb };
            let a: [f64; S] = values[self.la + r * S..self.la + r * S + S]
                .try_into()
                .expect("a row of S values");
            for t in 0..cols {
                let b = &values[self.lb + t * S..self.lb + t * S + S];
                let mut s = 0.0;
                for c in 0..S {
                    s += a[c] * b[c];
                }
                values[self.target + r * self.sb + t] -= s;
            }
        }
    }

    /// The update for an eliminated block of `sk` rows, any size.
    fn apply_sized(&self, values: &mut [f64], sk: usize) {
        for r in 0..self.sa {
            let cols = if self.diagonal { r + 1 } else { self.sb };
            for t in 0..cols {
                let mut s = 0.0;
                for c in 0..sk {
                    s += values[self.la + r * sk + c] * values[self.lb + t * sk + c];
                }
                values[self.target + r * self.sb + t] -= s;
            }
        }
    }
}

/// Solves `L Lᵀ x = rhs` in place (`rhs` in the island's row order).
pub(crate) fn solve(pattern: &Pattern, layout: &Layout, factor: &[f64], x: &mut [f64]) {
    let n = pattern.len();
    for k in 0..n {
        let (fk, sk) = layout.rows(k);
        let l = &factor[layout.offset(k)..];
        forward_solve(l, sk, &mut x[fk..fk + sk]);
        for (i, &a) in pattern.later(k).iter().enumerate() {
            let (fa, sa) = layout.rows(a as usize);
            let blk = &factor[layout.offset(pattern.off_slot(k, i))..];
            for r in 0..sa {
                let mut s = 0.0;
                for c in 0..sk {
                    s += blk[r * sk + c] * x[fk + c];
                }
                x[fa + r] -= s;
            }
        }
    }
    for k in (0..n).rev() {
        let (fk, sk) = layout.rows(k);
        for (i, &a) in pattern.later(k).iter().enumerate() {
            let (fa, sa) = layout.rows(a as usize);
            let blk = &factor[layout.offset(pattern.off_slot(k, i))..];
            for r in 0..sa {
                let xa = x[fa + r];
                for c in 0..sk {
                    x[fk + c] -= blk[r * sk + c] * xa;
                }
            }
        }
        let l = &factor[layout.offset(k)..];
        backward_solve(l, sk, &mut x[fk..fk + sk]);
    }
}

/// Dense Cholesky of the lower triangle of `d` (s×s, row-major) in place. A pivot not above
/// `tiny` (or not a number) becomes `floor`; returns whether one did.
fn cholesky_in_place(d: &mut [f64], s: usize, tiny: f64, floor: f64) -> bool {
    let mut regularised = false;
    for i in 0..s {
        for j in 0..=i {
            let mut v = d[i * s + j];
            for c in 0..j {
                v -= d[i * s + c] * d[j * s + c];
            }
            if i == j {
                if v.is_nan() || v <= tiny {
                    v = floor;
                    regularised = true;
                }
                d[i * s + i] = v.sqrt();
            } else {
                d[i * s + j] = v / d[j * s + j];
            }
        }
    }
    regularised
}

/// `y ← L⁻¹ y` for the lower triangle `l` (s×s).
fn forward_solve(l: &[f64], s: usize, y: &mut [f64]) {
    for i in 0..s {
        let mut v = y[i];
        for c in 0..i {
            v -= l[i * s + c] * y[c];
        }
        y[i] = v / l[i * s + i];
    }
}

/// `y ← L⁻ᵀ y` for the lower triangle `l` (s×s).
fn backward_solve(l: &[f64], s: usize, y: &mut [f64]) {
    for i in (0..s).rev() {
        let mut v = y[i];
        for r in i + 1..s {
            v -= l[r * s + i] * y[r];
        }
        y[i] = v / l[i * s + i];
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::solver::sparse::pattern::{BlockBodies, PatternCache};

    /// A deterministic pseudo-random number in [-1, 1).
    pub(crate) fn rnd(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// A random island: `blocks` blocks of 1–6 rows on `bodies` bodies (some touching one), and
    /// its dense system `A = Σ J_b J_bᵀ + 0.1 I` (row-major, rows in block order).
    pub(crate) struct RandomIsland {
        pub key: Vec<BlockBodies>,
        pub first: Vec<u32>,
        pub size: Vec<u32>,
        pub dense: Vec<f64>,
        pub bodies: usize,
    }

    impl RandomIsland {
        pub(crate) fn new(seed: &mut u64, blocks: usize, bodies: usize, tree: bool) -> Self {
            let mut key = Vec::new();
            for k in 0..blocks {
                let pick = |seed: &mut u64| ((rnd(seed) + 1.0) * 0.5 * bodies as f64) as u32;
                // A tree: block k joins body k+1 to an earlier body (or to nothing).
                let pair = if tree {
                    let b = (k as u32 + 1).min(bodies as u32 - 1);
                    let a = pick(seed) % b.max(1);
                    [b, if rnd(seed) > -0.6 { a } else { u32::MAX }]
                } else {
                    let a = pick(seed).min(bodies as u32 - 1);
                    let b = pick(seed).min(bodies as u32 - 1);
                    [a, if b != a { b } else { u32::MAX }]
                };
                key.push(pair);
            }
            let size: Vec<u32> = (0..blocks)
                .map(|_| 1 + ((rnd(seed) + 1.0) * 2.99) as u32 * 2 % 6)
                .collect();
            let mut first = Vec::new();
            let mut n = 0;
            for &s in &size {
                first.push(n);
                n += s;
            }
            let n = n as usize;
            // Six velocity unknowns per body.
            let mut j = vec![0.0; n * 6 * bodies];
            for (k, pair) in key.iter().enumerate() {
                for r in 0..size[k] as usize {
                    let row = first[k] as usize + r;
                    for &b in pair.iter().filter(|&&b| b != u32::MAX) {
                        for c in 0..6 {
                            j[row * 6 * bodies + b as usize * 6 + c] = rnd(seed);
                        }
                    }
                }
            }
            let mut dense = vec![0.0; n * n];
            for r in 0..n {
                for c in 0..n {
                    let s: f64 = (0..6 * bodies)
                        .map(|v| j[r * 6 * bodies + v] * j[c * 6 * bodies + v])
                        .sum();
                    dense[r * n + c] = s + if r == c { 0.1 } else { 0.0 };
                }
            }
            Self {
                key,
                first,
                size,
                dense,
                bodies,
            }
        }

        pub(crate) fn rows(&self) -> usize {
            self.size.iter().sum::<u32>() as usize
        }

        /// The dense system's values laid out over `pattern`; panics if a coupling is missing.
        pub(crate) fn values(&self, pattern: &Pattern, layout: &Layout) -> Vec<f64> {
            let n = self.rows();
            let mut v = vec![0.0; layout.values()];
            let mut covered = vec![false; n * n];
            for k in 0..pattern.len() {
                let (fk, sk) = layout.rows(k);
                for r in 0..sk {
                    for c in 0..sk {
                        v[layout.offset(k) + r * sk + c] = self.dense[(fk + r) * n + fk + c];
                        covered[(fk + r) * n + fk + c] = true;
                    }
                }
                for (i, &a) in pattern.later(k).iter().enumerate() {
                    let (fa, sa) = layout.rows(a as usize);
                    for r in 0..sa {
                        for c in 0..sk {
                            v[layout.offset(pattern.off_slot(k, i)) + r * sk + c] =
                                self.dense[(fa + r) * n + fk + c];
                            covered[(fa + r) * n + fk + c] = true;
                            covered[(fk + c) * n + fa + r] = true;
                        }
                    }
                }
            }
            for i in 0..n * n {
                assert!(covered[i] || self.dense[i] == 0.0, "coupling {i} missing");
            }
            v
        }
    }

    #[test]
    fn block_factorisation_solves_random_islands() {
        let mut seed = 7u64;
        for case in 0..60 {
            let blocks = 1 + case % 23;
            let bodies = 2 + case % 9;
            let island = RandomIsland::new(&mut seed, blocks, bodies, case % 2 == 0);
            let mut cache = PatternCache::default();
            let pattern = cache.get(&island.key, &island.size, island.bodies);
            let mut layout = Layout::default();
            layout.build(pattern, &island.first, &island.size);
            let a = island.values(pattern, &layout);
            let n = island.rows();
            let x_true: Vec<f64> = (0..n).map(|_| rnd(&mut seed)).collect();
            let mut rhs = vec![0.0; n];
            multiply(pattern, &layout, &a, &x_true, &mut rhs);
            for r in 0..n {
                let dense: f64 = (0..n).map(|c| island.dense[r * n + c] * x_true[c]).sum();
                assert!(
                    (dense - rhs[r]).abs() < 1e-9,
                    "case {case}: product row {r}"
                );
            }
            let mut f = a.clone();
            assert!(!factorise(pattern, &layout, &mut f, 1e-13, 1e-9, None));
            solve(pattern, &layout, &f, &mut rhs);
            for r in 0..n {
                assert!(
                    (rhs[r] - x_true[r]).abs() < 1e-7 * (1.0 + x_true[r].abs()),
                    "case {case}: x[{r}] = {} for {}",
                    rhs[r],
                    x_true[r]
                );
            }
        }
    }

    #[test]
    fn a_chain_factorises_without_fill() {
        // Blocks k join bodies k and k+1: each eliminated block has one later neighbour.
        let key: Vec<BlockBodies> = (0..50u32).map(|k| [k, k + 1]).collect();
        let size = vec![3u32; 50];
        let mut cache = PatternCache::default();
        let pattern = cache.get(&key, &size, 51);
        let most = (0..pattern.len()).map(|k| pattern.later(k).len()).max();
        assert_eq!(most, Some(1));
        assert_eq!(pattern.slot_count(), 50 + 49);
    }
}
