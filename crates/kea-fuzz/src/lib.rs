//! A seeded random-operation driver over Kea's public API (issue 12's fuzz target).
//!
//! Each seed makes worlds and drives them with random operations ([`ops`]): bodies, every
//! joint, hand-made contacts, colliders of every shape, queries, steps with odd `dt`, settings.
//! Values are mostly ordinary and sometimes at or past the edges (NaN, infinities, zero,
//! negatives, the extremes of f32). The driver reports
//!
//! - **panics**: any panic, whether it escaped to the driver or was caught inside Kea (the
//!   collision layer turns a panic inside parry into an error; that still counts here);
//! - **hangs**: operations slower than the per-operation bound (a watchdog stops the process
//!   with the seed and operation if one takes more than ten times the bound);
//! - **refused calls that changed state**: a state fingerprint is taken before each call and
//!   compared after a refusal;
//! - **poisoned worlds**: a NaN or infinity in any body after an accepted call;
//! - **traded steps that differ**: a step taken by a worker world that trades states with
//!   the world (as `kea.Batch` steps) must give what the same step of a copy taken in place
//!   gives, to the bit (checked after the operation, outside its timing).
//!
//! CI runs [`run`] for a fixed number of operations on fixed seeds (`tests/ci.rs`); a long run
//! is `cargo run --release -p kea-fuzz -- --seeds 100 --ops 10000` (10⁶ operations).

pub mod ops;
pub mod random;

use ops::Sandbox;
use random::Rng;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// What a run found.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Report {
    /// Operations run.
    pub operations: u64,
    /// Of those, refused with an error (bad input, stale handle, …).
    pub refused: u64,
    /// Panics that reached the driver.
    pub escaped_panics: u64,
    /// Panics caught inside Kea and turned into errors (counted by the panic hook).
    pub caught_panics: u64,
    /// Operations slower than the bound.
    pub slow: u64,
    /// Refused calls after which the world differed from before.
    pub refused_but_changed: u64,
    /// Accepted calls after which some body held a NaN or infinity.
    pub poisoned: u64,
    /// Traded steps whose outcome or snapshot differed from the same step taken in place.
    pub traded_differs: u64,
    /// The slowest operation, and its name.
    pub slowest: (Duration, &'static str),
    /// The first few problems, each with its seed and operation number.
    pub problems: Vec<String>,
}

impl Report {
    /// Whether nothing went wrong.
    #[must_use]
    pub fn is_clean(&self) -> bool {
        self.escaped_panics == 0
            && self.caught_panics == 0
            && self.slow == 0
            && self.refused_but_changed == 0
            && self.poisoned == 0
            && self.traded_differs == 0
    }

    fn problem(&mut self, mut text: String) {
        if self.problems.len() < 20 {
            if let Some((cut, _)) = text.char_indices().nth(240) {
                text.truncate(cut);
                text.push('…');
            }
            self.problems.push(text);
        }
    }

    fn add(&mut self, other: &Report) {
        self.operations += other.operations;
        self.refused += other.refused;
        self.escaped_panics += other.escaped_panics;
        self.caught_panics += other.caught_panics;
        self.slow += other.slow;
        self.refused_but_changed += other.refused_but_changed;
        self.poisoned += other.poisoned;
        self.traded_differs += other.traded_differs;
        if other.slowest.0 > self.slowest.0 {
            self.slowest = other.slowest;
        }
        for p in &other.problems {
            self.problem(p.clone());
        }
    }
}

/// Panics seen by the hook since the driver installed it.
static PANICS: AtomicU64 = AtomicU64::new(0);
static HOOKED: AtomicBool = AtomicBool::new(false);

fn install_panic_counter() {
    if HOOKED.swap(true, Ordering::SeqCst) {
        return;
    }
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        PANICS.fetch_add(1, Ordering::SeqCst);
        previous(info);
    }));
}

/// The bits of a real, widened (in f32 and f64 alike).
#[allow(clippy::unnecessary_cast)] // a no-op in f64
fn bits(x: kea::Real) -> u64 {
    x.to_bits() as u64
}

/// The bits of everything a refused call must leave alone.
fn fingerprint(s: &Sandbox) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bits: u64| {
        h = (h ^ bits).wrapping_mul(0x0100_0000_01b3);
    };
    let w = s.world();
    for (handle, b) in w.bodies() {
        eat(u64::from(handle.index()));
        let (p, q) = (b.position(), b.orientation());
        let (v, o) = (b.linear_velocity(), b.angular_velocity());
        for x in [
            p.x,
            p.y,
            p.z,
            q.x,
            q.y,
            q.z,
            q.w,
            v.x,
            v.y,
            v.z,
            o.x,
            o.y,
            o.z,
            b.mass(),
        ] {
            eat(bits(x));
        }
        eat(u64::from(b.is_enabled()));
    }
    eat(w.constraint_count() as u64);
    // Hand-made contacts: their normal and points (a refused update must move neither).
    for (h, c, _) in w.contacts() {
        eat(u64::from(h.index()));
        let n = c.normal();
        for x in [n.x, n.y, n.z] {
            eat(bits(x));
        }
        for p in c.points() {
            for x in [p.position.x, p.position.y, p.position.z, p.penetration] {
                eat(bits(x));
            }
            eat(u64::from(p.id));
        }
    }
    eat(w.time().to_bits());
    eat(w.step_count());
    let g = w.settings().gravity;
    for x in [g.x, g.y, g.z, w.settings().epsilon, w.settings().gamma] {
        eat(bits(x));
    }
    eat(s.collision().collider_count() as u64);
    h
}

