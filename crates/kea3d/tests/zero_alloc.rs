//! A world that started too small grows while it fills, and once warm it steps (kinematic
//! driving and collision included) without touching the heap.

use kea3d::prelude::*;

mod counting;

use counting::allocations_in;

#[global_allocator]
static ALLOCATOR: counting::CountingAllocator = counting::CountingAllocator;

#[test]
fn a_grown_world_steps_warm_without_allocating() {
    let mut w = PhysicsWorld::with_def(kea3d::dynamics::WorldDef {
        max_bodies: 1,
        max_constraints: 1,
        max_island_rows: 8,
        ..kea3d::dynamics::WorldDef::default()
    })
    .unwrap();
    let ground = w.insert_body(Body::fixed()).unwrap();
    w.insert_collider(Collider::cuboid([10.0, 0.5, 10.0]), Some(ground))
        .unwrap();
    for row in 0..6 {
        for i in 0..(6 - row) {
            let x = (i as Real - (5 - row) as Real * 0.5) * 1.02;
            let b = w
                .insert_body(Body::dynamic().position([x, 1.0 + row as Real, 0.0]))
                .unwrap();
            w.insert_collider(Collider::cuboid([0.5, 0.5, 0.5]), Some(b))
                .unwrap();
        }
    }
    let sweeper = w
        .insert_body(Body::kinematic_position_based().position([-8.0, 1.0, 3.0]))
        .unwrap();
    w.insert_collider(Collider::ball(0.5), Some(sweeper))
        .unwrap();
    let mut x = -8.0;
    let mut step = |w: &mut PhysicsWorld| {
        x += 0.01;
        w.set_kinematic_target(sweeper, [x, 1.0, 3.0], Quat::IDENTITY)
            .unwrap();
        w.step(1.0 / 60.0).unwrap();
    };
    for _ in 0..240 {
        step(&mut w);
    }
    assert!(w.dynamics().max_constraints() > 1, "the world grew");
    let n = allocations_in(|| {
        for _ in 0..120 {
            step(&mut w);
        }
    });
    assert_eq!(n, 0, "{n} allocations in 120 warm steps");
    // The counter really counts on this thread.
    let n = allocations_in(|| drop(std::hint::black_box(vec![1u8; 64])));
    assert_eq!(n, 1, "a deliberate allocation counted {n} times");
}
