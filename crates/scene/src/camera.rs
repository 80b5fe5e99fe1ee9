//! The camera: a pinhole (or thin lens, or orthographic window) looking from an eye point at a
//! target.

use glam::{Vec2, Vec3, Vec4};
use raystage_kernel::Ray;

use crate::error::SceneError;

/// A camera (`rtLookAt` with `rtPerspective`, `rtFrustum` or `rtOrtho`): a pinhole, or a thin
/// lens that focuses at one distance and blurs the rest (depth of field), with a shutter that
/// stays open over part of the frame's time (motion blur). Its [`Projection`] says how pixels
/// map to rays: by default a symmetric field of view whose horizontal extent follows from the
/// image's aspect ratio.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Camera {
    /// Eye position (the centre of the lens).
    pub eye: Vec3,
    /// The point looked at.
    pub target: Vec3,
    /// Which way is up (need not be perpendicular to the view direction).
    pub up: Vec3,
    /// Vertical field of view in degrees, in `(0, 180)` (used by [`Projection::Perspective`]).
    pub fov_y_degrees: f32,
    /// How the image maps to rays.
    pub projection: Projection,
    /// Radius of the lens; 0 for a pinhole (everything sharp).
    pub aperture_radius: f32,
    /// Distance from the eye at which the lens focuses; 0 to focus on the target.
    pub focus_distance: f32,
    /// The shutter's opening and closing, as times in `[0, 1]` of the frame (instances move from
    /// their start to their end transform over that range); equal for an instant (no blur).
    pub shutter: [f32; 2],
}

impl Default for Camera {
    /// Looking down −z at the origin from (0, 0, 5), 45° vertical field of view, a pinhole with
    /// an instantaneous shutter.
    fn default() -> Self {
        Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_degrees: 45.0,
            projection: Projection::Perspective,
            aperture_radius: 0.0,
            focus_distance: 0.0,
            shutter: [0.0, 0.0],
        }
    }
}

/// How a camera maps the image to rays. The window variants are OpenGL's `glFrustum` and
/// `glOrtho`: the window `[left, right] × [bottom, top]` (in the camera's frame: x right, y up)
/// fills the whole image, whatever its aspect ratio, as OpenGL's viewport does.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Projection {
    /// Rays from the eye, through a window centred on the view direction that spans the
    /// camera's `fov_y_degrees` vertically and the image's aspect ratio horizontally.
    Perspective,
    /// Rays from the eye through the window `[left, right] × [bottom, top]` on the plane at
    /// distance `near` along the view direction (an off-axis perspective when not centred).
    Frustum {
        /// The window's edges on the near plane.
        left: f32,
        /// See `left`.
        right: f32,
        /// See `left`.
        bottom: f32,
        /// See `left`.
        top: f32,
        /// The window plane's distance from the eye, positive.
        near: f32,
    },
    /// Parallel rays along the view direction, one through each point of the window
    /// `[left, right] × [bottom, top]`, starting on the plane at distance `near` along the view
    /// direction (which may lie behind the eye, as OpenGL's may). No depth of field.
    Orthographic {
        /// The window's edges.
        left: f32,
        /// See `left`.
        right: f32,
        /// See `left`.
        bottom: f32,
        /// See `left`.
        top: f32,
        /// Where the rays start, along the view direction from the eye.
        near: f32,
    },
}

