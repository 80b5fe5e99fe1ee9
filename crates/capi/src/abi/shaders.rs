//! Shader classes and shaders: surface shaders for geometry, light shaders for lighting.

use std::ffi::c_char;

use crate::abi::types::{RTsizei, RTuint};
use crate::boundary::{call, text};

/// Reserves `n` consecutive shader class ids and returns the first (0 if `n` is 0 or on error).
#[unsafe(no_mangle)]
pub extern "C" fn rtGenShaderClasses(n: RTsizei) -> RTuint {
    call("rtGenShaderClasses", |ctx| ctx.gen_shader_classes(n))
}

/// Defines shader class `id` as the built-in class called `name` and binds it. `library` is the
/// OpenRT shader library to load it from; raystage's classes are built in, so it may be NULL and
/// is otherwise ignored. An unknown name records `RT_INVALID_VALUE` with the list of classes.
///
/// Surface classes (parameters in brackets) include "Diffuse" ("diffuse", and "diffuse_texture",
/// a texture multiplying it, written with `rtParameterTexture`), "VertexColor"
/// ("diffuse", multiplied by the vertex colours) and "Constant" ("color"); the message of an
/// unknown name lists them all. Light classes, whose shaders light the scene while they exist
/// (world coordinates, colours linear RGB): "PointLight" ("position", "intensity"), "SpotLight"
/// ("position", "direction", "intensity", and "cone" and "falloff" half-angles in degrees),
/// "DirectionalLight" ("direction", "intensity"), "AmbientLight" ("intensity"), "AreaLight"
/// ("corner", "edge_u", "edge_v", "radiance") and "EnvironmentLight" ("radiance", and "map", a
/// texture whose latitude-longitude image the radiance scales).
///
/// # Safety
/// `name` and `library` must each be NULL or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtNewShaderClass(id: RTuint, name: *const c_char, library: *const c_char) {
    let _ = library;
    // SAFETY: the caller's promise above.
    call("rtNewShaderClass", |ctx| ctx.new_shader_class(id, unsafe { text(name, "name")? }))
}

/// Binds shader class `id` (defined by `rtNewShaderClass`) for `rtNewShader`; 0 unbinds.
#[unsafe(no_mangle)]
pub extern "C" fn rtBindShaderClass(id: RTuint) {
    call("rtBindShaderClass", |ctx| ctx.bind_shader_class(id))
}

/// Reserves `n` consecutive shader ids and returns the first (0 if `n` is 0 or on error).
#[unsafe(no_mangle)]
pub extern "C" fn rtGenShaders(n: RTsizei) -> RTuint {
    call("rtGenShaders", |ctx| ctx.gen_shaders(n))
}

/// Defines shader `id` (from `rtGenShaders`) as a new shader of the bound class, every parameter
/// at its default, and binds it. If the id held a shader already, it is replaced: every triangle
/// bound to the id takes the new one.
#[unsafe(no_mangle)]
pub extern "C" fn rtNewShader(id: RTuint) {
    call("rtNewShader", |ctx| ctx.new_shader(id))
}

/// Binds shader `id` (defined by `rtNewShader`): triangles issued from now on refer to it, and
/// `rtParameter*` writes its parameters. 0 unbinds: triangles then get the default shader (matte
/// grey). Triangles store the id only, so changing the shader later changes them (late binding).
#[unsafe(no_mangle)]
pub extern "C" fn rtBindShader(id: RTuint) {
    call("rtBindShader", |ctx| ctx.bind_shader(id))
}

/// Deletes the shaders among ids `first` to `first + n - 1`: triangles bound to a deleted surface
/// shader get the default shader, and a deleted light shader's light goes out. The ids stay
/// generated (`rtNewShader` can define them again); a deleted bound shader is unbound.
#[unsafe(no_mangle)]
pub extern "C" fn rtDeleteShaders(first: RTuint, n: RTsizei) {
    call("rtDeleteShaders", |ctx| ctx.delete_shaders(first, n))
}
