//! Packing rows into the iterative path's arrays: rows, equality blocks (a joint's rows, solved
//! together) and pairs of tangential rows.

use super::super::bodies::{BodyStates, NONE};
use super::{JointRows, BOUNCE, HARD, MAX_BLOCK, UNILATERAL};
use crate::constraint::Row;
use crate::math::{wide, Real, Vec3};
use crate::solver::integrate::BodyScratch;
use crate::solver::{ConstraintBlock, SolverBody, SolverParams};

impl JointRows {
    /// Packs the rows of `island_blocks` (blocks of iterative islands), giving their bodies
    /// local slots in `states`. `warm` holds each row's λ of the last step.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn gather(
        &mut self,
        island_blocks: &[u32],
        blocks: &[ConstraintBlock],
        rows: &[Row],
        bodies: &[SolverBody],
        states: &mut BodyStates,
        scratch: &BodyScratch,
        params: &SolverParams,
        hs: Real,
        warm: &[Real],
        direct: bool,
    ) {
        self.any_direct |= direct && !island_blocks.is_empty();
        for &k in island_blocks {
            let blk = &blocks[k as usize];
            let base = self.row_global.len() as u32;
            for g in blk.first_row..blk.first_row + blk.row_count {
                let row = &rows[g as usize];
                let mut local = [NONE; 2];
                for s in 0..2 {
                    match blk.bodies[s] {
                        Some(b) if !bodies[b as usize].is_fixed() => {
                            local[s] = states.local(Some(b), bodies, scratch, params, hs);
                            states.follow_rotation(local[s]);
                        }
                        _ => {}
                    }
                }
                let (kinematic, jm, mut diag) =
                    row_masses(row, blk, bodies, |b| scratch.inv_inertia_world[b as usize]);
                // Two slots on the same body add their cross terms.
                if local[0] != NONE && local[0] == local[1] {
                    diag += 2.0
                        * (row.jacobian[0].linear.dot(jm[1].0)
                            + row.jacobian[0].angular.dot(jm[1].1));
                }
                let packed = PackedRow {
                    global: g,
                    local,
                    jm,
                    diag,
                    kinematic,
                    tuning: RowTuning::of(row, diag, params, hs),
                    warm: warm[g as usize],
                    direct,
                };
                self.push_row(row, &packed, base, hs);
            }
            self.close_block(k, blk, base, rows);
        }
        // Warm-start impulses must respect their bounds.
        for i in 0..self.row_global.len() {
            let (lo, hi) = self.bounds(i);
            self.impulse[i] = self.impulse[i].clamp(lo, hi);
        }
    }

    /// Appends one row to every array.
    fn push_row(&mut self, row: &Row, p: &PackedRow, base: u32, hs: Real) {
        let t = p.tuning;
        self.mass_scale.push(t.mass_scale);
        self.impulse_scale.push(t.impulse_scale);
        self.row_global.push(p.global);
        self.row_a.push(p.local[0]);
        self.row_b.push(p.local[1]);
        self.ja_lin.push(row.jacobian[0].linear);
        self.ja_ang.push(row.jacobian[0].angular);
        self.jb_lin.push(row.jacobian[1].linear);
        self.jb_ang.push(row.jacobian[1].angular);
        self.ma_lin.push(p.jm[0].0);
        self.ma_ang.push(p.jm[0].1);
        self.mb_lin.push(p.jm[1].0);
        self.mb_ang.push(p.jm[1].1);
        self.diag.push(p.diag);
        self.xi0.push(row.xi);
        // A bounce target waits for the post-pass; the substeps treat the row as resting.
        let c = if row.bounce { 0.0 } else { row.c };
        self.target.push(c - p.kinematic);
        self.bounce_target.push(row.c - p.kinematic);
        self.chord.push(0.5 * hs * row.curvature);
        self.lo.push(row.lo * hs);
        self.hi.push(row.hi * hs);
        match row.friction {
            Some(f) => {
                self.link.push(base + u32::from(f.normal_row));
                self.mu.push(f.mu);
            }
            None => {
                self.link.push(NONE);
                self.mu.push(0.0);
            }
        }
        self.extra.push(t.extra + row.slip / hs);
        self.rate.push(t.rate);
        self.flags.push(t.flags);
        let w = p.warm;
        self.impulse.push(if w.is_finite() { w * hs } else { 0.0 });
        self.total.push(0.0);
        self.in_block.push(false);
        self.direct.push(p.direct);
        self.pair_of.push(NONE);
        self.lever.push(row_lever(row));
    }

    /// Closes constraint `k`'s rows from `base` on: their shared lever, their equality block
    /// and tangent pairs, and the block's record.
    fn close_block(&mut self, k: u32, blk: &ConstraintBlock, base: u32, rows: &[Row]) {
        self.share_lever(base as usize..self.lever.len());
        let blocks_before = self.eq_start.len();
        // Rows solved directly need no block or pair inverse (the sweeps pass them by).
        let swept = self.direct.get(base as usize).is_none_or(|&d| !d);
        if swept {
            self.make_block(base as usize, rows, blk);
            self.make_pairs(base as usize, rows);
        }
        self.blk_global.push(k);
        self.blk_base.push(base);
        self.blk_count.push(blk.row_count);
        self.blk_eq.push(if self.eq_start.len() > blocks_before {
            blocks_before as u32
        } else {
            NONE
        });
    }

    /// Gives every row of one constraint (`rows`) the longest lever among them.
    pub(super) fn share_lever(&mut self, rows: std::ops::Range<usize>) {
        let lever = self.lever[rows.clone()]
            .iter()
            .fold(0.0 as Real, |m, &l| m.max(l));
        self.lever[rows].fill(lever);
    }

    /// Groups a constraint's unbounded rows (2 to 6 of them) into one block and stores the
    /// inverse of its `J M⁻¹ Jᵀ + E`, so that a joint's rows are solved together: per-row
    /// Gauss-Seidel converges slowly when rows share a badly conditioned body (a small sphere at
    /// the end of a long pendulum).
    fn make_block(&mut self, base: usize, rows: &[Row], blk: &ConstraintBlock) {
        let mut idx = [0usize; MAX_BLOCK];
        let mut m = 0;
        for i in base..self.row_global.len() {
            let row = &rows[self.row_global[i] as usize];
            let equality =
                row.lo == Real::NEG_INFINITY && row.hi == Real::INFINITY && row.friction.is_none();
            if equality {
                if m == MAX_BLOCK {
                    return;
                }
                idx[m] = i;
                m += 1;
            }
        }
        if m < 2 || (blk.bodies[0].is_some() && blk.bodies[0] == blk.bodies[1]) {
            return;
        }
        let mut k = block_matrix(self, &idx[..m]);
        let Some(inv) = invert(&mut k, m) else { return };
        self.eq_start.push(self.eq_rows.len() as u32);
        self.eq_len.push(m as u32);
        self.eq_kstart.push(self.eq_kinv.len() as u32);
        for a in 0..m {
            self.eq_rows.push(idx[a] as u32);
            self.in_block[idx[a]] = true;
            for b in 0..m {
                self.eq_kinv.push(inv[a][b] as Real);
            }
        }
    }

    /// Pairs consecutive bounded tangential rows of one constraint (Coulomb rows on the same
    /// normal row, or symmetric box bounds) and stores the inverse of their 2×2 `K + E`.
    fn make_pairs(&mut self, base: usize, rows: &[Row]) {
        let end = self.row_global.len();
        let mut i = base;
        while i + 1 < end {
            let j = i + 1;
            let (ri, rj) = (
                &rows[self.row_global[i] as usize],
                &rows[self.row_global[j] as usize],
            );
            let free = !self.in_block[i] && !self.in_block[j];
            let coulomb = matches!((ri.friction, rj.friction), (Some(a), Some(b)) if a.normal_row == b.normal_row);
            let boxed = ri.friction.is_none()
                && rj.friction.is_none()
                && ri.hi.is_finite()
                && rj.hi.is_finite()
                && ri.lo == -ri.hi
                && rj.lo == -rj.hi;
            if !(free && (coulomb || boxed)) {
                i += 1;
                continue;
            }
            let dot = |a: usize, b: usize| {
                self.ja_lin[a].dot(self.ma_lin[b])
                    + self.ja_ang[a].dot(self.ma_ang[b])
                    + self.jb_lin[a].dot(self.mb_lin[b])
                    + self.jb_ang[a].dot(self.mb_ang[b])
            };
            let (k11, k12, k22) = (
                dot(i, i) + self.extra[i],
                dot(i, j),
                dot(j, j) + self.extra[j],
            );
            let det = k11 * k22 - k12 * k12;
            if det.is_nan() || det <= 1.0e-9 * k11 * k22 {
                i += 1;
                continue;
            }
            self.pair_of[i] = self.pair_kinv.len() as u32;
            self.pair_second.push(j as u32);
            self.pair_kinv
                .push([k22 / det, -k12 / det, -k12 / det, k11 / det]);
            self.in_block[j] = true;
            i += 2;
        }
    }
}