impl Projection {
    /// Checks a window projection: finite numbers, a window of some width and height (either
    /// may be mirrored, as in OpenGL), and a positive `near` for a frustum.
    pub fn validate(&self) -> Result<(), SceneError> {
        let (window, near, frustum) = match *self {
            Projection::Perspective => return Ok(()),
            Projection::Frustum { left, right, bottom, top, near } => ([left, right, bottom, top], near, true),
            Projection::Orthographic { left, right, bottom, top, near } => ([left, right, bottom, top], near, false),
        };
        if let Some(index) = window.iter().chain([&near]).position(|v| !v.is_finite()) {
            return Err(SceneError::NotFinite { field: "camera.projection", index });
        }
        let [left, right, bottom, top] = window;
        // The window's extent is divided by: it must be a normal number, not just non-zero.
        if !((right - left).is_normal() && (top - bottom).is_normal()) {
            return Err(SceneError::OutOfRange {
                field: "camera.projection",
                message: format!("the window [{left}, {right}] × [{bottom}, {top}] has no width or no height"),
            });
        }
        if frustum && near <= 0.0 {
            return Err(SceneError::OutOfRange { field: "camera.projection", message: format!("near is {near}, not positive") });
        }
        // A frustum's rays go through the window scaled to distance 1: that must stay finite.
        if frustum && [right - left, top - bottom].iter().chain(&window).any(|v| !(v / near).is_finite()) {
            return Err(SceneError::OutOfRange {
                field: "camera.projection",
                message: format!("the window [{left}, {right}] × [{bottom}, {top}] is too wide for near {near}"),
            });
        }
        Ok(())
    }
}

impl Camera {
    /// A pinhole camera at `eye` looking at `target`, checked.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, fov_y_degrees: f32) -> Result<Camera, SceneError> {
        let camera = Camera { eye, target, up, fov_y_degrees, ..Camera::default() };
        camera.validate()?;
        Ok(camera)
    }

    /// Whether the lens blurs (depth of field): an aperture, and rays that meet at the eye.
    pub fn has_depth_of_field(&self) -> bool {
        self.aperture_radius > 0.0 && !matches!(self.projection, Projection::Orthographic { .. })
    }

    /// Whether the shutter stays open over an interval (motion blur is possible).
    pub fn has_open_shutter(&self) -> bool {
        self.shutter[1] > self.shutter[0]
    }

    /// Checks every number is finite, the eye is not at the target, `up` is not along the view
    /// direction, and the field of view is in `(0, 180)` degrees.
    pub fn validate(&self) -> Result<(), SceneError> {
        for (field, v) in [("camera.eye", self.eye), ("camera.target", self.target), ("camera.up", self.up)] {
            if !v.is_finite() {
                return Err(SceneError::NotFinite { field, index: 0 });
            }
        }
        let forward = self.target - self.eye;
        if forward.length_squared() == 0.0 {
            return Err(SceneError::OutOfRange { field: "camera.target", message: "equals the eye position".into() });
        }
        if forward.cross(self.up).length_squared() <= f32::MIN_POSITIVE {
            return Err(SceneError::OutOfRange { field: "camera.up", message: "is parallel to the view direction".into() });
        }
        if !(self.fov_y_degrees > 0.0 && self.fov_y_degrees < 180.0) {
            return Err(SceneError::OutOfRange {
                field: "camera.fov_y_degrees",
                message: format!("{} is not in (0, 180)", self.fov_y_degrees),
            });
        }
        self.projection.validate()?;
        for (field, v) in [("camera.aperture_radius", self.aperture_radius), ("camera.focus_distance", self.focus_distance)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SceneError::OutOfRange { field, message: format!("{v} is not a finite number >= 0") });
            }
        }
        let [open, close] = self.shutter;
        if !(0.0 <= open && open <= close && close <= 1.0) {
            return Err(SceneError::OutOfRange {
                field: "camera.shutter",
                message: format!("[{open}, {close}] is not an interval within [0, 1]"),
            });
        }
        Ok(())
    }

    /// The primary ray through image position `(px, py)` (in pixels, `(0, 0)` the top-left
    /// corner of the image, so pixel centres are at `x + 0.5`) of a `width × height` image,
    /// through the centre of the lens.
    pub fn ray(&self, px: f32, py: f32, width: u32, height: u32) -> Ray {
        self.rays(width, height).ray(px, py, [0.5, 0.5])
    }

    /// What generating primary rays for a `width × height` image takes, worked out once: the
    /// camera's frame and the image plane's scale.
    pub fn rays(&self, width: u32, height: u32) -> CameraRays {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let (w, h) = (width as f32, height as f32);
        let lens = self.has_depth_of_field().then(|| Lens {
            radius: self.aperture_radius,
            focus: if self.focus_distance > 0.0 { self.focus_distance } else { (self.target - self.eye).length() },
        });
        // The window `[left, right] × [bottom, top]` on the plane at distance `d` (1 for the
        // symmetric field of view) becomes a step per pixel along each axis and the pixel
        // position of the view axis, so that every projection makes its rays alike.
        let window = |left: f32, right_edge: f32, bottom: f32, top: f32, d: f32| {
            let step = Vec2::new((right_edge - left) / (d * w), (top - bottom) / (d * h));
            (step, Vec2::new(-left / (right_edge - left) * w, top / (top - bottom) * h))
        };
        let (step, centre, eye, parallel) = match self.projection {
            Projection::Perspective => {
                let tan = (0.5 * self.fov_y_degrees.to_radians()).tan();
                (Vec2::splat(2.0 * tan / h), Vec2::new(w, h) * 0.5, self.eye, false)
            }
            Projection::Frustum { left, right, bottom, top, near } => {
                let (step, centre) = window(left, right, bottom, top, near);
                (step, centre, self.eye, false)
            }
            Projection::Orthographic { left, right, bottom, top, near } => {
                let (step, centre) = window(left, right, bottom, top, 1.0);
                (step, centre, self.eye + forward * near, true)
            }
        };
        CameraRays { eye, forward, right: right * step.x, up: up * step.y, centre, lens, parallel }
    }
}

