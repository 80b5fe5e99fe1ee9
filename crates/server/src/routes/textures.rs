//! `/scenes/{scene}/textures`: textures for shaders' texture parameters and environment maps.
//! A body is a procedural texture as JSON, or the bytes of a PNG, JPEG, WebP or Radiance HDR file,
//! told apart by its content type. JSON edits run through [`raystage_service::model::Command`] as batch commands
//! do; image uploads are decoded off the reactor and edit the scene directly.

use axum::Json;
use axum::extract::{FromRequest, Request, State};
use axum::http::{StatusCode, header};
use raystage_scene::{Image, TextureId};
use raystage_service::model::{Command, Delete, Ref, SetTexture, TextureInfo, TextureSpec, decode_image};
use raystage_service::{AppState, Applied, Blob, Edit, Error, unknown_texture};

use super::{CreatedResponse, Updated, create, update};
use crate::error::{ApiError, ApiResult, ErrorBody};
use crate::extract::{JsonBody, RawBody, Target};

/// Content types of image bodies: the file's own bytes, whose format is read from them.
const IMAGE_TYPES: [&str; 5] = ["image/png", "image/jpeg", "image/webp", "image/vnd.radiance", "application/octet-stream"];

/// A texture body: a procedural texture, or an image file decoded.
pub(crate) enum TextureBody {
    /// JSON: a checker or noise texture.
    Procedural(TextureSpec),
    /// A PNG, JPEG, WebP or Radiance HDR file: its bytes, and decoded to linear RGB.
    Image(Vec<u8>, Image),
}

impl FromRequest<AppState> for TextureBody {
    type Rejection = ApiError;

    /// JSON for `application/json` (or `…+json`, no content type, or curl's default for `-d`,
    /// `application/x-www-form-urlencoded`, as every other route takes JSON), an image for the
    /// image types; 415 for any other.
    async fn from_request(req: Request, state: &AppState) -> ApiResult<TextureBody> {
        let content_type = req.headers().get(header::CONTENT_TYPE).map(|v| v.to_str().unwrap_or("").to_string());
        // The media type without its parameters (`; charset=utf-8`).
        let essence = content_type.as_deref().map(|t| t.split(';').next().unwrap_or("").trim().to_ascii_lowercase());
        if essence.as_deref().is_none_or(|t| t == "application/json" || t.ends_with("+json") || t == "application/x-www-form-urlencoded") {
            return Ok(TextureBody::Procedural(JsonBody::from_request(req, state).await?.0));
        }
        if essence.as_deref().is_some_and(|t| IMAGE_TYPES.contains(&t)) {
            let bytes = RawBody::from_request(req, state).await?.0;
            let limits = state.config().limits;
            let (bytes, image) = tokio::task::spawn_blocking(move || decode_image(&bytes, &limits).map(|image| (bytes, image)))
                .await
                .map_err(|e| Error::internal(e.to_string()))??;
            return Ok(TextureBody::Image(bytes.into(), image));
        }
        Err(ApiError::unsupported_media_type(format!(
            "content type `{}` is not a texture: send JSON (application/json) for a procedural texture, or a file as {}",
            content_type.unwrap_or_default(),
            IMAGE_TYPES.join(", ")
        )))
    }
}

async fn all(target: &Target) -> raystage_service::Result<Vec<TextureInfo>> {
    target.scene.read(|scene, _| scene.textures().map(|(id, t)| TextureInfo::of(id.0, t)).collect()).await
}

/// Every texture.
#[utoipa::path(get, path = "/scenes/{scene}/textures", tag = "textures",
    params(("scene" = u32, Path, description = "The scene's id")),
    responses(
        (status = 200, description = "Success", body = [TextureInfo]),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn list(target: Target) -> ApiResult<Json<Vec<TextureInfo>>> {
    Ok(Json(all(&target).await?))
}

/// Adds a texture: a procedural one described as JSON, or an image sent as the bytes of a PNG,
/// JPEG, WebP or Radiance HDR file (`image/png`, `image/jpeg`, `image/webp`,
/// `image/vnd.radiance` or `application/octet-stream`; integer channels are taken as sRGB and
/// decoded to linear light, HDR stays linear).
#[utoipa::path(post, path = "/scenes/{scene}/textures", tag = "textures",
    params(("scene" = u32, Path, description = "The scene's id")),
    request_body(content(
        (TextureSpec = "application/json"),
        (raystage_service::model::Binary = "image/png"),
        (raystage_service::model::Binary = "image/jpeg"),
        (raystage_service::model::Binary = "image/webp"),
        (raystage_service::model::Binary = "image/vnd.radiance"),
        (raystage_service::model::Binary = "application/octet-stream"),
    )),
    responses(
        (status = 201, description = "Created", body = CreatedResponse),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 413, description = "Larger than the server allows", body = ErrorBody),
        (status = 415, description = "A content type the route does not take", body = ErrorBody),
        (status = 422, description = "A value is not acceptable (the error names the field), or the image cannot be read", body = ErrorBody),
    ))]
