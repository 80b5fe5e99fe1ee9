//! One frame, end to end: primary rays through every pixel, eye-light shading, statistics.

use std::time::Instant;

use raystage_kernel::{Bvh8, IndexedMesh, TriangleSource};

use crate::{Camera, EyeLight, Film, render_tiles};

/// The triangles a frame is traced against and the BVH built over them.
///
/// A stand-in for the retained scene: when `raystage-scene` exists, it takes this pair's place.
#[derive(Clone, Copy, Debug)]
pub struct Geometry<'a> {
    /// The triangles, for shading: the BVH reports hits by triangle index.
    pub triangles: IndexedMesh<'a>,
    /// The BVH built from `triangles`.
    pub bvh: &'a Bvh8,
}

/// What a frame cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStats {
    /// Rays traced (primary rays only in an eye-light frame: one per pixel).
    pub rays: u64,
    /// Wall-clock time of tracing and shading, in seconds (excludes encoding).
    pub seconds: f64,
}

impl FrameStats {
    /// Throughput in millions of rays per second.
    pub fn mrays_per_second(&self) -> f64 {
        self.rays as f64 / self.seconds / 1e6
    }
}

/// Renders a `width × height` eye-light frame of `geometry` seen by `camera`, in parallel on the
/// current rayon pool.
pub fn render_frame(
    geometry: &Geometry<'_>,
    camera: &impl Camera,
    shader: &EyeLight,
    width: u32,
    height: u32,
) -> (Film, FrameStats) {
    let mut film = Film::new(width, height);
    let start = Instant::now();
    render_tiles(&mut film, |x, y| {
        let ray = camera.primary_ray(x, y, width, height);
        match geometry.bvh.intersect(&ray) {
            Some(hit) => shader.shade_hit(ray.dir, &hit, &geometry.triangles.triangle(hit.prim)),
            None => shader.sky(ray.dir),
        }
    });
    let stats = FrameStats { rays: u64::from(width) * u64::from(height), seconds: start.elapsed().as_secs_f64() };
    (film, stats)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use raystage_kernel::{BuildOptions, Ray};

    use super::*;

    /// An orthographic camera looking down −z over `[-1, 1]²`.
    struct Orthographic;

    impl Camera for Orthographic {
        fn primary_ray(&self, x: u32, y: u32, width: u32, height: u32) -> Ray {
            let u = (x as f32 + 0.5) / width as f32 * 2.0 - 1.0;
            let v = 1.0 - (y as f32 + 0.5) / height as f32 * 2.0;
            Ray::new(Vec3::new(u, v, 1.0), Vec3::NEG_Z)
        }
    }

    #[test]
    fn a_square_in_front_of_the_sky() {
        // Two triangles covering [-0.5, 0.5]² at z = 0, each its own colour group.
        let vertices = [
            Vec3::new(-0.5, -0.5, 0.0),
            Vec3::new(0.5, -0.5, 0.0),
            Vec3::new(0.5, 0.5, 0.0),
            Vec3::new(-0.5, 0.5, 0.0),
        ];
        let indices = [[0, 1, 2], [0, 2, 3]];
        let triangles = IndexedMesh { vertices: &vertices, indices: &indices };
        let bvh = Bvh8::build(&triangles, &BuildOptions::default());
        let shader = EyeLight { group_size: 1, plain_from: u32::MAX };

        let (film, stats) = render_frame(&Geometry { triangles, bvh: &bvh }, &Orthographic, &shader, 20, 20);

        assert_eq!(stats.rays, 400);
        assert!(stats.seconds > 0.0 && stats.mrays_per_second() > 0.0);
        // Head-on hits get the full base colour; (14, 8) is below the diagonal, in triangle 0.
        assert_eq!(film.pixel(14, 8), shader.base_colour(0));
        assert_eq!(film.pixel(6, 12), shader.base_colour(1));
        assert_eq!(film.pixel(0, 0), shader.sky(Vec3::NEG_Z));
    }
}
