//! The `kea` command: run and benchmark scene files headless.
//!
//! - `kea run [SCENE] [--steps N] [--dt H] [--csv FILE] [--json FILE] [--keep-going]
//!   [--save-at STEP FILE] [--restore FILE]` steps a scene (the embedded pyramid when no file
//!   is given, or a snapshot saved by `--save-at`), shows a progress bar on long runs, and ends
//!   with a summary: steps per second, time per stage, bodies awake and asleep, energy, solver
//!   warnings, quarantined bodies.
//! - `kea bench SCENE… [--steps N] [--dt H]` prints one machine-readable line per scene.
//! - `kea render SCENE --out FILE.png|FILE.gif [--steps N] [--frames F --every K] [--width W]
//!   [--height H] [--throttle T] [--steer S] [--focus NAME]` draws the scene on the CPU (no
//!   GPU, no display): the frame after `--steps`, or an animation of `--frames` frames, one
//!   every `--every` steps; `--throttle`/`--steer` drive the scene's car as the Viewer's arrow
//!   keys do, `--focus` frames the named bodies.
//!
//! - `kea plot SCENE --out FILE.png [--steps N] [--dt H]` plots energy, momentum and
//!   constraint error against time.
//! - `kea view [SCENE] [--dt H] [--report] [--frames N]` opens the Viewer (a window).
//!
//! Exit code 0 on success; 1 with a message on stderr for a bad scene, a failed step or a
//! blow-up (an island quarantined; `kea run --keep-going` runs on), and nothing is written
//! then; 130 after Ctrl-C, with temporary files removed. Kea's warnings are printed on stderr,
//! each kind once with a count of the rest (`KEA_LOG=off|error|warn|info|debug`).

mod bench;
mod logger;
mod plot;
mod record;
mod render;
mod summary;

use clap::{Args, Parser, Subcommand};
use kea::Real;
use kea3d::PhysicsWorld;
use kea_scene::{build, Scene, SceneSnapshot};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

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
        /// Run to the end even if an island blows up (it is quarantined and reported);
        /// without it the run stops there and exits with status 1.
        #[arg(long)]
        keep_going: bool,
        /// Save the whole state after step STEP (0: before the first) to FILE: JSON if FILE
        /// ends in `.json`, the binary form otherwise. `--restore FILE` goes on from it, bit
        /// for bit.
        #[arg(long, num_args = 2, value_names = ["STEP", "FILE"])]
        save_at: Option<Vec<String>>,
        /// Start from a snapshot saved by `--save-at` instead of a scene file.
        #[arg(long, conflicts_with = "scene")]
        restore: Option<PathBuf>,
    },
    /// Step a scene and write its last frame as a PNG (or an animation as a GIF), drawn on
    /// the CPU.
    Render(RenderArgs),
    /// Step a scene and plot energy, momentum and constraint error against time (PNG).
    Plot {
        /// The scene file (JSON).
        scene: PathBuf,
        /// The PNG to write.
        #[arg(long)]
        out: PathBuf,
        /// Steps to take.
        #[arg(long, default_value_t = 600)]
        steps: u32,
        /// Step size, s.
        #[arg(long, default_value_t = 1.0 / 60.0)]
        dt: Real,
        /// Image width, pixels.
        #[arg(long, default_value_t = 900)]
        width: u32,
        /// Image height, pixels.
        #[arg(long, default_value_t = 900)]
        height: u32,
    },
    /// Open the Viewer: a window to watch, poke and measure a scene (F1 lists the keys).
    View(ViewArgs),
    /// Step scenes headless and print, one line per scene, the median ms per step over
    /// repeated runs, its spread, and the median per stage (collision included).
    Bench {
        /// Scene files.
        #[arg(required = true)]
        scenes: Vec<PathBuf>,
        /// Steps to time in each run (after 10 warm-up steps).
        #[arg(long, default_value_t = 300)]
        steps: u32,
        /// Step size, s.
        #[arg(long, default_value_t = 1.0 / 60.0)]
        dt: Real,
        /// Runs of each scene, each from its start; the line gives their median and spread.
        #[arg(long, default_value_t = 5)]
        repeats: u32,
    },
}

