//! Driving a scene's car: the arrow keys become drive and steering motors on its car-wheel
//! joints.

use crate::app::App;
use kea::Real;

/// Wheel speed a full throttle asks for, rad/s, and the torque the motor may use, N·m.
pub const DRIVE: (Real, Real) = (25.0, 400.0);
/// Steering angle a full turn asks for, rad, and the steering motor's torque, N·m.
pub const STEER: (Real, Real) = (0.5, 800.0);

impl App {
    /// Drives every car wheel: `throttle` and `steer` in −1..1 (keys give −1, 0 or 1). Wheels
    /// whose steering the scene locked are not steered.
    pub fn drive(&mut self, throttle: Real, steer: Real) {
        let world = self.physics.dynamics_mut();
        for &(h, forwards) in &self.wheels {
            let Ok(wheel) = h.wheel_mut(world) else {
                continue;
            };
            let drive = if throttle == 0.0 {
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
            if let Err(e) = drive {
                self.message = Some(format!("cannot drive: {e}"));
            }
            if let Ok([Some(b1), b2]) = world.constraint_bodies(h) {
                let _ = world.wake_body(b1);
                if let Some(b2) = b2 {
                    let _ = world.wake_body(b2);
                }
            }
        }
    }
}