/// A row's mass data on its block's bodies: the velocity term of its kinematic bodies (a
/// constant target offset), `M⁻¹Jᵀ` per body, and `J M⁻¹ Jᵀ` (without the cross terms of a row
/// whose two slots are one body). `inv_inertia` gives a solver body's world inverse inertia.
/// One row as [`JointRows::gather`] packs it.
struct PackedRow {
    global: u32,
    local: [u32; 2],
    jm: [(Vec3, Vec3); 2],
    diag: Real,
    kinematic: Real,
    tuning: RowTuning,
    warm: Real,
    direct: bool,
}

/// How a row is solved in the substeps: its error-correction rate, extra compliance, kind
/// flags and (for hard unilateral rows) softening.
#[derive(Clone, Copy)]
struct RowTuning {
    rate: Real,
    extra: Real,
    flags: u8,
    mass_scale: Real,
    impulse_scale: Real,
}

impl RowTuning {
    /// A row with effective inverse mass `diag`, in substeps of `hs` of a step `params.dt`.
    fn of(row: &Row, diag: Real, params: &SolverParams, hs: Real) -> Self {
        let h = params.dt;
        let n_sub = params.iterative.substeps as Real;
        // Only a row's own softness is a physical spring; the world's ε regularises the exact
        // path's matrix and is not needed here (see the module docs).
        let (eps, gamma) = match row
            .spring
            .and_then(|sp| (diag > 0.0).then(|| sp.softness(1.0 / diag, h)).flatten())
        {
            Some(s) => (s.epsilon, row.gamma.unwrap_or(s.gamma)),
            None => (
                row.softness.unwrap_or(0.0),
                row.gamma.unwrap_or(params.gamma),
            ),
        };
        let mut flags = 0u8;
        let (rate, extra) = if eps > 0.0 {
            let k = gamma / (eps * h * h);
            let d = (1.0 - gamma) / (eps * h);
            let hkd = hs * k + d;
            (hs * k / hkd / hs, 1.0 / (hs * hkd))
        } else {
            flags |= HARD;
            ((1.0 - (1.0 - gamma).powf(1.0 / n_sub)) / hs, 0.0)
        };
        if row.bounce {
            flags |= BOUNCE;
        }
        if row.friction.is_none() && row.hi == Real::INFINITY && row.lo > Real::NEG_INFINITY {
            flags |= UNILATERAL;
        }
        // Only rows that can only push (stops, user contacts) are softened: Gauss-Seidel on a
        // stiff stack needs it, while joints converge without and keep their geometry
        // (softened, a hinged rod swung 1% slow).
        let (mass_scale, impulse_scale) = if flags & HARD != 0 && flags & UNILATERAL != 0 {
            hard_softening(rate, hs)
        } else {
            (1.0, 0.0)
        };
        Self {
            rate,
            extra,
            flags,
            mass_scale,
            impulse_scale,
        }
    }
}