pub(crate) async fn add(State(state): State<AppState>, target: Target, body: TextureBody) -> ApiResult<(StatusCode, Json<CreatedResponse>)> {
    match body {
        TextureBody::Procedural(spec) => create(&state, &target.scene, Command::AddTexture(spec)).await,
        TextureBody::Image(file, image) => {
            let (id, version) = image_edit(&state, &target, None, file, image).await?;
            Ok((StatusCode::CREATED, Json(CreatedResponse { id, version, ignored: Vec::new() })))
        }
    }
}

/// A texture: a procedural one's kind, colours and scale, or an image's size.
#[utoipa::path(get, path = "/scenes/{scene}/textures/{id}", tag = "textures",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The texture's id")),
    responses(
        (status = 200, description = "Success", body = TextureInfo),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn get(target: Target) -> ApiResult<Json<TextureInfo>> {
    let id = target.id();
    let texture = target.scene.read(move |scene, _| scene.texture(TextureId(id)).map(|t| TextureInfo::of(id, t)).ok()).await?;
    texture.map(Json).ok_or_else(|| unknown_texture(id).into())
}

/// Replaces a texture, with the same bodies as `POST`: every shader and environment light
/// using it changes with it.
#[utoipa::path(put, path = "/scenes/{scene}/textures/{id}", tag = "textures",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The texture's id")),
    request_body(content(
        (TextureSpec = "application/json"),
        (raystage_service::model::Binary = "image/png"),
        (raystage_service::model::Binary = "image/jpeg"),
        (raystage_service::model::Binary = "image/webp"),
        (raystage_service::model::Binary = "image/vnd.radiance"),
        (raystage_service::model::Binary = "application/octet-stream"),
    )),
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 413, description = "Larger than the server allows", body = ErrorBody),
        (status = 415, description = "A content type the route does not take", body = ErrorBody),
        (status = 422, description = "A value is not acceptable (the error names the field), or the image cannot be read", body = ErrorBody),
    ))]
pub(crate) async fn set(State(state): State<AppState>, target: Target, body: TextureBody) -> ApiResult<Json<Updated>> {
    let id = target.id();
    match body {
        TextureBody::Procedural(texture) => {
            // Within a texture body, fields are named as they are in it (`scale`, not `texture.scale`).
            let command = Command::SetTexture(SetTexture { id: Ref::Id(id), texture });
            update(&state, &target.scene, command).await.map_err(|e| ApiError(e.0.without_prefix("texture.")))
        }
        TextureBody::Image(file, image) => {
            let (_, version) = image_edit(&state, &target, Some(id), file, image).await?;
            Ok(Json(Updated { version, ignored: Vec::new() }))
        }
    }
}

/// Adds an image `file` (decoded as `image`) as a texture, or replaces texture `texture` with
/// it; returns the texture's id and the scene's version.
async fn image_edit(state: &AppState, target: &Target, texture: Option<u32>, file: Vec<u8>, image: Image) -> raystage_service::Result<(u32, u64)> {
    match target.scene.edit(state, Edit::Image { texture, file: Blob(file), decoded: Some(image) }).await? {
        (Applied::Texture(id), version) => Ok((id, version)),
        _ => Err(Error::internal("an image texture gave back something else")),
    }
}

/// Removes a texture: shaders and environment lights using it render as if they had none.
#[utoipa::path(delete, path = "/scenes/{scene}/textures/{id}", tag = "textures",
    params(("scene" = u32, Path, description = "The scene's id"), ("id" = u32, Path, description = "The texture's id")),
    responses(
        (status = 200, description = "Success", body = Updated),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn delete(State(state): State<AppState>, target: Target) -> ApiResult<Json<Updated>> {
    update(&state, &target.scene, Command::DeleteTexture(Delete { id: Ref::Id(target.id()) })).await
}
