//! The object being defined between `rtNewObject` and `rtEndObject`: its vertices with their
//! attributes, its triangles with the shader bound when each was issued, and the primitive in
//! progress. `rtEndObject` turns it into a scene [`Mesh`].

use glam::{Vec2, Vec3};
use raystage_scene::{Mesh, ObjectId, ShaderId};

use crate::assembly::{Assembled, PrimitiveMode, assemble};
use crate::error::Error;

/// Most vertices one object can hold: the scene's indices are 32-bit.
const MAX_OBJECT_VERTICES: usize = u32::MAX as usize;

/// A vertex as issued: already transformed by the matrices in force when it was issued.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Vertex {
    pub position: Vec3,
    pub normal: Vec3,
    pub color: Vec3,
    pub uv: Vec2,
}

/// Which per-vertex attributes the object stores. An attribute is stored once the application
/// set it during the object's definition; otherwise the scene uses the face normal, no vertex
/// colour, no texture coordinates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Attributes {
    pub normals: bool,
    pub colors: bool,
    pub uvs: bool,
}

/// A primitive between `rtBegin` and `rtEnd`.
#[derive(Clone, Debug)]
pub(crate) struct Primitive {
    pub mode: PrimitiveMode,
    /// The shader bound at `rtBegin`, given to every triangle.
    pub shader: Option<ShaderId>,
    /// Flat shading was in force at `rtBegin`.
    pub flat: bool,
    pub vertices: Vec<Vertex>,
}

/// An object under definition.
#[derive(Debug)]
pub(crate) struct ObjectBuilder {
    pub id: ObjectId,
    pub uses: Attributes,
    pub primitive: Option<Primitive>,
    vertices: Vec<Vertex>,
    triangles: Vec<[u32; 3]>,
    shaders: Vec<Option<ShaderId>>,
}

impl ObjectBuilder {
    /// An empty definition of object `id`.
    pub fn new(id: ObjectId) -> ObjectBuilder {
        ObjectBuilder {
            id,
            uses: Attributes::default(),
            primitive: None,
            vertices: Vec::new(),
            triangles: Vec::new(),
            shaders: Vec::new(),
        }
    }

    /// Adds a vertex to the primitive in progress (which the caller checked exists).
    pub fn push_vertex(&mut self, vertex: Vertex) -> Result<(), Error> {
        let pending = self.primitive.as_ref().map_or(0, |p| p.vertices.len());
        self.check_capacity(pending + 1)?;
        let primitive = self.primitive.as_mut().expect("the caller checked that a primitive is in progress");
        primitive.vertices.try_reserve(1).map_err(|_| out_of_memory(self.id))?;
        primitive.vertices.push(vertex);
        Ok(())
    }

    /// Ends the primitive in progress: assembles its triangles into the object.
    pub fn end_primitive(&mut self) -> Result<(), Error> {
        let primitive = self.primitive.take().expect("the caller checked that a primitive is in progress");
        let triangles = assemble(primitive.mode, primitive.vertices.len());
        let added = self.add(&primitive.vertices, &triangles, primitive.shader, primitive.flat);
        if added.is_err() {
            self.primitive = Some(primitive);
        }
        added
    }

    /// Adds triangles over `vertices` (indices into it), each with `shader`. Under flat shading
    /// each triangle gets vertices of its own that carry its provoking vertex's normal and colour.
    /// Adds nothing if it fails.
    pub fn add(&mut self, vertices: &[Vertex], triangles: &[Assembled], shader: Option<ShaderId>, flat: bool) -> Result<(), Error> {
        if triangles.is_empty() {
            return Ok(());
        }
        let new_vertices = if flat { 3 * triangles.len() } else { vertices.len() };
        self.check_capacity(new_vertices)?;
        let oom = |_| out_of_memory(self.id);
        self.vertices.try_reserve(new_vertices).map_err(oom)?;
        self.triangles.try_reserve(triangles.len()).map_err(oom)?;
        self.shaders.try_reserve(triangles.len()).map_err(oom)?;
        let base = self.vertices.len();
        if flat {
            for t in triangles {
                let p = vertices[t.provoking];
                self.vertices.extend(t.corners.map(|c| Vertex { normal: p.normal, color: p.color, ..vertices[c] }));
            }
            self.triangles.extend((0..triangles.len()).map(|i| [0, 1, 2].map(|k| (base + 3 * i + k) as u32)));
        } else {
            self.vertices.extend_from_slice(vertices);
            self.triangles.extend(triangles.iter().map(|t| t.corners.map(|c| (base + c) as u32)));
        }
        self.shaders.extend(std::iter::repeat_n(shader, triangles.len()));
        Ok(())
    }

    /// Number of triangles so far.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The shader of each triangle, `None` where none was bound or where `live` says the shader
    /// was deleted since.
    pub fn triangle_shaders(&self, live: impl Fn(ShaderId) -> bool) -> Vec<Option<ShaderId>> {
        self.shaders.iter().map(|s| s.filter(|&s| live(s))).collect()
    }

