//! The stream's messages (`api/stream.md` describes the protocol).

use raystage_service::model::{CameraPatch, Command, CommandResult};
use raystage_service::{Error, ErrorDetail, RaysJson};
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};

// The settings list names the schemas of the integrators and tone curves.
use crate::render::{IntegratorName, ToneMapName, settings_type};

/// The protocol's version, sent in `hello`.
pub const PROTOCOL: u32 = 1;

raystage_render::frame_settings!(settings_type! {
    /// How a stream starts (query parameters of the upgrade request).
    #[derive(Clone, Debug, Default, Deserialize, IntoParams)]
    #[serde(deny_unknown_fields)]
    #[into_params(parameter_in = Query)]
    pub struct StreamQuery [param] {
        /// Samples per pixel after which the image stops refining until something changes;
        /// default 256.
        #[param(minimum = 1)]
        pub max_samples: Option<u32>,
        /// How frames are encoded: `png` (lossless, the default) or `jpeg` (lossy, for
        /// browsers on slow links: a fifth of the bytes of the sphere grid's PNG at 1080p).
        #[param(value_type = Option<Encoding>)]
        pub encoding: Option<String>,
        /// JPEG quality, 1 to 100; default 80. Kept for when `jpeg` is chosen.
        #[param(minimum = 1, maximum = 100)]
        pub quality: Option<u8>,
        /// The access token, for clients that cannot send an `Authorization` header.
        #[allow(dead_code, reason = "checked by the authentication middleware, from the raw query")]
        pub token: Option<String>,
    }
});

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

raystage_render::frame_settings!(settings_type! {
    /// The `settings` message's fields: those of the stream's query, and `request`.
    #[derive(Clone, Debug, Default, Deserialize, ToSchema)]
    #[serde(deny_unknown_fields)]
    pub struct SettingsChange [schema] {
        /// Echoed in the reply.
        pub request: Option<u64>,
        /// Samples per pixel to refine to.
        pub max_samples: Option<u32>,
        /// How frames are encoded: `png` or `jpeg`.
        #[schema(value_type = Option<Encoding>)]
        pub encoding: Option<String>,
        /// JPEG quality, 1 to 100.
        #[schema(minimum = 1, maximum = 100)]
        pub quality: Option<u8>,
    }
});

/// How a stream's frames are encoded (the binary message after each `frame`). A stream option,
/// not a frame setting: a new encoding re-encodes the image it has, as a new grading does.
/// (Requests name it as a string, parsed by [`Encoding::parse`], so that a wrong name is
/// refused naming the field, as a wrong integrator is.)
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum Encoding {
    /// PNG: lossless, sRGB, RGB8.
    #[default]
    Png,
    /// Baseline JPEG at the stream's `quality`: lossy, fewer bytes (a fifth of the sphere
    /// grid's PNG at 1080p and quality 80), twice the time to encode.
    Jpeg,
}

impl Encoding {
    /// The encoding called `name` (422 naming the field `encoding` if there is none).
    pub(crate) fn parse(name: &str) -> raystage_service::Result<Encoding> {
        match name {
            "png" => Ok(Encoding::Png),
            "jpeg" => Ok(Encoding::Jpeg),
            _ => Err(Error::unprocessable(Some("encoding".into()), format!("encoding `{name}` is not png or jpeg"))),
        }
    }
}


/// A message from the server (a JSON text message; every `frame` is followed by one binary
/// message, the image).
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
    /// A frame: its statistics. The next message is its image (binary).
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
    /// The animation time the image shows (see `/scenes/{scene}/clock`); absent for a scene
    /// never posed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene_time: Option<f64>,
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
    /// How the image that follows is encoded.
    pub encoding: Encoding,
    /// Seconds the image took to encode.
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
