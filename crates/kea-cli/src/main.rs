//! The `kea` command: run and benchmark scene files headless.
//!
//! - `kea run [SCENE] [--steps N] [--dt H] [--csv FILE] [--json FILE]` steps a scene (the
//!   embedded pyramid when no file is given), shows a progress bar on long runs, and ends with a
//!   summary: steps per second, time per stage, bodies awake and asleep, energy, solver warnings.
//! - `kea bench SCENE… [--steps N] [--dt H]` prints one machine-readable line per scene.
//! - `kea render SCENE --out FILE.png [--steps N] [--width W] [--height H]` steps the scene and
//!   writes its last frame, drawn on the CPU (no GPU, no display).
//!
//! Exit code 0 on success; 1 with a message on stderr for a bad scene or a failed step, and
//! nothing is written then.

mod record;
mod summary;

use clap::{Parser, Subcommand};
use kea::Real;
use kea_scene::{build, BuiltScene, Scene};
use std::path::PathBuf;
use std::process::ExitCode;

/// The scene `kea run` uses when given none: a 210-box pyramid.
const DEFAULT_SCENE: &str = include_str!("../../../scenes/pyramid.json");

#[derive(Parser)]
#[command(name = "kea", version, about = "Run and benchmark Kea scenes")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Step a scene headless and print a summary.
    Run {
        /// The scene file (JSON); the embedded pyramid if absent.
        scene: Option<PathBuf>,
        /// Steps to take.
        #[arg(long, default_value_t = 600)]
        steps: u32,
        /// Step size, s.
        #[arg(long, default_value_t = 1.0 / 60.0)]
        dt: Real,
        /// Write every body's trajectory as CSV.
        #[arg(long)]
        csv: Option<PathBuf>,
        /// Write every body's trajectory as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Step a scene and write its last frame as a PNG, drawn on the CPU.
    Render {
        /// The scene file (JSON).
        scene: PathBuf,
        /// The PNG to write.
        #[arg(long)]
        out: PathBuf,
        /// Steps to take before drawing.
        #[arg(long, default_value_t = 0)]
        steps: u32,
        /// Step size, s.
        #[arg(long, default_value_t = 1.0 / 60.0)]
        dt: Real,
        /// Image width, pixels.
        #[arg(long, default_value_t = 800)]
        width: u32,
        /// Image height, pixels.
        #[arg(long, default_value_t = 600)]
        height: u32,
    },
    /// Step scenes headless and print ms per step and per stage, one line per scene.
    Bench {
        /// Scene files.
        #[arg(required = true)]
        scenes: Vec<PathBuf>,
        /// Steps to time (after 10 warm-up steps).
        #[arg(long, default_value_t = 300)]
        steps: u32,
        /// Step size, s.
        #[arg(long, default_value_t = 1.0 / 60.0)]
        dt: Real,
    },
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Run {
            scene,
            steps,
            dt,
            csv,
            json,
        } => run(scene.as_deref(), steps, dt, csv.as_deref(), json.as_deref()),
        Command::Bench { scenes, steps, dt } => bench(&scenes, steps, dt),
        Command::Render {
            scene,
            out,
            steps,
            dt,
            width,
            height,
        } => render(&scene, &out, steps, dt, (width, height)),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("kea: {message}");
            ExitCode::FAILURE
        }
    }
}

/// Loads and builds a scene file (or the embedded default), naming the file in any error.
fn load(path: Option<&std::path::Path>) -> Result<(String, BuiltScene), String> {
    let (name, text) = match path {
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))?;
            (p.display().to_string(), text)
        }
        None => ("(embedded pyramid)".to_string(), DEFAULT_SCENE.to_string()),
    };
    let scene = Scene::from_json(&text).map_err(|e| format!("{name}: {e}"))?;
    let built = build(&scene).map_err(|e| format!("{name}: {e}"))?;
    Ok((name, built))
}

fn check_run(steps: u32, dt: Real) -> Result<(), String> {
    if steps == 0 {
        return Err("--steps must be at least 1".into());
    }
    if !(dt.is_finite() && dt > 0.0) {
        return Err(format!(
            "--dt must be a positive number of seconds, got {dt}"
        ));
    }
    Ok(())
}

fn run(
    path: Option<&std::path::Path>,
    steps: u32,
    dt: Real,
    csv: Option<&std::path::Path>,
    json: Option<&std::path::Path>,
) -> Result<(), String> {
    check_run(steps, dt)?;
    let (name, mut built) = load(path)?;
    let mut recorder = record::Recorder::new(csv.is_some() || json.is_some());
    let mut summary = summary::Summary::new(&built);
    let bar = (steps >= 1000).then(|| indicatif::ProgressBar::new(u64::from(steps)));
    recorder.capture(0.0, &built);
    for n in 1..=steps {
        let stats = built
            .step(dt)
            .map_err(|e| format!("{name}: step {n}: {e}"))?;
        summary.add(&stats);
        recorder.capture(n as Real * dt, &built);
        if let Some(bar) = &bar {
            bar.inc(1);
        }
    }
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    // Write outputs only once the whole run succeeded.
    if let Some(p) = csv {
        std::fs::write(p, recorder.csv()).map_err(|e| format!("{}: {e}", p.display()))?;
    }
    if let Some(p) = json {
        std::fs::write(p, recorder.json()).map_err(|e| format!("{}: {e}", p.display()))?;
    }
    summary.print(&name, &built, steps, dt);
    Ok(())
}

fn bench(paths: &[PathBuf], steps: u32, dt: Real) -> Result<(), String> {
    check_run(steps, dt)?;
    for path in paths {
        let (name, mut built) = load(Some(path))?;
        for _ in 0..10 {
            built.step(dt).map_err(|e| format!("{name}: {e}"))?;
        }
        let mut summary = summary::Summary::new(&built);
        for n in 1..=steps {
            let stats = built
                .step(dt)
                .map_err(|e| format!("{name}: step {n}: {e}"))?;
            summary.add(&stats);
        }
        println!("{}", summary.bench_line(&name, &built, steps));
    }
    Ok(())
}

fn render(
    path: &std::path::Path,
    out: &std::path::Path,
    steps: u32,
    dt: Real,
    (width, height): (u32, u32),
) -> Result<(), String> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(format!(
            "--dt must be a positive number of seconds, got {dt}"
        ));
    }
    if out.extension().is_none_or(|e| e != "png") {
        return Err(format!(
            "--out {}: only .png is written so far",
            out.display()
        ));
    }
    if !(1..=8192).contains(&width) || !(1..=8192).contains(&height) {
        return Err(format!(
            "--width and --height must be 1 to 8192, got {width}×{height}"
        ));
    }
    let (name, mut built) = load(Some(path))?;
    for n in 1..=steps {
        built
            .step(dt)
            .map_err(|e| format!("{name}: step {n}: {e}"))?;
    }
    let camera = kea_render::Camera::framing(&built.world);
    let image = kea_render::render(&built.world, &built.collision, &camera, width, height);
    image.write_png(out)?;
    println!(
        "{name}: wrote {} ({width}×{height}) after {steps} steps",
        out.display()
    );
    Ok(())
}
