//! Triangle meshes as the scene stores them: positions and indices, optional per-vertex normals,
//! colours and texture coordinates, and a shader per triangle.

use glam::{UVec3, Vec2, Vec3, Vec4};
use raystage_kernel::{Aabb, TriangleSource};

use crate::error::SceneError;
use crate::ids::ShaderId;

/// Cells per axis of the grid whose occupied cells make a mesh's cover ([`Mesh::cover`]).
const COVER_CELLS: u32 = 4;

/// An indexed triangle mesh with its attributes.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Three vertex indices per triangle, counter-clockwise seen from the front.
    pub indices: Vec<[u32; 3]>,
    /// Per-vertex shading normals (any length); empty for none, then the geometric normal shades.
    pub normals: Vec<Vec3>,
    /// Per-vertex colours (linear RGB); empty for none.
    pub colors: Vec<Vec3>,
    /// Per-vertex texture coordinates; empty for none.
    pub uvs: Vec<Vec2>,
    /// A second set of per-vertex texture coordinates (glTF's `TEXCOORD_1`), for textures that
    /// ask for it; empty for none.
    pub uvs1: Vec<Vec2>,
    /// Per-vertex tangents for normal maps: the direction of increasing u (of the texture
    /// coordinates the normal map reads) and, in `w`, ±1, the handedness of the bitangent
    /// `w · normal × tangent` (glTF's `TANGENT`). Empty for none: shading then derives a tangent
    /// from each triangle's texture coordinates. A zero tangent marks a vertex with none.
    pub tangents: Vec<Vec4>,
    /// The shader of each triangle; empty to shade every triangle with the scene's default.
    pub shaders: Vec<ShaderId>,
}

impl Mesh {
    /// A mesh of positions and indices only.
    pub fn new(positions: Vec<Vec3>, indices: Vec<[u32; 3]>) -> Mesh {
        Mesh { positions, indices, ..Mesh::default() }
    }

    /// The memory its vertices, triangles and attributes take.
    pub fn memory_bytes(&self) -> u64 {
        let vec3 = (self.positions.len() + self.normals.len() + self.colors.len()) * 12;
        (vec3 + self.indices.len() * 12 + (self.uvs.len() + self.uvs1.len()) * 8 + self.tangents.len() * 16 + self.shaders.len() * 4) as u64
    }

    /// The same mesh with every triangle bound to `shader`.
    pub fn with_shader(mut self, shader: ShaderId) -> Mesh {
        self.shaders = vec![shader; self.indices.len()];
        self
    }

    /// Checks that the mesh is well formed: at least one triangle, every index in range, every
    /// number finite, every attribute array of the right length. Shader ids are checked by the
    /// scene, which knows them.
    pub fn validate(&self) -> Result<(), SceneError> {
        if self.indices.is_empty() {
            return Err(SceneError::EmptyMesh);
        }
        let vertices = self.positions.len();
        for (triangle, tri) in self.indices.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= vertices) {
                return Err(SceneError::IndexOutOfRange { triangle, index, vertices });
            }
        }
        finite("positions", self.positions.iter().map(|p| p.is_finite()))?;
        for (field, len) in [("normals", self.normals.len()), ("colors", self.colors.len()), ("uvs", self.uvs.len()), ("uvs1", self.uvs1.len()), ("tangents", self.tangents.len())] {
            if len != 0 && len != vertices {
                return Err(SceneError::WrongLength { field, got: len, expected: vertices });
            }
        }
        finite("normals", self.normals.iter().map(|n| n.is_finite()))?;
        finite("colors", self.colors.iter().map(|c| c.is_finite()))?;
        finite("uvs", self.uvs.iter().map(|t| t.is_finite()))?;
        finite("uvs1", self.uvs1.iter().map(|t| t.is_finite()))?;
        finite("tangents", self.tangents.iter().map(|t| t.is_finite()))?;
        if !self.shaders.is_empty() && self.shaders.len() != self.indices.len() {
            return Err(SceneError::WrongLength {
                field: "shaders",
                got: self.shaders.len(),
                expected: self.indices.len(),
            });
        }
        Ok(())
    }

    /// Fills [`Mesh::tangents`] from the texture coordinates `set` (0: [`Mesh::uvs`], 1:
    /// [`Mesh::uvs1`]: those the normal map reads) and the normals, MikkTSpace-style (see
    /// `tangents::vertex_tangents`); leaves them empty for a mesh without those coordinates.
    /// Degenerate texture coordinates or normals give zero tangents, never NaNs.
    pub fn generate_tangents(&mut self, set: usize) {
        self.tangents = crate::tangents::vertex_tangents(self, set);
    }

    /// Bounds of the vertices the triangles use.
    pub fn bounds(&self) -> Aabb {
        // Written out: the `flatten` and `array::map` adapters are not inlined into these loops,
        // and they run over every vertex of every redefinition of an unstructured object.
        // Each triangle's own box first, so that the running bounds wait on one `min` and one
        // `max` per triangle, not per vertex.
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for &[a, b, c] in &self.indices {
            let (a, b, c) = (self.positions[a as usize], self.positions[b as usize], self.positions[c as usize]);
            lo = lo.min(a.min(b).min(c));
            hi = hi.max(a.max(b).max(c));
        }
        // No triangles leave it empty: `Aabb::EMPTY` is exactly this infinite inside-out box.
        Aabb { min: lo, max: hi }
    }

    /// Boxes that together hold every vertex the triangles use: the vertices' own box in each
    /// occupied cell of a [`COVER_CELLS`]³ grid over `bounds` (the mesh's [`Mesh::bounds`]).
    /// Turned by a rotation, the box around these is much tighter than the box around the
    /// turned `bounds`, whose corners stick out past the geometry.
    pub(crate) fn cover(&self, bounds: &Aabb) -> Vec<Aabb> {
        const N: u32 = COVER_CELLS;
        if bounds.is_empty() {
            return Vec::new();
        }
        // A flat side has one layer of cells (the guard keeps the scale finite).
        let scale = Vec3::splat(N as f32) / bounds.extent().max(Vec3::splat(f32::MIN_POSITIVE));
        let mut cells = [Aabb::EMPTY; (N * N * N) as usize];
        for corners in &self.indices {
            for &v in corners {
                let p = self.positions[v as usize];
                let cell = ((p - bounds.min) * scale).as_uvec3().min(UVec3::splat(N - 1));
                let slot = &mut cells[(cell.x + N * (cell.y + N * cell.z)) as usize];
                *slot = slot.grow(p);
            }
        }
        cells.into_iter().filter(|c| !c.is_empty()).collect()
    }

    /// The vertices of triangle `prim`.
    #[inline]
    pub fn triangle(&self, prim: u32) -> [Vec3; 3] {
        let [a, b, c] = self.indices[prim as usize];
        [self.positions[a as usize], self.positions[b as usize], self.positions[c as usize]]
    }
}

/// The first index at which `ok` is false, as an error about `field`.
fn finite(field: &'static str, ok: impl Iterator<Item = bool>) -> Result<(), SceneError> {
    match ok.enumerate().find(|(_, ok)| !ok) {
        Some((index, _)) => Err(SceneError::NotFinite { field, index }),
        None => Ok(()),
    }
}

impl TriangleSource for Mesh {
    fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    #[inline]
    fn triangle(&self, index: u32) -> [Vec3; 3] {
        Mesh::triangle(self, index)
    }

    #[inline]
    fn prefetch(&self, index: u32, vertices: bool) {
        raystage_kernel::prefetch_indexed(&self.positions, &self.indices, index, vertices);
    }
}
