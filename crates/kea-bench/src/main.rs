//! `kea-bench`: Kea and Rapier on the same scenes, one after the other in one process.
//!
//! For each scene, both engines build it from one description ([`mod@scenes`]), step it at 60 Hz
//! on one thread (sleeping off, except in the sleeping scene), and are timed over several
//! runs, alternating engines so that a machine whose speed drifts treats both alike. The table
//! gives the median ms/step of each, Rapier's time over Kea's (above 1: Kea is faster), and a
//! quality figure per scene: the largest displacement of any body (stacks that should stand),
//! the final kinetic energy (balls that should settle) or the largest joint gap (chains).
//!
//! With the `parallel` feature a second table times Kea on one thread and on every core, and
//! checks that both end in the same bits.
//!
//! `cargo run --profile bench-lto -p kea-bench [--features parallel] [-- [--runs N] [--quick]
//! [--rapier-simd8 PATH] [--kea-only] [--steps N] [FILTER]]`
//!
//! Built with the workspace's `bench-lto` profile (`lto = "thin"`, `codegen-units = 1`), both
//! engines get what a speed-minded user ships; the output names the profile it was built with.
//! `--rapier-simd8 PATH` names a second build of this crate with the `simd8` feature (Rapier on
//! 8 lanes): each run of each scene then also runs Rapier there, and the ratio is taken
//! against the faster Rapier. `crates/kea-bench/fair.sh` builds both and runs them.
//!
//! `KEA_BENCH_MODE=exact|split|iterative` forces Kea's routing (default: hybrid, except the
//! hanging chain, which measures the exact path), to compare its paths on the same scenes.

mod kea_run;
mod rapier_run;
mod scenes;

use scenes::{Quality, Scene};

/// One timed run of one scene in one engine.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// Time per step, ms.
    pub ms: f64,
    /// The scene's quality figure.
    pub quality: f64,
    /// Kea's stage times per step, ms: solver, broad phase, narrow phase.
    pub stages_ms: [f64; 3],
    /// Why the run stopped early (the engine refused a step), if it did.
    pub failed: Option<String>,
    /// A hash of the final state (Kea's; 0 for Rapier).
    pub hash: u64,
    /// The largest hinge limit overrun at any step, rad ([`scenes::hinge_overrun`]).
    pub overrun: f64,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn spread(v: &[f64]) -> f64 {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    hi - lo
}

fn scenes(quick: bool) -> Vec<Scene> {
    let s = |n: usize| if quick { n.div_ceil(4) } else { n };
    vec![
        scenes::pyramid(20, s(300)),
        scenes::pyramid(40, s(200)),
        scenes::pyramid(80, s(100)),
        scenes::balls(1000, s(300)),
        scenes::column(40, s(600)),
        scenes::heavy_light(10, s(600)),
        scenes::sleeping_pyramid(40, s(100)),
        scenes::sleeping_pyramid_beside_a_pendulum(40, s(100)),
        scenes::chain(100, s(600)),
        scenes::chain(333, s(300)),
        scenes::hanging_chain(333, s(300)),
        scenes::ragdolls(8, s(300)),
        scenes::ragdolls(32, s(300)),
        scenes::ball_net(30, s(300)),
    ]
}

fn quality(q: Quality, x: f64) -> String {
    match q {
        Quality::Displacement => format!("moved {:.1} cm", x * 100.0),
        Quality::Energy => format!("KE {x:.2e} J"),
        Quality::JointGap => format!("gap {:.1} mm", x * 1000.0),
    }
}

fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!(
        "{cpu}, {cores} cores; Kea's contact solver uses {} SIMD lanes",
        kea::SimdLevel::Auto.lanes()
    )
}

/// The build this binary is: its Cargo profile and whether that is the fair one.
fn build() -> String {
    let profile = env!("KEA_BENCH_PROFILE");
    let rapier = if cfg!(feature = "simd8") {
        "Rapier with `simd8`"
    } else {
        "Rapier without `simd8`"
    };
    if profile == "bench-lto" {
        format!(
            "profile `bench-lto` (lto = \"thin\", codegen-units = 1) for both engines; {rapier}"
        )
    } else {
        format!("profile `{profile}`: NOT the fair build (use `--profile bench-lto`); {rapier}")
    }
}

/// One Rapier run of the scene named `name` in the `simd8` build at `path`: (ms, quality).
fn rapier_simd8(path: &str, name: &str, quick: bool) -> Option<(f64, f64)> {
    let mut cmd = std::process::Command::new(path);
    cmd.args(["--rapier-only", name]);
    if quick {
        cmd.arg("--quick");
    }
    let out = cmd.output().ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    let mut it = text.split_whitespace().map(|x| x.parse::<f64>().ok());
    Some((it.next()??, it.next()??))
}

