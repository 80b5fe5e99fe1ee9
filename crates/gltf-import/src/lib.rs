//! # raystage-gltf-import
//!
//! Reads a glTF 2.0 file (`.gltf` JSON or binary `.glb`) into raystage's retained scene: each
//! glTF mesh becomes one object (its primitives' triangles together, each bound to the shader of
//! its material), each node that holds a mesh becomes an instance with the node's world
//! transform, each material becomes a `PhysicallyBased` shader (see [`shader_for`]) with its
//! images as textures, and `KHR_lights_punctual` lights and
//! the first perspective camera come along. What a material has that is not rendered yet is a
//! note ([`notes`]). Animations, skins and morph targets become the scene's rig
//! ([`raystage_scene::Rig`], posed by [`raystage_scene::Scene::pose`]): a mesh that only node
//! animation moves is an animated object, a skinned or morphed one an unstructured object per
//! node that holds it.
//!
//! Reading and adding are two steps: [`read`] checks everything (buffer bounds, accessor types,
//! indices, numbers, sizes) and returns an [`Import`] that no longer refers to the file, and
//! [`Import::add_to`] puts it into a scene. A file that [`read`] accepted cannot fail half-way
//! into a scene, and nothing a file contains can panic the reader.
//!
//! Vertices may be quantised (`KHR_mesh_quantization`) and buffers compressed by meshoptimizer
//! (`EXT_meshopt_compression`, `KHR_meshopt_compression`), as `gltfpack` writes files; a
//! node's mesh may be repeated by `EXT_mesh_gpu_instancing`, one instance per element.
//!
//! Not in here: `KHR_materials_volume`'s thickness texture and the clearcoat's normal texture,
//! texture coordinate sets beyond the second, `KHR_animation_pointer`, animated cameras and
//! lights, points and lines, Draco-compressed meshes and Basis or WebP textures (a file that
//! requires them is refused, naming the extension).

mod accessor;
mod animation;
mod buffers;
mod compressed;
mod error;
mod images;
mod import;
mod material;
mod mesh;
mod nodes;

use std::path::Path;

pub use error::ImportError;
pub use import::{Added, Import};
pub use material::{ShaderSpec, TextureUse, notes, shader_for};

/// Limits on what a file may ask for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Most triangles over all meshes (an instanced mesh counts once).
    pub max_triangles: usize,
    /// Most vertices over all meshes.
    pub max_vertices: usize,
    /// Most instances (nodes with a mesh, counted along every path from a root).
    pub max_instances: usize,
    /// Most texels on either side of a texture's image.
    pub max_image_side: usize,
    /// Most bytes one texture's image may take decoded, counted from its header before it is
    /// decoded as width × height × 16 (three colour channels and coverage, as `f32`): a small
    /// PNG of a large, flat image would otherwise cost gigabytes.
    pub max_image_bytes: usize,
    /// Most bytes all the file's images may take decoded together, counted as
    /// `max_image_bytes` is, before any is decoded.
    pub max_images_bytes: usize,
    /// Most bytes the buffers that a file's compressed views decode into may take together
    /// (`EXT_meshopt_compression`'s fallback buffers), counted from their declared sizes before
    /// any is made: a few kilobytes of compressed zeros could otherwise declare gigabytes.
    pub max_decompressed_bytes: usize,
    /// Longest the file's images may take to decode: none is started past it (they are decoded
    /// in parallel), and the import fails.
    pub max_decode_seconds: std::time::Duration,
}

impl Default for Limits {
    /// Four million triangles and vertices, a million instances, images of 8192 texels a side
    /// (a GiB decoded: the side's limit is the one that holds by default), 16 GiB of images
    /// together, 4 GiB of decompressed buffers, ten minutes of decoding.
    fn default() -> Limits {
        Limits {
            max_triangles: 4_000_000,
            max_vertices: 4_000_000,
            max_instances: 1_000_000,
            max_image_side: 8192,
            max_image_bytes: 8192 * 8192 * 16,
            max_images_bytes: 16 << 30,
            max_decompressed_bytes: 4 << 30,
            max_decode_seconds: std::time::Duration::from_secs(600),
        }
    }
}

/// Reads a glTF or GLB file from memory. `base` is the directory that relative buffer URIs are
/// resolved against; without one (an upload), only the GLB binary chunk and `data:` URIs are
/// read and any other URI is an error.
pub fn read(bytes: &[u8], base: Option<&Path>, limits: &Limits) -> Result<Import, ImportError> {
    // The reader checks every offset before it reads; the guard only turns a bug in a
    // dependency into an error instead of a crashed server.
    std::panic::catch_unwind(|| import::read(bytes, base, limits)).unwrap_or(Err(ImportError::Internal))
}

/// Reads a glTF or GLB file from disk, resolving its external buffers next to it.
pub fn read_file(path: &Path, limits: &Limits) -> Result<Import, ImportError> {
    let bytes = std::fs::read(path).map_err(|source| ImportError::Io { path: path.to_owned(), source })?;
    read(&bytes, Some(path.parent().unwrap_or(Path::new("."))), limits)
}

/// A binary glTF (`.glb`) of a JSON document and its binary buffer, as [`read`] takes it: the
/// 12-byte header, then the JSON chunk padded with spaces and the binary chunk padded with
/// zeros to four bytes each (glTF 2.0, §4.4).
pub fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |len: usize| len.next_multiple_of(4);
    let total = 12 + 8 + pad(json.len()) + 8 + pad(bin.len());
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    for (chunk, kind, fill) in [(json, b"JSON", b' '), (bin, b"BIN\0", 0)] {
        out.extend((pad(chunk.len()) as u32).to_le_bytes());
        out.extend(kind);
        out.extend(chunk);
        out.resize(out.len() + pad(chunk.len()) - chunk.len(), fill);
    }
    out
}
