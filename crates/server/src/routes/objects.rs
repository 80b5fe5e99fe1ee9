//! `/scenes/{scene}/objects`: geometry. `PUT` redefines an object (an unstructured update:
//! every instance follows, and the tree is refitted when the triangle count stays);
//! `PATCH` moves its vertices.

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use raystage_scene::{ObjectId, Scene};
use raystage_service::model::{Command, DefineObject, Delete, Kind, ObjectBody, ObjectUpdate, PositionsBody, Ref, SetPositions};
use raystage_service::AppState;
use serde::Serialize;
use utoipa::ToSchema;

use super::{CreatedResponse, Updated, create, update};
use crate::error::{ApiResult, ErrorBody};
use crate::extract::{JsonBody, Target};

/// An object at a glance.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct ObjectInfo {
    /// Its id.
    pub id: u32,
    /// How its geometry changes.
    pub kind: Kind,
    /// Its triangles.
    pub triangles: usize,
    /// Its vertices.
    pub vertices: usize,
    /// Whether its tree for the current geometry has been built (trees are built by the first
    /// ray that needs them).
    pub built: bool,
}

fn info(scene: &Scene, id: ObjectId) -> raystage_service::Result<ObjectInfo> {
    let mesh = scene.mesh(id)?;
    Ok(ObjectInfo {
        id: id.0,
        kind: Kind::from_scene(scene.object_kind(id)?),
        triangles: mesh.indices.len(),
        vertices: mesh.positions.len(),
        built: scene.is_built(id)?,
    })
}

/// Every object.
#[utoipa::path(get, path = "/scenes/{scene}/objects", tag = "objects",
    params(("scene" = u32, Path, description = "The scene's id")),
    responses(
        (status = 200, description = "Success", body = [ObjectInfo]),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn list(target: Target) -> ApiResult<Json<Vec<ObjectInfo>>> {
    let objects = target.scene.read(|scene, _| scene.object_ids().map(|id| info(scene, id)).collect::<raystage_service::Result<Vec<_>>>()).await??;
    Ok(Json(objects))
}

/// Adds an object.
#[utoipa::path(post, path = "/scenes/{scene}/objects", tag = "objects",
    params(("scene" = u32, Path, description = "The scene's id")),
    request_body = ObjectBody,
    responses(
        (status = 201, description = "Created", body = CreatedResponse),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 413, description = "Larger than the server allows", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn add(State(state): State<AppState>, target: Target, JsonBody(body): JsonBody<ObjectBody>) -> ApiResult<(StatusCode, Json<CreatedResponse>)> {
    create(&state, &target.scene, Command::AddObject(body)).await
}

/// An object at a glance.
#[utoipa::path(get, path = "/scenes/{scene}/objects/{id}", tag = "objects",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The object's id")),
    responses(
        (status = 200, description = "Success", body = ObjectInfo),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn get(target: Target) -> ApiResult<Json<ObjectInfo>> {
    let id = ObjectId(target.id());
    Ok(Json(target.scene.read(move |scene, _| info(scene, id)).await??))
}

/// Redefines an object's geometry: every instance follows.
#[utoipa::path(put, path = "/scenes/{scene}/objects/{id}", tag = "objects",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The object's id")),
    request_body = ObjectUpdate,
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 413, description = "Larger than the server allows", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn define(State(state): State<AppState>, target: Target, JsonBody(body): JsonBody<ObjectUpdate>) -> ApiResult<Json<Updated>> {
    let command = Command::DefineObject(DefineObject { id: Ref::Id(target.id()), kind: body.kind, mesh: body.mesh });
    update(&state, &target.scene, command).await
}

/// Moves an object's vertices (same count).
#[utoipa::path(patch, path = "/scenes/{scene}/objects/{id}", tag = "objects",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The object's id")),
    request_body = PositionsBody,
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn move_vertices(State(state): State<AppState>, target: Target, JsonBody(body): JsonBody<PositionsBody>) -> ApiResult<Json<Updated>> {
    let command = Command::SetPositions(SetPositions { id: Ref::Id(target.id()), positions: body.positions, positions_base64: body.positions_base64 });
    update(&state, &target.scene, command).await
}

/// Deletes an object and every instance of it.
#[utoipa::path(delete, path = "/scenes/{scene}/objects/{id}", tag = "objects",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The object's id")),
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn delete(State(state): State<AppState>, target: Target) -> ApiResult<Json<Updated>> {
    update(&state, &target.scene, Command::DeleteObject(Delete { id: Ref::Id(target.id()) })).await
}
