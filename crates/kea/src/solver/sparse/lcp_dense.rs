//! The exact boxed LCP solver: block principal pivoting with a single-pivot fallback, in `f64`.
//!
//! Problem (BLCP). Given a symmetric positive (semi)definite `A` (n×n, row-major), `b`, and bounds
//! `lo ≤ hi` (possibly infinite), find `x` and `w = A x − b` with, for every `i`,
//!
//! ```text
//!   lo_i < x_i < hi_i  and  w_i = 0        (free)
//!   x_i = lo_i         and  w_i ≥ 0        (at lower bound)
//!   x_i = hi_i         and  w_i ≤ 0        (at upper bound)
//! ```
//!
//! Method. Guess which indices are free, at `lo` or at `hi`; solve `A_FF x_F = b_F − A_FN x_N`
//! by Cholesky; move every index that violates its condition to the set it asks for (a *block*
//! pivot, Júdice & Pires 1994, after Kostreva). If the number of violations stops falling for a
//! few block pivots, switch to Murty's single-pivot rule (move only the highest-index
//! violation), which terminates finitely when `A` is a P-matrix (any `A + εI` with ε > 0).
//! Each iteration costs one factorisation of the free block, so the cost is O(iterations·n³):
//! meant for islands up to a few hundred rows. Complementarity holds to round-off.
//!
//! A zero or negative pivot in the factorisation means the free block is singular (redundant
//! constraints with ε = 0): the block is regularised by a small multiple of its largest diagonal,
//! and the result is flagged. A state visited twice flags a cycle; the iteration cap is a
//! parameter. None of these abort: the caller gets the best `x` found, clamped to its bounds.

use super::dot_lanes;
pub(crate) use super::sets::Bound;
pub(crate) use super::sets::Unknowns;
use super::sets::{settle_states, violations, PivotRule};

/// What happened in one LCP solve.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct LcpReport {
    /// Pivoting iterations (each is one factorisation).
    pub iterations: u32,
    /// Indices moved between sets in total.
    pub pivots: u32,
    /// All conditions met to tolerance.
    pub converged: bool,
    /// A free block was singular and was regularised.
    pub singular: bool,
    /// A set of states repeated.
    pub cycled: bool,
    /// The iteration cap was reached.
    pub capped: bool,
}

/// Scratch memory for [`solve`]; grows to the largest problem seen and is then reused.
#[derive(Debug, Default, Clone)]
pub(crate) struct LcpWorkspace {
    free: Vec<usize>,
    /// The held indices away from zero, in order: the only ones the free rows' right side
    /// reads (most contacts are held at zero).
    held: Vec<usize>,
    factor: Vec<f64>,
    rhs: Vec<f64>,
}

impl LcpWorkspace {
    /// Makes room for problems of `n` unknowns (allocates only if bigger than before).
    pub(crate) fn reserve(&mut self, n: usize) {
        if self.factor.len() < n * n {
            self.factor.resize(n * n, 0.0);
        }
        if self.rhs.len() < n {
            self.rhs.resize(n, 0.0);
        }
        for list in [&mut self.free, &mut self.held] {
            if list.capacity() < n {
                list.reserve(n - list.len());
            }
        }
    }

    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        self.factor.capacity() * 8
            + self.rhs.capacity() * 8
            + (self.free.capacity() + self.held.capacity()) * 8
    }

    /// Bytes needed for a problem of `n` unknowns.
    pub(crate) fn bytes_for(n: usize) -> usize {
        (n * n + n) * 8 + 2 * n * 8
    }
}

/// Initial set for each index: unbounded ones free, others at the bound nearer zero (contacts
/// start at rest, friction starts free because its bounds straddle zero).
pub(crate) fn initial_state(lo: &[f64], hi: &[f64], state: &mut [Bound]) {
    for i in 0..state.len() {
        state[i] = if lo[i] == hi[i] {
            Bound::Lower
        } else if lo[i] <= 0.0 && hi[i] >= 0.0 {
            if lo[i] == 0.0 && hi[i] > 0.0 {
                Bound::Lower
            } else {
                Bound::Free
            }
        } else if lo[i] > 0.0 {
            Bound::Lower
        } else {
            Bound::Upper
        };
    }
}

