//! Textures, named, bound and given images as in OpenGL (`rtGenTextures`, `rtBindTexture`,
//! `rtTexImage2D`), plus image files and procedural textures. A texture colours surfaces
//! through a shader's texture parameter ("diffuse_texture" of "Diffuse", written with
//! `rtParameterTexture`), or lights the scene as the "map" of an "EnvironmentLight" (a
//! latitude-longitude image, its top row straight up). Textures are looked up by id when a
//! frame starts, so redefining one changes everything that uses it.

use std::ffi::{c_char, c_void};
use std::path::Path;

use raystage_scene::Texture;

use crate::abi::types::{RTenum, RTfloat, RTint, RTsizei, RTuint};
use crate::boundary::{array, c_str, call, slice};
use crate::error::Error;
use crate::textures::PixelLayout;

/// Sets a sampling parameter of the bound texture, as OpenGL's `glTexParameteri`:
/// `RT_TEXTURE_WRAP_S` and `RT_TEXTURE_WRAP_T` (`RT_REPEAT`, `RT_CLAMP_TO_EDGE`,
/// `RT_MIRRORED_REPEAT`), `RT_TEXTURE_MAG_FILTER` (`RT_NEAREST`, `RT_LINEAR`) and
/// `RT_TEXTURE_MIN_FILTER` (accepted, without effect). `target` is `RT_TEXTURE_2D`. A texture
/// is sampled with its parameters by every shader that uses it, now or later (shaders of
/// classes with texture samplers, such as "Diffuse", "Phong" and "PhysicallyBased"; the
/// parameters are written to the shader's `{slot}_wrap_s`, `{slot}_wrap_t` and `{slot}_filter`,
/// and `rtParameterTexture` writes them too). Another `pname` or value records
/// `RT_INVALID_ENUM`; no bound texture `RT_INVALID_OPERATION`.
#[unsafe(no_mangle)]
pub extern "C" fn rtTexParameteri(target: RTenum, pname: RTenum, param: RTint) {
    call("rtTexParameteri", |ctx| ctx.tex_parameter(target, pname, param))
}

/// Reserves `n` consecutive texture ids and returns the first (0 if `n` is 0 or on error).
#[unsafe(no_mangle)]
pub extern "C" fn rtGenTextures(n: RTsizei) -> RTuint {
    call("rtGenTextures", |ctx| ctx.gen_textures(n))
}

/// Binds texture `texture` (from `rtGenTextures`) for the calls that define it: `rtTexImage2D`,
/// `rtTexImageFile`, `rtTexChecker`, `rtTexNoise`. 0 unbinds. `target` is `RT_TEXTURE_2D`.
#[unsafe(no_mangle)]
pub extern "C" fn rtBindTexture(target: RTenum, texture: RTuint) {
    call("rtBindTexture", |ctx| ctx.bind_texture(target, texture))
}

