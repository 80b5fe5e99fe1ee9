//! Geometry: primitives between `rtBegin` and `rtEnd`, vertex attributes, and bulk meshes. All
//! of it goes into the object being defined. Between `rtBegin` and `rtEnd` only `rtVertex*`,
//! `rtNormal*`, `rtColor*`, `rtTexCoord*`, `rtEnd`, `rtEndObject` (which ends the primitive
//! too), the `rtGet*` queries and the error calls are allowed.

use crate::abi::types::{RTdouble, RTenum, RTfloat, RTsizei, RTuint};
use crate::boundary::{array, call, call_in_primitive, slice};
use crate::error::single;
use crate::geometry::MeshArrays;

/// Starts a primitive: `RT_TRIANGLES`, `RT_TRIANGLE_STRIP`, `RT_TRIANGLE_FAN`, `RT_QUADS`,
/// `RT_QUAD_STRIP` or `RT_POLYGON` (convex). Its triangles get the shader bound now (which must
/// be a surface shader, or none). Only inside an object definition.
#[unsafe(no_mangle)]
pub extern "C" fn rtBegin(mode: RTenum) {
    call("rtBegin", |ctx| ctx.begin(mode))
}

/// Ends the primitive and adds its triangles to the object. Vertices that do not complete a
/// triangle or quadrilateral are ignored, as in OpenGL.
#[unsafe(no_mangle)]
pub extern "C" fn rtEnd() {
    call_in_primitive("rtEnd", |ctx| ctx.end())
}

/// Adds a vertex with the current normal, colour and texture coordinates to the primitive.
/// Once transformed by the modelview matrix, each coordinate must be within
/// ±`RT_MAX_COORDINATE` (`RT_INVALID_VALUE` beyond, and the vertex is not added).
#[unsafe(no_mangle)]
pub extern "C" fn rtVertex3f(x: RTfloat, y: RTfloat, z: RTfloat) {
    call_in_primitive("rtVertex3f", |ctx| ctx.vertex([x, y, z]))
}

/// `rtVertex3f(x, y, 0)`, as OpenGL's `glVertex2f`.
#[unsafe(no_mangle)]
pub extern "C" fn rtVertex2f(x: RTfloat, y: RTfloat) {
    call_in_primitive("rtVertex2f", |ctx| ctx.vertex([x, y, 0.0]))
}

/// `rtVertex3f` in double precision (converted to single: a coordinate beyond its range is
/// refused, and precision beyond it is lost).
#[unsafe(no_mangle)]
pub extern "C" fn rtVertex3d(x: RTdouble, y: RTdouble, z: RTdouble) {
    call_in_primitive("rtVertex3d", |ctx| ctx.vertex(single("(x, y, z)", [x, y, z])?))
}

/// `rtVertex3f` with the coordinates in an array of three.
///
/// # Safety
/// `v` must be NULL (an error) or point to three floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtVertex3fv(v: *const RTfloat) {
    // SAFETY: the caller's promise above.
    call_in_primitive("rtVertex3fv", |ctx| ctx.vertex(unsafe { array(v, "v")? }))
}

/// Sets the current normal (any length; the modelview matrix applies when a vertex is issued).
/// An object stores per-vertex normals once its definition sets one; otherwise it is shaded
/// with its faces' normals.
#[unsafe(no_mangle)]
pub extern "C" fn rtNormal3f(nx: RTfloat, ny: RTfloat, nz: RTfloat) {
    call_in_primitive("rtNormal3f", |ctx| ctx.normal([nx, ny, nz]))
}

/// `rtNormal3f` with the components in an array of three.
///
/// # Safety
/// `v` must be NULL (an error) or point to three floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtNormal3fv(v: *const RTfloat) {
    // SAFETY: the caller's promise above.
    call_in_primitive("rtNormal3fv", |ctx| ctx.normal(unsafe { array(v, "v")? }))
}

