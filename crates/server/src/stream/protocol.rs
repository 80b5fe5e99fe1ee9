//! The stream's messages (`api/stream.md` describes the protocol).

use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};

use crate::error::ErrorDetail;
use crate::model::{CameraPatch, Command, CommandResult};
use crate::stats::RaysJson;

/// The protocol's version, sent in `hello`.
pub const PROTOCOL: u32 = 1;

/// How a stream starts (query parameters of the upgrade request).
#[derive(Clone, Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct StreamQuery {
    /// Width in pixels; default 640.
    #[param(minimum = 1)]
    pub width: Option<u32>,
    /// Height in pixels; default 360.
    #[param(minimum = 1)]
    pub height: Option<u32>,
    /// `eyelight`, `whitted`, `distribution` or `path`; default `whitted` if the scene has
    /// lights, else `eyelight`.
    #[param(value_type = Option<crate::render::IntegratorName>)]
    pub integrator: Option<String>,
    /// Samples per pixel after which the image stops refining until something changes;
    /// default 256.
    #[param(minimum = 1)]
    pub max_samples: Option<u32>,
    /// What camera rays that hit nothing show: `sky`, `black` or `R,G,B` (as for frames).
    pub background: Option<String>,
    /// Whether a scene that nothing lights is lit by the default sky (as for frames).
    pub default_lights: Option<bool>,
    /// Longest path in segments, the camera ray included, or deepest recursion: 1 to 64.
    #[param(minimum = 1, maximum = 64)]
    pub max_depth: Option<u32>,
    /// Whether the path tracer may end paths early by Russian roulette.
    pub russian_roulette: Option<bool>,
    /// The pixel filter: `box`, `gaussian` or `gaussian:RADIUS`.
    pub filter: Option<String>,
    /// Seed of the sample sequences.
    pub seed: Option<u32>,
    /// Adaptive sampling: tiles stop taking samples once each pixel's standard error is below
    /// this fraction of its brightness, in (0, 1].
    #[param(exclusive_minimum = 0, maximum = 1)]
    pub noise_threshold: Option<f32>,
    /// Exposure in stops. Changing it (or `tonemap`) re-grades the image without rendering
    /// it again.
    pub exposure: Option<f32>,
    /// The PNG's tone curve: `clamp` or `neutral`.
    #[param(value_type = Option<crate::render::ToneMapName>)]
    pub tonemap: Option<String>,
    /// The access token, for clients that cannot send an `Authorization` header.
    #[allow(dead_code, reason = "checked by the authentication middleware, from the raw query")]
    pub token: Option<String>,
}

/// A message from the client (a JSON text message).
#[derive(Clone, Debug, Deserialize, ToSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ClientMessage {
    /// Changes the scene's camera (fields left out stay): every stream of the scene restarts.
    Camera {
        /// Echoed in the reply.
        request: Option<u64>,
        /// The change.
        camera: CameraPatch,
    },
    /// Edits the scene, as `POST /scenes/{scene}/commands`.
    Commands {
        /// Echoed in the reply.
        request: Option<u64>,
        /// The edits.
        commands: Vec<Command>,
    },
    /// Changes this stream's image (fields left out stay): it restarts, unless only `exposure`
    /// and `tonemap` changed, which re-grade the image as it is.
    Settings(SettingsChange),
}

