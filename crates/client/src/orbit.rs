//! Orbit, pan and zoom around the camera's target: how mouse motion becomes a camera.
//!
//! The eye moves on a sphere around the target, with the camera's `up` as the pole: a drag to
//! the right turns the scene to the right (the eye goes left around it), a drag up tilts it
//! towards the viewer. The elevation stops short of the poles, where `up` and the view direction
//! would be parallel and the camera undefined. Panning moves eye and target together so that
//! the point at the target's depth follows the mouse; zooming scales the eye's distance.

use glam::{Quat, Vec3};

use crate::protocol::{CameraJson, CameraPatch};

/// Radians of orbit per point of mouse motion: half a turn for about 314 points.
pub const ORBIT_RADIANS_PER_POINT: f32 = 0.01;
/// Distance factor per point of scroll: 100 points of scroll bring the eye 1/e² ≈ 14 % closer.
pub const ZOOM_PER_POINT: f32 = 0.002;
/// The closest the view direction comes to `up` (radians).
const POLE_MARGIN: f32 = 0.01;

/// A camera that orbits its target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Eye position.
    pub eye: Vec3,
    /// The point orbited and looked at.
    pub target: Vec3,
    /// Which way is up (the pole of the orbit).
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f32,
}

impl Orbit {
    /// The orbit of a camera as the server describes it.
    pub fn from_camera(camera: &CameraJson) -> Orbit {
        Orbit { eye: camera.eye.into(), target: camera.target.into(), up: camera.up.into(), fov_y_degrees: camera.fov_y_degrees }
    }

    /// The change to send for this camera.
    pub fn patch(&self) -> CameraPatch {
        CameraPatch { eye: self.eye.to_array(), target: self.target.to_array() }
    }

    fn up(&self) -> Vec3 {
        self.up.try_normalize().unwrap_or(Vec3::Y)
    }

    /// Orbits by a mouse motion of (`dx`, `dy`) points (y down, as on screen).
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        let up = self.up();
        let offset = self.eye - self.target;
        let distance = offset.length();
        if distance <= 0.0 || !distance.is_finite() {
            return;
        }
        // Yaw about the pole: dragging right moves the eye left around the target.
        let yawed = Quat::from_axis_angle(up, -dx * ORBIT_RADIANS_PER_POINT) * offset;
        // Pitch about the camera's right axis, clamped short of the poles: dragging down moves
        // the eye up (the scene tilts the way the mouse goes).
        let polar = yawed.normalize().dot(up).clamp(-1.0, 1.0).acos();
        let new_polar = (polar - dy * ORBIT_RADIANS_PER_POINT).clamp(POLE_MARGIN, std::f32::consts::PI - POLE_MARGIN);
        let right = up.cross(yawed).try_normalize();
        let offset = match right {
            Some(right) => Quat::from_axis_angle(right, new_polar - polar) * yawed,
            None => yawed,
        };
        self.eye = self.target + offset.normalize() * distance;
    }

    /// Pans by a mouse motion of (`dx`, `dy`) points in a view `height` points high.
    pub fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        let forward = self.target - self.eye;
        let distance = forward.length();
        let Some(right) = forward.cross(self.up()).try_normalize() else { return };
        let screen_up = right.cross(forward).normalize();
        // World units per point at the target's depth.
        let scale = 2.0 * distance * (self.fov_y_degrees.to_radians() * 0.5).tan() / height.max(1.0);
        let delta = (-dx * right + dy * screen_up) * scale;
        self.eye += delta;
        self.target += delta;
    }

    /// Zooms by `scroll` points (positive: closer).
    pub fn zoom(&mut self, scroll: f32) {
        let offset = self.eye - self.target;
        let distance = (offset.length() * (-scroll * ZOOM_PER_POINT).exp()).max(1e-4);
        if let Some(direction) = offset.try_normalize() {
            self.eye = self.target + direction * distance;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Orbit {
        Orbit { eye: Vec3::new(0.0, 0.0, 5.0), target: Vec3::ZERO, up: Vec3::Y, fov_y_degrees: 90.0 }
    }

    #[test]
    fn a_drag_to_the_right_takes_the_eye_left_around_the_target() {
        let mut c = camera();
        c.orbit(100.0, 0.0);
        // One radian about +y, clockwise seen from above.
        assert!(c.eye.abs_diff_eq(Vec3::new(-5.0 * 1f32.sin(), 0.0, 5.0 * 1f32.cos()), 1e-4), "{c:?}");
        assert_eq!(c.target, Vec3::ZERO);
    }

    #[test]
    fn a_drag_down_raises_the_eye_and_stops_short_of_the_pole() {
        let mut c = camera();
        c.orbit(0.0, 50.0);
        assert!(c.eye.abs_diff_eq(Vec3::new(0.0, 5.0 * 0.5f32.sin(), 5.0 * 0.5f32.cos()), 1e-4), "{c:?}");
        c.orbit(0.0, 1000.0);
        assert!((c.eye.length() - 5.0).abs() < 1e-3 && c.eye.y < 5.0 && c.eye.z > 0.0, "{c:?}");
    }

    #[test]
    fn panning_moves_eye_and_target_together_and_zoom_keeps_the_target() {
        let mut c = camera();
        // 90° at distance 5: the view is 10 units high; 100 of 200 points is 5 units.
        c.pan(100.0, 0.0, 200.0);
        assert!(c.eye.abs_diff_eq(Vec3::new(-5.0, 0.0, 5.0), 1e-4) && c.target.abs_diff_eq(Vec3::new(-5.0, 0.0, 0.0), 1e-4), "{c:?}");
        let mut z = camera();
        z.zoom(500.0);
        assert!(z.eye.abs_diff_eq(Vec3::new(0.0, 0.0, 5.0 * (-1f32).exp()), 1e-4) && z.target == Vec3::ZERO, "{z:?}");
    }
}
