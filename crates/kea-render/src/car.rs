//! Driving a scene's car: its car-wheel joints, which way each spins to roll the chassis
//! forwards, and a throttle and a steering turned into the wheels' motors. The Viewer's arrow
//! keys and `kea render --throttle --steer` both drive through it, so a picture shows what
//! the keys do.

use kea::{BodyHandle, CarWheel, JointHandle, KeaResult, Real, Vec3, World};

/// Wheel speed a full throttle asks for, rad/s, and the torque the motor may use, N·m.
pub const DRIVE: (Real, Real) = (25.0, 400.0);
/// Steering angle a full turn asks for, rad, and the steering motor's torque, N·m.
pub const STEER: (Real, Real) = (0.5, 800.0);

/// A scene's car wheels: each car-wheel joint with the sign of spin (±1) that rolls its
/// chassis forwards.
pub type Wheels = Vec<(JointHandle<CarWheel>, Real)>;

/// Every car-wheel joint with the sign of spin that rolls its chassis forwards: towards the
/// steerable wheels (or the chassis's +x if none steer), on ground below the wheel.
#[must_use]
pub fn car_wheels(world: &World) -> Wheels {
    let wheels: Vec<(JointHandle<CarWheel>, [Option<BodyHandle>; 2])> = world
        .enabled_joints()
        .map(|(h, bodies)| (JointHandle::from_raw(h), bodies))
        .filter(|(h, _)| h.get(world).is_ok())
        .collect();
    let position = |b: Option<BodyHandle>| {
        b.and_then(|b| world.body(b).ok())
            .map_or(Vec3::ZERO, |b| b.position())
    };
    let mut out = Vec::with_capacity(wheels.len());
    for &(h, [chassis, _]) in &wheels {
        let Ok(joint) = h.get(world) else {
            continue;
        };
        let Some(body) = chassis.and_then(|c| world.body(c).ok()) else {
            continue;
        };
        let steering = body.orientation() * joint.local_steering1;
        let axle = body.orientation() * joint.local_axle1;
        // The car's forward: from its wheels' middle towards its steerable wheels' middle.
        let same_car: Vec<_> = wheels.iter().filter(|(_, b)| b[0] == chassis).collect();
        let middle = |only_steerable: bool| {
            let picked: Vec<Vec3> = same_car
                .iter()
                .filter(|(w, _)| !only_steerable || w.get(world).is_ok_and(|j| !j.steering_locked))
                .map(|(_, b)| position(b[1]))
                .collect();
            (!picked.is_empty())
                .then(|| picked.iter().copied().sum::<Vec3>() / picked.len() as Real)
        };
        let forward = match (middle(true), middle(false)) {
            (Some(front), Some(all)) if (front - all).length() > 1e-3 => front - all,
            _ => body.orientation() * Vec3::X,
        };
        // Spin ω about the axle rolls the wheel at ω r (axle × up) on ground below it.
        let rolling = axle.cross(steering).dot(forward);
        out.push((h, if rolling >= 0.0 { 1.0 } else { -1.0 }));
    }
    out
}

/// Drives every wheel of `wheels` (from [`car_wheels`]): `throttle` and `steer` in −1..1, a
/// full throttle asking [`DRIVE`], a full turn [`STEER`] (to the left, seen from above). At
/// throttle 0 the motors brake (at a quarter of the torque). Wheels whose steering the scene
/// locked are not steered. The car's bodies are woken. Every wheel is driven even if one
/// fails; the first failure is returned.
pub fn drive(
    world: &mut World,
    wheels: &[(JointHandle<CarWheel>, Real)],
    throttle: Real,
    steer: Real,
) -> KeaResult<()> {
    let mut result = Ok(());
    for &(h, forwards) in wheels {
        let Ok(wheel) = h.wheel_mut(world) else {
            continue;
        };
        let driven = if throttle == 0.0 {
            wheel.drive_mut().set_motor(0.0, DRIVE.1 * 0.25) // engine braking
        } else {
            wheel
                .drive_mut()
                .set_motor(forwards * throttle * DRIVE.0, DRIVE.1)
        };
        if !wheel.steering_locked {
            let target = steer * STEER.0;
            let speed = 6.0 * (target - wheel.steering_angle());
            let _ = wheel.steering_limit_mut().set_motor(speed, STEER.1);
        }
        if let (Err(e), Ok(())) = (driven, &result) {
            result = Err(e);
        }
        if let Ok([Some(b1), b2]) = world.constraint_bodies(h) {
            let _ = world.wake_body(b1);
            if let Some(b2) = b2 {
                let _ = world.wake_body(b2);
            }
        }
    }
    result
}
