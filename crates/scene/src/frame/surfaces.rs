//! The surface geometry of a packet of hits, computed side by side.
//!
//! [`Frame::surface`] of one hit is a chain of dependent steps: fetch the triangle, normalise
//! its normal (a square root and a division), interpolate the point and bound its error. A
//! packet's hits do not depend on each other, so [`Frame::surface_lanes`] gathers every hit's
//! triangle first, letting the loads overlap, then runs each arithmetic step across all the
//! hits at once, in loops over the lanes that the compiler turns into vector instructions,
//! with exactly the operations of the scalar path in the same order: the geometry is bit for bit
//! the same. The lanes stay lanes for whoever lights the hits next (shadow rays, matte shading),
//! so no hit is copied into a [`SurfacePoint`](super::SurfacePoint) it does not need.

use glam::Vec3;
use raystage_kernel::{PACKET_SIZE, Ray};

use super::{Frame, SceneHit, barycentrics, shading_normal};
use crate::ids::ShaderId;
use crate::spawn::{ERROR_FACTORS, placed_hit_point, spawn_origin};

/// One value per lane of a packet.
type Lanes = [f32; PACKET_SIZE];

/// Three components per lane.
type Lanes3 = [Lanes; 3];

/// The vector of lane `k`.
#[inline(always)]
fn at(v: &Lanes3, k: usize) -> Vec3 {
    Vec3::new(v[0][k], v[1][k], v[2][k])
}

/// The geometry of up to [`PACKET_SIZE`] hits, lane `k` for `hits[k]`: of each hit, exactly
/// the position, error bound, normals, side and shader id that [`Frame::surface`] computes.
/// Lanes without a hit hold zeros.
#[derive(Clone, Copy, Debug, Default)]
pub struct SurfaceLanes {
    /// The lanes that hold a hit: bit `k` for `hits[k]`.
    pub hits: u32,
    position: Lanes3,
    position_error: Lanes3,
    geometric_normal: Lanes3,
    shading_normal: Lanes3,
    front_face: [bool; PACKET_SIZE],
    shader_id: [Option<ShaderId>; PACKET_SIZE],
}

impl SurfaceLanes {
    /// The hit point of lane `k` (see [`SurfacePoint::position`](super::SurfacePoint::position)).
    #[inline]
    pub fn position(&self, k: usize) -> Vec3 {
        at(&self.position, k)
    }

    /// The unit geometric normal of lane `k`, facing the side the ray came from.
    #[inline]
    pub fn geometric_normal(&self, k: usize) -> Vec3 {
        at(&self.geometric_normal, k)
    }

    /// The unit shading normal of lane `k`, on the geometric normal's side.
    #[inline]
    pub fn shading_normal(&self, k: usize) -> Vec3 {
        at(&self.shading_normal, k)
    }

    /// Whether the ray of lane `k` hit the triangle's front.
    #[inline]
    pub fn front_face(&self, k: usize) -> bool {
        self.front_face[k]
    }

    /// The id of the shader of the triangle of lane `k`, `None` if it has none. A shader the
    /// scene has removed since stands for the default shader, as in
    /// [`PreviewPoint`](super::PreviewPoint).
    #[inline]
    pub fn shader_id(&self, k: usize) -> Option<ShaderId> {
        self.shader_id[k]
    }

    /// Where a ray leaving lane `k`'s surface in direction `dir` starts: exactly
    /// [`SurfacePoint::spawn_origin`](super::SurfacePoint::spawn_origin) of its point.
    #[inline]
    pub fn spawn_origin(&self, k: usize, dir: Vec3) -> Vec3 {
        spawn_origin(self.position(k), at(&self.position_error, k), self.geometric_normal(k), dir)
    }
}

