//! Every demo scene, once warm, steps (collision included) without touching the heap: its
//! bodies keep colliding, waking, sleeping and sliding, its pairs and contacts come and go,
//! and not one allocation happens.

mod common;

use kea::Real;
use kea3d::PhysicsWorld;
use kea_scene::{build, Scene};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

struct CountingAllocator;
// On the threads that step (the test's own and the `parallel` feature's workers); this file
// holds one test, so nothing else steps beside it.
static COUNTING: AtomicBool = AtomicBool::new(false);
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator; only counts on the side.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: the caller's contract is passed on unchanged.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        // SAFETY: as above.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

thread_local! {
    /// Whether this thread steps the scenes (the test's thread, or a pool worker): the test
    /// harness's own threads may allocate meanwhile (a report, a timer), and that is no step's.
    static STEPS_HERE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

fn count() {
    if COUNTING.load(Ordering::Relaxed) && STEPS_HERE.with(std::cell::Cell::get) {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

fn allocations_in(f: impl FnOnce()) -> usize {
    ALLOCATIONS.store(0, Ordering::SeqCst);
    COUNTING.store(true, Ordering::SeqCst);
    f();
    COUNTING.store(false, Ordering::SeqCst);
    ALLOCATIONS.load(Ordering::SeqCst)
}

const DT: Real = 1.0 / 60.0;

#[test]
fn every_demo_scene_steps_warm_without_allocating() {
    let names = common::demo_scene_paths();
    assert!(names.len() >= 10, "demo scenes: {names:?}");
    // With threads, the steps run inside a pool, where rayon's fork-join allocates nothing
    // (a call from outside a pool goes through rayon's injector queue, which allocates a block
    // every 63 calls).
    #[cfg(feature = "parallel")]
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    // Every worker has started (the OS may be slow to run a new thread) and registered with
    // the work-stealing deques before anything is counted: a thread's start-up allocations are
    // not a step's.
    #[cfg(feature = "parallel")]
    for _ in 0..4 {
        pool.broadcast(|_| STEPS_HERE.with(|c| c.set(true)));
    }
    STEPS_HERE.with(|c| c.set(true));
    #[cfg(feature = "parallel")]
    pool.install(|| {
        check_scenes(&names);
        check_sleeping_pile_beside_motion();
    });
    #[cfg(not(feature = "parallel"))]
    {
        check_scenes(&names);
        check_sleeping_pile_beside_motion();
    }
}

/// A pyramid asleep beside a box sliding to a stop and a swinging pendulum: the steps that
/// list the awake bodies' constraints and the pairs that may move, and merge the pile's
/// contact events with the moving bodies', allocate nothing once warm either.
fn check_sleeping_pile_beside_motion() {
    use kea3d::prelude::{Body, Collider, Joint};
    let path = format!("{}/../../scenes/pyramid.json", env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
    let mut w = PhysicsWorld::from_scene(build(&scene).unwrap());
    w.dynamics_mut()
        .update_settings(|s| s.dem.mode = kea::DemMode::PartitionAutoDisable)
        .unwrap();
    for _ in 0..240 {
        w.step(DT).unwrap();
    }
    let sled = w
        .insert_body(Body::dynamic().position([-6.0, 0.5, 4.0]))
        .unwrap();
    w.insert_collider(Collider::cuboid([0.5; 3]), Some(sled))
        .unwrap();
    w.set_linear_velocity(sled, [2.0, 0.0, 0.0]).unwrap();
    let bob = w
        .insert_body(Body::dynamic().position([8.0, 1.2, 4.0]))
        .unwrap();
    w.insert_collider(Collider::ball(0.2), Some(bob)).unwrap();
    w.insert_joint(bob, None, Joint::hinge([10.0, 1.2, 4.0], [0.0, 0.0, 1.0]))
        .unwrap();
    for _ in 0..120 {
        w.step(DT).unwrap();
    }
    let asleep = w.step(DT).unwrap().sleeping_bodies;
    assert!(asleep >= 200, "the pile sleeps beside the motion: {asleep}");
    let n = allocations_in(|| {
        for _ in 0..240 {
            w.step(DT).unwrap();
        }
    });
    assert_eq!(
        n, 0,
        "{n} allocations over 240 warm steps beside a sleeping pile"
    );
}

fn check_scenes(names: &[std::path::PathBuf]) {
    let mut failures = Vec::new();
    for path in names {
        let text = std::fs::read_to_string(path).unwrap();
        let mut built = PhysicsWorld::from_scene(build(&Scene::from_json(&text).unwrap()).unwrap());
        // Warm: the scene has found the contacts it makes and the sizes it needs.
        for _ in 0..240 {
            built.step(DT).unwrap();
        }
        let n = allocations_in(|| {
            for _ in 0..240 {
                built.step(DT).unwrap();
            }
        });
        eprintln!("{}: {n} allocations over 240 warm steps", path.display());
        if n > 0 {
            failures.push(format!("{}: {n}", path.display()));
        }
    }
    assert!(failures.is_empty(), "warm steps allocated: {failures:?}");
    // The counter really counts, on this thread and on the pool's.
    let n = allocations_in(|| drop(std::hint::black_box(vec![1u8; 64])));
    assert_eq!(n, 1, "a deliberate allocation counted {n} times");
    #[cfg(feature = "parallel")]
    {
        let n = allocations_in(|| {
            rayon::join(|| drop(std::hint::black_box(vec![1u8; 64])), || ());
        });
        assert!(n >= 1, "a pool thread's allocation counted {n} times");
    }
}