pub(super) fn row_masses(
    row: &Row,
    blk: &ConstraintBlock,
    bodies: &[SolverBody],
    inv_inertia: impl Fn(u32) -> crate::math::Mat3,
) -> (Real, [(Vec3, Vec3); 2], Real) {
    let mut kinematic = 0.0;
    let mut jm = [(Vec3::ZERO, Vec3::ZERO); 2];
    let mut diag = 0.0;
    for s in 0..2 {
        let Some(b) = blk.bodies[s] else { continue };
        let body = &bodies[b as usize];
        let j = row.jacobian[s];
        if body.is_fixed() {
            kinematic += j.linear.dot(body.linear_velocity) + j.angular.dot(body.angular_velocity);
            continue;
        }
        let ml = j.linear * body.inv_mass;
        let ma = inv_inertia(b) * j.angular;
        diag += j.linear.dot(ml) + j.angular.dot(ma);
        jm[s] = (ml, ma);
    }
    (kinematic, jm, diag)
}

/// A row's lever `|J_ang| / |J_lin|` (the longest of its two bodies'; 0 for an angular row).
pub(super) fn row_lever(row: &Row) -> Real {
    let [j1, j2] = row.jacobian;
    let lin = j1.linear.length().max(j2.linear.length());
    let ang = j1.angular.length().max(j2.angular.length());
    if lin > 0.0 {
        ang / lin
    } else {
        0.0
    }
}