/// `kea render`'s options.
#[derive(Args)]
struct RenderArgs {
    /// The scene file (JSON).
    scene: PathBuf,
    /// The file to write: `.png` (the last frame) or `.gif` (an animation).
    #[arg(long)]
    out: PathBuf,
    /// For a GIF: frames to draw, one every `--every` steps after the first `--steps`.
    #[arg(long, default_value_t = 60)]
    frames: u32,
    /// For a GIF: steps between frames.
    #[arg(long, default_value_t = 2)]
    every: u32,
    /// Steps to take before drawing: by default 600 for a PNG (the last frame of `kea run`'s
    /// default run), 0 for a GIF (the animation starts at the start).
    #[arg(long)]
    steps: Option<u32>,
    /// Step size, s.
    #[arg(long, default_value_t = 1.0 / 60.0)]
    dt: Real,
    /// Image width, pixels.
    #[arg(long, default_value_t = 800)]
    width: u32,
    /// Image height, pixels.
    #[arg(long, default_value_t = 600)]
    height: u32,
    /// Drive the scene's car: before each step every car-wheel joint's motor asks this
    /// share of full speed, -1 to 1 (negative: reverse; 0: brake), as the Viewer's Up and
    /// Down keys do. Without it (and `--steer`) the scene's own motors run.
    #[arg(long, allow_negative_numbers = true, value_name = "T")]
    throttle: Option<Real>,
    /// Steer the scene's car: every steerable wheel turns to this share of its full
    /// angle, -1 to 1 (positive: left), as the Left and Right keys do. Alone, it steers
    /// with the throttle at 0 (braking).
    #[arg(long, allow_negative_numbers = true, value_name = "S")]
    steer: Option<Real>,
    /// Frame the camera on this body, or on a group's bodies (`ragdoll1` frames every
    /// `ragdoll1.*` body), and the static geometry near them, rather than on every body.
    /// Give it again to frame several.
    #[arg(long, value_name = "NAME")]
    focus: Vec<String>,
}

impl RenderArgs {
    fn run(&self) -> Result<(), String> {
        render::render(&render::RenderOptions {
            scene: &self.scene,
            out: &self.out,
            steps: self.steps,
            dt: self.dt,
            size: (self.width, self.height),
            frames: (self.frames, self.every),
            throttle: self.throttle,
            steer: self.steer,
            focus: &self.focus,
        })
    }
}

/// `kea view`'s options.
#[derive(Args)]
struct ViewArgs {
    /// The scene file (JSON); the embedded pyramid if absent.
    scene: Option<PathBuf>,
    /// Fixed step size, s.
    #[arg(long, default_value_t = 1.0 / 60.0)]
    dt: Real,
    /// Window width, pixels.
    #[arg(long, default_value_t = 1024)]
    width: u32,
    /// Window height, pixels.
    #[arg(long, default_value_t = 720)]
    height: u32,
    /// Where the screenshot key (P) writes.
    #[arg(long, default_value = "kea-screenshot.png")]
    screenshot: PathBuf,
    /// Where the record key (G) writes its GIF.
    #[arg(long, default_value = "kea-recording.gif")]
    recording: PathBuf,
    /// Print a line on stdout for every action (`paused step=12`), for scripts and tests.
    #[arg(long)]
    report: bool,
    /// Close after this many frames.
    #[arg(long)]
    frames: Option<u64>,
}

impl ViewArgs {
    fn run(self) -> Result<(), String> {
        let title = format!(
            "Kea Viewer: {}",
            self.scene
                .as_deref()
                .map_or("pyramid".into(), |p| p.display().to_string())
        );
        let options = kea_viewer::ViewerOptions {
            title,
            width: self.width,
            height: self.height,
            dt: self.dt,
            screenshot: self.screenshot,
            recording: self.recording,
            report: self.report,
            frames: self.frames,
            scene_file: self.scene.clone(),
        };
        view(self.scene.as_deref(), options)
    }
}

/// Set by Ctrl-C: long loops stop at their next step and clean up (temporary files go).
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Whether Ctrl-C was pressed.
pub(crate) fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::Relaxed)
}

fn main() -> ExitCode {
    logger::install();
    // A second Ctrl-C while cleaning up still ends the process (the default handler is gone,
    // so exit by hand).
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::Relaxed) {
            std::process::exit(130);
        }
    });
    let result = match Cli::parse().command {
        Command::Run {
            scene,
            steps,
            dt,
            csv,
            json,
            keep_going,
            save_at,
            restore,
        } => save_at_flag(save_at.as_deref()).and_then(|save_at| {
            run(&RunOptions {
                scene: scene.as_deref(),
                restore: restore.as_deref(),
                steps,
                dt,
                csv: csv.as_deref(),
                json: json.as_deref(),
                keep_going,
                save_at,
            })
        }),
        Command::Bench {
            scenes,
            steps,
            dt,
            repeats,
        } => bench::bench(&scenes, steps, dt, repeats),
        Command::Plot {
            scene,
            out,
            steps,
            dt,
            width,
            height,
        } => plot_scene(&scene, &out, steps, dt, (width, height)),
        Command::View(args) => args.run(),
        Command::Render(args) => args.run(),
    };
    logger::report_repeats();
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("kea: {message}");
            if interrupted() {
                ExitCode::from(130)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}

