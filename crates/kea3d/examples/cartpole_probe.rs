use kea3d::prelude::*;
fn main() {
    let mut w = PhysicsWorld::new();
    let cart = w.insert_body(Body::dynamic().mass(1.0)).unwrap();
    w.insert_collider(Collider::cuboid([0.25, 0.1, 0.15]), Some(cart))
        .unwrap();
    let pole = w.insert_body(Body::dynamic().mass(0.1)).unwrap();
    w.insert_collider(
        Collider::capsule([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 0.03),
        Some(pole),
    )
    .unwrap();
    w.insert_joint(
        cart,
        None,
        Joint::prismatic([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
            .limits(-2.4, 2.4)
            .motor(0.0, 30.0),
    )
    .unwrap();
    w.insert_joint(
        pole,
        Some(cart),
        Joint::hinge([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
    )
    .unwrap();
    let n: usize = std::env::args()
        .nth(1)
        .map_or(200_000, |s| s.parse().unwrap());
    let t = std::time::Instant::now();
    for _ in 0..n {
        w.step(0.01).unwrap();
    }
    let e = t.elapsed();
    println!("{:.3} us/step", e.as_secs_f64() * 1e6 / n as f64);
    let s = w.step(0.01).unwrap();
    println!("rows {} {:?}", s.rows, w.dynamics().island_reports());
}
