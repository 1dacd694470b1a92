//! A GreaseMonkey-like car: a chassis on four car-wheel joints (suspension, steering on the
//! front wheels, drive on the rear ones), on flat ground with contacts from simple analytic
//! sphere-on-plane code. It drives straight, then steers into a turn (wheels are spheres, for
//! the simplest ground contact).
//!
//! Run: `cargo run --release --example car`

use kea::{
    inertia, BodyDef, BodyHandle, ConstraintHandle, Contact, ContactParams, FrictionModel, Real,
    SingleLimit, Vec3, World,
};

const WHEEL_R: Real = 0.35;

fn main() -> Result<(), kea::KeaError> {
    let mut world = World::with_capacity(8, 16)?;
    let chassis = world.create_body(&BodyDef {
        mass: 400.0,
        position: Vec3::new(0.0, 0.9, 0.0),
        inertia: inertia::solid_box(400.0, Vec3::new(1.0, 0.2, 2.0))?,
        ..Default::default()
    })?;
    // Wheels at the corners; the car faces +z, axles along x, steering along y.
    let corners = [(-0.9, 1.4), (0.9, 1.4), (-0.9, -1.4), (0.9, -1.4)];
    let mut wheels: Vec<(BodyHandle, kea::JointHandle<kea::CarWheel>)> = Vec::new();
    for (i, &(x, z)) in corners.iter().enumerate() {
        let wheel = world.create_body(&BodyDef {
            mass: 20.0,
            position: Vec3::new(x, WHEEL_R, z),
            inertia: inertia::solid_sphere(20.0, WHEEL_R)?,
            ..Default::default()
        })?;
        let j = world.create_joint(
            chassis,
            Some(wheel),
            kea::JointSpec::car_wheel(Vec3::Y, Vec3::X, 40_000.0, 4_000.0),
        )?;
        let cw = j.wheel_mut(&mut world)?;
        cw.suspension_limit_mut()
            .set_limits(SingleLimit::hard(-0.15, 0.0), SingleLimit::hard(0.15, 0.0))?;
        if i < 2 {
            cw.steering_locked = false;
            cw.steering_limit_mut()
                .set_limits(SingleLimit::hard(-0.5, 0.0), SingleLimit::hard(0.5, 0.0))?;
        }
        wheels.push((wheel, j));
    }
    let tyre = ContactParams {
        friction: [FrictionModel::Coulomb { mu: 1.0 }; 2],
        ..Default::default()
    };
    let mut contacts: Vec<Option<ConstraintHandle>> = vec![None; 4];
    println!("car: 400 kg chassis, four 20 kg wheels; rear drive 12 rad/s, then steer into a turn at t = 3 s");
    println!(
        "{:>6} {:>8} {:>24} {:>9} {:>22}",
        "t [s]", "speed", "position", "steer", "suspension (FL FR RL RR)"
    );
    let h: Real = 1.0 / 60.0;
    for n in 1..=480 {
        let t = n as Real * h;
        // Ground contacts, updated in place (persistent, as a collision layer would).
        for (k, &(wheel, _)) in wheels.iter().enumerate() {
            let p = world.body(wheel)?.position();
            let gap = p.y - WHEEL_R;
            match (gap < 0.02, contacts[k]) {
                (true, Some(c)) => {
                    let c = world.contact_mut(c)?;
                    c.set_position(Vec3::new(p.x, 0.0, p.z))?;
                    c.set_penetration(-gap)?;
                }
                (true, None) => {
                    let mut c = Contact::new(Vec3::new(p.x, 0.0, p.z), Vec3::Y, -gap)?;
                    c.set_params(tyre)?;
                    contacts[k] = Some(world.create_contact(wheel, None, c)?);
                }
                (false, Some(c)) => {
                    world.destroy_constraint(c)?;
                    contacts[k] = None;
                }
                (false, None) => {}
            }
        }
        // Controls: rear drive; front steering towards a target angle by its motor.
        let target = if t > 3.0 { 0.35 } else { 0.0 };
        for (k, &(_, j)) in wheels.iter().enumerate() {
            let cw = j.wheel_mut(&mut world)?;
            if k >= 2 {
                // The axle points along +x; rolling forward (+z) spins it about +x.
                cw.drive_mut().set_motor(12.0, 600.0)?;
            } else {
                let steer = cw.steering_angle();
                cw.steering_limit_mut()
                    .set_motor(4.0 * (target - steer), 2_000.0)?;
            }
        }
        world.step(h)?;
        if n % 30 == 0 {
            let b = world.body(chassis)?;
            let susp: Vec<String> = wheels
                .iter()
                .map(|&(_, j)| format!("{:+.3}", j.get(&world).unwrap().suspension_position()))
                .collect();
            println!(
                "{:>6.2} {:>7.2} ({:>6.2}, {:>5.2}, {:>6.2}) {:>9.3} {:>22}",
                t,
                b.linear_velocity().length(),
                b.position().x,
                b.position().y,
                b.position().z,
                wheels[0].1.get(&world)?.steering_angle(),
                susp.join(" ")
            );
        }
    }
    Ok(())
}
