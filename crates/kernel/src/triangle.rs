//! Triangle input and the watertight ray/triangle test of Woop, Benthin and Wald (JCGT 2013).
//!
//! Watertightness: the test transforms the three vertices into a ray-centred, sheared frame in
//! which the ray is the +z axis, then evaluates the three 2D edge functions. An edge shared by two
//! triangles produces exactly negated edge values in both (the products are rounded separately,
//! never fused, so `a·b − c·d` is exactly antisymmetric), so a ray through a shared edge or vertex
//! hits at least one of them. Edge values of exactly zero are recomputed in double precision,
//! where the 24-bit products are exact and the sign is therefore exact.
//!
//! The SIMD leaf kernels perform the same IEEE single-precision operations in the same order
//! (no FMA), so every layout returns bit-identical distances and barycentrics to this scalar code.

use glam::Vec3;

use crate::prepared::PreparedRay;

/// Anything that can hand the builder its triangles by index.
pub trait TriangleSource: Sync {
    /// Number of triangles.
    fn triangle_count(&self) -> usize;
    /// The three vertices of triangle `index` (`index < triangle_count()`).
    fn triangle(&self, index: u32) -> [Vec3; 3];

    /// A hint that triangle `index` is read soon, in two stages for sources that find a
    /// triangle's vertices through an index buffer: `vertices` false starts loading its
    /// indices, true (issued later) its vertices. Builders and refits gather triangles in tree
    /// order, at random in memory, and issue these a few blocks ahead. The default does nothing.
    #[inline]
    fn prefetch(&self, index: u32, vertices: bool) {
        let _ = (index, vertices);
    }
}

/// [`TriangleSource::prefetch`] for a source that finds the vertices of triangle `index`
/// through `indices`.
#[inline]
pub fn prefetch_indexed(vertices: &[Vec3], indices: &[[u32; 3]], index: u32, load_vertices: bool) {
    if !load_vertices {
        crate::prefetch(indices, index as usize);
    } else if let Some(corners) = indices.get(index as usize) {
        corners.iter().for_each(|&v| crate::prefetch(vertices, v as usize));
    }
}

/// A borrowed indexed triangle mesh.
#[derive(Clone, Copy, Debug)]
pub struct IndexedMesh<'a> {
    /// Vertex positions.
    pub vertices: &'a [Vec3],
    /// Three vertex indices per triangle; every index must be `< vertices.len()`.
    pub indices: &'a [[u32; 3]],
}

impl TriangleSource for IndexedMesh<'_> {
    fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    #[inline]
    fn triangle(&self, index: u32) -> [Vec3; 3] {
        let [a, b, c] = self.indices[index as usize];
        [self.vertices[a as usize], self.vertices[b as usize], self.vertices[c as usize]]
    }

    #[inline]
    fn prefetch(&self, index: u32, vertices: bool) {
        prefetch_indexed(self.vertices, self.indices, index, vertices);
    }
}

impl TriangleSource for [[Vec3; 3]] {
    fn triangle_count(&self) -> usize {
        self.len()
    }

    #[inline]
    fn triangle(&self, index: u32) -> [Vec3; 3] {
        self[index as usize]
    }
}

impl TriangleSource for Vec<[Vec3; 3]> {
    fn triangle_count(&self) -> usize {
        self.len()
    }

    #[inline]
    fn triangle(&self, index: u32) -> [Vec3; 3] {
        self[index as usize]
    }
}

/// The geometric normal `(v1 − v0) × (v2 − v0)` (not normalised); it faces the side from which
/// the vertices appear counter-clockwise.
pub fn geometric_normal(tri: &[Vec3; 3]) -> Vec3 {
    (tri[1] - tri[0]).cross(tri[2] - tri[0])
}

