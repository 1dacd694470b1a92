//! The tree solve against the dense system on random forests.
use super::*;
use crate::solver::sparse::factor::tests::rnd;

/// A random forest (or a loop when asked) of blocks over `bodies` bodies: each block joins
/// a body to an earlier one, to none, or repeats a pair.
fn random_blocks(seed: &mut u64, bodies: usize, blocks: usize) -> (Vec<[u32; 2]>, Vec<u32>) {
    let pick =
        |seed: &mut u64, n: usize| (((rnd(seed) + 1.0) * 0.5 * n as f64) as usize).min(n - 1);
    let mut key = Vec::new();
    let mut size = Vec::new();
    // A spanning forest first, so every body is used.
    for b in 1..bodies {
        if rnd(seed) > -0.7 {
            let a = pick(seed, b) as u32;
            key.push(if rnd(seed) > 0.0 {
                [a, b as u32]
            } else {
                [b as u32, a]
            });
            size.push(1 + pick(seed, 6) as u32);
        }
    }
    while key.len() < blocks {
        let b = pick(seed, bodies) as u32;
        let k = match pick(seed, 3) {
            0 => [b, NONE],
            1 => [NONE, b],
            _ => match key.iter().find(|k| k.contains(&b) && !k.contains(&NONE)) {
                Some(&k) => [k[1], k[0]],
                None => [b, NONE],
            },
        };
        key.push(k);
        size.push(1 + pick(seed, 4) as u32);
    }
    (key, size)
}

/// Jacobians and inverse masses for every row of the blocks.
fn random_rows(seed: &mut u64, rows: usize) -> Vec<([DVec3; 4], [DVec3; 4])> {
    (0..rows)
        .map(|_| {
            let mut v = || DVec3::new(rnd(seed), rnd(seed), rnd(seed));
            let jac = [v(), v(), v(), v()];
            (jac, jac.map(|j| j * 0.7)) // M⁻¹ = 0.7 I: positive definite
        })
        .collect()
}

/// The dense `A` of the same rows, for comparison.
fn dense(
    key: &[[u32; 2]],
    first: &[u32],
    size: &[u32],
    rows: &[([DVec3; 4], [DVec3; 4])],
) -> Vec<f64> {
    let n = rows.len();
    let mut a = vec![0.0; n * n];
    let block_of = |i: u32| first.partition_point(|&f| f <= i) - 1;
    for i in 0..n {
        for j in 0..n {
            let (bi, bj) = (block_of(i as u32), block_of(j as u32));
            let mut v = 0.0;
            for s in 0..2 {
                for t in 0..2 {
                    if key[bi][s] != NONE && key[bi][s] == key[bj][t] {
                        v += rows[i].0[2 * s].dot(rows[j].1[2 * t])
                            + rows[i].0[2 * s + 1].dot(rows[j].1[2 * t + 1]);
                    }
                }
            }
            a[i * n + j] = v;
        }
    }
    let _ = size;
    a
}

/// The tree solve's `A x`, factor and solve agree with the dense system on random forests,
/// with and without held rows, and a partial refactorisation gives a fresh one's bits.
#[test]
fn tree_solve_matches_the_dense_system() {
    let mut seed = 99u64;
    let mut trees = 0;
    for case in 0..200 {
        let bodies = 1 + case % 11;
        let (key, size) = random_blocks(&mut seed, bodies, bodies + case % 5);
        let mut first = Vec::new();
        let mut n = 0u32;
        for &s in &size {
            first.push(n);
            n += s;
        }
        let n = n as usize;
        let rows = random_rows(&mut seed, n);
        let mut sys = TreeSystem::default();
        if !sys.order.analyse(&key, &first, &size, bodies) {
            continue;
        }
        trees += 1;
        sys.fill(|i| rows[i]);
        for i in 0..n {
            sys.add_diagonal(i, 0.1);
        }
        let mut a = dense(&key, &first, &size, &rows);
        for i in 0..n {
            a[i * n + i] += 0.1;
        }
        let x: Vec<f64> = (0..n).map(|_| rnd(&mut seed)).collect();
        let mut ax = vec![0.0; n];
        sys.multiply(&x, &mut ax);
        for i in 0..n {
            let d: f64 = (0..n).map(|j| a[i * n + j] * x[j]).sum();
            assert!(
                (d - ax[i]).abs() < 1e-9 * (1.0 + d.abs()),
                "case {case}: A x row {i}"
            );
        }
        // Held rows: identity rows with their diagonal; the slack of the rows held.
        let mut w = vec![0.0; n];
        let state0: Vec<Bound> = (0..n)
            .map(|_| {
                if rnd(&mut seed) > 0.0 {
                    Bound::Upper
                } else {
                    Bound::Free
                }
            })
            .collect();
        sys.slack(&x, &x, &state0, &mut w);
        for i in 0..n {
            let expect = if state0[i] == Bound::Free {
                0.0
            } else {
                ax[i] - x[i]
            };
            assert!(
                (w[i] - expect).abs() < 1e-9 * (1.0 + ax[i].abs()),
                "case {case}: slack {i}"
            );
        }
        let state: Vec<Bound> = (0..n)
            .map(|_| {
                if rnd(&mut seed) > 0.4 {
                    Bound::Lower
                } else {
                    Bound::Free
                }
            })
            .collect();
        let mut held_a = a.clone();
        for i in 0..n {
            for j in 0..n {
                if i != j && (state[i] != Bound::Free || state[j] != Bound::Free) {
                    held_a[i * n + j] = 0.0;
                }
            }
        }
        for (st, m) in [(vec![Bound::Free; n], &a), (state.clone(), &held_a)] {
            let mut fresh = TreeSystem::default();
            fresh.order.analyse(&key, &first, &size, bodies);
            fresh.fill(|i| rows[i]);
            for i in 0..n {
                fresh.add_diagonal(i, 0.1);
            }
            assert!(!fresh.factor(&st, 1e-13, 1e-9));
            // The kept factor, moved from all-free to this set, agrees to the bit.
            sys.factor(&st, 1e-13, 1e-9);
            assert_eq!(sys.l, fresh.l, "case {case}: partial refactorisation");
            let mut y = x.clone();
            sys.solve(&mut y);
            for i in 0..n {
                let d: f64 = (0..n).map(|j| m[i * n + j] * y[j]).sum();
                assert!(
                    (d - x[i]).abs() < 1e-8 * (1.0 + x[i].abs()),
                    "case {case}: solve row {i}"
                );
            }
        }
    }
    assert!(trees > 100, "{trees} forests");
}

/// A loop (three bodies joined in a ring) is refused; the same blocks without the ring's
/// last one are taken; blocks repeating a pair join one node.
#[test]
fn loops_are_refused_and_pairs_merged() {
    let mut order = TreeOrder::default();
    let ring = [[0, 1], [1, 2], [2, 0]];
    assert!(!order.analyse(&ring, &[0, 3, 6], &[3, 3, 3], 3));
    assert!(order.analyse(&ring[..2], &[0, 3], &[3, 3], 3));
    let twice = [[0, 1], [1, 0], [0, NONE], [NONE, 0]];
    assert!(order.analyse(&twice, &[0, 3, 5, 6], &[3, 2, 1, 1], 2));
    assert_eq!(order.positions(), 2);
}
