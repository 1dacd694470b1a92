//! The orbit camera: it circles a target point (orbit), moves the target (pan) and comes
//! closer or goes away (zoom), and turns a mouse position into a ray for picking and shooting.

use kea::{Real, Vec3, World};

/// A camera on a sphere around a target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at.
    pub target: Vec3,
    /// Angle about the vertical, rad.
    pub yaw: Real,
    /// Angle above the horizon, rad.
    pub pitch: Real,
    /// Distance from the target, m.
    pub distance: Real,
    /// Vertical field of view, rad.
    pub fov_y: Real,
}

impl OrbitCamera {
    /// A camera that sees every body of `world`, from the same place `kea render` uses.
    #[must_use]
    pub fn framing(world: &World) -> Self {
        let c = kea_render::Camera::framing(world);
        let offset = c.eye - c.target;
        let distance = offset.length().max(1.0);
        Self {
            target: c.target,
            yaw: offset.x.atan2(offset.z),
            pitch: (offset.y / distance).clamp(-1.0, 1.0).asin(),
            distance,
            fov_y: c.fov_y,
        }
    }

    /// Where the eye is.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + Vec3::new(cp * sy, sp, cp * cy) * self.distance
    }

    /// The unit view direction.
    #[must_use]
    pub fn forward(&self) -> Vec3 {
        (self.target - self.eye()).normalize_or_zero()
    }

    fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let forward = self.forward();
        let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        (forward, right, right.cross(forward))
    }

    /// Turns by a mouse movement of `dx`, `dy` pixels.
    pub fn orbit(&mut self, dx: Real, dy: Real) {
        self.yaw -= dx * 0.008;
        self.pitch = (self.pitch + dy * 0.008).clamp(-1.5, 1.5);
    }

    /// Moves the target by a mouse movement, scaled so the scene follows the pointer.
    pub fn pan(&mut self, dx: Real, dy: Real, screen_height: Real) {
        let (_, right, up) = self.basis();
        let metres_per_pixel = 2.0 * self.distance * (self.fov_y * 0.5).tan() / screen_height;
        self.target += (-right * dx + up * dy) * metres_per_pixel;
    }

    /// Zooms by wheel `clicks` (positive: closer).
    pub fn zoom(&mut self, clicks: Real) {
        self.distance = (self.distance * (0.88 as Real).powf(clicks)).clamp(0.2, 5000.0);
    }

    /// The unit ray through pixel (`x`, `y`) of a `width` × `height` view.
    #[must_use]
    pub fn ray(&self, x: Real, y: Real, width: Real, height: Real) -> Vec3 {
        let (forward, right, up) = self.basis();
        let t = (self.fov_y * 0.5).tan();
        let sx = (2.0 * x / width - 1.0) * t * width / height;
        let sy = (1.0 - 2.0 * y / height) * t;
        (forward + right * sx + up * sy).normalize_or_zero()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> OrbitCamera {
        OrbitCamera {
            target: Vec3::new(1.0, 2.0, 3.0),
            yaw: 0.3,
            pitch: 0.4,
            distance: 10.0,
            fov_y: 0.8,
        }
    }

    #[test]
    fn the_centre_ray_is_the_view_direction_and_hits_the_target() {
        let c = camera();
        let ray = c.ray(400.0, 300.0, 800.0, 600.0);
        assert!((ray - c.forward()).length() < 1e-5);
        assert!((c.eye() + ray * c.distance - c.target).length() < 1e-4);
    }

    #[test]
    fn the_top_edge_ray_is_half_the_field_of_view_above_the_centre() {
        let c = camera();
        let top = c.ray(400.0, 0.0, 800.0, 600.0);
        let angle = top.dot(c.forward()).clamp(-1.0, 1.0).acos();
        assert!((angle - c.fov_y * 0.5).abs() < 1e-4, "{angle}");
        assert!(top.y > c.forward().y);
    }

    #[test]
    fn orbiting_keeps_the_distance_and_zoom_changes_it() {
        let mut c = camera();
        c.orbit(120.0, -40.0);
        assert!(((c.eye() - c.target).length() - 10.0).abs() < 1e-4);
        c.zoom(2.0);
        assert!((c.distance - 10.0 * 0.88 * 0.88).abs() < 1e-4);
    }
}
