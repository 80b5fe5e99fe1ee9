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
/// The classes and their parameters (3f: `rtParameter3f`, 1f: `rtParameter1f`, texture:
/// `rtParameterTexture`; colours are linear RGB, fractions 0 to 1; `rtGetShaderParameterDoc`
/// says each one's meaning, default and range at run time, and a name not listed is ignored):
///
/// Surface classes:
/// - "Diffuse": diffuse (3f, albedo), diffuse_texture (texture multiplying it).
/// - "VertexColor": diffuse (3f, multiplying the vertex colours).
/// - "Constant": color (3f, shown as it is, unlit).
/// - "Phong": diffuse (3f), specular (3f), shininess (1f, the Blinn-Phong exponent, 1 to 10000),
///   diffuse_texture. There is no "exponent".
/// - "Mirror": reflectance (3f).
/// - "Glossy": reflectance (3f), roughness (1f, GGX's α, 0.01 to 1; "Mirror" is its smooth limit).
/// - "Glass": ior (1f, 1 to 4), absorption (3f, per unit length inside).
/// - "Emissive": emission (3f, radiance from its front).
/// - "PhysicallyBased": glTF 2.0's metallic-roughness material; base_color (3f), metallic (1f),
///   roughness (1f), ior (1f), specular (1f), specular_color (3f, tinting the reflection
///   head-on), sheen_color (3f) and sheen_roughness (1f: cloth's rim of fibres), transmission (1f, the share of the dielectric base
///   refracted instead of diffusely reflected), thickness (1f: 0 a thin wall, else a volume
///   whose path length the geometry gives), attenuation_color (3f) and attenuation_distance (1f,
///   world units: the colour white light turns inside a volume after that distance), clearcoat
///   and clearcoat_roughness (1f: a clear coat of index 1.5 over it all),
///   emissive (3f, radiance), normal_scale (1f),
///   occlusion_strength (1f), opacity (1f), alpha_mode (1f: 0 opaque, 1 mask, 2 blend),
///   alpha_cutoff (1f), double_sided (1f: 1, the default, seen and emitting from both sides;
///   0 seen and emitting from the front only), and the textures base_color_texture,
///   metallic_roughness_texture (blue metallic, green roughness), normal_texture,
///   emissive_texture, occlusion_texture, and those of glTF's extensions, each multiplying its
///   factor: specular_texture (alpha), specular_color_texture (colour), transmission_texture
///   (red), clearcoat_texture (red), clearcoat_roughness_texture (green), sheen_color_texture
///   (colour), sheen_roughness_texture (alpha).
/// - "AmbientOcclusion": diffuse (3f), distance (1f, how far occluders count).
///
/// Every `X_texture` parameter comes with how it is sampled, all 1f: X_wrap_s and X_wrap_t
/// (`RT_REPEAT`, `RT_CLAMP_TO_EDGE`, `RT_MIRRORED_REPEAT`), X_filter (`RT_LINEAR`, `RT_NEAREST`),
/// X_texcoord (0 or 1: which texture coordinates), and the transform X_offset_u, X_offset_v,
/// X_rotation (radians), X_scale_u, X_scale_v.
///
/// Light classes, whose shaders light the scene while they exist, in world coordinates and
/// physical units (a diffuse surface of albedo ρ at distance d from a point light of intensity I,
/// facing it, reflects radiance ρ/π · I/d²):
/// - "PointLight": position (3f), intensity (3f, radiant intensity: the irradiance at distance 1).
/// - "SpotLight": position (3f), direction (3f, the cone's axis), intensity (3f), cone and
///   falloff (1f, half-angles in degrees: full light inside falloff, none outside cone).
/// - "DirectionalLight": direction (3f, the way the light travels, towards the scene: the
///   opposite of OpenGL's `GL_POSITION` with w = 0), intensity (3f, irradiance facing it).
/// - "AmbientLight": intensity (3f, irradiance added everywhere, unshadowed).
/// - "AreaLight": corner, edge_u, edge_v (3f: the parallelogram, emitting towards
///   edge_u × edge_v), radiance (3f).
/// - "EnvironmentLight": radiance (3f, from every direction), map (texture: a
///   latitude-longitude image, top row straight up, that the radiance scales), rotate (1f,
///   degrees the map turns about +y, counter-clockwise seen from above; default 0).
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
