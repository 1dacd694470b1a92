//! `kea-fuzz [--seeds N] [--first S] [--ops M] [--bound-ms B]`: runs the fuzz driver over seeds
//! `S..S+N`, `M` operations each, and prints what it found. An operation slower than `B` ms
//! (default 16: a frame at 60 Hz) counts as a stall. Exit status 1 if anything went
//! wrong. The long run of issue 12 is `cargo run --release -p kea-fuzz -- --seeds 100 --ops
//! 10000` (10⁶ operations).

use std::time::Duration;

fn arg(args: &[String], name: &str, default: u64) -> Result<u64, String> {
    match args.iter().position(|a| a == name) {
        None => Ok(default),
        Some(i) => args
            .get(i + 1)
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| format!("{name} needs a whole number, got {:?}", args.get(i + 1))),
    }
}

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let parsed = (|| {
        Ok::<_, String>((
            arg(&args, "--seeds", 10)?,
            arg(&args, "--first", 0)?,
            arg(&args, "--ops", 10_000)?,
            arg(&args, "--bound-ms", 16)?,
        ))
    })();
    let (seeds, first, ops, bound) = match parsed {
        Ok(p) => p,
        Err(e) => {
            eprintln!("kea-fuzz: {e}");
            return std::process::ExitCode::FAILURE;
        }
    };
    let started = std::time::Instant::now();
    let report = kea_fuzz::run(first..first + seeds, ops, Duration::from_millis(bound));
    println!(
        "{} operations ({} refused) in {:.1} s: {} panics escaped, {} caught inside Kea, {} slower than {bound} ms, {} refused calls changed the world, {} poisoned worlds, {} traded steps differed; slowest {:?} ({})",
        report.operations,
        report.refused,
        started.elapsed().as_secs_f64(),
        report.escaped_panics,
        report.caught_panics,
        report.slow,
        report.refused_but_changed,
        report.poisoned,
        report.traded_differs,
        report.slowest.0,
        report.slowest.1
    );
    for p in &report.problems {
        println!("  {p}");
    }
    if report.is_clean() {
        std::process::ExitCode::SUCCESS
    } else {
        std::process::ExitCode::FAILURE
    }
}
