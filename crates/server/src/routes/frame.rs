//! `/scenes/{scene}/frame.png`, `/scenes/{scene}/channels/{channel}` and `/scenes/{scene}/pick`.

use axum::Json;
use axum::extract::{Path, State};
use raystage_render::{Channel, RenderSettings};
use axum::http::header;
use axum::response::{IntoResponse, Response};
use raystage_service::{AppState, Error, on_a_turn};
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};

use crate::error::{ApiResult, ErrorBody};
use crate::extract::{Params, Target};
use crate::render::{FrameQuery, check_limits, render_png};

/// Renders a frame as PNG. The statistics come as headers: `x-render-seconds`,
/// `x-encode-seconds`, `x-rays`, `x-effects`, `x-integrator`, `x-scene-version` (and, in full,
/// from `/scenes/{scene}/stats`).
#[utoipa::path(get, path = "/scenes/{scene}/frame.png", tag = "frames",
    params(("scene" = u32, Path, description = "The scene's id"), FrameQuery),
    responses(
        (status = 200, description = "The frame", content_type = "image/png", body = raystage_service::model::Binary),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn frame_png(State(state): State<AppState>, target: Target, Params(query): Params<FrameQuery>) -> ApiResult<Response> {
    let frame = query.check(&state.config().limits)?;
    let rendered = render_png(&state, &target.scene, target.client, None, frame, Default::default()).await?;
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
    let mut response = (headers, rendered.png).into_response();
    if let Some(time) = r.scene_time {
        response.headers_mut().insert("x-scene-time", header::HeaderValue::from_str(&format!("{time:.6}")).expect("a number is a header value"));
    }
    Ok(response)
}

/// Bytes a channel takes per pixel while it renders: what the first hit holds (distances,
/// normal, albedo, ids) and the encoded channel.
const CHANNEL_BYTES_PER_PIXEL: u64 = 48 + 16;

/// Which channel image to render.
#[derive(Clone, Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct ChannelQuery {
    /// Width in pixels; default 640.
    #[param(minimum = 1)]
    pub width: Option<u32>,
    /// Height in pixels; default 360.
    #[param(minimum = 1)]
    pub height: Option<u32>,
    /// `png` (8-bit: normals as 0.5 + 0.5·n, albedo sRGB, ids in 24 bits with red the low byte
    /// and white for none) or `pfm` (floats; ids exact below 2²⁴, −1 for none); default `png`,
    /// and `pfm` for `depth` and `z`, which have no PNG form.
    #[param(value_type = Option<String>, pattern = "^(png|pfm)$")]
    pub format: Option<String>,
}

/// Renders a channel of what the first surface each pixel sees is, with one ray through each
/// pixel's centre: `depth` (distance along the ray), `z` (camera-space depth), `normal`
/// (shading normal in the world), `albedo`, `instance`, `object` or `primitive` (ids).
#[utoipa::path(get, path = "/scenes/{scene}/channels/{channel}", tag = "frames",
    params(("scene" = u32, Path, description = "The scene's id"),
        ("channel" = String, Path, description = "depth, z, normal, albedo, instance, object or primitive"), ChannelQuery),
    responses(
        (status = 200, description = "The channel", content_type = "image/png", body = raystage_service::model::Binary),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn channel(
    State(state): State<AppState>,
    target: Target,
    Path((_, name)): Path<(u32, String)>,
    Params(q): Params<ChannelQuery>,
) -> ApiResult<Response> {
    let channel: Channel = name.parse().map_err(|e: raystage_render::Error| Error::not_found(Some("channel".into()), e.to_string()))?;
    let defaults = RenderSettings::default();
    let request = RenderSettings { width: q.width.unwrap_or(defaults.width), height: q.height.unwrap_or(defaults.height), ..defaults };
    check_limits(&request, "spp", &state.config().limits)?;
    let pfm = match q.format.as_deref() {
        None => channel.is_distance(),
        Some("pfm") => true,
        Some("png") if channel.is_distance() => {
            return Err(Error::unprocessable(Some("format".into()), format!("the {name} channel has no PNG form: ask for pfm")).into());
        }
        Some("png") => false,
        Some(other) => return Err(Error::unprocessable(Some("format".into()), format!("format `{other}` is not png or pfm")).into()),
    };
    let memory = request.width as u64 * request.height as u64 * CHANNEL_BYTES_PER_PIXEL;
    // One ray a pixel: short enough that it runs to the end once started.
    let bytes = on_a_turn(&state, &target.scene, target.client, None, memory, move |scene, _, _| {
        let [image] = &raystage_render::render_channels(&scene.frame(), request.width, request.height, &[channel]).map_err(|e| Error::unprocessable(None, e.to_string()))?[..] else {
            return Err(Error::internal("one channel asked for, one rendered").into());
        };
        if pfm { Ok(image.pfm()) } else { image.png().map_err(|e| Error::internal(e.to_string())) }
    })
    .await?;
    let content_type = if pfm { "image/x-portable-floatmap" } else { "image/png" };
    Ok(([(header::CONTENT_TYPE, content_type), (header::CACHE_CONTROL, "no-store")], bytes).into_response())
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
            return Err(Error::unprocessable(Some(name.into()), format!("{name} {value} is not in 1..={max}")).into());
        }
    }
    if q.x >= width || q.y >= height {
        let field = if q.x >= width { "x" } else { "y" };
        return Err(Error::unprocessable(Some(field.into()), format!("pixel ({}, {}) is outside the {width}×{height} image", q.x, q.y)).into());
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