/// Most `iterations × n³` the dense solves of one island (all friction passes) may spend: each
/// iteration factorises the free block (n³/3 multiply-adds, about 1.5 ms for 256 rows here).
/// Islands with contacts reach this path only up to [`crate::DENSE_EXACT_MAX_ROWS`] rows
/// (bigger ones are routed off it), which afford 15 iterations; islands of up to 63 rows never
/// reach it. Past it the solve stops as if capped, and says so: an island's solve stays under
/// about a frame (at 5·10⁸ a 154-row pile forced exact took 19 ms, now 11 ms; at 10⁸ the
/// demo car's island, 4 wheels with their stops and contacts, was cut short and the car
/// reared; at 3·10¹⁰, 100 iterations × 16 friction passes of a 500-row island took a minute).
const DENSE_WORK_BUDGET: f64 = 2.5e8;

/// Pivoting iterations an island of `n` rows can afford in all (see [`DENSE_WORK_BUDGET`]).
pub(crate) fn affordable_iterations(n: usize) -> u32 {
    (DENSE_WORK_BUDGET / (n.max(1) as f64).powi(3)).clamp(2.0, 1.0e6) as u32
}

/// Solves the BLCP. `u.state` is read as the starting guess and left at the final sets;
/// `u.x` and `u.w` receive the solution and `A x − b`.
pub(crate) fn solve(
    n: usize,
    (a, b): (&[f64], &[f64]),
    u: &mut Unknowns<'_>,
    ws: &mut LcpWorkspace,
    max_iterations: u32,
) -> LcpReport {
    ws.reserve(n);
    let mut report = LcpReport::default();
    // Indices that cannot be at a bound (both infinite) stay free; fix impossible states.
    settle_states(u);
    let b_scale = b[..n].iter().fold(1.0_f64, |m, v| m.max(v.abs()));
    let diag_max = (0..n).fold(0.0_f64, |m, i| m.max(a[i * n + i].abs()));
    let tol_w = 1.0e-11 * b_scale;
    let mut rule = PivotRule::default();
    for iteration in 0..max_iterations {
        report.iterations = iteration + 1;
        report.singular |= solve_free_block(n, (a, b), u, ws, diag_max);
        // w = A x − b everywhere.
        for i in 0..n {
            u.w[i] = dot_lanes(&a[i * n..i * n + n], &u.x[..n]) - b[i];
        }
        let tol_x = 1.0e-11 * u.x[..n].iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        let (count, last) = violations(n, u, (tol_x, tol_w));
        if count == 0 {
            report.converged = true;
            break;
        }
        report.pivots += rule.pivot(iteration, (n, count, last), u, (tol_x, tol_w));
        if iteration + 1 == max_iterations {
            report.capped = true;
        }
    }
    if !report.converged {
        // A revisited state only matters if the single-pivot fallback did not recover.
        report.cycled = rule.fallback;
        for i in 0..n {
            u.x[i] = u.x[i].clamp(u.lo[i], u.hi[i]);
        }
    }
    report
}

/// Sets bound indices to their bound and solves the free block for the rest. Returns true if
/// the block had to be regularised.
#[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
fn solve_free_block(
    n: usize,
    (a, b): (&[f64], &[f64]),
    u: &mut Unknowns<'_>,
    ws: &mut LcpWorkspace,
    diag_max: f64,
) -> bool {
    let Unknowns {
        lo, hi, x, state, ..
    } = u;
    ws.free.clear();
    ws.held.clear();
    for i in 0..n {
        let bound = match state[i] {
            Bound::Free => {
                ws.free.push(i);
                continue;
            }
            Bound::Lower => lo[i],
            Bound::Upper => hi[i],
        };
        x[i] = bound;
        // Rows held at a zero bound (most contacts') add nothing to the right side.
        if bound != 0.0 {
            ws.held.push(i);
        }
    }
    let m = ws.free.len();
    if m == 0 {
        return false;
    }
    // rhs_F = b_F − A_FN x_N
    for (k, &i) in ws.free.iter().enumerate() {
        let row = &a[i * n..i * n + n];
        let mut s = b[i];
        for &j in &ws.held {
            s -= row[j] * x[j];
        }
        ws.rhs[k] = s;
    }
    let Some(regularised) = factor_free(a, n, ws, diag_max) else {
        // Leave the free unknowns at zero: no force rather than a wild one.
        for &i in &ws.free {
            x[i] = 0.0;
        }
        return true;
    };
    substitute(&ws.factor, &mut ws.rhs, m);
    for (k, &i) in ws.free.iter().enumerate() {
        x[i] = ws.rhs[k];
    }
    regularised
}