/// Reads a scene file (or the embedded default), naming the file in any error.
fn load_scene(path: Option<&std::path::Path>) -> Result<(String, Scene), String> {
    let (name, text) = match path {
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))?;
            (p.display().to_string(), text)
        }
        None => ("(embedded pyramid)".to_string(), DEFAULT_SCENE.to_string()),
    };
    let scene = Scene::from_json(&text).map_err(|e| format!("{name}: {e}"))?;
    // Robot files are named relative to the scene file.
    let folder = path
        .and_then(std::path::Path::parent)
        .unwrap_or(std::path::Path::new("."));
    Ok((name, scene.with_paths_from(folder)))
}

/// Loads and builds a scene file (or the embedded default), naming the file in any error.
pub(crate) fn load(path: Option<&std::path::Path>) -> Result<(String, PhysicsWorld), String> {
    let (name, scene) = load_scene(path)?;
    let built = build(&scene).map_err(|e| format!("{name}: {e}"))?;
    let mut world = PhysicsWorld::from_scene(built);
    world
        .load_scene_robots(&scene.robots)
        .map_err(|e| format!("{name}: {e}"))?;
    Ok((name, world))
}

/// Refuses, before any work, an output whose folder does not exist.
pub(crate) fn check_output_folder(
    path: Option<&std::path::Path>,
    flag: &str,
) -> Result<(), String> {
    let Some(path) = path else { return Ok(()) };
    match path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() && !folder.is_dir() => Err(format!(
            "{flag} {}: the folder {} does not exist",
            path.display(),
            folder.display()
        )),
        _ => Ok(()),
    }
}

pub(crate) fn check_size(width: u32, height: u32) -> Result<(), String> {
    if !(1..=8192).contains(&width) || !(1..=8192).contains(&height) {
        return Err(format!(
            "--width and --height must be 1 to 8192, got {width}×{height}"
        ));
    }
    Ok(())
}

fn plot_scene(
    path: &std::path::Path,
    out: &std::path::Path,
    steps: u32,
    dt: Real,
    size: (u32, u32),
) -> Result<(), String> {
    check_run(steps, dt)?;
    check_size(size.0, size.1)?;
    if out.extension().and_then(|e| e.to_str()) != Some("png") {
        return Err(format!("--out {}: write a .png", out.display()));
    }
    check_output_folder(Some(out), "--out")?;
    let (name, mut built) = load(Some(path))?;
    let mut record = plot::Record::new();
    record.capture(0.0, &built, 0.0)?;
    for n in 1..=steps {
        let stats = built
            .step(dt)
            .map_err(|e| format!("{name}: step {n}: {e}"))?;
        if stats.quarantined_bodies > 0 {
            return Err(format!(
                "{name}: blew up at step {n}: {}; nothing to plot",
                summary::quarantine_report(&built)
            ));
        }
        let joint_error = built.dynamics_mut().joint_error();
        record
            .capture(n as Real * dt, &built, joint_error)
            .map_err(|e| format!("{name}: {e}"))?;
    }
    let labelled = plot::draw(&record, out, size)?;
    println!(
        "wrote {} ({}×{}, {steps} steps){}",
        out.display(),
        size.0,
        size.1,
        if labelled {
            ""
        } else {
            " without labels: no font found (set KEA_FONT to a .ttf)"
        }
    );
    Ok(())
}

fn view(path: Option<&std::path::Path>, options: kea_viewer::ViewerOptions) -> Result<(), String> {
    check_size(options.width, options.height)?;
    let (name, scene) = load_scene(path)?;
    let has_display = ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|d| !d.is_empty()));
    if !has_display {
        return Err(
            "kea view needs a display and DISPLAY is not set (kea render draws frames without one)"
                .into(),
        );
    }
    kea_viewer::run(scene, options).map_err(|e| format!("{name}: {e}"))
}

pub(crate) fn check_run(steps: u32, dt: Real) -> Result<(), String> {
    if steps == 0 {
        return Err("--steps must be at least 1".into());
    }
    check_dt(dt)
}

pub(crate) fn check_dt(dt: Real) -> Result<(), String> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(format!(
            "--dt must be a positive number of seconds, got {dt}"
        ));
    }
    Ok(())
}

