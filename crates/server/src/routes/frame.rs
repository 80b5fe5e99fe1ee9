//! `/scenes/{scene}/frame.png` and `/scenes/{scene}/pick`.

use axum::Json;
use axum::extract::State;
use axum::http::header;
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};

use crate::error::{ApiError, ApiResult, ErrorBody};
use crate::extract::{Params, Target};
use crate::render::{FrameQuery, render_png};
use crate::state::AppState;

/// Renders a frame as PNG. The statistics come as headers: `x-render-seconds`,
/// `x-encode-seconds`, `x-rays`, `x-effects`, `x-integrator`, `x-scene-version` (and, in full,
/// from `/scenes/{scene}/stats`).
#[utoipa::path(get, path = "/scenes/{scene}/frame.png", tag = "frames",
    params(("scene" = u32, Path, description = "The scene's id"), FrameQuery),
    responses(
        (status = 200, description = "The frame", content_type = "image/png", body = crate::model::Binary),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn frame_png(State(state): State<AppState>, target: Target, Params(query): Params<FrameQuery>) -> ApiResult<Response> {
    let request = query.check(&state.config().limits)?;
    let rendered = render_png(&state, &target.scene, request).await?;
    let r = &rendered.report;
    let headers = [
        (header::CONTENT_TYPE, "image/png".to_string()),
        (header::CACHE_CONTROL, "no-store".to_string()),
        (header::HeaderName::from_static("x-render-seconds"), format!("{:.6}", r.render_seconds)),
        (header::HeaderName::from_static("x-encode-seconds"), format!("{:.6}", r.encode_seconds)),
        (header::HeaderName::from_static("x-rays"), r.rays.total.to_string()),
        (header::HeaderName::from_static("x-effects"), r.effects.join(",")),
        (header::HeaderName::from_static("x-integrator"), r.integrator.clone()),
        (header::HeaderName::from_static("x-scene-version"), r.scene_version.to_string()),
    ];
    Ok((headers, rendered.png).into_response())
}

/// Which pixel to pick.
#[derive(Clone, Debug, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct PickQuery {
    /// Column, from 0 at the left.
    pub x: u32,
    /// Row, from 0 at the top.
    pub y: u32,
    /// Image width; default 640.
    #[param(minimum = 1)]
    pub width: Option<u32>,
    /// Image height; default 360.
    #[param(minimum = 1)]
    pub height: Option<u32>,
}

/// What a pixel sees.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct PickResult {
    /// The closest hit through the pixel's centre, or null if the ray escapes.
    pub hit: Option<PickHit>,
}

/// A hit.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct PickHit {
    /// The instance hit.
    pub instance: u32,
    /// Its object.
    pub object: u32,
    /// The triangle, by index in the object's mesh.
    pub triangle: u32,
    /// Distance along the ray.
    pub t: f32,
    /// The hit point in world space.
    pub position: [f32; 3],
}

/// What pixel (x, y) of a width × height image sees (`rtPick`).
#[utoipa::path(get, path = "/scenes/{scene}/pick", tag = "frames",
    params(("scene" = u32, Path, description = "The scene's id"), PickQuery),
    responses(
        (status = 200, description = "Success", body = PickResult),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn pick(State(state): State<AppState>, target: Target, Params(q): Params<PickQuery>) -> ApiResult<Json<PickResult>> {
    let (width, height) = (q.width.unwrap_or(640), q.height.unwrap_or(360));
    let max = state.config().limits.max_dimension;
    for (name, value) in [("width", width), ("height", height)] {
        if !(1..=max).contains(&value) {
            return Err(ApiError::unprocessable(Some(name.into()), format!("{name} {value} is not in 1..={max}")));
        }
    }
    if q.x >= width || q.y >= height {
        let field = if q.x >= width { "x" } else { "y" };
        return Err(ApiError::unprocessable(Some(field.into()), format!("pixel ({}, {}) is outside the {width}×{height} image", q.x, q.y)));
    }
    let (x, y) = (q.x, q.y);
    let hit = target
        .scene
        .read(move |scene, _| {
            let frame = scene.frame();
            let ray = scene.camera().ray(x as f32 + 0.5, y as f32 + 0.5, width, height);
            frame.pick(x, y, width, height).map(|h| PickHit {
                instance: h.instance.0,
                object: h.object.0,
                triangle: h.prim,
                t: h.t,
                position: (ray.origin + ray.dir * h.t).to_array(),
            })
        })
        .await?;
    Ok(Json(PickResult { hit }))
}
