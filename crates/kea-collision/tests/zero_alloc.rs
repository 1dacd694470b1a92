//! Once a scene has warmed up, a collision step (broad phase, narrow phase, contact sync and the
//! world's step) whose pair set does not change performs zero heap allocations.
//!
//! The plane and polygonal-feature pairs go through Kea's own allocation-free generators (parry
//! 0.31's rebuild their point lists every step); a box on a plane checks that path.

use kea::{BodyDef, Quat, Vec3, World, WorldDef};
use kea_collision::{ColliderDef, CollisionWorld, Shape};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
mod common;

struct CountingAllocator;
thread_local! {
    // Both the flag and the count are per thread: the two tests here run in parallel.
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count_one() {
    if COUNTING.with(Cell::get) {
        ALLOCATIONS.with(|n| n.set(n.get() + 1));
    }
}

/// Runs `f` and returns how many allocations this thread made inside it.
fn allocations_in(f: impl FnOnce()) -> usize {
    ALLOCATIONS.with(|n| n.set(0));
    COUNTING.with(|c| c.set(true));
    f();
    COUNTING.with(|c| c.set(false));
    ALLOCATIONS.with(Cell::get)
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count_one();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count_one();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn a_warm_collision_step_allocates_nothing() {
    let mut world = World::new(WorldDef {
        max_bodies: 16,
        max_constraints: 256,
        ..Default::default()
    })
    .unwrap();
    let mut collision = CollisionWorld::new();
    let mut ground = ColliderDef::new(None, Shape::cuboid(Vec3::new(10.0, 0.5, 10.0)).unwrap());
    ground.offset = Vec3::new(0.0, -0.5, 0.0);
    collision.add_collider(&world, ground).unwrap();
    let cube = Shape::cuboid(Vec3::splat(0.5)).unwrap();
    let ball = Shape::sphere(0.4).unwrap();
    // A stack of two boxes and a ball, on a box ground: face and point manifolds.
    let scene: [(Shape, Vec3, Quat); 3] = [
        (cube.clone(), Vec3::new(0.0, 0.5, 0.0), Quat::IDENTITY),
        (cube, Vec3::new(0.1, 1.5, 0.0), Quat::IDENTITY),
        (ball, Vec3::new(2.0, 0.4, 0.0), Quat::IDENTITY),
    ];
    for (shape, position, orientation) in scene {
        let mp = shape.mass_properties(500.0).unwrap();
        let b = world
            .create_body(&BodyDef {
                mass: mp.mass,
                inertia: mp.inertia,
                position,
                orientation,
                ..Default::default()
            })
            .unwrap();
        collision
            .add_collider(&world, ColliderDef::new(Some(b), shape))
            .unwrap();
    }
    for _ in 0..120 {
        common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
    }
    let contacts = world.constraint_count();
    let n = allocations_in(|| {
        for _ in 0..120 {
            common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
        }
    });
    eprintln!("{contacts} contacts; allocations over 120 warm steps: {n}");
    assert_eq!(
        world.constraint_count(),
        contacts,
        "the scene should be at rest"
    );
    assert_eq!(n, 0, "a warm collision step allocated");
}

#[test]
fn plane_pairs_allocate_nothing_in_a_warm_step() {
    let mut world = World::with_capacity(4, 64).unwrap();
    let mut collision = CollisionWorld::new();
    collision
        .add_collider(
            &world,
            ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap()),
        )
        .unwrap();
    let cube = Shape::cuboid(Vec3::splat(0.5)).unwrap();
    let b = world
        .create_body(&BodyDef {
            position: Vec3::new(0.0, 0.5, 0.0),
            ..Default::default()
        })
        .unwrap();
    collision
        .add_collider(&world, ColliderDef::new(Some(b), cube))
        .unwrap();
    for _ in 0..60 {
        common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
    }
    let n = allocations_in(|| {
        for _ in 0..60 {
            common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
        }
    });
    eprintln!("box on a plane: allocations over 60 warm steps: {n}");
    assert_eq!(n, 0, "a box on a plane allocated in a warm step");
}