/// Factorises the free block `A_FF` into `ws.factor`, regularising by growing shifts, 1e-10
/// to 1e4 of the largest diagonal (8 tries); whether it had to (`None`: a matrix that needs
/// more, or holds a non-finite number, is hopeless).
fn factor_free(a: &[f64], n: usize, ws: &mut LcpWorkspace, diag_max: f64) -> Option<bool> {
    let mut shift = 0.0;
    let mut regularised = false;
    for _ in 0..=REGULARISATION_TRIES {
        if !diag_max.is_finite() {
            return None;
        }
        if cholesky(a, n, &ws.free, &mut ws.factor, shift, diag_max) {
            return Some(regularised);
        }
        regularised = true;
        shift = if shift == 0.0 {
            1.0e-10 * diag_max.max(1.0e-300)
        } else {
            shift * 100.0
        };
    }
    None
}

/// Forward and back substitution with `L` (m×m, row-major lower triangle, its diagonal held
/// inverted): `y ← (L Lᵀ)⁻¹ y`.
fn substitute(l: &[f64], y: &mut [f64], m: usize) {
    for i in 0..m {
        let s = y[i] - dot_lanes(&l[i * m..i * m + i], &y[..i]);
        y[i] = s * l[i * m + i];
    }
    for i in (0..m).rev() {
        let mut s = y[i];
        for k in i + 1..m {
            s -= l[k * m + i] * y[k];
        }
        y[i] = s * l[i * m + i];
    }
}

/// Shifts tried before a free block is given up as hopeless.
const REGULARISATION_TRIES: usize = 8;

/// Cholesky factor of `A_FF + shift·I` into `out` (m×m), each diagonal entry stored as its
/// reciprocal (a multiply on the factorisation's and substitutions' serial chains instead of a
/// divide). False if a pivot is not clearly positive (relative to the largest diagonal of the
/// whole matrix).
fn cholesky(
    a: &[f64],
    n: usize,
    free: &[usize],
    out: &mut [f64],
    shift: f64,
    diag_max: f64,
) -> bool {
    let m = free.len();
    let tiny = 1.0e-13 * diag_max.max(1.0e-300);
    // Column by column: each entry is the same sum as row by row (so the same bits), and a
    // column's rows below the diagonal, which share row `j`'s entries, go four at a time.
    for j in 0..m {
        let (above, below) = out[..m * m].split_at_mut((j + 1) * m);
        let lj = &mut above[j * m..j * m + j + 1];
        let s = a[free[j] * n + free[j]] + shift - dot_lanes(&lj[..j], &lj[..j]);
        if s.is_nan() || s <= tiny {
            return false;
        }
        let inv = 1.0 / s.sqrt();
        lj[j] = inv;
        let lj = &lj[..j];
        let aj = free[j];
        let mut rows = below.chunks_exact_mut(m);
        let mut i = j + 1;
        while i + 4 <= m {
            let [r0, r1, r2, r3] = [(); 4].map(|()| rows.next().expect("rows below"));
            let dots = dot_lanes_four([&r0[..j], &r1[..j], &r2[..j], &r3[..j]], lj);
            for (k, r) in [r0, r1, r2, r3].into_iter().enumerate() {
                r[j] = (a[free[i + k] * n + aj] - dots[k]) * inv;
            }
            i += 4;
        }
        for r in rows {
            r[j] = (a[free[i] * n + aj] - dot_lanes(&r[..j], lj)) * inv;
            i += 1;
        }
    }
    true
}

