//! `/scenes/{scene}/instances`: objects placed in the world.

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use raystage_service::model::{Command, Delete, InstanceBody, InstanceUpdate, Ref, SetInstance, Transform};
use raystage_service::{AppState, Error};
use serde::Serialize;
use utoipa::ToSchema;

use super::{CreatedResponse, Updated, create, update};
use crate::error::{ApiResult, ErrorBody};
use crate::extract::{JsonBody, Target};

/// An instance.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct InstanceInfo {
    /// Its id.
    pub id: u32,
    /// The object it places.
    pub object: u32,
    /// Object to world (at the shutter's opening), row by row.
    pub matrix: [[f32; 4]; 4],
}

async fn all(target: &Target) -> raystage_service::Result<Vec<InstanceInfo>> {
    target
        .scene
        .read(|scene, _| scene.instances().map(|(id, object, t)| InstanceInfo { id: id.0, object: object.0, matrix: Transform::rows(&t) }).collect())
        .await
}

/// Every instance.
#[utoipa::path(get, path = "/scenes/{scene}/instances", tag = "instances",
    params(("scene" = u32, Path, description = "The scene's id")),
    responses(
        (status = 200, description = "Success", body = [InstanceInfo]),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn list(target: Target) -> ApiResult<Json<Vec<InstanceInfo>>> {
    Ok(Json(all(&target).await?))
}

/// Places an instance of an object.
#[utoipa::path(post, path = "/scenes/{scene}/instances", tag = "instances",
    params(("scene" = u32, Path, description = "The scene's id")),
    request_body = InstanceBody,
    responses(
        (status = 201, description = "Created", body = CreatedResponse),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn add(State(state): State<AppState>, target: Target, JsonBody(body): JsonBody<InstanceBody>) -> ApiResult<(StatusCode, Json<CreatedResponse>)> {
    create(&state, &target.scene, Command::AddInstance(body)).await
}

/// An instance.
#[utoipa::path(get, path = "/scenes/{scene}/instances/{id}", tag = "instances",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The instance's id")),
    responses(
        (status = 200, description = "Success", body = InstanceInfo),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn get(target: Target) -> ApiResult<Json<InstanceInfo>> {
    let id = target.id();
    all(&target).await?.into_iter().find(|i| i.id == id).map(Json).ok_or_else(|| Error::not_found(Some("id".into()), format!("unknown instance {id}")).into())
}

/// Moves an instance.
#[utoipa::path(put, path = "/scenes/{scene}/instances/{id}", tag = "instances",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The instance's id")),
    request_body = InstanceUpdate,
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn set(State(state): State<AppState>, target: Target, JsonBody(body): JsonBody<InstanceUpdate>) -> ApiResult<Json<Updated>> {
    let command = Command::SetInstance(SetInstance { id: Ref::Id(target.id()), transform: body.transform, end_transform: body.end_transform });
    update(&state, &target.scene, command).await
}

/// Removes an instance.
#[utoipa::path(delete, path = "/scenes/{scene}/instances/{id}", tag = "instances",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The instance's id")),
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn delete(State(state): State<AppState>, target: Target) -> ApiResult<Json<Updated>> {
    update(&state, &target.scene, Command::DeleteInstance(Delete { id: Ref::Id(target.id()) })).await
}
