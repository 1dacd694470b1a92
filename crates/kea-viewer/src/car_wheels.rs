//! Finding a scene's car: its car-wheel joints, and which way each spins to roll the chassis
//! forwards (what `App::drive` turns the arrow keys into).

use kea::{BodyHandle, CarWheel, JointHandle, Real, Vec3, World};

/// Every car-wheel joint with the sign of spin that rolls its chassis forwards: towards the
/// steerable wheels (or the chassis's +x if none steer), on ground below the wheel.
pub(crate) fn car_wheels(world: &World) -> Vec<(JointHandle<CarWheel>, Real)> {
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
