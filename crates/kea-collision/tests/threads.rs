//! The `parallel` feature: the same bits for every thread count.
//!
//! Run with `cargo test -p kea-collision --features parallel --test threads`. The scene is
//! big enough that every parallel stage splits its work: 900 two-box stacks on the ground
//! (each colour of contacts holds about 900 manifolds, past the solver's split threshold),
//! 1,800 bodies (several narrow-phase chunks and body chunks), tilted so that they slide,
//! topple and collide.
#![cfg(feature = "parallel")]

use kea::{BodyDef, Quat, Real, Vec3, World, WorldDef};
use kea_collision::{ColliderDef, CollisionWorld, Shape};
mod common;

/// Steps the stacks for `steps` steps on a pool of `threads` threads; returns every body's
/// position and orientation bits, and how many bodies moved more than 20 cm.
fn run(threads: usize, steps: usize) -> (Vec<u64>, usize) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let side = 30;
        let count = side * side * 2;
        let mut world = World::new(WorldDef {
            max_bodies: count,
            max_constraints: count * 8,
            ..Default::default()
        })
        .unwrap();
        let mut collision = CollisionWorld::new();
        collision
            .add_collider(
                &world,
                ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap()),
            )
            .unwrap();
        let cube = Shape::cuboid(Vec3::splat(0.5)).unwrap();
        let mp = cube.mass_properties(1.0).unwrap();
        let mut bodies = Vec::new();
        for i in 0..side {
            for j in 0..side {
                for level in 0..2 {
                    // A different tilt and spin for every box: nothing stays symmetric.
                    let k = (i * side + j) as Real;
                    let tilt = Quat::from_rotation_z(0.05 * (k * 0.37).sin())
                        * Quat::from_rotation_x(0.05 * (k * 0.71).cos());
                    let b = world
                        .create_body(&BodyDef {
                            mass: mp.mass,
                            inertia: mp.inertia,
                            position: Vec3::new(
                                // Every other stack's top box hangs past its support's edge.
                                i as Real * 1.3 + 0.6 * (level * ((i + j) % 2)) as Real,
                                0.55 + 1.05 * level as Real,
                                j as Real * 1.3,
                            ),
                            orientation: tilt,
                            angular_velocity: Vec3::new(0.0, 0.5 * (k * 0.13).sin(), 0.0),
                            ..Default::default()
                        })
                        .unwrap();
                    collision
                        .add_collider(&world, ColliderDef::new(Some(b), cube.clone()))
                        .unwrap();
                    bodies.push((b, world.body(b).unwrap().position()));
                }
            }
        }
        for _ in 0..steps {
            common::step(&mut collision, &mut world, 1.0 / 60.0).unwrap();
        }
        let (mut bits, mut moved) = (Vec::new(), 0);
        for (b, start) in bodies {
            let body = world.body(b).unwrap();
            let (p, q) = (body.position(), body.orientation());
            for x in [p.x, p.y, p.z, q.x, q.y, q.z, q.w] {
                assert!(x.is_finite());
                bits.push(u64::from(x.to_bits()));
            }
            moved += usize::from((p - start).length() > 0.2);
        }
        (bits, moved)
    })
}

#[test]
fn one_two_and_four_threads_give_the_same_bits() {
    let (one, moved) = run(1, 150);
    // The run does something: overhanging top boxes topple onto their neighbours.
    assert!(moved >= 100, "only {moved} bodies moved more than 20 cm");
    for threads in [2, 4] {
        let (other, _) = run(threads, 150);
        let differ = one.iter().zip(&other).filter(|(a, b)| a != b).count();
        assert_eq!(
            differ, 0,
            "{threads} threads: {differ} numbers differ from 1 thread"
        );
    }
}