impl<'a> Frame<'a> {
    /// The geometry of up to [`PACKET_SIZE`] hits `hits` of `rays` at shutter time `time`, bit
    /// for bit what [`Frame::surface`] computes of each, written over `lanes` (a caller that
    /// resolves packet after packet keeps one set of lanes, rather than copying each packet's
    /// half a kilobyte out of a return value).
    ///
    /// # Panics
    /// If there are more than [`PACKET_SIZE`] hits, or not one ray per hit.
    pub fn surface_lanes(&self, rays: &[Ray], hits: &[Option<SceneHit>], time: f32, lanes: &mut SurfaceLanes) {
        let n = hits.len();
        assert!(n <= PACKET_SIZE && rays.len() == n, "one ray per hit, at most a packet");
        // Gathered lane by lane; lanes without a hit keep zeros, computed on and ignored.
        let mut normal: Lanes3 = [[0.0; PACKET_SIZE]; 3];
        let mut dir: Lanes3 = [[0.0; PACKET_SIZE]; 3];
        let mut vertices: [Lanes3; 3] = [[[0.0; PACKET_SIZE]; 3]; 3];
        let mut weights: Lanes3 = [[0.0; PACKET_SIZE]; 3];
        // Each hit's triangle (its corners' vertex indices), for the second pass.
        let mut triangles = [[0usize; 3]; PACKET_SIZE];
        *lanes = SurfaceLanes::default();
        for (k, hit) in hits.iter().enumerate() {
            let Some(hit) = hit else { continue };
            lanes.hits |= 1 << k;
            let fi = &self.instances[hit.item as usize];
            let mesh = &fi.object.mesh;
            let (w, corners) = barycentrics(mesh, hit);
            let world_normal = fi.placed_at(time).normal_to_world(hit.ng);
            let positions = corners.map(|i| mesh.positions[i]);
            triangles[k] = corners;
            lanes.shader_id[k] = mesh.shaders.get(hit.prim as usize).copied();
            for corner in 0..3 {
                weights[corner][k] = w[corner];
            }
            for axis in 0..3 {
                normal[axis][k] = world_normal[axis];
                dir[axis][k] = rays[k].dir[axis];
                for corner in 0..3 {
                    vertices[corner][axis][k] = positions[corner][axis];
                }
            }
        }
        (lanes.geometric_normal, lanes.front_face) = facing_normals(&normal, &dir);
        let (local, local_error) = interpolated_points(&vertices, &weights);
        for (k, hit) in hits.iter().enumerate() {
            let Some(hit) = hit else { continue };
            let fi = &self.instances[hit.item as usize];
            // A still instance's placement is borrowed; a moving one's is computed again.
            let placed = fi.placed_at(time);
            let (position, _, position_error) = placed_hit_point(at(&local, k), at(&local_error, k), &placed);
            let w = [weights[0][k], weights[1][k], weights[2][k]];
            let shading = shading_normal(&fi.object.mesh, &placed, triangles[k], w, lanes.geometric_normal(k));
            for axis in 0..3 {
                lanes.position[axis][k] = position[axis];
                lanes.position_error[axis][k] = position_error[axis];
                lanes.shading_normal[axis][k] = shading[axis];
            }
        }
    }
}

/// Each lane's world normal `normal` normalised (zero if it cannot be) and turned to face the
/// ray's direction `dir`, and whether it was facing it already (the ray hit the front): as
/// `normalize_or_zero`, `dot` and negation compute them.
fn facing_normals(normal: &Lanes3, dir: &Lanes3) -> (Lanes3, [bool; PACKET_SIZE]) {
    let mut facing = [[0.0; PACKET_SIZE]; 3];
    let mut front = [false; PACKET_SIZE];
    for k in 0..PACKET_SIZE {
        let (x, y, z) = (normal[0][k], normal[1][k], normal[2][k]);
        let rcp = 1.0 / ((x * x) + (y * y) + (z * z)).sqrt();
        let (x, y, z) = if rcp.is_finite() && rcp > 0.0 { (x * rcp, y * rcp, z * rcp) } else { (0.0, 0.0, 0.0) };
        let towards = (x * dir[0][k]) + (y * dir[1][k]) + (z * dir[2][k]) < 0.0;
        let (x, y, z) = if towards { (x, y, z) } else { (-x, -y, -z) };
        facing[0][k] = x;
        facing[1][k] = y;
        facing[2][k] = z;
        front[k] = towards;
    }
    (facing, front)
}

/// Each lane's point interpolated from `vertices` with barycentric `weights`, and the bound of
/// its rounding error: `spawn::hit_point`'s object-space part, lane by lane.
fn interpolated_points(vertices: &[Lanes3; 3], weights: &Lanes3) -> (Lanes3, Lanes3) {
    let (interpolation, kernel) = ERROR_FACTORS;
    let max = |a: f32, b: f32| if a > b { a } else { b };
    // The largest magnitude per axis over the three vertices, then over the axes.
    let [x, y, z] = [0, 1, 2].map(|axis| -> Lanes {
        std::array::from_fn(|k| max(max(vertices[0][axis][k].abs(), vertices[1][axis][k].abs()), vertices[2][axis][k].abs()))
    });
    let largest: Lanes = std::array::from_fn(|k| max(max(x[k], y[k]), z[k]));
    let mut point = [[0.0; PACKET_SIZE]; 3];
    let mut error = [[0.0; PACKET_SIZE]; 3];
    for axis in 0..3 {
        for k in 0..PACKET_SIZE {
            let a = vertices[0][axis][k] * weights[0][k];
            let b = vertices[1][axis][k] * weights[1][k];
            let c = vertices[2][axis][k] * weights[2][k];
            point[axis][k] = a + b + c;
            error[axis][k] = interpolation * (a.abs() + b.abs() + c.abs()) + kernel * largest[k];
        }
    }
    (point, error)
}
