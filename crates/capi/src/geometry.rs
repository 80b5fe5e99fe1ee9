//! Issuing geometry into the object being defined, as in OpenGL: `rtBegin`/`rtEnd` with the
//! current normal, colour and texture coordinates attached to each `rtVertex3f`, or whole meshes
//! with `rtTriangleMesh`. Vertices and normals are transformed by the modelview matrix and
//! texture coordinates by the texture matrix in force when they are issued (as display lists
//! record them), and each triangle refers to the shader bound when it was issued.

use glam::{Vec2, Vec3};
use raystage_scene::ShaderId;

use crate::abi::enums::{RT_FLAT, RT_MAX_COORDINATE, RT_SMOOTH};
use crate::abi::types::RTenum;
use crate::assembly::{Assembled, PrimitiveMode};
use crate::builder::{Primitive, Vertex};
use crate::context::Context;
use crate::error::{Error, finite};
use crate::matrix::normal_transform;

/// The attributes the next vertex takes (OpenGL's current normal, colour, texture coordinates).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CurrentVertex {
    pub normal: Vec3,
    pub color: Vec3,
    /// `rtColor4f`'s alpha: state only (raystage blends nothing), read back by `rtGetFloatv`.
    pub alpha: f32,
    pub uv: Vec2,
}

impl Default for CurrentVertex {
    /// OpenGL's initial state: normal +z, opaque white, texture coordinates (0, 0).
    fn default() -> Self {
        CurrentVertex { normal: Vec3::Z, color: Vec3::ONE, alpha: 1.0, uv: Vec2::ZERO }
    }
}

/// A bulk mesh for `rtTriangleMesh`, borrowed from the application. Attribute arrays are empty
/// when not given; otherwise they have one entry per vertex.
pub(crate) struct MeshArrays<'a> {
    pub positions: &'a [[f32; 3]],
    pub normals: &'a [[f32; 3]],
    pub colors: &'a [[f32; 3]],
    pub uvs: &'a [[f32; 2]],
    pub indices: &'a [[u32; 3]],
}

impl Context {
    /// `rtBegin`: starts a primitive in the object being defined.
    pub fn begin(&mut self, mode: RTenum) -> Result<(), Error> {
        self.definition("rtBegin")?;
        let mode = PrimitiveMode::from_enum(mode)?;
        let shader = self.geometry_shader()?;
        let flat = self.flat;
        let definition = self.definition("rtBegin")?;
        definition.primitive = Some(Primitive { mode, shader, flat, vertices: Vec::new() });
        Ok(())
    }

    /// `rtEnd`: assembles the primitive's triangles into the object.
    pub fn end(&mut self) -> Result<(), Error> {
        match self.definition.as_mut() {
            Some(d) if d.primitive.is_some() => d.end_primitive(),
            _ => Err(Error::invalid_operation("rtEnd without rtBegin")),
        }
    }

    /// `rtVertex3f`: adds a vertex with the current attributes to the primitive.
    pub fn vertex(&mut self, position: [f32; 3]) -> Result<(), Error> {
        if !self.in_primitive() {
            return Err(Error::invalid_operation("a vertex outside rtBegin/rtEnd"));
        }
        finite("(x, y, z)", &position)?;
        let vertex = self.issue(Vec3::from(position), self.current)?;
        self.definition("rtVertex3f")?.push_vertex(vertex)
    }

    /// `rtNormal3f`: sets the current normal (any length). Once set during an object's
    /// definition, the object stores a normal per vertex.
    pub fn normal(&mut self, normal: [f32; 3]) -> Result<(), Error> {
        finite("(nx, ny, nz)", &normal)?;
        self.current.normal = Vec3::from(normal);
        if let Some(d) = self.definition.as_mut() {
            d.uses.normals = true;
        }
        Ok(())
    }

    /// `rtColor3f`: sets the current colour (linear RGB). Once set during an object's definition,
    /// the object stores a colour per vertex.
    pub fn color(&mut self, color: [f32; 3]) -> Result<(), Error> {
        self.color_alpha(color, 1.0)
    }

    /// `rtColor4f`: sets the current colour and alpha (`rtColor3f` sets alpha 1, as OpenGL's
    /// `glColor3f` does).
    pub fn color_alpha(&mut self, color: [f32; 3], alpha: f32) -> Result<(), Error> {
        finite("(r, g, b)", &color)?;
        finite("alpha", &[alpha])?;
        (self.current.color, self.current.alpha) = (Vec3::from(color), alpha);
        if let Some(d) = self.definition.as_mut() {
            d.uses.colors = true;
        }
        Ok(())
    }

