//! `/scenes/{scene}/lights`: light sources, by the C ABI's light class names.

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use raystage_service::model::{Command, Delete, LightInfo, LightSpec, Ref, SetLight};
use raystage_service::{AppState, Error};

use super::{CreatedResponse, Updated, create, update};
use crate::error::{ApiError, ApiResult, ErrorBody};
use crate::extract::{JsonBody, Target};

async fn all(target: &Target) -> raystage_service::Result<Vec<LightInfo>> {
    target.scene.read(|scene, _| scene.lights().map(|(id, l)| LightInfo { id: id.0, light: LightSpec::from_light(l) }).collect()).await
}

/// Every light.
#[utoipa::path(get, path = "/scenes/{scene}/lights", tag = "lights",
    params(("scene" = u32, Path, description = "The scene's id")),
    responses(
        (status = 200, description = "Success", body = [LightInfo]),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn list(target: Target) -> ApiResult<Json<Vec<LightInfo>>> {
    Ok(Json(all(&target).await?))
}

/// Adds a light.
#[utoipa::path(post, path = "/scenes/{scene}/lights", tag = "lights",
    params(("scene" = u32, Path, description = "The scene's id")),
    request_body = LightSpec,
    responses(
        (status = 201, description = "Created", body = CreatedResponse),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn add(State(state): State<AppState>, target: Target, JsonBody(body): JsonBody<LightSpec>) -> ApiResult<(StatusCode, Json<CreatedResponse>)> {
    create(&state, &target.scene, Command::AddLight(body)).await
}

/// A light.
#[utoipa::path(get, path = "/scenes/{scene}/lights/{id}", tag = "lights",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The light's id")),
    responses(
        (status = 200, description = "Success", body = LightInfo),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn get(target: Target) -> ApiResult<Json<LightInfo>> {
    let id = target.id();
    all(&target).await?.into_iter().find(|l| l.id == id).map(Json).ok_or_else(|| Error::not_found(Some("id".into()), format!("unknown light {id}")).into())
}

/// Replaces a light.
#[utoipa::path(put, path = "/scenes/{scene}/lights/{id}", tag = "lights",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The light's id")),
    request_body = LightSpec,
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn set(State(state): State<AppState>, target: Target, JsonBody(body): JsonBody<LightSpec>) -> ApiResult<Json<Updated>> {
    // Within a light body, fields are named as they are in it (`intensity`, not `light.intensity`).
    update(&state, &target.scene, Command::SetLight(SetLight { id: Ref::Id(target.id()), light: body })).await.map_err(|e| ApiError(e.0.without_prefix("light.")))
}

/// Removes a light.
#[utoipa::path(delete, path = "/scenes/{scene}/lights/{id}", tag = "lights",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The light's id")),
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn delete(State(state): State<AppState>, target: Target) -> ApiResult<Json<Updated>> {
    update(&state, &target.scene, Command::DeleteLight(Delete { id: Ref::Id(target.id()) })).await
}