fn poisoned(s: &Sandbox) -> bool {
    s.world().bodies().any(|(_, b)| {
        !(b.position().is_finite()
            && b.orientation().is_finite()
            && b.linear_velocity().is_finite()
            && b.angular_velocity().is_finite())
    })
}

/// The watchdog: a detached thread that exits the process if the operation in flight (its
/// start, ms since `epoch`, stored in the first flag; `u64::MAX` between operations) runs past
/// ten times `bound`; it ends when the second flag is set.
fn watchdog(seed: u64, bound: Duration, epoch: Instant) -> (Arc<AtomicU64>, Arc<AtomicBool>) {
    let started_ms = Arc::new(AtomicU64::new(u64::MAX));
    let done = Arc::new(AtomicBool::new(false));
    let (started, finished) = (started_ms.clone(), done.clone());
    let limit = bound.as_millis() as u64 * 10;
    std::thread::spawn(move || {
        while !finished.load(Ordering::Relaxed) {
            let at = started.load(Ordering::Relaxed);
            let now = epoch.elapsed().as_millis() as u64;
            if at != u64::MAX && now.saturating_sub(at) > limit {
                eprintln!("kea-fuzz: HANG: seed {seed}: an operation ran past {limit} ms");
                std::process::exit(3);
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    });
    (started_ms, done)
}

/// Runs `ops` operations from `seed`, with `bound` as the per-operation time bound.
pub fn run_seed(seed: u64, ops: u64, bound: Duration) -> Report {
    install_panic_counter();
    let mut report = Report::default();
    let mut rng = Rng::new(seed);
    let mut sandbox = Sandbox::new(&mut rng);
    let epoch = Instant::now();
    let (started_ms, done) = watchdog(seed, bound, epoch);
    for n in 0..ops {
        if rng.chance(0.002) {
            sandbox = sandbox.renew(&mut rng);
        }
        let before = fingerprint(&sandbox);
        let panics_before = PANICS.load(Ordering::SeqCst);
        started_ms.store(epoch.elapsed().as_millis() as u64, Ordering::Relaxed);
        let t0 = Instant::now();
        let result = catch_unwind(AssertUnwindSafe(|| sandbox.operate(&mut rng)));
        let took = t0.elapsed();
        started_ms.store(u64::MAX, Ordering::Relaxed);
        report.operations += 1;
        if took > report.slowest.0 {
            report.slowest = (took, result.as_ref().map_or("(panicked)", |r| r.0));
        }
        let (name, outcome) = match result {
            Ok(r) => r,
            Err(_) => {
                report.escaped_panics += 1;
                report.problem(format!("seed {seed} op {n}: panic escaped"));
                sandbox = sandbox.renew(&mut rng);
                continue;
            }
        };
        match catch_unwind(AssertUnwindSafe(|| sandbox.verify_traded_step())) {
            Ok(None) => {}
            Ok(Some(why)) => {
                report.traded_differs += 1;
                report.problem(format!("seed {seed} op {n} {name}: {why}"));
            }
            Err(_) => {
                report.escaped_panics += 1;
                report.problem(format!(
                    "seed {seed} op {n}: panic escaped checking a traded step"
                ));
                sandbox = sandbox.renew(&mut rng);
                continue;
            }
        }
        let caught = PANICS.load(Ordering::SeqCst) - panics_before;
        if caught > 0 {
            report.caught_panics += caught;
            report.problem(format!(
                "seed {seed} op {n} {name}: a panic was caught inside Kea"
            ));
        }
        if took > bound {
            report.slow += 1;
            report.problem(format!("seed {seed} op {n} {name}: took {took:?}"));
        }
        match outcome {
            Err(e) => {
                report.refused += 1;
                if fingerprint(&sandbox) != before {
                    report.refused_but_changed += 1;
                    report.problem(format!(
                        "seed {seed} op {n} {name}: refused ({e}) but changed the world"
                    ));
                }
            }
            Ok(()) => {
                if poisoned(&sandbox) {
                    report.poisoned += 1;
                    report.problem(format!(
                        "seed {seed} op {n} {name}: accepted, and a body is now NaN"
                    ));
                    sandbox = sandbox.renew(&mut rng);
                }
            }
        }
    }
    done.store(true, Ordering::Relaxed);
    report
}

/// Runs `ops` operations from each seed in `seeds`, one after the other.
pub fn run(seeds: std::ops::Range<u64>, ops: u64, bound: Duration) -> Report {
    let mut total = Report::default();
    for seed in seeds {
        total.add(&run_seed(seed, ops, bound));
    }
    total
}