    /// `rtTexCoord2f`: sets the current texture coordinates. Once set during an object's
    /// definition, the object stores texture coordinates per vertex.
    pub fn tex_coord(&mut self, uv: [f32; 2]) -> Result<(), Error> {
        finite("(s, t)", &uv)?;
        self.current.uv = Vec2::from(uv);
        if let Some(d) = self.definition.as_mut() {
            d.uses.uvs = true;
        }
        Ok(())
    }

    /// `rtShadeModel`: flat or smooth shading for the primitives issued from now on.
    pub fn shade_model(&mut self, mode: RTenum) -> Result<(), Error> {
        self.flat = match mode {
            RT_FLAT => true,
            RT_SMOOTH => false,
            _ => return Err(Error::invalid_enum(format!("{mode:#x} is not a shade model (RT_FLAT or RT_SMOOTH)"))),
        };
        Ok(())
    }

    /// `rtTriangleMesh`: adds an indexed mesh to the object being defined, with the current
    /// matrices, shader and shade model; vertices without a normal, colour or texture coordinate
    /// array take the current one. Checks everything before adding anything.
    pub fn triangle_mesh(&mut self, mesh: &MeshArrays<'_>) -> Result<(), Error> {
        self.definition("rtTriangleMesh")?;
        let shader = self.geometry_shader()?;
        let n = mesh.positions.len();
        if let Some((t, &i)) = mesh.indices.iter().enumerate().find_map(|(t, tri)| tri.iter().find(|&&i| i as usize >= n).map(|i| (t, i))) {
            return Err(Error::invalid_value(format!("triangle {t} uses vertex {i}, but there are {n} vertices")));
        }
        for (what, values) in [
            ("positions", mesh.positions.as_flattened()),
            ("normals", mesh.normals.as_flattened()),
            ("colors", mesh.colors.as_flattened()),
            ("texcoords", mesh.uvs.as_flattened()),
        ] {
            finite(what, values)?;
        }
        let mut vertices = Vec::new();
        vertices.try_reserve_exact(n).map_err(|_| Error::out_of_memory(format!("no memory for {n} vertices")))?;
        for i in 0..n {
            let attributes = CurrentVertex {
                normal: mesh.normals.get(i).map_or(self.current.normal, |&n| Vec3::from(n)),
                color: mesh.colors.get(i).map_or(self.current.color, |&c| Vec3::from(c)),
                uv: mesh.uvs.get(i).map_or(self.current.uv, |&uv| Vec2::from(uv)),
                ..self.current
            };
            vertices.push(self.issue(Vec3::from(mesh.positions[i]), attributes)?);
        }
        let triangles: Vec<Assembled> =
            mesh.indices.iter().map(|t| Assembled { corners: t.map(|i| i as usize), provoking: t[2] as usize }).collect();
        let flat = self.flat;
        let definition = self.definition("rtTriangleMesh")?;
        definition.add(&vertices, &triangles, shader, flat)?;
        let uses = &mut definition.uses;
        uses.normals |= !mesh.normals.is_empty();
        uses.colors |= !mesh.colors.is_empty();
        uses.uvs |= !mesh.uvs.is_empty();
        Ok(())
    }

    /// A vertex at `position` with `attributes`, through the current matrices.
    fn issue(&self, position: Vec3, attributes: CurrentVertex) -> Result<Vertex, Error> {
        let modelview = self.matrices.modelview.top();
        let vertex = Vertex {
            position: modelview.transform_point3(position),
            normal: normal_transform(&modelview) * attributes.normal,
            color: attributes.color,
            uv: self.matrices.transform_uv(attributes.uv),
        };
        if !(vertex.position.is_finite() && vertex.normal.is_finite() && vertex.uv.is_finite()) {
            return Err(Error::invalid_value("the vertex is not finite once transformed by the current matrices"));
        }
        if vertex.position.abs().max_element() > RT_MAX_COORDINATE {
            return Err(Error::invalid_value(format!(
                "the vertex is at {}, beyond RT_MAX_COORDINATE ({RT_MAX_COORDINATE:e}) once transformed by the modelview matrix",
                format_point(vertex.position)
            )));
        }
        Ok(vertex)
    }

    /// The shader new triangles get: the bound shader, which must be a surface shader.
    fn geometry_shader(&self) -> Result<Option<ShaderId>, Error> {
        match self.shaders.bound_surface() {
            Ok(shader) => Ok(shader),
            Err(light) => Err(Error::invalid_operation(format!(
                "the bound shader {light} is a light shader: bind a surface shader (or 0) before issuing geometry"
            ))),
        }
    }
}

/// A point in a message, its coordinates in scientific notation (huge ones stay readable).
fn format_point(p: Vec3) -> String {
    format!("({:e}, {:e}, {:e})", p.x, p.y, p.z)
}
