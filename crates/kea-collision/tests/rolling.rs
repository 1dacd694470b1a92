//! VALIDATION #33: a sphere and a solid cylinder released on slopes of 10°, 20° and 30° with
//! μ = 0.6 roll without slipping, on every path a user can force.
//!
//! Rolling without slipping down a slope of angle θ: a = g·sinθ / (1 + I/(m r²)), so
//! a = 5/7·g·sinθ for a solid sphere (I = 2/5·m r²) and 2/3·g·sinθ for a solid cylinder
//! (I = 1/2·m r²). It needs μ ≥ tanθ·(I/(m r²))/(1 + I/(m r²)) — at 30°, 0.165 for the sphere
//! and 0.192 for the cylinder — so μ = 0.6 holds everywhere. The contact point does not slip
//! and the body does not sink into the slope.

use kea::{BodyDef, Quat, Real, Routing, SolverMode, Vec3, World, WorldDef};
use kea_collision::{ColliderDef, CollisionWorld, Shape, Surface};
mod common;

const G: Real = 9.81;
const DT: Real = 1.0 / 60.0;
const RADIUS: Real = 0.5;
const PATHS: [SolverMode; 4] = [
    SolverMode::Hybrid,
    SolverMode::Iterative,
    SolverMode::Exact,
    SolverMode::Split,
];

#[derive(Debug, Clone, Copy)]
enum Roller {
    Sphere,
    Cylinder,
}

/// What one roll measured.
struct Roll {
    /// Acceleration down the slope between 0.25 s and 1.25 s, m/s².
    accel: Real,
    /// Deepest the body sank into the slope, m.
    sink: Real,
    /// Fastest the contact point slid, m/s (after the first tenth of a second).
    slip: Real,
}

fn roll(mode: SolverMode, roller: Roller, degrees: Real) -> Roll {
    let theta = degrees.to_radians();
    let mut w = World::new(WorldDef {
        max_bodies: 2,
        max_constraints: 16,
        settings: kea::WorldSettings {
            gravity: Vec3::new(0.0, -G, 0.0),
            ..Default::default()
        },
        ..Default::default()
    })
    .unwrap();
    w.update_settings(|s| {
        s.routing = Routing {
            mode,
            ..Default::default()
        }
    })
    .unwrap();
    let mut c = CollisionWorld::new();
    c.materials
        .set_surface(
            0,
            Surface {
                friction: 0.6,
                ..Default::default()
            },
        )
        .unwrap();
    // The slope's normal leans towards −x: down the slope is −x and −y.
    let tilt = Quat::from_rotation_z(theta);
    let n = tilt * Vec3::Y;
    let down = tilt * Vec3::NEG_X;
    c.add_collider(&w, ColliderDef::new(None, Shape::plane(n).unwrap()))
        .unwrap();
    // A cylinder's axis is its y: laid along z, square to the direction it rolls.
    let (shape, orientation) = match roller {
        Roller::Sphere => (Shape::sphere(RADIUS).unwrap(), Quat::IDENTITY),
        Roller::Cylinder => (
            Shape::cylinder(0.3, RADIUS).unwrap(),
            Quat::from_rotation_x(std::f64::consts::FRAC_PI_2 as Real),
        ),
    };
    let mp = shape.mass_properties(1000.0).unwrap();
    let b = w
        .create_body(&BodyDef {
            mass: mp.mass,
            inertia: mp.inertia,
            position: n * RADIUS,
            orientation,
            ..Default::default()
        })
        .unwrap();
    c.add_collider(&w, ColliderDef::new(Some(b), shape))
        .unwrap();

    let (mut sink, mut slip): (Real, Real) = (0.0, 0.0);
    let (mut v1, mut v2) = (0.0, 0.0);
    for step in 1..=90 {
        common::step(&mut c, &mut w, DT).unwrap();
        let body = w.body(b).unwrap();
        let x = body.position();
        sink = sink.max(RADIUS - n.dot(x));
        let contact_point_velocity =
            body.linear_velocity() + body.angular_velocity().cross(-n * RADIUS);
        if step > 6 {
            slip = slip.max(contact_point_velocity.length());
        }
        let along = body.linear_velocity().dot(down);
        if step == 15 {
            v1 = along;
        }
        if step == 75 {
            v2 = along;
        }
    }
    Roll {
        accel: (v2 - v1) / (60.0 * DT),
        sink,
        slip,
    }
}

#[test]
fn a_sphere_and_a_cylinder_roll_without_slipping_on_every_path() {
    let mut failures = Vec::new();
    for mode in PATHS {
        for roller in [Roller::Sphere, Roller::Cylinder] {
            for degrees in [10.0, 20.0, 30.0] {
                let theta: Real = (degrees as Real).to_radians();
                let factor = match roller {
                    Roller::Sphere => 5.0 / 7.0,
                    Roller::Cylinder => 2.0 / 3.0,
                };
                let want = factor * G * theta.sin();
                let r = roll(mode, roller, degrees);
                let error = (r.accel - want).abs() / want;
                eprintln!(
                    "{mode:?} {roller:?} {degrees}°: a = {:.4} (want {want:.4}, {:.2}%), sink {:.3} mm, slip {:.2} mm/s",
                    r.accel,
                    error * 100.0,
                    r.sink * 1e3,
                    r.slip * 1e3
                );
                if error > 0.01 || r.sink > 5e-4 || r.slip > 0.01 {
                    failures.push(format!("{mode:?} {roller:?} {degrees}°"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "failed: {failures:?}");
}