/// Primary rays of one camera and image size (see [`Camera::rays`]).
#[derive(Clone, Copy, Debug)]
pub struct CameraRays {
    eye: Vec3,
    forward: Vec3,
    /// The camera's right and up vectors, scaled to one pixel on the image plane at distance 1
    /// (or, for parallel rays, on the plane of their origins).
    right: Vec3,
    up: Vec3,
    /// Where the view axis meets the image, in pixels (the image centre unless off-axis).
    centre: Vec2,
    lens: Option<Lens>,
    /// Orthographic: every ray goes along `forward`, from its own point of the plane through
    /// `eye` (which then is on the near plane).
    parallel: bool,
}

/// A thin lens.
#[derive(Clone, Copy, Debug)]
struct Lens {
    radius: f32,
    focus: f32,
}

impl CameraRays {
    /// The primary ray through image position `(px, py)` (in pixels, `(0, 0)` the top-left
    /// corner, pixel centres at `x + 0.5`) and lens position `lens` (a point of `[0, 1)²`,
    /// mapped uniformly onto the lens disc). With a pinhole every lens position gives the same
    /// ray; with an aperture, all rays through one image position meet at the focus distance,
    /// so only objects there are sharp. The direction is a unit vector.
    pub fn ray(&self, px: f32, py: f32, lens: [f32; 2]) -> Ray {
        if self.parallel {
            let offset = self.right * (px - self.centre.x) + self.up * (self.centre.y - py);
            return Ray::new(self.eye + offset, self.forward);
        }
        let dir = self.pinhole_direction(px, py).normalize();
        let Some(Lens { radius, focus }) = self.lens else {
            return Ray::new(self.eye, dir);
        };
        // The point in focus, at the focus distance along the view axis.
        let focal_point = self.eye + dir * (focus / dir.dot(self.forward));
        let (r, phi) = (radius * lens[0].sqrt(), std::f32::consts::TAU * lens[1]);
        let (right, up) = (self.right.normalize(), self.up.normalize());
        let origin = self.eye + right * (r * phi.cos()) + up * (r * phi.sin());
        Ray::new(origin, (focal_point - origin).normalize())
    }

    /// How wide one pixel is at point `p` (the geometric mean of its width and height there,
    /// seen from the camera: the spacing of neighbouring pixels' rays), and the unit direction
    /// of the camera's rays to `p`: what texture filtering takes a lookup's footprint from.
    /// Lens and shutter are left out.
    pub fn pixel_footprint(&self, p: Vec3) -> (f32, Vec3) {
        let pixel = (self.right.length() * self.up.length()).sqrt();
        if self.parallel {
            return (pixel, self.forward);
        }
        let to = p - self.eye;
        let distance = to.length();
        (pixel * distance, if distance > 0.0 { to / distance } else { self.forward })
    }