/// [`dot_lanes`] of four rows with one vector, each the same sum in the same order (so the
/// same bits), the vector's entries loaded once for the four.
#[inline]
fn dot_lanes_four(rows: [&[f64]; 4], b: &[f64]) -> [f64; 4] {
    let len = b.len();
    let whole = len - len % 4;
    let mut s = [[0.0_f64; 4]; 4];
    for c in (0..whole).step_by(4) {
        let y = &b[c..c + 4];
        for (r, row) in rows.iter().enumerate() {
            let x = &row[c..c + 4];
            for k in 0..4 {
                s[r][k] += x[k] * y[k];
            }
        }
    }
    let mut out = [0.0; 4];
    for (r, row) in rows.iter().enumerate() {
        let tail: f64 = row[whole..len]
            .iter()
            .zip(&b[whole..len])
            .map(|(x, y)| x * y)
            .sum();
        out[r] = (s[r][0] + s[r][1]) + (s[r][2] + s[r][3]) + tail;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_solution(n: usize, a: &[f64], b: &[f64], lo: &[f64], hi: &[f64], x: &[f64]) {
        for i in 0..n {
            let w: f64 = (0..n).map(|j| a[i * n + j] * x[j]).sum::<f64>() - b[i];
            assert!(x[i] >= lo[i] - 1e-9 && x[i] <= hi[i] + 1e-9, "bounds {i}");
            if x[i] > lo[i] + 1e-9 && x[i] < hi[i] - 1e-9 {
                assert!(w.abs() < 1e-8, "free {i} w={w}");
            } else if (x[i] - lo[i]).abs() <= 1e-9 {
                assert!(w >= -1e-8, "lower {i} w={w}");
            } else {
                assert!(w <= 1e-8, "upper {i} w={w}");
            }
        }
    }

    fn run(n: usize, a: &[f64], b: &[f64], lo: &[f64], hi: &[f64]) -> (Vec<f64>, LcpReport) {
        let mut x = vec![0.0; n];
        let mut w = vec![0.0; n];
        let mut st = vec![Bound::Free; n];
        initial_state(lo, hi, &mut st);
        let mut ws = LcpWorkspace::default();
        let (mut lo, mut hi) = (lo.to_vec(), hi.to_vec());
        let mut u = Unknowns {
            lo: &mut lo,
            hi: &mut hi,
            x: &mut x,
            w: &mut w,
            state: &mut st,
        };
        let r = solve(n, (a, b), &mut u, &mut ws, 100);
        (x, r)
    }

    #[test]
    fn random_spd_problems_meet_complementarity() {
        // Deterministic pseudo-random SPD matrices A = MᵀM + 0.01 I with mixed bounds.
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for n in [1usize, 2, 5, 12, 30] {
            for _ in 0..20 {
                let m: Vec<f64> = (0..n * n).map(|_| rnd()).collect();
                let mut a = vec![0.0; n * n];
                for i in 0..n {
                    for j in 0..n {
                        a[i * n + j] = (0..n).map(|k| m[k * n + i] * m[k * n + j]).sum::<f64>()
                            + if i == j { 0.01 } else { 0.0 };
                    }
                }
                let b: Vec<f64> = (0..n).map(|_| 3.0 * rnd()).collect();
                let mut lo = vec![0.0; n];
                let mut hi = vec![f64::INFINITY; n];
                for i in 0..n {
                    match i % 3 {
                        0 => {}
                        1 => {
                            lo[i] = -0.5;
                            hi[i] = 0.5;
                        }
                        _ => {
                            lo[i] = f64::NEG_INFINITY;
                        }
                    }
                }
                let (x, r) = run(n, &a, &b, &lo, &hi);
                assert!(r.converged, "n={n} {r:?}");
                check_solution(n, &a, &b, &lo, &hi, &x);
            }
        }
    }

    #[test]
    fn singular_system_is_flagged_and_finite() {
        // Two identical unbounded rows: A = [[1,1],[1,1]], consistent b.
        let a = [1.0, 1.0, 1.0, 1.0];
        let b = [2.0, 2.0];
        let lo = [f64::NEG_INFINITY; 2];
        let hi = [f64::INFINITY; 2];
        let (x, r) = run(2, &a, &b, &lo, &hi);
        assert!(r.singular);
        assert!(x.iter().all(|v| v.is_finite()));
        assert!((x[0] + x[1] - 2.0).abs() < 1e-6);
    }
}