/// Options of one run of the benchmark.
struct Options {
    runs: usize,
    /// Kea alone (for profiling): Rapier's columns read 0.
    kea_only: bool,
    quick: bool,
    filter: String,
    simd8: Option<String>,
    /// Timed steps of every scene instead of its own count (to profile a phase).
    steps: Option<usize>,
}

fn options() -> Options {
    let mut o = Options {
        runs: 3,
        kea_only: false,
        quick: false,
        filter: String::new(),
        simd8: None,
        steps: None,
    };
    let mut args = std::env::args().skip(1);
    let mut rapier_only = None;
    while let Some(a) = args.next() {
        match a.as_str() {
            "--runs" => o.runs = args.next().and_then(|n| n.parse().ok()).unwrap_or(3),
            "--quick" => o.quick = true,
            "--kea-only" => o.kea_only = true,
            "--rapier-simd8" => o.simd8 = args.next(),
            "--rapier-only" => rapier_only = args.next(),
            "--steps" => o.steps = args.next().and_then(|n| n.parse().ok()),
            _ => o.filter = a,
        }
    }
    if let Some(name) = rapier_only {
        // The peer mode: one Rapier run of one scene, printed as `ms quality`.
        if let Some(scene) = scenes(o.quick).into_iter().find(|s| s.name == name) {
            let r = rapier_run::run(&scene);
            println!("{} {}", r.ms, r.quality);
        }
        std::process::exit(0);
    }
    o
}

fn main() {
    let Options {
        runs,
        kea_only,
        quick,
        filter,
        simd8,
        steps,
    } = options();
    let engines = if cfg!(feature = "parallel") {
        "Kea on every core (the `parallel` feature), Rapier on one thread"
    } else {
        "one thread"
    };
    println!("Kea vs Rapier 0.36 (defaults), dt 1/60, {engines}: median of {runs} runs");
    println!("Machine: {}", machine());
    println!("Build: {}", build());
    if let Some(path) = &simd8 {
        println!("Rapier with `simd8`: {path}; Rapier / Kea is taken against the faster Rapier");
    }
    println!();
    println!("| scene | Rapier ms/step | Rapier simd8 ms/step | Kea ms/step | Rapier / Kea | Kea quality | Rapier quality | Kea solve / broad / narrow ms | µs per joint per substep, Kea / Rapier |");
    println!("|---|---|---|---|---|---|---|---|---|");
    let mut per_scene: Vec<(String, usize, f64)> = Vec::new();
    for mut scene in scenes(quick)
        .into_iter()
        .filter(|s| s.name.contains(&filter))
    {
        scene.steps = steps.unwrap_or(scene.steps);
        let m = measure(&scene, runs, kea_only, simd8.as_deref(), quick);
        per_scene.push((scene.name.clone(), scene.bodies.len(), median(m.kea_ms())));
        print_row(&scene, &m);
    }
    scaling(&per_scene);
    #[cfg(feature = "parallel")]
    threads(runs, quick, &filter);
}

/// One scene's runs in each engine.
struct Measured {
    kea: Vec<Outcome>,
    rapier: Vec<Outcome>,
    /// Rapier's `simd8` build, ms per step.
    wide: Vec<f64>,
}

impl Measured {
    fn kea_ms(&self) -> Vec<f64> {
        self.kea.iter().map(|o| o.ms).collect()
    }
}

/// Runs `scene` `runs` times in each engine, alternating them (a machine whose speed drifts
/// treats both alike).
fn measure(
    scene: &Scene,
    runs: usize,
    kea_only: bool,
    simd8: Option<&str>,
    quick: bool,
) -> Measured {
    let mut m = Measured {
        kea: Vec::new(),
        rapier: Vec::new(),
        wide: Vec::new(),
    };
    for _ in 0..runs {
        m.kea.push(kea_run::run(scene));
        if kea_only {
            continue;
        }
        m.rapier.push(rapier_run::run(scene));
        if let Some(r) = simd8.and_then(|p| rapier_simd8(p, &scene.name, quick)) {
            m.wide.push(r.0);
        }
    }
    m
}

