//! `kea bench`: each scene stepped from its start several times, one `key=value` line per
//! scene with the median time per step and its spread over the repeats, per stage (the
//! collision stage included).

use crate::{check_run, load, summary::Summary};
use kea::Real;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Warm-up steps before each timed run (caches, workspaces and contacts settle).
const WARM_UP: u32 = 10;

/// One timed run: milliseconds per step in all and per stage.
#[derive(Debug, Clone, Copy, Default)]
struct Run {
    total: f64,
    broad: f64,
    narrow: f64,
    collect: f64,
    rows: f64,
    exact: f64,
    iterative: f64,
    integrate: f64,
}

/// Times `steps` steps of the scene at `path`, from its start after the warm-up.
fn time_once(path: &Path, steps: u32, dt: Real) -> Result<(String, Run, String), String> {
    let (name, mut built) = load(Some(path))?;
    for n in 1..=WARM_UP {
        built
            .step(dt)
            .map_err(|e| format!("{name}: warm-up step {n}: {e}"))?;
    }
    let mut summary = Summary::new(&built);
    let mut stage = [Duration::ZERO; 7];
    let start = Instant::now();
    for n in 1..=steps {
        let s = built
            .step(dt)
            .map_err(|e| format!("{name}: step {n}: {e}"))?;
        summary.add(&s);
        for (acc, d) in stage.iter_mut().zip([
            s.collision.time_broad_phase,
            s.collision.time_narrow_phase,
            s.time_collect,
            s.time_gather,
            s.solver.time_solve_exact,
            s.solver.time_solve_iterative,
            s.solver.time_integrate,
        ]) {
            *acc += d;
        }
    }
    let per_step = |d: Duration| d.as_secs_f64() * 1000.0 / f64::from(steps);
    let run = Run {
        total: per_step(start.elapsed()),
        broad: per_step(stage[0]),
        narrow: per_step(stage[1]),
        collect: per_step(stage[2]),
        rows: per_step(stage[3]),
        exact: per_step(stage[4]),
        iterative: per_step(stage[5]),
        integrate: per_step(stage[6]),
    };
    Ok((name, run, summary.bench_counts(&built)))
}

/// The median of `values` (not empty).
fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// `kea bench`: one line per scene.
pub fn bench(paths: &[PathBuf], steps: u32, dt: Real, repeats: u32) -> Result<(), String> {
    check_run(steps, dt)?;
    if !(1..=1000).contains(&repeats) {
        return Err(format!("--repeats {repeats}: must be 1 to 1000"));
    }
    for path in paths {
        let mut runs = Vec::with_capacity(repeats as usize);
        let mut label = (String::new(), String::new());
        for _ in 0..repeats {
            let (name, run, counts) = time_once(path, steps, dt)?;
            label = (name, counts);
            runs.push(run);
        }
        let stage = |f: fn(&Run) -> f64| median(&mut runs.iter().map(f).collect::<Vec<_>>());
        let mut totals: Vec<f64> = runs.iter().map(|r| r.total).collect();
        let mid = median(&mut totals);
        let (min, max) = (totals[0], totals[totals.len() - 1]);
        println!(
            "scene={} steps={steps} repeats={repeats} {} ms_per_step={mid:.4} min_ms={min:.4} max_ms={max:.4} spread_pct={:.1} collision_ms={:.4} broad_ms={:.4} narrow_ms={:.4} collect_ms={:.4} rows_ms={:.4} exact_ms={:.4} iterative_ms={:.4} integrate_ms={:.4}",
            label.0,
            label.1,
            100.0 * (max - min) / mid.max(1e-12),
            stage(|r| r.broad + r.narrow),
            stage(|r| r.broad),
            stage(|r| r.narrow),
            stage(|r| r.collect),
            stage(|r| r.rows),
            stage(|r| r.exact),
            stage(|r| r.iterative),
            stage(|r| r.integrate),
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::median;

    #[test]
    fn the_median_of_odd_and_even_counts() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(median(&mut [7.0]), 7.0);
    }
}
