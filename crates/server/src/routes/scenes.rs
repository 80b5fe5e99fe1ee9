//! `/scenes`: creating (empty, a built-in demo, or a glTF file), listing, describing and
//! deleting scenes, and their statistics.

use axum::Json;
use axum::extract::{FromRequest, Request, State};
use axum::http::{HeaderMap, StatusCode, header};
use raystage_scene::Scene;
use raystage_service::model::CameraJson;
use raystage_service::{AppState, Blob, Error, FrameReport, SceneBuild, SceneSlot, SceneStart, parse_environment};
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};

use crate::error::{ApiResult, ErrorBody};
use crate::extract::{Params, RawBody, Target, parse_json};

/// A new scene: empty, or a built-in demo. (To start from a glTF file, send the file itself
/// with content type `model/gltf-binary` or `model/gltf+json`.)
#[derive(Clone, Debug, Default, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct NewScene {
    /// A built-in scene: `spheres`, `soup`, `cornell`, `materials`, `robots`, `museum`,
    /// `museum-<triangles>`, `terrain`.
    pub demo: Option<String>,
    /// The frame of an animated demo; default 0.
    pub frame: Option<u32>,
}

/// Options of a new scene.
#[derive(Clone, Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct NewSceneQuery {
    /// The environment that lights the new scene besides its own lights: `studio` (the neutral
    /// studio glTF viewers light a file with), `none`, or a uniform radiance (`R,G,B` or one
    /// number). Default: the studio for a glTF file without lights of its own, else none.
    pub environment: Option<String>,
}

/// A scene at a glance.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct SceneInfo {
    /// Its id.
    pub id: u32,
    /// Where it came from: `empty`, `demo:<name>`, `gltf`.
    pub origin: String,
    /// Edits so far.
    pub version: u64,
    /// Objects defined.
    pub objects: usize,
    /// Instances placed.
    pub instances: usize,
    /// Lights.
    pub lights: usize,
    /// Textures.
    pub textures: usize,
    /// Triangles over all objects (each object counted once).
    pub triangles: usize,
    /// The memory its geometry, trees (counted as built) and images take, as the server's
    /// `max_scene_bytes` and `max_total_scene_bytes` budgets count it.
    pub memory_bytes: u64,
    /// The camera.
    pub camera: CameraJson,
}

/// A scene and its last frame's statistics.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct SceneStats {
    /// The scene.
    pub scene: SceneInfo,
    /// The last frame rendered (by `frame.png` or a stream), if any.
    pub last_frame: Option<FrameReport>,
}

pub(crate) fn info_of(slot: &SceneSlot, scene: &Scene, version: u64) -> SceneInfo {
    SceneInfo {
        id: slot.id,
        origin: slot.origin.clone(),
        version,
        objects: scene.object_ids().count(),
        instances: scene.instances().count(),
        lights: scene.lights().count(),
        textures: scene.textures().count(),
        triangles: scene.object_ids().filter_map(|id| scene.mesh(id).ok()).map(|m| m.indices.len()).sum(),
        memory_bytes: scene.memory_bytes(),
        camera: CameraJson::from(scene.camera()),
    }
}

/// Every scene.
#[utoipa::path(get, path = "/scenes", tag = "scenes", responses((status = 200, description = "Success", body = [SceneInfo])))]
pub(crate) async fn list(State(state): State<AppState>) -> ApiResult<Json<Vec<SceneInfo>>> {
    let mut out = Vec::new();
    for slot in state.scenes() {
        let s = slot.clone();
        out.push(slot.read(move |scene, version| info_of(&s, scene, version)).await?);
    }
    Ok(Json(out))
}

/// Creates a scene: empty (`{}` or no body), a built-in demo (`{"demo": "spheres"}`), or from
/// a glTF file sent as the body with content type `model/gltf-binary` or `model/gltf+json`
/// (the file's camera, or one that frames everything).
#[utoipa::path(post, path = "/scenes", tag = "scenes",
    params(NewSceneQuery),
    request_body(description = "Optional: no body makes an empty scene", content(
        (NewScene = "application/json"),
        (raystage_service::model::Binary = "model/gltf-binary"),
        (raystage_service::model::Binary = "model/gltf+json"),
    )),
    responses(
        (status = 201, description = "Created", body = SceneInfo),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 413, description = "Larger than the server allows", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn create(
    State(state): State<AppState>,
    Params(query): Params<NewSceneQuery>,
    headers: HeaderMap,
    request: Request,
) -> ApiResult<(StatusCode, Json<SceneInfo>)> {
    if let Some(text) = &query.environment {
        parse_environment(text)?;
    }
    let gltf = headers.get(header::CONTENT_TYPE).and_then(|v| v.to_str().ok()).is_some_and(|t| t.starts_with("model/gltf"));
    let body = RawBody::from_request(request, &state).await?.0;
    let limits = state.config().limits;
    state.check_room_for_scene()?;
    let start = if gltf {
        SceneStart::Gltf(Blob(body.into()))
    } else {
        let new: NewScene = if body.iter().all(u8::is_ascii_whitespace) { NewScene::default() } else { parse_json(&body)? };
        match new.demo {
            None if new.frame.is_some() => return Err(Error::bad_request(Some("frame".into()), "`frame` needs a `demo`").into()),
            None => SceneStart::Empty,
            Some(name) => SceneStart::Demo { name, frame: new.frame.unwrap_or(0) },
        }
    };
    let build = SceneBuild { start, environment: query.environment };
    // The same build, in a cluster, makes every worker's replica.
    let state_for_build = state.clone();
    let id = tokio::task::spawn_blocking(move || {
        let (scene, origin) = build.build(&limits)?;
        state_for_build.create_scene(scene, origin, &build)
    })
    .await
    .map_err(|e| Error::internal(e.to_string()))??;
    let slot = state.scene(id)?;
    let s = slot.clone();
    Ok((StatusCode::CREATED, Json(slot.read(move |scene, version| info_of(&s, scene, version)).await?)))
}

/// A scene at a glance.
#[utoipa::path(get, path = "/scenes/{scene}", tag = "scenes",
    params(("scene" = u32, Path, description = "The scene's id")),
    responses(
        (status = 200, description = "Success", body = SceneInfo),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn info(target: Target) -> ApiResult<Json<SceneInfo>> {
    let s = target.scene.clone();
    Ok(Json(target.scene.read(move |scene, version| info_of(&s, scene, version)).await?))
}

/// Deletes a scene.
#[utoipa::path(delete, path = "/scenes/{scene}", tag = "scenes",
    params(("scene" = u32, Path, description = "The scene's id")),
    responses(
        (status = 204, description = "Deleted"),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn delete(State(state): State<AppState>, target: Target) -> ApiResult<StatusCode> {
    state.delete_scene(target.scene.id).await?;
    Ok(StatusCode::NO_CONTENT)
}

/// The scene and the statistics of its last frame.
#[utoipa::path(get, path = "/scenes/{scene}/stats", tag = "scenes",
    params(("scene" = u32, Path, description = "The scene's id")),
    responses(
        (status = 200, description = "Success", body = SceneStats),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn stats(target: Target) -> ApiResult<Json<SceneStats>> {
    let s = target.scene.clone();
    let scene = target.scene.read(move |scene, version| info_of(&s, scene, version)).await?;
    let last_frame = target.scene.last_frame.lock().unwrap_or_else(|e| e.into_inner()).clone();
    Ok(Json(SceneStats { scene, last_frame }))
}
