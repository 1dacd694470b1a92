//! Shapes: mass properties against closed forms, and degenerate input refused by name.

use kea::{BodyDef, Quat, Real, Vec3, World};
use kea_collision::{ColliderDef, CollisionError, CollisionWorld, MassProperties, Shape};

const PI: Real = std::f64::consts::PI as Real;

fn close(a: Real, b: Real, what: &str) {
    assert!(
        (a - b).abs() <= 1e-4 * b.abs().max(1e-6),
        "{what}: {a} vs {b}"
    );
}

fn diag(m: &MassProperties) -> Vec3 {
    Vec3::new(m.inertia.x_axis.x, m.inertia.y_axis.y, m.inertia.z_axis.z)
}

#[test]
fn mass_properties_match_the_closed_forms() {
    let rho = 2.0;
    // Sphere: m = ρ·4/3·πr³, I = 2/5·m·r².
    let r = 0.3;
    let s = Shape::sphere(r).unwrap().mass_properties(rho).unwrap();
    let m = rho * 4.0 / 3.0 * PI * r * r * r;
    close(s.mass, m, "sphere mass");
    close(diag(&s).x, 0.4 * m * r * r, "sphere I");
    // Box: m = ρ·8abc, I_x = m/3·(b² + c²) with half extents.
    let h = Vec3::new(0.5, 0.2, 0.1);
    let b = Shape::cuboid(h).unwrap().mass_properties(rho).unwrap();
    let m = rho * 8.0 * h.x * h.y * h.z;
    close(b.mass, m, "box mass");
    close(diag(&b).x, m / 3.0 * (h.y * h.y + h.z * h.z), "box Ix");
    close(diag(&b).y, m / 3.0 * (h.x * h.x + h.z * h.z), "box Iy");
    // Cylinder (axis y, height 2hh): I_y = m r²/2, I_x = m(3r² + (2hh)²)/12.
    let (hh, r) = (0.4, 0.25);
    let c = Shape::cylinder(hh, r)
        .unwrap()
        .mass_properties(rho)
        .unwrap();
    let m = rho * PI * r * r * 2.0 * hh;
    close(c.mass, m, "cylinder mass");
    close(diag(&c).y, 0.5 * m * r * r, "cylinder Iy");
    close(
        diag(&c).x,
        m * (3.0 * r * r + 4.0 * hh * hh) / 12.0,
        "cylinder Ix",
    );
    // Cone (height H = 2hh): m = ρπr²H/3, centre of mass H/4 above the base, I_y = 3/10·m r²,
    // I_x about the centre of mass = m(3r²/20 + 3H²/80).
    let k = Shape::cone(hh, r).unwrap().mass_properties(rho).unwrap();
    let big_h = 2.0 * hh;
    let m = rho * PI * r * r * big_h / 3.0;
    close(k.mass, m, "cone mass");
    close(k.center_of_mass.y, -hh + big_h / 4.0, "cone centre of mass");
    close(diag(&k).y, 0.3 * m * r * r, "cone Iy");
    close(
        diag(&k).x,
        m * (3.0 * r * r / 20.0 + 3.0 * big_h * big_h / 80.0),
        "cone Ix",
    );
    // Capsule: a cylinder plus a sphere; I_y = m_c r²/2 + 2/5 m_s r².
    let p = Shape::capsule(hh, r).unwrap().mass_properties(rho).unwrap();
    let (mc, ms) = (
        rho * PI * r * r * 2.0 * hh,
        rho * 4.0 / 3.0 * PI * r * r * r,
    );
    close(p.mass, mc + ms, "capsule mass");
    close(
        diag(&p).y,
        0.5 * mc * r * r + 0.4 * ms * r * r,
        "capsule Iy",
    );
    // A convex hull of a box's corners weighs what the box does.
    let corners: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { -h.x } else { h.x },
                if i & 2 == 0 { -h.y } else { h.y },
                if i & 4 == 0 { -h.z } else { h.z },
            )
        })
        .collect();
    let hull = Shape::convex_hull(&corners)
        .unwrap()
        .mass_properties(rho)
        .unwrap();
    close(hull.mass, b.mass, "hull mass");
    close(diag(&hull).x, diag(&b).x, "hull Ix");
    // Two unit spheres 2 m apart: centre between them, parallel axis adds m·d².
    let one = Shape::sphere(0.5).unwrap();
    let two = MassProperties::of_shapes(
        &[
            (Vec3::new(-1.0, 0.0, 0.0), Quat::IDENTITY, one.clone()),
            (Vec3::new(1.0, 0.0, 0.0), Quat::IDENTITY, one.clone()),
        ],
        rho,
    )
    .unwrap();
    let single = one.mass_properties(rho).unwrap();
    close(two.mass, 2.0 * single.mass, "pair mass");
    assert!(two.center_of_mass.length() < 1e-5);
    close(
        diag(&two).y,
        2.0 * (diag(&single).y + single.mass),
        "pair Iy (parallel axis)",
    );
}