/// Sets the current colour (linear RGB, used by the "VertexColor" class). An object stores
/// per-vertex colours once its definition sets one.
#[unsafe(no_mangle)]
pub extern "C" fn rtColor3f(r: RTfloat, g: RTfloat, b: RTfloat) {
    call_in_primitive("rtColor3f", |ctx| ctx.color([r, g, b]))
}

/// `rtColor3f` with an alpha, as OpenGL's `glColor4f`: raystage blends nothing, so alpha is
/// kept only as state (`rtGetFloatv(RT_CURRENT_COLOR)`); it must be finite like the others.
#[unsafe(no_mangle)]
pub extern "C" fn rtColor4f(r: RTfloat, g: RTfloat, b: RTfloat, a: RTfloat) {
    call_in_primitive("rtColor4f", |ctx| ctx.color_alpha([r, g, b], a))
}

/// `rtColor3f` with the components in an array of three.
///
/// # Safety
/// `v` must be NULL (an error) or point to three floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtColor3fv(v: *const RTfloat) {
    // SAFETY: the caller's promise above.
    call_in_primitive("rtColor3fv", |ctx| ctx.color(unsafe { array(v, "v")? }))
}

/// Sets the current texture coordinates (the texture matrix applies when a vertex is issued).
/// An object stores per-vertex texture coordinates once its definition sets them.
#[unsafe(no_mangle)]
pub extern "C" fn rtTexCoord2f(s: RTfloat, t: RTfloat) {
    call_in_primitive("rtTexCoord2f", |ctx| ctx.tex_coord([s, t]))
}

/// `rtTexCoord2f` with the coordinates in an array of two.
///
/// # Safety
/// `v` must be NULL (an error) or point to two floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtTexCoord2fv(v: *const RTfloat) {
    // SAFETY: the caller's promise above.
    call_in_primitive("rtTexCoord2fv", |ctx| ctx.tex_coord(unsafe { array(v, "v")? }))
}

/// `RT_SMOOTH` (the default) interpolates normals and colours across triangles; with `RT_FLAT`
/// each triangle takes those of its primitive's provoking vertex, as in OpenGL (the last vertex
/// of each triangle or quadrilateral, the first of a polygon). Applies to primitives begun later.
#[unsafe(no_mangle)]
pub extern "C" fn rtShadeModel(mode: RTenum) {
    call("rtShadeModel", |ctx| ctx.shade_model(mode))
}

/// Adds an indexed triangle mesh to the object being defined, as if its triangles were issued
/// with `RT_TRIANGLES`: the current matrices, bound shader and shade model apply.
/// `positions` holds `vertex_count` × 3 floats; `normals` and `colors` (× 3) and `texcoords`
/// (× 2) may each be NULL, and the vertices then take the current normal, colour or texture
/// coordinates. `indices` holds `triangle_count` × 3 vertex indices, counter-clockwise seen from
/// the front. Everything is checked (indices in range, numbers finite) before anything is added.
///
/// # Safety
/// Each non-NULL pointer must point to as many values as described above.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtTriangleMesh(
    positions: *const RTfloat,
    normals: *const RTfloat,
    colors: *const RTfloat,
    texcoords: *const RTfloat,
    vertex_count: RTsizei,
    indices: *const RTuint,
    triangle_count: RTsizei,
) {
    call("rtTriangleMesh", |ctx| {
        let optional = |ptr: *const RTfloat| if ptr.is_null() { 0 } else { vertex_count };
        // SAFETY: the caller's promise above; `[f32; N]` has the alignment of `f32`.
        let mesh = unsafe {
            MeshArrays {
                positions: slice(positions.cast::<[f32; 3]>(), vertex_count, "positions")?,
                normals: slice(normals.cast::<[f32; 3]>(), optional(normals), "normals")?,
                colors: slice(colors.cast::<[f32; 3]>(), optional(colors), "colors")?,
                uvs: slice(texcoords.cast::<[f32; 2]>(), optional(texcoords), "texcoords")?,
                indices: slice(indices.cast::<[u32; 3]>(), triangle_count, "indices")?,
            }
        };
        ctx.triangle_mesh(&mesh)
    })
}