/// Whether the triangle has no area: two equal vertices, or three on one line. The cross
/// product of its edges is evaluated in double precision, where the differences of single
/// precision coordinates are exact (for coordinates within 2²⁹ of each other in magnitude) and
/// equal products round alike, so exactly collinear vertices give exactly zero.
///
/// The watertight test cannot be trusted to miss such a triangle: shearing it into the ray's
/// frame rounds its three points off their line, and a ray that passes within that rounding of
/// the line "hits" a sliver whose normal is zero. The builders leave these triangles out (unless
/// the tree is refittable, when they may move apart), and the brute-force reference skips them.
pub fn is_degenerate(tri: &[Vec3; 3]) -> bool {
    let d = |p: Vec3| [p.x as f64, p.y as f64, p.z as f64];
    let (a, b, c) = (d(tri[0]), d(tri[1]), d(tri[2]));
    let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    e1[1] * e2[2] == e1[2] * e2[1] && e1[2] * e2[0] == e1[0] * e2[2] && e1[0] * e2[1] == e1[1] * e2[0]
}

/// A hit of the scalar test: distance and barycentrics of the second and third vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TriangleHit {
    pub t: f32,
    pub u: f32,
    pub v: f32,
}

/// Intersects the prepared ray with one triangle and returns the hit if its distance lies in
/// `(ray.tnear, tfar]`. Degenerate triangles (zero area, collinear, or seen exactly edge-on) never
/// hit.
#[inline]
pub(crate) fn intersect(ray: &PreparedRay, v: &[[f32; 3]; 3], tfar: f32) -> Option<TriangleHit> {
    let [kx, ky, kz] = ray.axes();
    let [sx, sy, sz] = ray.shear;
    // Vertices relative to the origin, in the permuted frame.
    let rel = |p: &[f32; 3]| [p[kx] - ray.org[kx], p[ky] - ray.org[ky], p[kz] - ray.org[kz]];
    let (a, b, c) = (rel(&v[0]), rel(&v[1]), rel(&v[2]));
    // Shear so that the ray becomes the z axis.
    let (ax, ay) = (a[0] - sx * a[2], a[1] - sy * a[2]);
    let (bx, by) = (b[0] - sx * b[2], b[1] - sy * b[2]);
    let (cx, cy) = (c[0] - sx * c[2], c[1] - sy * c[2]);
    let (mut eu, mut ev, mut ew) = (cx * by - cy * bx, ax * cy - ay * cx, bx * ay - by * ax);
    if eu == 0.0 || ev == 0.0 || ew == 0.0 {
        [eu, ev, ew] = edge_functions_f64([ax, ay], [bx, by], [cx, cy]);
    }
    edge_test_and_distance(eu, ev, ew, [a[2], b[2], c[2]], sz, ray.tnear, tfar)
}

/// The edge functions recomputed in double precision (exact products, exact sign).
#[inline(never)]
#[cold]
pub(crate) fn edge_functions_f64(a: [f32; 2], b: [f32; 2], c: [f32; 2]) -> [f32; 3] {
    let d = |p: [f32; 2]| [p[0] as f64, p[1] as f64];
    let (a, b, c) = (d(a), d(b), d(c));
    [
        (c[0] * b[1] - c[1] * b[0]) as f32,
        (a[0] * c[1] - a[1] * c[0]) as f32,
        (b[0] * a[1] - b[1] * a[0]) as f32,
    ]
}

/// Second half of the test, from the edge values on: sign test, determinant, distance.
#[inline(always)]
pub(crate) fn edge_test_and_distance(
    eu: f32,
    ev: f32,
    ew: f32,
    z: [f32; 3],
    sz: f32,
    tnear: f32,
    tfar: f32,
) -> Option<TriangleHit> {
    if (eu < 0.0 || ev < 0.0 || ew < 0.0) && (eu > 0.0 || ev > 0.0 || ew > 0.0) {
        return None;
    }
    let det = eu + ev + ew;
    if det == 0.0 {
        return None;
    }
    let (az, bz, cz) = (sz * z[0], sz * z[1], sz * z[2]);
    let t = (eu * az + ev * bz + ew * cz) / det;
    if !(t > tnear && t <= tfar) {
        return None;
    }
    Some(TriangleHit { t, u: ev / det, v: ew / det })
}