/// The `settings` message's fields: those of the stream's query, and `request`.
#[derive(Clone, Debug, Default, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SettingsChange {
    /// Echoed in the reply.
    pub request: Option<u64>,
    /// Width in pixels.
    pub width: Option<u32>,
    /// Height in pixels.
    pub height: Option<u32>,
    /// The integrator.
    pub integrator: Option<String>,
    /// Samples per pixel to refine to.
    pub max_samples: Option<u32>,
    /// What camera rays that hit nothing show: `sky`, `black` or `R,G,B` (as for frames).
    pub background: Option<String>,
    /// Whether a scene that nothing lights is lit by the default sky (as for frames).
    pub default_lights: Option<bool>,
    /// Longest path in segments, the camera ray included, or deepest recursion: 1 to 64.
    #[schema(minimum = 1, maximum = 64)]
    pub max_depth: Option<u32>,
    /// Whether the path tracer may end paths early by Russian roulette.
    pub russian_roulette: Option<bool>,
    /// The pixel filter: `box`, `gaussian` or `gaussian:RADIUS`.
    pub filter: Option<String>,
    /// Seed of the sample sequences.
    pub seed: Option<u32>,
    /// Adaptive sampling: tiles stop taking samples once each pixel's standard error is below
    /// this fraction of its brightness, in (0, 1].
    #[schema(exclusive_minimum = 0, maximum = 1)]
    pub noise_threshold: Option<f32>,
    /// Exposure in stops. Changing it (or `tonemap`) re-grades the image without rendering
    /// it again.
    pub exposure: Option<f32>,
    /// The PNG's tone curve: `clamp` or `neutral`.
    #[schema(value_type = Option<crate::render::ToneMapName>)]
    pub tonemap: Option<String>,
}

/// The frame setup that a stream's query or `settings` message sets, as a frame's query would
/// (so that both are checked the same way).
macro_rules! setup_query {
    ($fields:expr) => {
        crate::render::FrameQuery {
            background: $fields.background.clone(),
            default_lights: $fields.default_lights,
            max_depth: $fields.max_depth,
            russian_roulette: $fields.russian_roulette,
            filter: $fields.filter.clone(),
            seed: $fields.seed,
            noise_threshold: $fields.noise_threshold,
            exposure: $fields.exposure,
            tonemap: $fields.tonemap.clone(),
            ..Default::default()
        }
    };
}

impl StreamQuery {
    /// The setup the query asks for (422 naming the parameter that is wrong).
    pub(crate) fn setup(&self) -> crate::error::ApiResult<crate::render::Setup> {
        setup_query!(self).setup_over(crate::render::Setup::default())
    }
}

impl SettingsChange {
    /// `base` with what the message sets replaced (422 naming the parameter that is wrong).
    pub(crate) fn setup_over(&self, base: crate::render::Setup) -> crate::error::ApiResult<crate::render::Setup> {
        setup_query!(self).setup_over(base)
    }
}

/// A message from the server (a JSON text message; every `frame` is followed by one binary
/// message, the PNG).
#[derive(Clone, Debug, Serialize, ToSchema)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ServerMessage {
    /// The first message: the stream's settings.
    Hello {
        /// [`PROTOCOL`].
        protocol: u32,
        /// The scene.
        scene: u32,
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// The integrator, if chosen (else it follows the scene's lights).
        integrator: Option<String>,
        /// Samples per pixel to refine to.
        max_samples: u32,
    },
    /// A frame: its statistics. The next message is its PNG (binary).
    Frame(FrameMessage),
    /// A client message succeeded.
    Result {
        /// The client's `request`, if it gave one.
        request: Option<u64>,
        /// The scene's version after an edit.
        version: u64,
        /// One per command (for `commands`).
        results: Vec<CommandResult>,
    },
    /// A client message failed (the stream goes on).
    Error {
        /// The client's `request`, if it gave one.
        request: Option<u64>,
        /// What went wrong, as in HTTP error bodies.
        error: ErrorDetail,
    },
}

/// A frame's statistics.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct FrameMessage {
    /// Frames sent on this stream so far, this one included.
    pub seq: u64,
    /// The scene version the image shows.
    pub scene_version: u64,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The integrator.
    pub integrator: String,
    /// Samples per pixel in the image.
    pub samples: u32,
    /// Samples per pixel the last pass added.
    pub pass_samples: u32,
    /// Seconds the last pass took.
    pub pass_seconds: f64,
    /// Seconds the PNG took to encode.
    pub encode_seconds: f64,
    /// Rays the last pass traced.
    pub rays: RaysJson,
    /// The last pass's tracing rate.
    pub mrays_per_second: f64,
    /// The effects simulated.
    pub effects: Vec<String>,
    /// Whether the image has all its samples (no more frames until something changes).
    pub converged: bool,
}
