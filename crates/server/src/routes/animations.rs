//! `/scenes/{scene}/animations`: the animations a glTF file brought, which the batch command
//! `set_time` plays.

use axum::Json;
use serde::Serialize;
use utoipa::ToSchema;

use crate::error::{ApiResult, ErrorBody};
use crate::extract::Target;

/// An animation.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct AnimationInfo {
    /// Its index, as `set_time` names it.
    pub index: u32,
    /// Its name (may be empty).
    pub name: String,
    /// Seconds to its last keyframe.
    pub duration: f32,
    /// How many channels (node properties or morph weights it moves) it has.
    pub channels: u32,
}

/// Every animation of the scene, in the file's order (none for a scene without).
#[utoipa::path(get, path = "/scenes/{scene}/animations", tag = "animations",
    params(("scene" = u32, Path, description = "The scene's id")),
    responses(
        (status = 200, description = "Success", body = [AnimationInfo]),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn list(target: Target) -> ApiResult<Json<Vec<AnimationInfo>>> {
    let animations = target.scene.read(|scene, _| scene.animations()).await?;
    Ok(Json(
        animations
            .into_iter()
            .enumerate()
            .map(|(k, a)| AnimationInfo { index: k as u32, name: a.name, duration: a.duration, channels: a.channels as u32 })
            .collect(),
    ))
}
