//! A chain of ball joints and a hinge hanging from the world, stepped in reduced coordinates
//! (built again every step: a ball joint's chart is centred each step), once warm, steps
//! without touching the heap. One test in this file: the count is the process's.

use kea3d::prelude::*;

mod counting;

use counting::allocations_in;

#[global_allocator]
static ALLOCATOR: counting::CountingAllocator = counting::CountingAllocator;

#[test]
fn a_warm_chain_of_ball_joints_in_reduced_coordinates_steps_without_allocating() {
    // Three bobs on ball joints and one on a hinge, hanging from the world: built again every
    // step (a ball joint's chart is centred each step) from buffers kept warm.
    let mut world = PhysicsWorld::new();
    let mut parent = None;
    for k in 0..4 {
        let x = 0.5 * k as Real;
        let b = world
            .insert_body(Body::dynamic().position([x + 0.5, 0.0, 0.1 * k as Real]))
            .unwrap();
        if k == 3 {
            let hinge = Joint::hinge([x, 0.0, 0.0], [0.0, 0.0, 1.0]);
            world.insert_joint(b, parent, hinge).unwrap();
        } else {
            world
                .insert_joint(b, parent, Joint::ball([x, 0.0, 0.0]))
                .unwrap();
        }
        parent = Some(b);
    }
    for k in 0..240 {
        let stats = world.step(1.0 / 240.0).unwrap();
        assert_eq!(stats.reduced_trees, 1, "step {k}: the chain is one tree");
    }
    let n = allocations_in(|| {
        for _ in 0..120 {
            world.step(1.0 / 240.0).unwrap();
        }
    });
    assert_eq!(n, 0, "{n} allocations in warm reduced steps");
    // The counter really counts on this thread.
    let n = allocations_in(|| drop(std::hint::black_box(vec![1u8; 64])));
    assert_eq!(n, 1, "a deliberate allocation counted {n} times");
}