    /// The scene mesh. `shaders` comes from [`ObjectBuilder::triangle_shaders`]; triangles without
    /// one get `fallback`, which must be given if some triangles have a shader and some do not.
    pub fn into_mesh(self, shaders: Vec<Option<ShaderId>>, fallback: Option<ShaderId>) -> Mesh {
        let uses = self.uses;
        let attribute = |used: bool, get: fn(&Vertex) -> Vec3| if used { self.vertices.iter().map(get).collect() } else { Vec::new() };
        let normals = attribute(uses.normals, |v| v.normal);
        let colors = attribute(uses.colors, |v| v.color);
        let uvs = if uses.uvs { self.vertices.iter().map(|v| v.uv).collect() } else { Vec::new() };
        let shaders = if shaders.iter().all(Option::is_none) {
            Vec::new()
        } else {
            shaders.into_iter().map(|s| s.or(fallback).expect("a fallback shader for unbound triangles")).collect()
        };
        let positions = self.vertices.iter().map(|v| v.position).collect();
        Mesh { positions, indices: self.triangles, normals, colors, uvs, shaders, ..Mesh::default() }
    }

    fn check_capacity(&self, more: usize) -> Result<(), Error> {
        if more > MAX_OBJECT_VERTICES - self.vertices.len() {
            return Err(Error::out_of_memory(format!(
                "object {} would have more than {MAX_OBJECT_VERTICES} vertices",
                crate::ids::to_c(self.id.0)
            )));
        }
        Ok(())
    }
}

fn out_of_memory(id: ObjectId) -> Error {
    Error::out_of_memory(format!("no memory for more geometry of object {}", crate::ids::to_c(id.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vertex(x: f32, normal: Vec3) -> Vertex {
        Vertex { position: Vec3::new(x, x * x, 0.0), normal, color: Vec3::splat(x), uv: Vec2::ZERO }
    }

    fn builder_with(mode: PrimitiveMode, flat: bool, vertices: &[Vertex], shader: Option<ShaderId>) -> ObjectBuilder {
        let mut b = ObjectBuilder::new(ObjectId(0));
        b.primitive = Some(Primitive { mode, shader, flat, vertices: Vec::new() });
        for &v in vertices {
            b.push_vertex(v).unwrap();
        }
        b.end_primitive().unwrap();
        b
    }

    #[test]
    fn smooth_primitives_share_vertices() {
        let vs: Vec<Vertex> = (0..4).map(|i| vertex(i as f32, Vec3::Z)).collect();
        let mut b = builder_with(PrimitiveMode::TriangleStrip, false, &vs, None);
        b.uses.normals = true;
        let shaders = b.triangle_shaders(|_| true);
        let mesh = b.into_mesh(shaders, None);
        assert_eq!(mesh.indices, [[0, 1, 2], [2, 1, 3]]);
        assert_eq!(mesh.positions.len(), 4);
        assert_eq!(mesh.normals, vec![Vec3::Z; 4]);
        assert!(mesh.colors.is_empty() && mesh.uvs.is_empty() && mesh.shaders.is_empty());
    }

    #[test]
    fn flat_primitives_take_the_provoking_vertex_attributes() {
        let vs = [vertex(0.0, Vec3::X), vertex(1.0, Vec3::Y), vertex(2.0, Vec3::Z), vertex(3.0, -Vec3::Z)];
        let mut b = builder_with(PrimitiveMode::Quads, true, &vs, None);
        b.uses = Attributes { normals: true, colors: true, uvs: false };
        let mesh = b.into_mesh(vec![None, None], None);
        assert_eq!(mesh.indices, [[0, 1, 2], [3, 4, 5]]);
        assert_eq!(mesh.normals, vec![-Vec3::Z; 6], "the quad's last vertex provokes");
        assert_eq!(mesh.colors, vec![Vec3::splat(3.0); 6]);
        assert_eq!(mesh.positions[4], vs[2].position);
    }

    #[test]
    fn unbound_triangles_beside_bound_ones_get_the_fallback() {
        let vs: Vec<Vertex> = (0..3).map(|i| vertex(i as f32, Vec3::Z)).collect();
        let mut b = builder_with(PrimitiveMode::Triangles, false, &vs, None);
        b.primitive = Some(Primitive { mode: PrimitiveMode::Triangles, shader: Some(ShaderId(4)), flat: false, vertices: vec![] });
        for &v in &vs {
            b.push_vertex(v).unwrap();
        }
        b.end_primitive().unwrap();
        assert_eq!(b.triangle_count(), 2);
        assert_eq!(b.triangle_shaders(|s| s != ShaderId(4)), [None, None], "a deleted shader counts as unbound");
        let shaders = b.triangle_shaders(|_| true);
        assert_eq!(b.into_mesh(shaders, Some(ShaderId(9))).shaders, [ShaderId(9), ShaderId(4)]);
    }

    #[test]
    fn leftover_vertices_add_no_triangles() {
        let vs: Vec<Vertex> = (0..2).map(|i| vertex(i as f32, Vec3::Z)).collect();
        let b = builder_with(PrimitiveMode::Polygon, false, &vs, None);
        assert_eq!(b.triangle_count(), 0);
        let mesh = b.into_mesh(Vec::new(), None);
        assert!(mesh.positions.is_empty(), "no triangle, no vertex");
    }
}
