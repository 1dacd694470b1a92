//! A 20-link chain of ball joints hanging from the world, released sideways: the links swing
//! and settle. Prints the largest joint gap and the chain's energy as it goes.
//!
//! Run: `cargo run --release --example chain`

use kea::{inertia, BallJoint, BodyDef, Real, Vec3, World};

fn main() -> Result<(), kea::KeaError> {
    const LINKS: usize = 20;
    const SPACING: Real = 0.25;
    let mut world = World::with_capacity(LINKS, LINKS)?;
    let mut joints = Vec::new();
    let mut links = Vec::new();
    let mut prev = None;
    for i in 0..LINKS {
        let p = Vec3::new((i as Real + 1.0) * SPACING, 0.0, 0.0);
        let link = world.create_body(&BodyDef {
            mass: 0.5,
            position: p,
            inertia: inertia::solid_capsule(0.5, 0.04, 0.5 * SPACING)?,
            linear_damping: 0.01,
            ..Default::default()
        })?;
        joints.push(world.create_joint(
            link,
            prev,
            kea::JointSpec::ball(p - Vec3::new(SPACING, 0.0, 0.0)),
        )?);
        links.push(link);
        prev = Some(link);
    }
    println!("chain: {LINKS} links of {SPACING} m on ball joints, released horizontal");
    println!(
        "{:>6} {:>14} {:>14} {:>12} {:>10}",
        "t [s]", "tip y [m]", "max gap [m]", "energy [J]", "path"
    );
    let h: Real = 1.0 / 60.0;
    for n in 1..=600 {
        let stats = world.step(h)?;
        if n % 60 == 0 {
            let gap = joints
                .iter()
                .map(|&j| {
                    let bj: &BallJoint = j.get(&world).unwrap();
                    let [b1, b2] = world.constraint_bodies(j).unwrap();
                    let a1 = world
                        .body(b1.unwrap())
                        .unwrap()
                        .point_to_world(bj.local_anchor1);
                    let a2 = b2.map_or(bj.local_anchor2, |b| {
                        world.body(b).unwrap().point_to_world(bj.local_anchor2)
                    });
                    (a1 - a2).length()
                })
                .fold(0.0, Real::max);
            let energy: Real = links
                .iter()
                .map(|&l| {
                    let b = world.body(l).unwrap();
                    b.kinetic_energy() + b.mass() * 9.81 * b.position().y
                })
                .sum();
            let tip = world.body(*links.last().unwrap())?.position().y;
            let path = if stats.solver.exact_islands > 0 {
                "exact"
            } else {
                "iterative"
            };
            println!(
                "{:>6.1} {:>14.4} {:>14.2e} {:>12.3} {:>10}",
                n as Real * h,
                tip,
                gap,
                energy,
                path
            );
        }
    }
    Ok(())
}
