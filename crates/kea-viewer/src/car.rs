//! Driving a scene's car: the arrow keys become drive and steering motors on its car-wheel
//! joints, through [`kea_render::car`] (which `kea render --throttle` drives through too).

use crate::app::App;
use kea::Real;

pub use kea_render::car::{DRIVE, STEER};

impl App {
    /// Drives every car wheel: `throttle` and `steer` in −1..1 (keys give −1, 0 or 1). Wheels
    /// whose steering the scene locked are not steered.
    pub fn drive(&mut self, throttle: Real, steer: Real) {
        let world = self.physics.dynamics_mut();
        if let Err(e) = kea_render::car::drive(world, &self.wheels, throttle, steer) {
            self.message = Some(format!("cannot drive: {e}"));
        }
    }
}