/// Gives the bound texture an image of `width` × `height` pixels (each side 1 to
/// `RT_MAX_TEXTURE_SIZE`), rows from the top, copied from `pixels`: OpenGL's call and meaning.
/// `target` is `RT_TEXTURE_2D`, `level` and `border` 0. `format` is `RT_LUMINANCE`, `RT_RGB` or
/// `RT_RGBA` (alpha ignored) and `type` `RT_UNSIGNED_BYTE` or `RT_FLOAT` (linear values, any
/// non-negative number, for high dynamic range). Bytes are linear (byte ÷ 255) unless
/// `internalformat` is `RT_SRGB8` or `RT_SRGB8_ALPHA8`, which decode sRGB-encoded bytes (as
/// photographs hold them) to linear light; other internal formats: `RT_RGB`, `RT_RGBA`,
/// `RT_RGB8`, `RT_RGBA8`, `RT_RGB32F`, `RT_RGBA32F`, `RT_LUMINANCE`.
///
/// # Safety
/// `pixels` must be NULL (an error) or point to `width × height` pixels of the given format and
/// type, with no padding between rows.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments, reason = "OpenGL's glTexImage2D, argument for argument")]
pub unsafe extern "C" fn rtTexImage2D(
    target: RTenum,
    level: RTint,
    internalformat: RTint,
    width: RTsizei,
    height: RTsizei,
    border: RTint,
    format: RTenum,
    r#type: RTenum,
    pixels: *const c_void,
) {
    call("rtTexImage2D", |ctx| {
        let layout = PixelLayout::of(internalformat, format, r#type)?;
        let size = (crate::textures::check_size("width", width)?, crate::textures::check_size("height", height)?);
        let bytes = (size.0 as usize * size.1 as usize)
            .checked_mul(layout.pixel_bytes())
            .ok_or_else(|| Error::invalid_value("the image is larger than memory"))?;
        // SAFETY: the caller's promise above; bytes have no alignment to check.
        let pixels = unsafe { slice(pixels.cast::<u8>(), bytes, "pixels")? };
        ctx.tex_image(target, level, border, size, layout, pixels)
    })
}

/// Gives the bound texture the image in the file at `path`: PNG, JPEG, WebP or Radiance HDR
/// (`.hdr`), told apart by their contents. PNG and JPEG values are sRGB-encoded and decoded to
/// linear light; HDR values are linear. A file that cannot be read records `RT_IO_ERROR`; one
/// that is not such an image, or is wider or taller than `RT_MAX_TEXTURE_SIZE`,
/// `RT_INVALID_VALUE`. `target` is `RT_TEXTURE_2D`.
///
/// # Safety
/// `path` must be NULL (an error) or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtTexImageFile(target: RTenum, path: *const c_char) {
    call("rtTexImageFile", |ctx| {
        // SAFETY: the caller's promise above.
        let path = unsafe { c_str(path, "path")? };
        let path = path.to_str().map_err(|_| Error::invalid_value("path is not valid UTF-8"))?;
        ctx.tex_image_file(target, Path::new(path))
    })
}

/// Makes the bound texture a 3D checkerboard of cubes of edge `1 / scale` alternating colours
/// `a` and `b` (linear RGB), in texture coordinates where the mesh has them, else in object
/// space. `scale` must be positive. `target` is `RT_TEXTURE_2D`.
///
/// # Safety
/// `a` and `b` must each be NULL (an error) or point to three floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtTexChecker(target: RTenum, a: *const RTfloat, b: *const RTfloat, scale: RTfloat) {
    call("rtTexChecker", |ctx| {
        // SAFETY: the caller's promise above.
        let (a, b) = unsafe { (array::<f32, 3>(a, "a")?, array::<f32, 3>(b, "b")?) };
        ctx.tex_procedural(target, "rtTexChecker", |a, b, scale| Texture::Checker { a, b, scale }, a, b, scale)
    })
}

/// Makes the bound texture solid noise (Perlin's gradient noise, several octaves) blending
/// colour `a` into `b` (linear RGB), with `scale` features per unit length in object space.
/// `scale` must be positive. `target` is `RT_TEXTURE_2D`.
///
/// # Safety
/// `a` and `b` must each be NULL (an error) or point to three floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rtTexNoise(target: RTenum, a: *const RTfloat, b: *const RTfloat, scale: RTfloat) {
    call("rtTexNoise", |ctx| {
        // SAFETY: the caller's promise above.
        let (a, b) = unsafe { (array::<f32, 3>(a, "a")?, array::<f32, 3>(b, "b")?) };
        ctx.tex_procedural(target, "rtTexNoise", |a, b, scale| Texture::Noise { a, b, scale }, a, b, scale)
    })
}

/// Deletes the textures among ids `first` to `first + n - 1`: shaders and lights that use one
/// look untextured from the next frame on. The ids stay generated (a `rtTex*` call can define
/// them again); a deleted bound texture is unbound.
#[unsafe(no_mangle)]
pub extern "C" fn rtDeleteTextures(first: RTuint, n: RTsizei) {
    call("rtDeleteTextures", |ctx| ctx.delete_textures(first, n))
}
