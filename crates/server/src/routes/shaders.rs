//! `/scenes/{scene}/shaders`: surface shaders of the built-in classes and their parameters.

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use raystage_scene::ShaderId;
use raystage_service::model::{Command, DefineShader, Delete, ParamsBody, Ref, SetParams, ShaderBody, ShaderInfo, ShaderSummary, ShaderUpdate};
use raystage_service::{AppState, Error};

use super::{CreatedResponse, Updated, create, update};
use crate::error::{ApiResult, ErrorBody};
use crate::extract::{JsonBody, Target};

/// Every shader of the scene: id, class and name (the default shader is not listed).
#[utoipa::path(get, path = "/scenes/{scene}/shaders", tag = "shaders",
    params(("scene" = u32, Path, description = "The scene's id")),
    responses(
        (status = 200, description = "Success", body = [ShaderSummary]),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn list(target: Target) -> ApiResult<Json<Vec<ShaderSummary>>> {
    Ok(Json(target.scene.read(|scene, _| scene.shaders().map(|(id, s)| ShaderSummary::of(id.0, s)).collect()).await?))
}

/// Adds a shader.
#[utoipa::path(post, path = "/scenes/{scene}/shaders", tag = "shaders",
    params(("scene" = u32, Path, description = "The scene's id")),
    request_body = ShaderBody,
    responses(
        (status = 201, description = "Created", body = CreatedResponse),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn add(State(state): State<AppState>, target: Target, JsonBody(body): JsonBody<ShaderBody>) -> ApiResult<(StatusCode, Json<CreatedResponse>)> {
    create(&state, &target.scene, Command::AddShader(body)).await
}

/// A shader and every parameter's value.
#[utoipa::path(get, path = "/scenes/{scene}/shaders/{id}", tag = "shaders",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The shader's id")),
    responses(
        (status = 200, description = "Success", body = ShaderInfo),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn get(target: Target) -> ApiResult<Json<ShaderInfo>> {
    let id = target.id();
    Ok(Json(target.scene.read(move |scene, _| scene.shader(ShaderId(id)).map(|s| ShaderInfo::of(id, s))).await?.map_err(Error::from)?))
}

/// Replaces a shader (class and parameters): every triangle bound to it changes with it.
#[utoipa::path(put, path = "/scenes/{scene}/shaders/{id}", tag = "shaders",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The shader's id")),
    request_body = ShaderUpdate,
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn define(State(state): State<AppState>, target: Target, JsonBody(body): JsonBody<ShaderUpdate>) -> ApiResult<Json<Updated>> {
    let command = Command::DefineShader(DefineShader { id: Ref::Id(target.id()), class: body.class, params: body.params });
    update(&state, &target.scene, command).await
}

/// Writes parameters by name (those the class does not export are ignored, and listed).
#[utoipa::path(patch, path = "/scenes/{scene}/shaders/{id}", tag = "shaders",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The shader's id")),
    request_body = ParamsBody,
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn set_params(State(state): State<AppState>, target: Target, JsonBody(body): JsonBody<ParamsBody>) -> ApiResult<Json<Updated>> {
    update(&state, &target.scene, Command::SetParams(SetParams { id: Ref::Id(target.id()), params: body.params })).await
}

/// Deletes a shader: its triangles fall back to the default shader.
#[utoipa::path(delete, path = "/scenes/{scene}/shaders/{id}", tag = "shaders",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The shader's id")),
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn delete(State(state): State<AppState>, target: Target) -> ApiResult<Json<Updated>> {
    update(&state, &target.scene, Command::DeleteShader(Delete { id: Ref::Id(target.id()) })).await
}