    /// The rays through pixel centres `(x + 0.5, y + 0.5)` of up to eight `pixels`, into
    /// `out`: exactly [`CameraRays::ray`] of each (lens centre), computed four at a time with
    /// the same correctly rounded operations (the square roots and divisions of the
    /// normalisations dominate a camera ray).
    ///
    /// # Panics
    /// If `out` is shorter than `pixels`, or either holds more than eight.
    pub fn centre_rays(&self, pixels: &[(u32, u32)], out: &mut [Ray]) {
        const N: usize = 8;
        assert!(pixels.len() <= N && out.len() >= pixels.len(), "up to eight pixels, a ray each");
        if self.lens.is_some() || self.parallel {
            for (&(x, y), ray) in pixels.iter().zip(out.iter_mut()) {
                *ray = self.ray(x as f32 + 0.5, y as f32 + 0.5, [0.5, 0.5]);
            }
            return;
        }
        // `pinhole_direction`: each pixel's offsets from the image centre (zero in unused
        // lanes, whose direction is then `forward`), then each coordinate of the directions.
        let (mut across, mut down) = ([0.0f32; N], [0.0f32; N]);
        for (k, &(x, y)) in pixels.iter().enumerate() {
            across[k] = (x as f32 + 0.5) - self.centre.x;
            down[k] = self.centre.y - (y as f32 + 0.5);
        }
        let (mut x, mut y, mut z) = ([0.0f32; N], [0.0f32; N], [0.0f32; N]);
        for lane in (0..N).step_by(4) {
            let (a, d) = (Vec4::from_slice(&across[lane..]), Vec4::from_slice(&down[lane..]));
            let coordinate = |f: f32, r: f32, u: f32| (Vec4::splat(f) + Vec4::splat(r) * a) + Vec4::splat(u) * d;
            let (cx, cy, cz) = (coordinate(self.forward.x, self.right.x, self.up.x), coordinate(self.forward.y, self.right.y, self.up.y), coordinate(self.forward.z, self.right.z, self.up.z));
            // `Vec3::normalize`: the reciprocal of the length, then the scaled coordinates.
            let scale = ((cx * cx + cy * cy) + cz * cz).sqrt().recip();
            (cx * scale).write_to_slice(&mut x[lane..]);
            (cy * scale).write_to_slice(&mut y[lane..]);
            (cz * scale).write_to_slice(&mut z[lane..]);
        }
        for (k, ray) in out.iter_mut().take(pixels.len()).enumerate() {
            *ray = Ray::new(self.eye, Vec3::new(x[k], y[k], z[k]));
        }
    }

