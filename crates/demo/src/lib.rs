//! # raystage-demo
//!
//! raystage's built-in procedural scenes. The two standard benchmark scenes, the sphere grid and
//! the triangle soup, their camera and their random number generator reproduce
//! `bench/embree_probe.c` (the Embree 3 baseline) operation for operation in single precision, so
//! raystage and Embree can be compared on bit-identical triangles and rays.
//!
//! Each standard scene also comes as a retained [`raystage_scene::Scene`], coloured and lit
//! ([`StandardScene::scene`]), which is what `raystage render --demo` draws.
//!
//! Not in here: acceleration structures, shading arithmetic, frame loops.

pub mod animated;
pub mod animated_assets;
pub mod cornell_box;
pub mod image_compare;
pub mod material_scenes;
pub mod probe_math;
mod scenes;
pub mod shading;

use glam::Vec3;
use raystage_kernel::IndexedMesh;

pub use probe_math::Xorshift64;
use probe_math::{add, cross, mul, norm, sub};

/// An owned indexed triangle mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub vertices: Vec<Vec3>,
    /// Three vertex indices per triangle.
    pub indices: Vec<[u32; 3]>,
}

impl Mesh {
    /// A borrowed view the kernel can build from.
    pub fn as_indexed(&self) -> IndexedMesh<'_> {
        IndexedMesh { vertices: &self.vertices, indices: &self.indices }
    }

    /// The three vertices of triangle `prim`.
    pub fn triangle(&self, prim: u32) -> [Vec3; 3] {
        self.indices[prim as usize].map(|i| self.vertices[i as usize])
    }
}

/// The standard scenes of the benchmark probe.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StandardScene {
    /// 10×10 UV spheres of 100×50 segments (1,000,000 triangles) on a 2-triangle ground plane.
    Spheres,
    /// 1,000,000 random small triangles in the unit cube: the pathological BVH case.
    Soup,
}

impl StandardScene {
    /// Every standard scene.
    pub const ALL: [StandardScene; 2] = [StandardScene::Spheres, StandardScene::Soup];

    /// The name used on command lines and in reports (`sphere`, `soup`).
    pub fn name(self) -> &'static str {
        match self {
            StandardScene::Spheres => "sphere",
            StandardScene::Soup => "soup",
        }
    }

    /// Parses `sphere`/`spheres` or `soup`.
    pub fn from_name(name: &str) -> Option<StandardScene> {
        match name {
            "sphere" | "spheres" => Some(StandardScene::Spheres),
            "soup" => Some(StandardScene::Soup),
            _ => None,
        }
    }

    /// Generates the triangles, exactly as the probe does.
    pub fn mesh(self) -> Mesh {
        match self {
            StandardScene::Spheres => sphere_grid(),
            StandardScene::Soup => soup(),
        }
    }

    /// The box the probe draws random ray origins from (`bmin`, `bmax` in the probe).
    pub fn ray_box(self) -> (Vec3, Vec3) {
        match self {
            StandardScene::Spheres => (Vec3::new(-13.0, 0.0, -25.0), Vec3::new(13.0, 2.0, 2.0)),
            StandardScene::Soup => (Vec3::ZERO, Vec3::ONE),
        }
    }

    /// The probe's camera for this scene.
    pub fn camera(self) -> ProbeCamera {
        match self {
            StandardScene::Spheres => ProbeCamera::look_at([0.0, 8.0, 8.0], [0.0, 0.0, -10.0], 60.0),
            StandardScene::Soup => ProbeCamera::look_at([0.5, 0.5, 2.5], [0.5, 0.5, 0.5], 60.0),
        }
    }
}

