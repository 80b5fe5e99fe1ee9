//! Procedural building blocks for the animated scenes: subdivided boxes, cylinders, spheres, and
//! gathering several of them into one mesh.

use glam::{Affine3A, Vec3};

use crate::{Mesh, Xorshift64};

impl Mesh {
    /// Appends `other` transformed by `t`.
    pub(crate) fn append(&mut self, other: &Mesh, t: Affine3A) {
        let base = self.vertices.len() as u32;
        self.vertices.extend(other.vertices.iter().map(|&v| t.transform_point3(v)));
        self.indices.extend(other.indices.iter().map(|tri| tri.map(|i| i + base)));
    }

    /// Appends the quad `a b c d` (counter-clockwise from the front) as two triangles.
    pub(crate) fn quad(&mut self, corners: [Vec3; 4]) {
        let base = self.vertices.len() as u32;
        self.vertices.extend(corners);
        self.indices.push([base, base + 1, base + 2]);
        self.indices.push([base, base + 2, base + 3]);
    }
}

/// A box centred at the origin with edge lengths `size`, each face cut into `n × n` quads
/// (12·n² triangles), facing outwards.
pub(crate) fn grid_box(size: Vec3, n: u32) -> Mesh {
    let mut mesh = Mesh::default();
    let h = size * 0.5;
    // Each face: its normal axis, sign, and the two in-plane axes (right-handed with the normal).
    for (axis, sign) in [(0usize, 1.0f32), (0, -1.0), (1, 1.0), (1, -1.0), (2, 1.0), (2, -1.0)] {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let (u, v) = if sign > 0.0 { (u, v) } else { (v, u) };
        let point = |a: f32, b: f32| {
            let mut p = Vec3::ZERO;
            p[axis] = sign * h[axis];
            p[u] = (a * 2.0 - 1.0) * h[u];
            p[v] = (b * 2.0 - 1.0) * h[v];
            p
        };
        for i in 0..n {
            for j in 0..n {
                let (a0, a1, b0, b1) = (i as f32 / n as f32, (i + 1) as f32 / n as f32, j as f32 / n as f32, (j + 1) as f32 / n as f32);
                mesh.quad([point(a0, b0), point(a1, b0), point(a1, b1), point(a0, b1)]);
            }
        }
    }
    mesh
}

/// A cylinder (or cone frustum) along +y from radius `r0` at `y = 0` to `r1` at `y = height`,
/// `segments` around, open at both ends.
pub(crate) fn cylinder(r0: f32, r1: f32, height: f32, segments: u32) -> Mesh {
    let mut mesh = Mesh::default();
    let ring = |k: u32, r: f32, y: f32| {
        let a = k as f32 / segments as f32 * std::f32::consts::TAU;
        Vec3::new(r * a.cos(), y, -r * a.sin())
    };
    for k in 0..segments {
        mesh.quad([ring(k, r0, 0.0), ring(k + 1, r0, 0.0), ring(k + 1, r1, height), ring(k, r1, height)]);
    }
    mesh
}

/// A UV sphere of radius `r` around the origin, `su × sv` segments.
pub(crate) fn uv_sphere(r: f32, su: u32, sv: u32) -> Mesh {
    let mut mesh = Mesh::default();
    for j in 0..=sv {
        for i in 0..=su {
            let (th, ph) = (std::f32::consts::PI * j as f32 / sv as f32, std::f32::consts::TAU * i as f32 / su as f32);
            mesh.vertices.push(Vec3::new(r * th.sin() * ph.cos(), r * th.cos(), r * th.sin() * ph.sin()));
        }
    }
    for j in 0..sv {
        for i in 0..su {
            let a = j * (su + 1) + i;
            let (b, c) = (a + 1, a + su + 1);
            mesh.indices.push([a, c, b]);
            mesh.indices.push([b, c, c + 1]);
        }
    }
    mesh
}

/// A uniformly random unit vector.
pub(crate) fn random_direction(rng: &mut Xorshift64) -> Vec3 {
    let z = 1.0 - 2.0 * rng.next_f32();
    let r = (1.0 - z * z).max(0.0).sqrt();
    let ph = std::f32::consts::TAU * rng.next_f32();
    Vec3::new(r * ph.cos(), r * ph.sin(), z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_have_the_expected_triangle_counts() {
        assert_eq!(grid_box(Vec3::ONE, 3).indices.len(), 12 * 9);
        assert_eq!(cylinder(1.0, 0.5, 2.0, 8).indices.len(), 16);
        assert_eq!(uv_sphere(1.0, 10, 5).indices.len(), 100);
    }

    #[test]
    fn box_faces_point_outwards() {
        let b = grid_box(Vec3::new(2.0, 4.0, 6.0), 2);
        for t in &b.indices {
            let [p0, p1, p2] = t.map(|i| b.vertices[i as usize]);
            let n = (p1 - p0).cross(p2 - p0);
            assert!(n.dot((p0 + p1 + p2) / 3.0) > 0.0, "inward face {t:?}");
        }
    }
}
