//! glTF files added to a scene as the service adds them: the camera to see them through, the
//! environment to light them with, and the importer's limits from the server's.

use glam::Vec3;
use raystage_scene::{Light, LightId, Scene, SceneError, parse_color, studio_environment};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::config::Limits;
use crate::error::{Error, Result};

/// What to do with the camera.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum CameraChoice {
    /// The file's camera if it has one; else, if the scene had no instances before, one that
    /// frames the file's contents; else the scene's camera stays.
    #[default]
    Auto,
    /// The file's camera (the scene's stays if the file has none).
    File,
    /// A camera that frames the file's contents.
    Frame,
    /// The scene's camera stays.
    Keep,
}

/// An environment an `environment` query parameter asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Environment {
    /// The studio ([`studio_environment`]).
    Studio,
    /// None at all, not even the default.
    None,
    /// The same radiance from every direction.
    Uniform(Vec3),
}

/// Parses an `environment` query parameter (unprocessable, naming it, unless it is `studio`, `none`, or one
/// or three finite radiances, none negative).
pub fn parse_environment(text: &str) -> Result<Environment> {
    match text {
        "studio" => return Ok(Environment::Studio),
        "none" => return Ok(Environment::None),
        _ => {}
    }
    let wrong = || {
        Error::unprocessable(Some("environment".into()), format!("environment `{text}` is neither studio, none nor a radiance: one number or R,G,B, none negative"))
    };
    match parse_color(text) {
        Some(radiance) if radiance.is_finite() && radiance.min_element() >= 0.0 => Ok(Environment::Uniform(radiance)),
        _ => Err(wrong()),
    }
}

/// Adds the environment `asked` for to `scene`, or, where none was asked for and `unlit` (a
/// glTF file without lights went into a scene without lights), the studio, as glTF viewers light
/// such a file. Returns the light added, if any.
pub fn add_environment(scene: &mut Scene, asked: Option<Environment>, unlit: bool) -> Result<Option<LightId>, SceneError> {
    let light = match asked.unwrap_or(if unlit { Environment::Studio } else { Environment::None }) {
        Environment::None => return Ok(None),
        Environment::Uniform(radiance) => Light::Environment { radiance, map: None, rotate_degrees: 0.0 },
        Environment::Studio => return scene.add_environment_map(studio_environment(), Vec3::ONE, 0.0).map(Some),
    };
    scene.add_light(light).map(Some)
}

/// What an upload added.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct GltfAdded {
    /// One shader per material (and vertex-colour use).
    pub shaders: Vec<u32>,
    /// One object per glTF mesh with triangles.
    pub objects: Vec<u32>,
    /// One instance per node holding such a mesh.
    pub instances: Vec<u32>,
    /// The file's punctual lights, and the environment the query asked for (or the default
    /// studio).
    pub lights: Vec<u32>,
    /// Whether the camera changed.
    pub camera_changed: bool,
    /// Triangles added.
    pub triangles: usize,
    /// What the file had that was left out.
    pub notes: Vec<String>,
    /// The scene's version after the upload.
    pub version: u64,
}

/// The importer's limits, from the server's: a file's images together, and its decompressed
/// buffers, may take no more than a scene may hold, checked before any is decoded, and no
/// longer to decode than a render may run.
pub fn import_limits(limits: &Limits) -> raystage_gltf_import::Limits {
    raystage_gltf_import::Limits {
        max_triangles: limits.max_triangles,
        max_vertices: limits.max_vertices,
        max_image_side: limits.max_dimension as usize,
        max_image_bytes: limits.max_texture_bytes,
        max_images_bytes: usize::try_from(limits.max_scene_bytes.min(limits.max_total_scene_bytes)).unwrap_or(usize::MAX),
        max_decompressed_bytes: usize::try_from(limits.max_scene_bytes.min(limits.max_total_scene_bytes)).unwrap_or(usize::MAX),
        max_decode_seconds: std::time::Duration::from_secs(limits.max_render_seconds),
        ..raystage_gltf_import::Limits::default()
    }
}
