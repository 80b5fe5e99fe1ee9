//! `/scenes/{scene}/gltf`: a glTF or GLB file added to a scene.

use axum::Json;
use axum::extract::State;
use glam::Vec3;
use raystage_scene::{Light, LightId, Scene, SceneError, studio_environment};
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};

use crate::config::Limits;
use crate::edit::{Applied, Blob, Edit};
use crate::error::{ApiError, ApiResult, ErrorBody};
use crate::extract::{Params, RawBody, Target};
use crate::state::AppState;

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

/// Options of an upload.
#[derive(Clone, Debug, Default, Deserialize, Serialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct GltfQuery {
    /// What to do with the camera; default `auto`.
    pub camera: Option<CameraChoice>,
    /// The environment that lights the scene besides the file's own lights: `studio` (the
    /// neutral studio glTF viewers light a file with), `none`, or a uniform radiance (`R,G,B`
    /// or one number). Default: the studio where neither the file nor the scene has lights of
    /// its own, else none. (An image environment of your own is an `EnvironmentLight` with a
    /// texture, `POST /scenes/{scene}/lights`.)
    pub environment: Option<String>,
}

/// An environment an `environment` query parameter asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Environment {
    /// The studio ([`studio_environment`]).
    Studio,
    /// None at all, not even the default.
    None,
    /// The same radiance from every direction.
    Uniform(Vec3),
}

/// Parses an `environment` query parameter (422 naming it unless it is `studio`, `none`, or one
/// or three finite radiances, none negative).
pub(crate) fn parse_environment(text: &str) -> ApiResult<Environment> {
    match text {
        "studio" => return Ok(Environment::Studio),
        "none" => return Ok(Environment::None),
        _ => {}
    }
    let wrong = || {
        ApiError::unprocessable(Some("environment".into()), format!("environment `{text}` is neither studio, none nor a radiance: one number or R,G,B, none negative"))
    };
    let values: Vec<f32> = text.split(',').map(|v| v.trim().parse::<f32>()).collect::<Result<_, _>>().map_err(|_| wrong())?;
    let radiance = match values[..] {
        [v] => Vec3::splat(v),
        [r, g, b] => Vec3::new(r, g, b),
        _ => return Err(wrong()),
    };
    if !(radiance.is_finite() && radiance.min_element() >= 0.0) {
        return Err(wrong());
    }
    Ok(Environment::Uniform(radiance))
}

/// Adds the environment `asked` for to `scene`, or, where none was asked for and `unlit` (a
/// glTF file without lights went into a scene without lights), the studio, as glTF viewers light
/// such a file. Returns the light added, if any.
pub(crate) fn add_environment(scene: &mut Scene, asked: Option<Environment>, unlit: bool) -> Result<Option<LightId>, SceneError> {
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

/// The importer's limits, from the server's: a file's images together may take no more than a
/// scene may hold, checked from their headers before any is decoded, and no longer to decode
/// than a render may run.
pub(crate) fn import_limits(limits: &Limits) -> raystage_gltf_import::Limits {
    raystage_gltf_import::Limits {
        max_triangles: limits.max_triangles,
        max_vertices: limits.max_vertices,
        max_image_side: limits.max_dimension as usize,
        max_image_bytes: limits.max_texture_bytes,
        max_images_bytes: usize::try_from(limits.max_scene_bytes.min(limits.max_total_scene_bytes)).unwrap_or(usize::MAX),
        max_decode_seconds: std::time::Duration::from_secs(limits.max_render_seconds),
        ..raystage_gltf_import::Limits::default()
    }
}

/// Adds a glTF 2.0 file (`.glb`, or `.gltf` with its buffers as `data:` URIs) to the scene:
/// meshes become objects, nodes instances, materials shaders of the nearest class (base-colour
/// images textures), punctual lights lights. The whole file is checked before anything is added.
#[utoipa::path(post, path = "/scenes/{scene}/gltf", tag = "scenes",
    params(("scene" = u32, Path, description = "The scene's id"), GltfQuery),
    request_body(content((crate::model::Binary = "model/gltf-binary"), (crate::model::Binary = "model/gltf+json"))),
    responses(
        (status = 200, description = "Success", body = GltfAdded),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 413, description = "Larger than the server allows", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn upload(State(state): State<AppState>, target: Target, Params(query): Params<GltfQuery>, RawBody(body): RawBody) -> ApiResult<Json<GltfAdded>> {
    let limits = import_limits(&state.config().limits);
    let (body, import) = tokio::task::spawn_blocking(move || raystage_gltf_import::read(&body, None, &limits).map(|import| (body, import)))
        .await
        .map_err(|e| ApiError::internal(e.to_string()))??;
    // Checked before the edit, which then adds what was imported here.
    let edit = Edit::Gltf { file: Blob(body.into()), camera: query.camera.unwrap_or_default(), environment: query.environment, import: Some(Box::new(import)) };
    if let Edit::Gltf { environment: Some(text), .. } = &edit {
        parse_environment(text)?;
    }
    let (added, version) = match target.scene.edit(&state, edit).await? {
        (Applied::Gltf(added), version) => (added, version),
        _ => return Err(ApiError::internal("a glTF file gave back something else")),
    };
    Ok(Json(GltfAdded { version, ..added }))
}
