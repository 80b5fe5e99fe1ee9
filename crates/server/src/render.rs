//! Rendering frames for requests: settings checked against the limits, the render on a
//! blocking thread (it runs on the rayon pool, never on the reactor), the PNG encoded there too.

use std::sync::Arc;

use raystage_render::{Integrator, RenderSettings};
use raystage_scene::Scene;
use serde::Deserialize;
use utoipa::IntoParams;

use crate::config::Limits;
use crate::error::{ApiError, ApiResult};
use crate::state::{AppState, SceneSlot};
use crate::stats::FrameReport;

/// What frame to render.
#[derive(Clone, Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct FrameQuery {
    /// Width in pixels; default 640.
    pub width: Option<u32>,
    /// Height in pixels; default 360.
    pub height: Option<u32>,
    /// Samples per pixel; default 1.
    pub spp: Option<u32>,
    /// `eyelight`, `whitted`, `distribution` or `path`; default `whitted` if the scene has
    /// lights, else `eyelight`.
    pub integrator: Option<String>,
}

/// A frame request checked against the limits; the integrator is chosen once the scene is seen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FrameRequest {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub integrator: Option<Integrator>,
}

impl FrameQuery {
    /// Checks the query (422 naming the parameter out of range).
    pub(crate) fn check(&self, limits: &Limits) -> ApiResult<FrameRequest> {
        let request = FrameRequest {
            width: self.width.unwrap_or(640),
            height: self.height.unwrap_or(360),
            spp: self.spp.unwrap_or(1),
            integrator: self.integrator.as_deref().map(parse_integrator).transpose()?,
        };
        request.check(limits)?;
        Ok(request)
    }
}

/// An integrator by name (422 naming `integrator` if there is none).
pub(crate) fn parse_integrator(name: &str) -> ApiResult<Integrator> {
    Integrator::from_name(name).ok_or_else(|| {
        ApiError::unprocessable(Some("integrator".into()), format!("unknown integrator `{name}`: expected eyelight, whitted, distribution or path"))
    })
}

impl FrameRequest {
    /// Checks size and samples against the limits (422 naming the parameter).
    pub(crate) fn check(&self, limits: &Limits) -> ApiResult<()> {
        let max = limits.max_dimension;
        for (name, value) in [("width", self.width), ("height", self.height)] {
            if !(1..=max).contains(&value) {
                return Err(ApiError::unprocessable(Some(name.into()), format!("{name} {value} is not in 1..={max}")));
            }
        }
        if !(1..=limits.max_spp).contains(&self.spp) {
            return Err(ApiError::unprocessable(Some("spp".into()), format!("spp {} is not in 1..={}", self.spp, limits.max_spp)));
        }
        let samples = self.width as u64 * self.height as u64 * self.spp as u64;
        if samples > limits.max_frame_samples {
            return Err(ApiError::unprocessable(
                Some("spp".into()),
                format!("{}×{} at {} spp is {samples} samples, more than the limit of {}", self.width, self.height, self.spp, limits.max_frame_samples),
            ));
        }
        Ok(())
    }

    /// The render settings for `scene`.
    pub(crate) fn settings(&self, scene: &Scene) -> RenderSettings {
        RenderSettings {
            width: self.width,
            height: self.height,
            samples_per_pixel: self.spp,
            integrator: self.integrator.unwrap_or_else(|| default_integrator(scene)),
            ..RenderSettings::default()
        }
    }
}

/// Whitted's ray tracing if the scene has lights, else the eye-light preview (so that an unlit
/// scene is not black), as `raystage render` chooses.
pub(crate) fn default_integrator(scene: &Scene) -> Integrator {
    if scene.lights().next().is_some() { Integrator::Whitted } else { Integrator::EyeLight }
}

/// A rendered frame.
pub(crate) struct Rendered {
    /// The PNG.
    pub png: Vec<u8>,
    /// What it cost.
    pub report: FrameReport,
}

/// Renders a frame of `slot` and encodes it, waiting for a turn to render first.
pub(crate) async fn render_png(state: &AppState, slot: &Arc<SceneSlot>, request: FrameRequest) -> ApiResult<Rendered> {
    let _permit = state.render_permit().await;
    let rendered = slot
        .read(move |scene, version| -> ApiResult<Rendered> {
            let settings = request.settings(scene);
            let (png, stats, rendered, encoded) = crate::png::render_png(&scene.frame(), &settings)?;
            let mut report = FrameReport::new(&settings, &stats, encoded, version);
            // The whole render, with the film's allocation and resolve, which the frame
            // statistics leave out.
            report.render_seconds = rendered;
            Ok(Rendered { png, report })
        })
        .await??;
    *slot.last_frame.lock().unwrap_or_else(|e| e.into_inner()) = Some(rendered.report.clone());
    Ok(rendered)
}