/// The table's row for one scene: each engine's median and spread, the ratio against the
/// faster Rapier, the quality figures and Kea's stage times.
fn print_row(scene: &Scene, m: &Measured) {
    let k = median(m.kea_ms());
    let rapier_ms: Vec<f64> = m.rapier.iter().map(|o| o.ms).collect();
    let plain = median(rapier_ms.clone());
    let (r, wide_text) = if m.wide.is_empty() {
        (plain, "—".to_string())
    } else {
        let w = median(m.wide.clone());
        (
            plain.min(w),
            format!("{w:.3} (±{:.3})", 0.5 * spread(&m.wide)),
        )
    };
    let kq = m.kea.last().map_or(0.0, |o| o.quality);
    let kea_quality = match m.kea.iter().find_map(|o| o.failed.as_ref()) {
        Some(why) => format!("**failed** at {why}"),
        None => quality(scene.quality, kq),
    };
    let rq = m.rapier.last().map_or(0.0, |o| o.quality);
    let (kea_quality, rapier_quality) = if scenes::has_hinges(scene) {
        let worst = |o: &[Outcome]| o.iter().map(|o| o.overrun).fold(0.0, f64::max);
        (
            format!("{kea_quality}, limits overrun {:.2} rad", worst(&m.kea)),
            format!(
                "{}, limits overrun {:.2} rad",
                quality(scene.quality, rq),
                worst(&m.rapier)
            ),
        )
    } else {
        (kea_quality, quality(scene.quality, rq))
    };
    let stage = |i: usize| median(m.kea.iter().map(|o| o.stages_ms[i]).collect());
    // Both take 4 substeps a step on these scenes (Kea's split and iterative paths, Rapier's
    // default solver iterations); Kea's exact path, forced, takes one.
    let per_joint = if scene.joints.is_empty() {
        "—".to_string()
    } else {
        let kea_substeps = if scene.kea_exact { 1.0 } else { 4.0 };
        let joints = scene.joints.len() as f64;
        format!(
            "{:.3} / {:.3}",
            1000.0 * k / (joints * kea_substeps),
            1000.0 * r / (joints * 4.0)
        )
    };
    println!(
        "| {} | {:.3} (±{:.3}) | {} | {:.3} (±{:.3}) | {:.2} | {} | {} | {:.3} / {:.3} / {:.3} | {} |",
        scene.name,
        plain,
        0.5 * spread(&rapier_ms),
        wide_text,
        k,
        0.5 * spread(&m.kea_ms()),
        r / k,
        kea_quality,
        rapier_quality,
        stage(0),
        stage(1),
        stage(2),
        per_joint,
    );
}

/// The scaling figures, where the scenes ran: ms per body at base 80 over base 20, and
/// a sleeping base-40 pyramid's cost over an awake one's, alone and beside a pendulum.
fn scaling(per_scene: &[(String, usize, f64)]) {
    let find = |name: &str| per_scene.iter().find(|(n, _, _)| n.starts_with(name));
    if let (Some(a), Some(b)) = (find("pyramid, base 20"), find("pyramid, base 80")) {
        let ratio = (b.2 / b.1 as f64) / (a.2 / a.1 as f64);
        println!("\nKea ms per body, base 80 over base 20: {ratio:.2} (target ≤ 1.2)");
    }
    let Some(awake) = find("pyramid, base 40") else {
        return;
    };
    for (name, label) in [
        ("sleeping pyramid, base 40", "alone"),
        (
            "sleeping pyramid, base 40, beside a pendulum",
            "beside a swinging pendulum",
        ),
    ] {
        if let Some(asleep) = per_scene.iter().find(|(n, _, _)| n == name) {
            println!(
                "Kea's sleeping base-40 pyramid over an awake one, {label}: {:.2}% (target ≤ 0.2%)",
                100.0 * asleep.2 / awake.2
            );
        }
    }
}

/// Kea on one thread against Kea on every core, scene by scene.
#[cfg(feature = "parallel")]
fn threads(runs: usize, quick: bool, filter: &str) {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("thread pool")
    };
    let (one, all) = (pool(1), pool(cores));
    println!("\nKea on 1 thread and on {cores} (the `parallel` feature): median of {runs} runs\n");
    println!("| scene | 1 thread ms/step | {cores} threads ms/step | speed-up | same bits |");
    println!("|---|---|---|---|---|");
    for scene in scenes(quick)
        .into_iter()
        .filter(|s| s.name.contains(filter))
    {
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for _ in 0..runs {
            a.push(one.install(|| kea_run::run(&scene)));
            b.push(all.install(|| kea_run::run(&scene)));
        }
        let t1 = median(a.iter().map(|o| o.ms).collect());
        let tn = median(b.iter().map(|o| o.ms).collect());
        let same = a.iter().chain(&b).all(|o| o.hash == a[0].hash);
        println!(
            "| {} | {t1:.3} | {tn:.3} | {:.2} | {} |",
            scene.name,
            t1 / tn,
            if same { "yes" } else { "**no**" }
        );
    }
}
