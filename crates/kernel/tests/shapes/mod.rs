//! Closed, consistently wound test meshes (counter-clockwise seen from outside) and a small
//! deterministic random number generator, shared by the numerical hard cases of the kernel, the
//! scene and the renderer (the other crates include this file by path).

#![allow(dead_code)]

use std::collections::HashMap;

use glam::Vec3;

/// An indexed closed mesh: every edge is shared by exactly two triangles, which use the same
/// two vertices (by index, so with bit-identical coordinates).
#[derive(Clone, Debug)]
pub struct Shape {
    pub vertices: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
    /// A point inside (for outward checks on convex shapes) .
    pub centre: Vec3,
    /// Per triangle: the flat face it belongs to (coplanar triangles share one).
    pub face: Vec<u32>,
}

impl Shape {
    /// The triangles as vertex triples.
    pub fn triangles(&self) -> Vec<[Vec3; 3]> {
        self.indices.iter().map(|t| t.map(|i| self.vertices[i as usize])).collect()
    }

    /// The same shape with every vertex mapped by `f` (shared vertices stay shared).
    pub fn mapped(&self, f: impl Fn(Vec3) -> Vec3) -> Shape {
        Shape { vertices: self.vertices.iter().map(|&v| f(v)).collect(), centre: f(self.centre), ..self.clone() }
    }

