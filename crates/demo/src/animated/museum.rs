//! BART *museum* look-alike: in a hall, a set of small triangles flies from a random cloud into
//! a sphere and back (period 80 frames), every triangle on its own path: unstructured motion,
//! the case RT-DEFORM calls the worst for refitting (docs/design/seeds.md §1.3, §5). The triangle
//! count is configurable (BART: 64 to 64k).

use glam::{Affine3A, Vec3};
use raystage_scene::ObjectKind;

use super::parts::{grid_box, random_direction};
use super::{AnimatedObject, Animation, View};
use crate::{Mesh, Xorshift64};

/// Frames from cloud to sphere.
const HALF_PERIOD: f32 = 40.0;
/// Sphere the triangles gather on.
const SPHERE_CENTRE: Vec3 = Vec3::new(0.0, 2.2, 0.0);
const SPHERE_RADIUS: f32 = 1.5;

/// The museum scene with `triangles` moving triangles.
#[derive(Clone, Debug)]
pub struct Museum {
    /// Vertices of each triangle in the cloud and on the sphere.
    cloud: Vec<Vec3>,
    sphere: Vec<Vec3>,
}

impl Museum {
    /// A museum of `triangles` moving triangles (at least one).
    pub fn new(triangles: usize) -> Museum {
        let n = triangles.max(1);
        let mut rng = Xorshift64::new(0xB0A7);
        // Triangle size: about the spacing of n points on the sphere.
        let size = (4.0 * std::f32::consts::PI * SPHERE_RADIUS * SPHERE_RADIUS / n as f32).sqrt() * 0.8;
        let (mut cloud, mut sphere) = (Vec::with_capacity(3 * n), Vec::with_capacity(3 * n));
        for i in 0..n {
            let shape = [Vec3::ZERO, Vec3::new(size, 0.0, 0.0), Vec3::new(0.3 * size, size, 0.0)];
            // In the cloud: a random spot in the hall's middle, turned at random.
            let at = Vec3::new(rng.next_f32() * 4.0 - 2.0, 0.3 + rng.next_f32() * 4.0, rng.next_f32() * 4.0 - 2.0);
            let turn = glam::Quat::from_axis_angle(random_direction(&mut rng), rng.next_f32() * std::f32::consts::TAU);
            cloud.extend(shape.map(|v| at + turn * v));
            // On the sphere: a Fibonacci point, the triangle lying in the tangent plane.
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let ph = i as f32 * 2.399_963;
            let normal = Vec3::new((1.0 - z * z).sqrt() * ph.cos(), z, (1.0 - z * z).sqrt() * ph.sin());
            let facing = glam::Quat::from_rotation_arc(Vec3::Z, normal);
            sphere.extend(shape.map(|v| SPHERE_CENTRE + normal * SPHERE_RADIUS + facing * (v - Vec3::new(0.4 * size, 0.3 * size, 0.0))));
        }
        Museum { cloud, sphere }
    }

    /// The moving triangles' vertices at frame `frame`.
    fn positions(&self, frame: u32) -> Vec<Vec3> {
        let s = 0.5 - 0.5 * (std::f32::consts::PI * frame as f32 / HALF_PERIOD).cos();
        self.cloud.iter().zip(&self.sphere).map(|(c, p)| c.lerp(*p, s)).collect()
    }
}

impl Animation for Museum {
    fn name(&self) -> String {
        format!("museum-{}", self.cloud.len() / 3)
    }

    fn objects(&self) -> Vec<AnimatedObject> {
        let n = self.cloud.len() as u32 / 3;
        let triangles = Mesh { vertices: self.positions(0), indices: (0..n).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect() };
        vec![AnimatedObject { kind: ObjectKind::Static, mesh: hall() }, AnimatedObject { kind: ObjectKind::Unstructured, mesh: triangles }]
    }

    fn instances(&self, _frame: u32) -> Vec<(usize, Affine3A)> {
        vec![(0, Affine3A::IDENTITY), (1, Affine3A::IDENTITY)]
    }

    fn deform(&self, frame: u32) -> Vec<(usize, Vec<Vec3>)> {
        vec![(1, self.positions(frame))]
    }

    fn view(&self) -> View {
        View { eye: Vec3::new(1.5, 3.5, 9.0), target: Vec3::new(0.0, 2.0, 0.0), fov_y_degrees: 45.0, sun: Vec3::new(-0.3, -1.0, -0.5) }
    }
}

/// The hall: floor, back and side walls, and pedestals along the walls.
fn hall() -> Mesh {
    let mut mesh = Mesh::default();
    let (w, h, d) = (10.0, 6.0, 10.0);
    mesh.quad([Vec3::new(-w, 0.0, d), Vec3::new(w, 0.0, d), Vec3::new(w, 0.0, -d), Vec3::new(-w, 0.0, -d)]);
    mesh.quad([Vec3::new(-w, 0.0, -d), Vec3::new(w, 0.0, -d), Vec3::new(w, h, -d), Vec3::new(-w, h, -d)]);
    mesh.quad([Vec3::new(-w, 0.0, d), Vec3::new(-w, 0.0, -d), Vec3::new(-w, h, -d), Vec3::new(-w, h, d)]);
    mesh.quad([Vec3::new(w, 0.0, -d), Vec3::new(w, 0.0, d), Vec3::new(w, h, d), Vec3::new(w, h, -d)]);
    for k in 0..8 {
        let x = -7.0 + 2.0 * k as f32;
        for z in [-8.0, 8.0] {
            mesh.append(&grid_box(Vec3::new(0.8, 1.2, 0.8), 4), Affine3A::from_translation(Vec3::new(x, 0.6, z)));
        }
    }
    mesh
}
