//! `/scenes/{scene}/gltf`: a glTF or GLB file added to a scene.

use axum::Json;
use axum::extract::State;
use raystage_service::{AppState, Applied, Blob, CameraChoice, Edit, Error, GltfAdded, import_limits, parse_environment};
use serde::{Deserialize, Serialize};
use utoipa::IntoParams;

use crate::error::{ApiResult, ErrorBody};
use crate::extract::{Params, RawBody, Target};

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

/// Adds a glTF 2.0 file (`.glb`, or `.gltf` with its buffers as `data:` URIs) to the scene:
/// meshes become objects, nodes instances, materials shaders of the nearest class (base-colour
/// images textures), punctual lights lights. The whole file is checked before anything is added.
#[utoipa::path(post, path = "/scenes/{scene}/gltf", tag = "scenes",
    params(("scene" = u32, Path, description = "The scene's id"), GltfQuery),
    request_body(content((raystage_service::model::Binary = "model/gltf-binary"), (raystage_service::model::Binary = "model/gltf+json"))),
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
        .map_err(|e| Error::internal(e.to_string()))?
        .map_err(Error::from)?;
    // Checked before the edit, which then adds what was imported here.
    let edit = Edit::Gltf { file: Blob(body.into()), camera: query.camera.unwrap_or_default(), environment: query.environment, import: Some(Box::new(import)) };
    if let Edit::Gltf { environment: Some(text), .. } = &edit {
        parse_environment(text)?;
    }
    let (added, version) = match target.scene.edit(&state, edit).await? {
        (Applied::Gltf(added), version) => (added, version),
        _ => return Err(Error::internal("a glTF file gave back something else").into()),
    };
    Ok(Json(GltfAdded { version, ..added }))
}