    /// Unit normals of the triangles (outward for a consistently wound closed shape).
    pub fn normals(&self) -> Vec<Vec3> {
        self.triangles().iter().map(|t| (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero()).collect()
    }

    /// Every distinct edge as a vertex index pair with the normals of its two triangles summed.
    pub fn edges(&self) -> Vec<(u32, u32, Vec3)> {
        let normals = self.normals();
        let mut edges: HashMap<(u32, u32), Vec3> = HashMap::new();
        for (t, tri) in self.indices.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                *edges.entry((a.min(b), a.max(b))).or_insert(Vec3::ZERO) += normals[t];
            }
        }
        let mut list: Vec<(u32, u32, Vec3)> = edges.into_iter().map(|((a, b), n)| (a, b, n.normalize_or_zero())).collect();
        list.sort_by_key(|e| (e.0, e.1));
        list
    }

    /// Per vertex: the unit normals of the triangles around it weighted by their angles there
    /// (so a cube's corner faces along its diagonal however its faces are split), normalised.
    pub fn vertex_normals(&self) -> Vec<Vec3> {
        let normals = self.normals();
        let mut sum = vec![Vec3::ZERO; self.vertices.len()];
        for (t, tri) in self.indices.iter().enumerate() {
            for k in 0..3 {
                let p = |j: usize| self.vertices[tri[(k + j) % 3] as usize];
                let angle = (p(1) - p(0)).angle_between(p(2) - p(0));
                sum[tri[k] as usize] += normals[t] * angle;
            }
        }
        sum.into_iter().map(|n| n.normalize_or_zero()).collect()
    }

    /// Checks that every edge is used exactly twice, once in each direction.
    pub fn assert_closed(&self) {
        let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
        for tri in &self.indices {
            for k in 0..3 {
                *directed.entry((tri[k], tri[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &directed {
            assert_eq!(n, 1, "edge {a}->{b} used {n} times");
            assert_eq!(directed.get(&(b, a)), Some(&1), "edge {a}-{b} is open");
        }
    }
}

/// An icosahedron subdivided `levels` times, projected onto the unit sphere (20·4^levels
/// triangles).
pub fn icosphere(levels: u32) -> Shape {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut vertices: Vec<Vec3> = [
        (-1.0, t, 0.0), (1.0, t, 0.0), (-1.0, -t, 0.0), (1.0, -t, 0.0),
        (0.0, -1.0, t), (0.0, 1.0, t), (0.0, -1.0, -t), (0.0, 1.0, -t),
        (t, 0.0, -1.0), (t, 0.0, 1.0), (-t, 0.0, -1.0), (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut indices: Vec<[u32; 3]> = vec![
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
        [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
        [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut middle: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, vertices: &mut Vec<Vec3>| {
            *middle.entry((a.min(b), a.max(b))).or_insert_with(|| {
                vertices.push(((vertices[a as usize] + vertices[b as usize]) * 0.5).normalize());
                vertices.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(indices.len() * 4);
        for [a, b, c] in indices {
            let (ab, bc, ca) = (mid(a, b, &mut vertices), mid(b, c, &mut vertices), mid(c, a, &mut vertices));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        indices = next;
    }
    let face = (0..indices.len() as u32).collect();
    Shape { vertices, indices, centre: Vec3::ZERO, face }
}

/// The cube [−1, 1]³ with each face split into `n × n` quads of two triangles (shared
/// vertices along the face seams and the cube's edges).
pub fn cube(n: u32) -> Shape {
    let mut index: HashMap<[i32; 3], u32> = HashMap::new();
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    let mut face = Vec::new();
    let mut vertex = |p: [i32; 3], vertices: &mut Vec<Vec3>| {
        *index.entry(p).or_insert_with(|| {
            vertices.push(Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) * (2.0 / n as f32) - Vec3::ONE);
            vertices.len() as u32 - 1
        })
    };
    let n = n as i32;
    // Each face: the fixed axis, its side, and two in-plane axes in counter-clockwise order.
    for (f, (axis, high)) in [(0, false), (0, true), (1, false), (1, true), (2, false), (2, true)].into_iter().enumerate() {
        let (u, v) = if high { ((axis + 1) % 3, (axis + 2) % 3) } else { ((axis + 2) % 3, (axis + 1) % 3) };
        for i in 0..n {
            for j in 0..n {
                let p = |di: i32, dj: i32| {
                    let mut q = [0; 3];
                    q[axis] = if high { n } else { 0 };
                    q[u] = i + di;
                    q[v] = j + dj;
                    q
                };
                let [a, b, c, d] = [p(0, 0), p(1, 0), p(1, 1), p(0, 1)].map(|q| vertex(q, &mut vertices));
                indices.push([a, b, c]);
                indices.push([a, c, d]);
                face.extend([f as u32, f as u32]);
            }
        }
    }
    Shape { vertices, indices, centre: Vec3::ZERO, face }
}

/// A torus around the y axis: ring radius `major`, tube radius `minor`, `nu × nv` quads of two
/// triangles each.
pub fn torus(major: f32, minor: f32, nu: u32, nv: u32) -> Shape {
    let mut vertices = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (phi, theta) = (std::f32::consts::TAU * i as f32 / nu as f32, std::f32::consts::TAU * j as f32 / nv as f32);
            let r = major + minor * theta.cos();
            vertices.push(Vec3::new(r * phi.cos(), minor * theta.sin(), r * phi.sin()));
        }
    }
    let at = |i: u32, j: u32| (i % nu) * nv + (j % nv);
    let mut indices = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            indices.push([a, c, b]);
            indices.push([a, d, c]);
        }
    }
    let face = (0..indices.len() as u32).collect();
    Shape { vertices, indices, centre: Vec3::ZERO, face }
}

/// SplitMix64 (Steele, Lea and Flood 2014): small, fast, and the same numbers on every machine.
#[derive(Clone, Debug)]
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f32()
    }

    /// Uniform in 0..n.
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// A uniformly distributed unit vector.
    pub fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            let l = v.length_squared();
            if l > 1e-4 && l <= 1.0 {
                return v / l.sqrt();
            }
        }
    }

    /// A unit vector within `max_angle` radians of the unit vector `axis` (uniform in the
    /// cosine of the angle).
    pub fn in_cone(&mut self, axis: Vec3, max_angle: f32) -> Vec3 {
        let cos = 1.0 - self.f32() * (1.0 - max_angle.cos());
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * self.f32();
        let (t, b) = axis.any_orthonormal_pair();
        (axis * cos + (t * phi.cos() + b * phi.sin()) * sin).normalize()
    }
}
