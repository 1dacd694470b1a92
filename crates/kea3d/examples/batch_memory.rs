//! What one world of a batch costs in memory: a robot world stepped as a whole world (its
//! state and its step's scratch), against the worlds of a batch, which hold only their
//! states and are stepped by a worker that trades states with each
//! (`PhysicsWorld::swap_state`, what `kea.Batch` does). A whole world's bytes are those a
//! clone of it allocates; a batch world's are the heap the batch's worlds hold, live, over
//! their number (what is shared among them — a robot's articulated model — counted once).
//! With `--noise`, each batch world starts from its own pose, as a training batch resets
//! (every joint coordinate moved by up to ±0.1, Gymnasium's reset noise).
//!
//! `cargo run --profile bench-lto -p kea3d --example batch_memory -- robot.xml|robot.urdf
//! [steps] [--fixed-base] [--noise]`

use kea3d::prelude::*;
use kea3d::robot::{MjcfOptions, UrdfOptions};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator, counting the bytes it hands out.
struct Counting;

static ALLOCATED: AtomicUsize = AtomicUsize::new(0);
static FREED: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call goes to the system allocator unchanged; only a counter is added.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATED.fetch_add(layout.size(), Ordering::Relaxed);
        // SAFETY: the caller's contract is passed on.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        FREED.fetch_add(layout.size(), Ordering::Relaxed);
        // SAFETY: the caller's contract is passed on.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Bytes a clone of `world` allocates.
fn bytes(world: &PhysicsWorld) -> usize {
    let before = ALLOCATED.load(Ordering::Relaxed);
    let copy = world.clone();
    let after = ALLOCATED.load(Ordering::Relaxed);
    drop(copy);
    after - before
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut words = args.iter().filter(|a| !a.starts_with("--"));
    let Some(path) = words.next() else {
        eprintln!("usage: batch_memory ROBOT.xml|ROBOT.urdf [steps] [--fixed-base] [--noise]");
        std::process::exit(2);
    };
    let steps: usize = words.next().map_or(Ok(500), |s| s.parse())?;
    let mut whole = PhysicsWorld::new();
    whole.set_gravity([0.0, 0.0, -9.81])?;
    let robot = if path.ends_with(".urdf") {
        let options = UrdfOptions {
            fixed_base: args.iter().any(|a| a == "--fixed-base"),
            ..UrdfOptions::default()
        };
        whole.load_urdf(path, &options)?
    } else {
        whole.load_mjcf(path, &MjcfOptions::default())?
    };
    let h = robot.timestep().unwrap_or(0.002);
    let mut worker = whole.clone();
    let live = || ALLOCATED.load(Ordering::Relaxed) - FREED.load(Ordering::Relaxed);
    const WORLDS: usize = 64;
    let before = live();
    let mut held = vec![whole.clone(); WORLDS];
    let noise = args.iter().any(|a| a == "--noise");
    let q0 = robot.joint_positions(&whole)?;
    // A fixed sequence in [-1, 1) (a linear congruential generator): the same worlds each run.
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut uniform = move || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    for w in &mut held {
        if noise {
            let q: Vec<Real> = q0.iter().map(|x| x + 0.1 * uniform() as Real).collect();
            robot.set_joint_positions(w, &q)?;
        }
        w.trim_to_state();
    }
    for _ in 0..steps {
        whole.step(h)?;
        for w in &mut held {
            worker.swap_state(w);
            worker.step(h)?;
            worker.swap_state(w);
        }
    }
    let per_world = (live() - before) / WORLDS;
    println!(
        "{}: after {steps} steps, a whole world {} bytes; a batch world {per_world} bytes \
         ({WORLDS} worlds holding their states; a worker per thread: {} bytes)",
        robot.name(),
        bytes(&whole),
        bytes(&worker)
    );
    Ok(())
}