/// The probe's sphere grid: 10×10 UV spheres of radius 1 with 100×50 segments at y = 1, spaced
/// 2.5 apart, then a 200×200 ground plane at y = 0 (1,000,002 triangles).
pub fn sphere_grid() -> Mesh {
    const G: i32 = 10;
    const SU: i32 = 100;
    const SV: i32 = 50;
    let pi = std::f32::consts::PI;
    let mut mesh = Mesh::default();
    for gx in 0..G {
        for gz in 0..G {
            let base = mesh.vertices.len() as u32;
            let cx = gx as f32 * 2.5 - (G - 1) as f32 * 1.25;
            let cz = (-gz) as f32 * 2.5;
            let cy = 1.0f32;
            for j in 0..=SV {
                for i in 0..=SU {
                    let th = pi * j as f32 / SV as f32;
                    let ph = 2.0 * pi * i as f32 / SU as f32;
                    mesh.vertices.push(Vec3::new(
                        cx + th.sin() * ph.cos(),
                        cy + th.cos(),
                        cz + th.sin() * ph.sin(),
                    ));
                }
            }
            for j in 0..SV as u32 {
                for i in 0..SU as u32 {
                    let a = base + j * (SU as u32 + 1) + i;
                    let (b, c) = (a + 1, a + SU as u32 + 1);
                    let d = c + 1;
                    mesh.indices.push([a, c, b]);
                    mesh.indices.push([b, c, d]);
                }
            }
        }
    }
    let p = 100.0;
    let vi = mesh.vertices.len() as u32;
    mesh.vertices.extend([
        Vec3::new(-p, 0.0, -p),
        Vec3::new(p, 0.0, -p),
        Vec3::new(p, 0.0, p),
        Vec3::new(-p, 0.0, p),
    ]);
    mesh.indices.push([vi, vi + 2, vi + 1]);
    mesh.indices.push([vi, vi + 3, vi + 2]);
    mesh
}

/// The probe's soup: 1,000,000 triangles, each with vertices jittered by ±0.01 around a random
/// centre in the unit cube (seed 12345, draws in the order centre x, y, z, then x, y, z per
/// vertex).
pub fn soup() -> Mesh {
    let n = 1_000_000u32;
    let mut rng = Xorshift64::new(12345);
    let mut mesh = Mesh { vertices: Vec::with_capacity(3 * n as usize), indices: Vec::with_capacity(n as usize) };
    for t in 0..n {
        let (cx, cy, cz) = (rng.next_f32(), rng.next_f32(), rng.next_f32());
        for _ in 0..3 {
            let x = cx + (rng.next_f32() - 0.5) * 0.02;
            let y = cy + (rng.next_f32() - 0.5) * 0.02;
            let z = cz + (rng.next_f32() - 0.5) * 0.02;
            mesh.vertices.push(Vec3::new(x, y, z));
        }
        mesh.indices.push([3 * t, 3 * t + 1, 3 * t + 2]);
    }
    mesh
}

/// The probe's pinhole camera: a look-at frame with world up +y and a vertical field of view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeCamera {
    /// Eye position.
    pub origin: Vec3,
    forward: [f32; 3],
    right: [f32; 3],
    up: [f32; 3],
    /// `tan(fov_y / 2)`.
    tan_half_fov: f32,
}

impl ProbeCamera {
    /// A camera at `eye` looking at `target` with vertical field of view `fov_y_deg`.
    pub fn look_at(eye: [f32; 3], target: [f32; 3], fov_y_deg: f32) -> ProbeCamera {
        let forward = norm(sub(target, eye));
        let right = norm(cross(forward, [0.0, 1.0, 0.0]));
        let up = cross(right, forward);
        let tan_half_fov = (0.5 * fov_y_deg * std::f32::consts::PI / 180.0).tan();
        ProbeCamera { origin: Vec3::from_array(eye), forward, right, up, tan_half_fov }
    }

    /// Unit direction through the centre of pixel `(x, y)` of a `width × height` image, row 0 at
    /// the top; at 1920×1080 bit-identical to the probe's `cam_dir`.
    pub fn dir(&self, x: u32, y: u32, width: u32, height: u32) -> Vec3 {
        let (w, h) = (width as f32, height as f32);
        let u = ((x as f32 + 0.5) / w * 2.0 - 1.0) * self.tan_half_fov * w / h;
        let v = (1.0 - (y as f32 + 0.5) / h * 2.0) * self.tan_half_fov;
        Vec3::from_array(norm(add(self.forward, add(mul(self.right, u), mul(self.up, v)))))
    }
}
