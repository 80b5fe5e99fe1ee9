//! `/scenes/{scene}/camera`.

use axum::Json;
use axum::extract::State;
use raystage_service::model::{CameraJson, CameraPatch, Command};
use raystage_service::AppState;

use super::{Updated, update};
use crate::error::{ApiResult, ErrorBody};
use crate::extract::{JsonBody, Target};

/// The camera.
#[utoipa::path(get, path = "/scenes/{scene}/camera", tag = "camera",
    params(("scene" = u32, Path, description = "The scene's id")),
    responses(
        (status = 200, description = "Success", body = CameraJson),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn get(target: Target) -> ApiResult<Json<CameraJson>> {
    Ok(Json(target.scene.read(|scene, _| CameraJson::from(scene.camera())).await?))
}

/// Changes the camera: the fields given replace the camera's, the others stay.
#[utoipa::path(put, path = "/scenes/{scene}/camera", tag = "camera",
    params(("scene" = u32, Path, description = "The scene's id")),
    request_body = CameraPatch,
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn set(State(state): State<AppState>, target: Target, JsonBody(body): JsonBody<CameraPatch>) -> ApiResult<Json<Updated>> {
    update(&state, &target.scene, Command::SetCamera(body)).await
}
