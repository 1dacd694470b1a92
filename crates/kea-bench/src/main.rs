use rapier3d::prelude::*;
fn main() {
    let n: usize = std::env::args().nth(1).map_or(40, |s| s.parse().unwrap());
    let steps: usize = std::env::args().nth(2).map_or(3600, |s| s.parse().unwrap());
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let mut ij = ImpulseJointSet::new();
    let mut mj = MultibodyJointSet::new();
    let mut sb = SoftBodySet::new();
    let mut islands = IslandManager::new();
    let mut bp = BroadPhaseBvh::new();
    let mut np = NarrowPhase::new();
    let mut ccd = CCDSolver::new();
    let mut pipe = PhysicsPipeline::new();
    let params = IntegrationParameters::default();
    println!("{:?}", params);
    let g = bodies.insert(RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)));
    colliders.insert_with_parent(ColliderBuilder::cuboid(50.0, 0.5, 50.0), g, &mut bodies);
    let mut hs = Vec::new();
    for i in 0..n {
        let h = bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, 0.5 + i as f32, 0.0))
                .can_sleep(false),
        );
        colliders.insert_with_parent(ColliderBuilder::cuboid(0.5, 0.5, 0.5), h, &mut bodies);
        hs.push(h);
    }
    let top0 = bodies[hs[n - 1]].translation();
    let t = std::time::Instant::now();
    for s in 0..steps {
        pipe.step(
            Vector::new(0.0, -9.81, 0.0),
            &params,
            &mut islands,
            &mut bp,
            &mut np,
            &mut bodies,
            &mut colliders,
            &mut ij,
            &mut mj,
            &mut sb,
            &mut ccd,
            &(),
            &(),
        );
        if s % 300 == 299 {
            let top = bodies[hs[n - 1]].translation();
            println!(
                "{s}: dy {:.4} dx {:.5} dz {:.5}",
                top.y - top0.y,
                top.x - top0.x,
                top.z - top0.z
            );
        }
    }
    println!(
        "{:.3} ms/step",
        t.elapsed().as_secs_f64() * 1000.0 / steps as f64
    );
}