/// `J M⁻¹ Jᵀ + E` of the rows `idx` (at most [`MAX_BLOCK`]), in `f64`.
pub(super) fn block_matrix(rows: &JointRows, idx: &[usize]) -> [[f64; MAX_BLOCK]; MAX_BLOCK] {
    let mut k = [[0.0f64; MAX_BLOCK]; MAX_BLOCK];
    for (a, &i) in idx.iter().enumerate() {
        for (b, &j) in idx.iter().enumerate() {
            let mut s = rows.ja_lin[i].dot(rows.ma_lin[j])
                + rows.ja_ang[i].dot(rows.ma_ang[j])
                + rows.jb_lin[i].dot(rows.mb_lin[j])
                + rows.jb_ang[i].dot(rows.mb_ang[j]);
            if a == b {
                s += rows.extra[i];
            }
            k[a][b] = wide(s);
        }
    }
    k
}

/// Damping ratio of the implicit softening of hard rows in the biased solve.
const HARD_DAMPING_RATIO: Real = 10.0;

/// Softening of a hard row in the biased solve (the soft step of Box2D v3, after Catto): the
/// row behaves there as a heavily damped spring, mass-normalised, whose bias rate equals the
/// γ-derived `rate`; this damps the Gauss-Seidel iteration of stiff stacks. The relax solve is
/// rigid. Returns (mass scale, impulse scale).
pub(super) fn hard_softening(rate: Real, hs: Real) -> (Real, Real) {
    if rate <= 0.0 {
        return (1.0, 0.0);
    }
    // Bias rate of a spring (ω, ζ) at step hs is ω/(2ζ + hs·ω); solve it for ω.
    let hr = (hs * rate).min(0.9);
    let omega = 2.0 * HARD_DAMPING_RATIO * rate / (1.0 - hr);
    let a1 = 2.0 * HARD_DAMPING_RATIO + hs * omega;
    let a2 = hs * omega * a1;
    (a2 / (1.0 + a2), 1.0 / (1.0 + a2))
}

/// Inverse of the leading `m×m` block of `k` by Gauss-Jordan elimination with partial pivoting;
/// `None` if it is singular.
#[allow(clippy::needless_range_loop)]
pub(super) fn invert(
    k: &mut [[f64; MAX_BLOCK]; MAX_BLOCK],
    m: usize,
) -> Option<[[f64; MAX_BLOCK]; MAX_BLOCK]> {
    let mut inv = [[0.0f64; MAX_BLOCK]; MAX_BLOCK];
    for (i, row) in inv.iter_mut().enumerate().take(m) {
        row[i] = 1.0;
    }
    let scale = (0..m).fold(0.0f64, |s, i| s.max(k[i][i].abs()));
    for col in 0..m {
        let pivot = (col..m).max_by(|&a, &b| k[a][col].abs().total_cmp(&k[b][col].abs()))?;
        if k[pivot][col].abs().is_nan() || k[pivot][col].abs() <= 1.0e-12 * scale {
            return None;
        }
        k.swap(col, pivot);
        inv.swap(col, pivot);
        let p = k[col][col];
        for j in 0..m {
            k[col][j] /= p;
            inv[col][j] /= p;
        }
        for r in 0..m {
            if r != col {
                let f = k[r][col];
                if f != 0.0 {
                    for j in 0..m {
                        k[r][j] -= f * k[col][j];
                        inv[r][j] -= f * inv[col][j];
                    }
                }
            }
        }
    }
    Some(inv)
}
