//! The surface points of a packet of hits, computed side by side.
//!
//! [`Frame::surface`] of one hit is a chain of dependent steps: fetch the triangle, normalise
//! its normal (a square root and a division), interpolate the point and bound its error. A
//! packet's hits do not depend on each other, so [`Frame::surfaces`] gathers every hit's
//! triangle first, letting the loads overlap, then runs each arithmetic step across all the
//! hits at once, in loops over the lanes that the compiler turns into vector instructions,
//! with exactly the operations of the scalar path in the same order: the points are bit for bit
//! the same.

use glam::Vec3;
use raystage_kernel::{PACKET_SIZE, Ray};

use super::{Frame, Geometry, SceneHit, SurfacePoint, barycentrics};
use crate::spawn::{ERROR_FACTORS, placed_hit_point};

/// One value per lane of a packet.
type Lanes = [f32; PACKET_SIZE];

/// Three components per lane.
type Lanes3 = [Lanes; 3];

impl<'a> Frame<'a> {
    /// [`Frame::surface`] of up to [`PACKET_SIZE`] hits at shutter time `time`, bit for bit
    /// what `surface` returns for each: `found(k, point)` for each hit `hits[k]` of `rays[k]`
    /// (handed over rather than returned, so that the caller can put each where it belongs
    /// without copying it again).
    ///
    /// # Panics
    /// If there are more than [`PACKET_SIZE`] hits, or not one ray per hit.
    #[inline]
    pub fn surfaces(&self, rays: &[Ray], hits: &[Option<SceneHit>], time: f32, mut found: impl FnMut(usize, SurfacePoint<'a>)) {
        let n = hits.len();
        assert!(n <= PACKET_SIZE && rays.len() == n, "one ray per hit, at most a packet");
        // Gathered lane by lane; lanes without a hit keep zeros, computed on and ignored.
        let mut normal: Lanes3 = [[0.0; PACKET_SIZE]; 3];
        let mut dir: Lanes3 = [[0.0; PACKET_SIZE]; 3];
        let mut vertices: [Lanes3; 3] = [[[0.0; PACKET_SIZE]; 3]; 3];
        let mut weights: Lanes3 = [[0.0; PACKET_SIZE]; 3];
        // Each hit's triangle (its corners' vertex indices), for the second pass.
        let mut triangles = [[0usize; 3]; PACKET_SIZE];
        for (k, hit) in hits.iter().enumerate() {
            let Some(hit) = hit else { continue };
            let fi = &self.instances[hit.item as usize];
            let mesh = &fi.object.mesh;
            let (w, corners) = barycentrics(mesh, hit);
            let world_normal = fi.placed_at(time).normal_to_world(hit.ng);
            let positions = corners.map(|i| mesh.positions[i]);
            triangles[k] = corners;
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
        let (outward, front_face) = facing_normals(&normal, &dir);
        let (local, local_error) = interpolated_points(&vertices, &weights);
        for (k, hit) in hits.iter().enumerate() {
            if let Some(hit) = hit {
                let fi = &self.instances[hit.item as usize];
                // A still instance's placement is borrowed; a moving one's is computed again.
                let placed = fi.placed_at(time);
                let at = |v: &Lanes3| Vec3::new(v[0][k], v[1][k], v[2][k]);
                let (position, local_position, position_error) = placed_hit_point(at(&local), at(&local_error), &placed);
                let geometry = Geometry { position, position_error, local_position, geometric_normal: at(&outward), front_face: front_face[k] };
                let w = [weights[0][k], weights[1][k], weights[2][k]];
                found(k, self.complete(&fi.object.mesh, &placed, hit.prim, triangles[k], w, geometry));
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