fn degenerate(e: CollisionError, words: &str) {
    let text = e.to_string();
    assert!(text.contains(words), "expected {words:?} in {text:?}");
}

#[test]
fn degenerate_shapes_are_refused_by_name() {
    degenerate(Shape::sphere(0.0).unwrap_err(), "radius");
    degenerate(Shape::sphere(Real::NAN).unwrap_err(), "radius");
    degenerate(
        Shape::cuboid(Vec3::new(1.0, -1.0, 1.0)).unwrap_err(),
        "half_extents.y",
    );
    degenerate(Shape::plane(Vec3::ZERO).unwrap_err(), "normal");
    degenerate(Shape::capsule(1.0, 0.0).unwrap_err(), "radius");
    let flat = [Vec3::ZERO, Vec3::X, Vec3::Z, Vec3::new(1.0, 0.0, 1.0)];
    degenerate(Shape::convex_hull(&flat).unwrap_err(), "flat");
    degenerate(Shape::convex_hull(&flat[..3]).unwrap_err(), "at least 4");
    let nan = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.0, 0.0, Real::NAN)];
    degenerate(Shape::convex_hull(&nan).unwrap_err(), "points");
    degenerate(
        Shape::trimesh(vec![], vec![]).unwrap_err(),
        "needs vertices",
    );
    degenerate(
        Shape::trimesh(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 5]]).unwrap_err(),
        "vertex 5",
    );
    degenerate(
        Shape::trimesh(vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0], vec![[0, 1, 2]]).unwrap_err(),
        "zero area",
    );
    // Three triangles on one edge: not a manifold.
    let fan = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, -Vec3::Y];
    degenerate(
        Shape::trimesh(fan, vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]).unwrap_err(),
        "triangle mesh",
    );
    degenerate(
        Shape::heightfield(&[vec![0.0, 1.0]], Vec3::ONE).unwrap_err(),
        "2×2",
    );
    degenerate(
        Shape::plane(Vec3::Y)
            .unwrap()
            .mass_properties(1.0)
            .unwrap_err(),
        "no volume",
    );
    degenerate(
        Shape::sphere(1.0)
            .unwrap()
            .mass_properties(-1.0)
            .unwrap_err(),
        "density",
    );
    let mesh = Shape::trimesh(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]).unwrap();
    degenerate(
        Shape::compound(&[(Vec3::ZERO, Quat::IDENTITY, mesh)]).unwrap_err(),
        "convex",
    );
}

#[test]
fn bad_colliders_are_refused_and_change_nothing() {
    let mut world = World::with_capacity(4, 16).unwrap();
    let mut collision = CollisionWorld::new();
    let b = world.create_body(&BodyDef::default()).unwrap();
    let mut def = ColliderDef::new(Some(b), Shape::sphere(0.5).unwrap());
    def.material = 7;
    degenerate(
        collision.add_collider(&world, def.clone()).unwrap_err(),
        "material id 7",
    );
    def.material = 0;
    def.rotation = Quat::from_xyzw(0.0, 0.0, 0.0, 2.0);
    degenerate(
        collision.add_collider(&world, def.clone()).unwrap_err(),
        "rotation",
    );
    def.rotation = Quat::IDENTITY;
    world.destroy_body(b).unwrap();
    degenerate(collision.add_collider(&world, def).unwrap_err(), "stale");
    assert_eq!(collision.collider_count(), 0);
}
