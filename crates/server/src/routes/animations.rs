//! `/scenes/{scene}/animations`: the animations a glTF file brought, which the batch command
//! `set_time` poses; `/scenes/{scene}/clock`: the clock that plays them (see
//! [`raystage_service::SceneSlot::change_clock`]).

use axum::Json;
use axum::extract::State;
use raystage_service::{AppState, ClockChange, ClockState, Error};
use serde::Serialize;
use utoipa::ToSchema;

use crate::error::{ApiResult, ErrorBody};
use crate::extract::{JsonBody, Target};

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

/// The scene's animation clock: the animation its frames show, the time, and whether and how
/// fast it plays (a glTF scene's opens paused at its pose, 0 s of the first animation). 404
/// naming `clock` for a scene without animations.
#[utoipa::path(get, path = "/scenes/{scene}/clock", tag = "animations",
    params(("scene" = u32, Path, description = "The scene's id")),
    responses(
        (status = 200, description = "Success", body = ClockState),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
    ))]
pub(crate) async fn clock(target: Target) -> ApiResult<Json<ClockState>> {
    target.scene.current_clock().await.map(Json).ok_or_else(|| {
        let message = format!("scene {} has no clock: it has no animations", target.scene.id);
        Error::not_found(Some("clock".into()), message).into()
    })
}

/// Sets the scene's clock: fields left out stay (a new clock starts paused at 0 s of the first
/// animation, at rate 1, looping). The scene is posed at the clock's time at once; while the
/// clock plays, every render (frames, render jobs, each pass of a stream) first moves the scene
/// to the clock's time, as a `set_time` edit, at most 60 times a second. Edits compose with it:
/// an instance moved while the animation plays stays where it was put unless the animation
/// moves it. 422 naming `animation` for a scene without animations.
#[utoipa::path(put, path = "/scenes/{scene}/clock", tag = "animations",
    params(("scene" = u32, Path, description = "The scene's id")),
    request_body = ClockChange,
    responses(
        (status = 200, description = "Success", body = ClockState),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn set_clock(State(state): State<AppState>, target: Target, JsonBody(change): JsonBody<ClockChange>) -> ApiResult<Json<ClockState>> {
    Ok(Json(target.scene.change_clock(&state, change).await?))
}