/// What `kea run` was asked to do.
struct RunOptions<'a> {
    scene: Option<&'a std::path::Path>,
    restore: Option<&'a std::path::Path>,
    steps: u32,
    dt: Real,
    csv: Option<&'a std::path::Path>,
    json: Option<&'a std::path::Path>,
    keep_going: bool,
    save_at: Option<(u32, PathBuf)>,
}

/// `--save-at STEP FILE`, checked.
fn save_at_flag(values: Option<&[String]>) -> Result<Option<(u32, PathBuf)>, String> {
    let Some([step, file]) = values else {
        return Ok(None);
    };
    let step = step
        .parse()
        .map_err(|_| format!("--save-at: STEP must be a whole number, got {step:?}"))?;
    Ok(Some((step, PathBuf::from(file))))
}

/// The scene to run: a scene file (or the embedded pyramid), or a restored snapshot.
fn start(o: &RunOptions<'_>) -> Result<(String, PhysicsWorld), String> {
    let Some(path) = o.restore else {
        return load(o.scene);
    };
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| format!("--restore {name}: {e}"))?;
    let snapshot = if bytes.first() == Some(&b'{') {
        let text = String::from_utf8(bytes).map_err(|e| format!("--restore {name}: {e}"))?;
        SceneSnapshot::from_json(&text)
    } else {
        SceneSnapshot::from_binary(&bytes)
    };
    let built = snapshot
        .and_then(PhysicsWorld::restore)
        .map_err(|e| format!("--restore {name}: {e}"))?;
    Ok((name, built))
}

/// A snapshot in the form its file name asks for (`.json`: JSON, otherwise binary).
fn snapshot_bytes(built: &PhysicsWorld, path: &std::path::Path) -> Result<Vec<u8>, String> {
    let json = path.extension().is_some_and(|e| e == "json");
    let bytes = built.snapshot().and_then(|s| {
        if json {
            s.to_json().map(String::into_bytes)
        } else {
            s.to_binary()
        }
    });
    bytes.map_err(|e| format!("--save-at {}: {e}", path.display()))
}

fn run(o: &RunOptions<'_>) -> Result<(), String> {
    check_run(o.steps, o.dt)?;
    check_output_folder(o.csv, "--csv")?;
    check_output_folder(o.json, "--json")?;
    if let Some((step, path)) = &o.save_at {
        check_output_folder(Some(path), "--save-at")?;
        if *step > o.steps {
            return Err(format!(
                "--save-at {step}: the run takes only {} steps",
                o.steps
            ));
        }
    }
    let (name, mut built) = start(o)?;
    let mut recorder = record::Recorder::new(o.csv, o.json)?;
    let mut summary = summary::Summary::new(&built);
    let bar = (o.steps >= 1000).then(|| indicatif::ProgressBar::new(u64::from(o.steps)));
    let t0 = built.time();
    recorder.capture(t0, &built)?;
    let mut saved = None;
    let mut blown_up = None;
    for n in 0..=o.steps {
        if let Some((step, path)) = &o.save_at {
            if *step == n {
                saved = Some((path, snapshot_bytes(&built, path)?));
            }
        }
        if n == o.steps || (blown_up.is_some() && !o.keep_going) {
            break;
        }
        if interrupted() {
            return Err(format!(
                "{name}: interrupted at step {}; nothing written",
                n + 1
            ));
        }
        let stats = built
            .step(o.dt)
            .map_err(|e| format!("{name}: step {}: {e}", n + 1))?;
        summary.add(&stats);
        summary.measure_joints(&mut built);
        recorder.capture(t0 + (n + 1) as Real * o.dt, &built)?;
        if let Some(bar) = &bar {
            bar.inc(1);
        }
        if stats.quarantined_bodies > 0 {
            blown_up.get_or_insert(n + 1);
        }
    }
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    if let Some(n) = blown_up {
        let report = summary::quarantine_report(&built);
        if !o.keep_going {
            summary.print(&name, &built, n, o.dt);
            return Err(format!(
                "{name}: blew up at step {n} (t = {:.3} s): {report}\n  nothing written; \
                 `--keep-going` runs on with the island frozen",
                t0 + n as Real * o.dt
            ));
        }
        eprintln!("kea: {name}: blew up at step {n}: {report}; kept going (--keep-going)");
    }
    // The outputs become visible only now that the whole run succeeded, all or none.
    recorder.commit()?;
    if let Some((path, bytes)) = saved {
        kea_render::write_file(path, &bytes)?;
    }
    summary.print(&name, &built, o.steps, o.dt);
    Ok(())
}