    /// The unnormalised direction of the pinhole ray through image position `(px, py)`.
    #[inline]
    fn pinhole_direction(&self, px: f32, py: f32) -> Vec3 {
        self.forward + self.right * (px - self.centre.x) + self.up * (self.centre.y - py)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_rays_are_the_rays_through_pixel_centres_bit_for_bit() {
        let camera = Camera::look_at(Vec3::new(0.3, 1.7, 5.0), Vec3::new(-0.2, 0.4, 0.0), Vec3::Y, 50.0).unwrap();
        let rays = camera.rays(97, 61);
        let pixels: Vec<(u32, u32)> = (0..61).flat_map(|y| (0..97).map(move |x| (x, y))).collect();
        for packet in pixels.chunks(5).chain(pixels.chunks(8)) {
            let mut out = [Ray::new(Vec3::ZERO, Vec3::Z); 8];
            rays.centre_rays(packet, &mut out);
            for (&(x, y), ray) in packet.iter().zip(&out) {
                let one = rays.ray(x as f32 + 0.5, y as f32 + 0.5, [0.5, 0.5]);
                assert_eq!((ray.origin, ray.dir), (one.origin, one.dir), "pixel ({x}, {y})");
            }
        }
    }

    /// A frustum centred on the view axis with the image's aspect ratio is the symmetric
    /// perspective; an off-axis one shifts the view axis in the image.
    #[test]
    fn frustum_windows_map_onto_the_image() {
        let eye = Vec3::new(0.0, 0.0, 5.0);
        let perspective = Camera::look_at(eye, Vec3::ZERO, Vec3::Y, 90.0).unwrap();
        let frustum = Camera { projection: Projection::Frustum { left: -0.4, right: 0.4, bottom: -0.2, top: 0.2, near: 0.2 }, ..perspective };
        frustum.validate().unwrap();
        let (a, b) = (perspective.rays(64, 32), frustum.rays(64, 32));
        for (x, y) in [(0.0, 0.0), (64.0, 32.0), (17.5, 3.25)] {
            let (p, f) = (a.ray(x, y, [0.5; 2]), b.ray(x, y, [0.5; 2]));
            assert!((p.dir - f.dir).length() < 1e-6 && p.origin == f.origin, "({x}, {y}): {p:?} {f:?}");
        }
        // The window [0, 1] × [0, 1] at distance 1: the view axis is the bottom-left corner.
        let corner = Camera { projection: Projection::Frustum { left: 0.0, right: 1.0, bottom: 0.0, top: 1.0, near: 1.0 }, ..perspective };
        let ray = corner.rays(10, 10).ray(0.0, 10.0, [0.5; 2]);
        assert!((ray.dir - Vec3::NEG_Z).length() < 1e-6, "{ray:?}");
        let ray = corner.rays(10, 10).ray(10.0, 0.0, [0.5; 2]);
        assert!((ray.dir - Vec3::new(1.0, 1.0, -1.0).normalize()).length() < 1e-6, "{ray:?}");
    }

    /// Orthographic rays are parallel, start on the near plane (behind the eye if it is
    /// negative), and cover the window, with packets the same as single rays.
    #[test]
    fn orthographic_rays_are_parallel_and_cover_the_window() {
        let camera = Camera {
            projection: Projection::Orthographic { left: -2.0, right: 2.0, bottom: -1.0, top: 1.0, near: -1.0 },
            aperture_radius: 0.5,
            ..Camera::default()
        };
        camera.validate().unwrap();
        assert!(!camera.has_depth_of_field(), "parallel rays have no lens");
        let rays = camera.rays(40, 20);
        let ray = rays.ray(0.0, 0.0, [0.5; 2]);
        assert_eq!((ray.origin, ray.dir), (Vec3::new(-2.0, 1.0, 6.0), Vec3::NEG_Z));
        let ray = rays.ray(40.0, 20.0, [0.5; 2]);
        assert_eq!((ray.origin, ray.dir), (Vec3::new(2.0, -1.0, 6.0), Vec3::NEG_Z));
        let mut out = [Ray::new(Vec3::ZERO, Vec3::Z); 8];
        let pixels: Vec<(u32, u32)> = (0..8).map(|i| (i * 5, i)).collect();
        rays.centre_rays(&pixels, &mut out);
        for (&(x, y), ray) in pixels.iter().zip(&out) {
            let one = rays.ray(x as f32 + 0.5, y as f32 + 0.5, [0.5, 0.5]);
            assert_eq!((ray.origin, ray.dir), (one.origin, one.dir));
        }
    }

    #[test]
    fn window_projections_are_checked() {
        let bad = [
            Projection::Frustum { left: 1.0, right: 1.0, bottom: 0.0, top: 1.0, near: 1.0 },
            Projection::Frustum { left: 0.0, right: 1.0, bottom: 0.0, top: 1.0, near: 0.0 },
            Projection::Orthographic { left: 0.0, right: 1.0, bottom: 2.0, top: 2.0, near: 0.0 },
            Projection::Orthographic { left: f32::NAN, right: 1.0, bottom: 0.0, top: 1.0, near: 0.0 },
            Projection::Frustum { left: -1e30, right: 1e30, bottom: 0.0, top: 1.0, near: 1e-20 },
        ];
        for projection in bad {
            assert!(Camera { projection, ..Camera::default() }.validate().is_err(), "{projection:?}");
        }
        let mirrored = Projection::Orthographic { left: 1.0, right: -1.0, bottom: 0.0, top: 1.0, near: -5.0 };
        assert!(Camera { projection: mirrored, ..Camera::default() }.validate().is_ok());
    }
}
