//! "You can add your own joint types": a joint written entirely as rows. This one keeps a point
//! of a body on a circle of radius R about a world axis (a bead on a ring, 2 DOF removed:
//! stay in the ring's plane, stay at distance R from its centre), and we watch a bob slide
//! round it under gravity, checking energy against the closed form.
//!
//! Run: `cargo run --release --example custom_joint`

use kea::{
    inertia, BodyDef, CustomConstraint, Jacobian, Real, Row, RowContext, RowWriter, Vec3, World,
};

/// A bead held on a vertical ring of radius `radius` centred at `centre`, in the plane z = 0.
#[derive(Debug, Clone)]
struct Ring {
    centre: Vec3,
    radius: Real,
}

impl CustomConstraint for Ring {
    fn name(&self) -> &'static str {
        "ring"
    }
    fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let p = ctx.bodies[0].position;
        // Row 1: stay in the plane z = 0. C = z, J = (ẑ, 0).
        out.push(Row::new(Jacobian::new(Vec3::Z, Vec3::ZERO), Jacobian::ZERO).with_error(p.z));
        // Row 2: stay at distance R. C = |p − c| − R, J = (u, 0) with u the unit radius.
        let d = p - self.centre;
        let u = d / d.length();
        out.push(
            Row::new(Jacobian::new(u, Vec3::ZERO), Jacobian::ZERO)
                .with_error(d.length() - self.radius),
        );
    }
}

fn main() -> Result<(), kea::KeaError> {
    let mut world = World::with_capacity(1, 1)?;
    let radius: Real = 1.0;
    let bead = world.create_body(&BodyDef {
        position: Vec3::new(radius, 0.0, 0.0),
        inertia: inertia::solid_sphere(0.1, 0.02)?,
        mass: 0.1,
        ..Default::default()
    })?;
    let ring = world.add_custom_constraint(
        bead,
        None,
        Ring {
            centre: Vec3::ZERO,
            radius,
        },
    )?;
    println!("custom_joint: a bead on a ring of radius {radius} m (a joint made only of rows)");
    println!(
        "{:>6} {:>8} {:>10} {:>12} {:>12}",
        "t [s]", "angle°", "speed", "closed form", "radius err"
    );
    let h: Real = 1.0 / 120.0;
    for n in 1..=240 {
        world.step(h)?;
        if n % 20 == 0 {
            let b = world.body(bead)?;
            let p = b.position();
            // Energy: released at rest at height 0, so v = √(−2 g y).
            let closed = (2.0 * 9.81 * (-p.y).max(0.0)).sqrt();
            println!(
                "{:>6.2} {:>8.1} {:>10.4} {:>12.4} {:>12.2e}",
                n as Real * h,
                p.y.atan2(p.x).to_degrees(),
                b.linear_velocity().length(),
                closed,
                p.length() - radius
            );
        }
    }
    let f = world.constraint_lambdas(ring)?;
    println!("last row forces: plane {:.3} N, radial {:.3} N", f[0], f[1]);
    Ok(())
}
