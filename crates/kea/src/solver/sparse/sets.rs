//! The complementarity sets both pivoting solvers keep (block-sparse `pivoting`, dense
//! `lcp_dense`): each row free or held at a bound, which rows break their complementarity, and
//! which of them change sets.
//!
//! Row `i` with bounds `lo ≤ x ≤ hi` and slack `w = (A x − b)_i` is **free** (`lo < x < hi`,
//! `w = 0`), held at its **lower** bound (`x = lo`, `w ≥ 0`) or at its **upper** bound (`x = hi`,
//! `w ≤ 0`). A pass solves the free rows with the held ones at their bounds; a free row past a
//! bound, or a held row with `w` of the wrong sign, violates, and moves sets. Block pivoting
//! (Júdice and Pires) moves every violator at once while their count falls; single pivoting
//! (Murty) moves one and cannot cycle.

/// Where an index currently sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Bound {
    Free,
    Lower,
    Upper,
}

/// The unknowns and their sets: read as the starting guess, left at the solution.
pub(crate) struct Unknowns<'a> {
    pub lo: &'a mut [f64],
    pub hi: &'a mut [f64],
    pub x: &'a mut [f64],
    pub w: &'a mut [f64],
    pub state: &'a mut [Bound],
}

/// Corrects sets a bound change made impossible: `lo = hi` is held at `lo`, an infinite bound
/// cannot hold an index.
pub(super) fn settle_states(u: &mut Unknowns<'_>) {
    for i in 0..u.state.len() {
        u.state[i] = match u.state[i] {
            _ if u.lo[i] == u.hi[i] => Bound::Lower,
            Bound::Lower if u.lo[i] == f64::NEG_INFINITY => Bound::Free,
            Bound::Upper if u.hi[i] == f64::INFINITY => Bound::Free,
            s => s,
        };
    }
}

/// Moves index `i` to the set its violation asks for.
pub(super) fn move_index(i: usize, u: &mut Unknowns<'_>) {
    u.state[i] = match u.state[i] {
        Bound::Free if u.x[i] < u.lo[i] => Bound::Lower,
        Bound::Free => Bound::Upper,
        _ => Bound::Free,
    };
}

/// Whether row `i` breaks its complementarity: a free row past a bound, a held row pushed the
/// wrong way.
pub(super) fn violates(i: usize, u: &Unknowns<'_>, (tol_x, tol_w): (f64, f64)) -> bool {
    match u.state[i] {
        _ if u.lo[i] == u.hi[i] => false,
        Bound::Free => u.x[i] < u.lo[i] - tol_x || u.x[i] > u.hi[i] + tol_x,
        Bound::Lower => u.w[i] < -tol_w,
        Bound::Upper => u.w[i] > tol_w,
    }
}

/// How many of the `n` rows violate, and the last of them.
pub(super) fn violations(n: usize, u: &Unknowns<'_>, tol: (f64, f64)) -> (usize, usize) {
    let (mut count, mut last) = (0, 0);
    for i in 0..n {
        if violates(i, u, tol) {
            count += 1;
            last = i;
        }
    }
    (count, last)
}

/// Which rows change sets each iteration: all the violators at once (block pivoting) while
/// their count keeps falling within three tries, else only the last one (single pivoting,
/// which cannot cycle), and single pivoting for good once a set of states comes back.
pub(super) struct PivotRule {
    best: usize,
    block_budget: u32,
    pub(super) fallback: bool,
    /// Hashes of the last 16 sets, to catch a cycle.
    history: [u64; 16],
}

impl Default for PivotRule {
    fn default() -> Self {
        Self {
            best: usize::MAX,
            block_budget: 3,
            fallback: false,
            history: [0; 16],
        }
    }
}

impl PivotRule {
    /// Moves the violators this iteration's rule picks (`count` of the `n` rows violate, `last`
    /// the last of them); returns how many moved.
    pub(super) fn pivot(
        &mut self,
        iteration: u32,
        (n, count, last): (usize, usize, usize),
        u: &mut Unknowns<'_>,
        tol: (f64, f64),
    ) -> u32 {
        let h = hash_state(u.state);
        self.fallback |= self.history.contains(&h);
        self.history[iteration as usize % 16] = h;
        if count < self.best {
            self.best = count;
            self.block_budget = 3;
        }
        if self.block_budget > 0 && !self.fallback {
            self.block_budget -= 1;
            let mut pivots = 0;
            for i in 0..n {
                if violates(i, u, tol) {
                    move_index(i, u);
                    pivots += 1;
                }
            }
            pivots
        } else {
            move_index(last, u);
            1
        }
    }
}

/// FNV-1a hash of a set pattern, to notice a pattern pivoting has seen before.
fn hash_state(state: &[Bound]) -> u64 {
    // FNV-1a over the set pattern.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for s in state {
        h ^= *s as u64 + 1;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}
