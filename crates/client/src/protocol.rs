//! What the client reads and writes on the wire: the stream's messages (`api/stream.md`) and the
//! few HTTP resources the side panel shows (`api/openapi.json`).
//!
//! The client talks to the server only over the network (docs/design/architecture.md), so these are
//! its own definitions of the published contract, not the server's types: each reads only the
//! fields the viewer uses, and unknown fields are ignored, so a newer server still works.

use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

/// The stream protocol this client speaks (`hello.protocol`).
pub const PROTOCOL: u32 = 1;

/// A JSON text message from the server.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ServerMessage {
    /// The first message: the stream's settings.
    Hello(Hello),
    /// A frame's statistics; its PNG is the next (binary) message.
    Frame(FrameStats),
    /// A client message succeeded.
    Result {
        /// The `request` number the client gave.
        request: Option<u64>,
        /// The scene's version after it.
        version: u64,
    },
    /// A client message failed; the stream goes on.
    Error {
        /// The `request` number the client gave.
        request: Option<u64>,
        /// What went wrong.
        error: ErrorDetail,
    },
}

/// The stream's settings, as the server took them.
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct Hello {
    /// The protocol's version.
    pub protocol: u32,
    /// The scene.
    pub scene: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The integrator, if one was chosen (else it follows the scene's lights).
    pub integrator: Option<String>,
    /// Samples per pixel the image refines to.
    pub max_samples: u32,
}

/// A scene's animation clock (`GET` and `PUT /scenes/{scene}/clock`), which plays its
/// animation on the server for every client.
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct Clock {
    /// The animation it plays: an index, or `"all"`.
    pub animation: Value,
    /// Seconds into it.
    pub time: f64,
    /// Whether the time moves.
    pub playing: bool,
}

/// A frame's statistics (the `frame` message).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
pub struct FrameStats {
    /// Frames sent on this stream so far, this one included.
    pub seq: u64,
    /// The scene version the image shows.
    pub scene_version: u64,
    /// The animation time the image shows, once the scene was posed.
    #[serde(default)]
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
    /// Seconds the PNG took to encode.
    pub encode_seconds: f64,
    /// Rays the last pass traced.
    pub rays: Rays,
    /// The last pass's tracing rate.
    pub mrays_per_second: f64,
    /// The effects simulated (only what the scene calls for).
    pub effects: Vec<String>,
    /// Whether the image has all its samples.
    pub converged: bool,
}

/// Rays traced, by kind.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(default)]
pub struct Rays {
    /// Camera rays.
    pub primary: u64,
    /// Shadow rays.
    pub shadow: u64,
    /// Reflection rays.
    pub reflection: u64,
    /// Refraction rays.
    pub refraction: u64,
    /// Diffuse bounce and ambient-occlusion rays.
    pub diffuse: u64,
    /// All of them.
    pub total: u64,
}

/// An error as the server reports it.
#[derive(Clone, Debug, Deserialize, PartialEq, Eq)]
pub struct ErrorDetail {
    /// `bad_request`, `not_found`, `unprocessable`, ...
    pub code: String,
    /// What was wrong, for a person.
    pub message: String,
    /// The part of the request at fault.
    #[serde(default)]
    pub field: Option<String>,
}

/// An error response body.
#[derive(Clone, Debug, Deserialize)]
pub(crate) struct ErrorBody {
    pub error: ErrorDetail,
}

/// The camera (`GET /scenes/{scene}/camera`, and in the scene's summary).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
pub struct CameraJson {
    /// Eye position.
    pub eye: [f32; 3],
    /// The point looked at.
    pub target: [f32; 3],
    /// Which way is up.
    pub up: [f32; 3],
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f32,
}

/// A light as `GET /scenes/{scene}/lights` lists it: what the viewer's lighting controls need
/// (other classes' parameters are left out).
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct LightInfo {
    /// Its id.
    pub id: u32,
    /// `EnvironmentLight`, `PointLight`, ...
    pub class: String,
    /// An environment's radiance (or its map's scale), linear RGB.
    #[serde(default)]
    pub radiance: Option<[f32; 3]>,
    /// An environment's map: a texture id.
    #[serde(default)]
    pub map: Option<u32>,
    /// An environment's turn about +y, in degrees.
    #[serde(default)]
    pub rotate: Option<f32>,
}

/// A scene at a glance (`GET /scenes/{scene}`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct SceneInfo {
    /// Its id.
    pub id: u32,
    /// Where it came from: `empty`, `demo:<name>`, `gltf`.
    pub origin: String,
    /// Edits so far.
    pub version: u64,
    /// Objects defined.
    pub objects: usize,
    /// Instances placed.
    pub instances: usize,
    /// Lights.
    pub lights: usize,
    /// Triangles over all objects.
    pub triangles: usize,
    /// The camera.
    pub camera: CameraJson,
}

/// An object (`GET /scenes/{scene}/objects`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct ObjectInfo {
    /// Its id.
    pub id: u32,
    /// `static`, `animated` or `unstructured`.
    pub kind: String,
    /// Its triangles.
    pub triangles: usize,
    /// Its vertices.
    pub vertices: usize,
    /// Whether its tree has been built.
    pub built: bool,
}

/// An instance (`GET /scenes/{scene}/instances`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct InstanceInfo {
    /// Its id.
    pub id: u32,
    /// The object it places.
    pub object: u32,
    /// Object to world, row by row.
    pub matrix: [[f32; 4]; 4],
}

/// An animation (`GET /scenes/{scene}/animations`), which the `set_time` command plays.
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct AnimationInfo {
    /// Its index, as `set_time` names it.
    pub index: u32,
    /// Its name (may be empty).
    pub name: String,
    /// Seconds to its last keyframe.
    pub duration: f32,
}

/// The `settings` message: changes this stream's image (fields left out stay).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Settings {
    /// Width in pixels.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub width: Option<u32>,
    /// Height in pixels.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub height: Option<u32>,
    /// `eyelight`, `whitted`, `distribution` or `path`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub integrator: Option<String>,
    /// Samples per pixel to refine to.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_samples: Option<u32>,
    /// Exposure in stops (the server re-grades the image without rendering it again).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub exposure: Option<f32>,
    /// The tone curve: `clamp` or `neutral`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tonemap: Option<String>,
    /// Whether a scene that nothing lights is lit by the default sky (the server's default).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub default_lights: Option<bool>,
}

impl Settings {
    /// `self` with the fields `later` gives replaced (two changes in a row as one).
    pub fn merged(mut self, later: Settings) -> Settings {
        self.width = later.width.or(self.width);
        self.height = later.height.or(self.height);
        self.integrator = later.integrator.or(self.integrator);
        self.max_samples = later.max_samples.or(self.max_samples);
        self.exposure = later.exposure.or(self.exposure);
        self.tonemap = later.tonemap.or(self.tonemap);
        self.default_lights = later.default_lights.or(self.default_lights);
        self
    }

    /// As query parameters of the stream's upgrade request (`width=640&...`).
    pub fn query(&self) -> String {
        let mut parts = Vec::new();
        if let Some(w) = self.width {
            parts.push(format!("width={w}"));
        }
        if let Some(h) = self.height {
            parts.push(format!("height={h}"));
        }
        if let Some(i) = &self.integrator {
            parts.push(format!("integrator={i}"));
        }
        if let Some(m) = self.max_samples {
            parts.push(format!("max_samples={m}"));
        }
        if let Some(e) = self.exposure {
            parts.push(format!("exposure={e}"));
        }
        if let Some(t) = &self.tonemap {
            parts.push(format!("tonemap={t}"));
        }
        parts.join("&")
    }
}

/// A camera change: the fields given replace the scene camera's.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CameraPatch {
    /// Eye position.
    pub eye: [f32; 3],
    /// The point looked at.
    pub target: [f32; 3],
}

/// What the viewer asks of its connection.
#[derive(Clone, Debug, PartialEq)]
pub enum Request {
    /// Move the scene's camera (`camera` message). Only the newest of several waiting is sent.
    Camera(CameraPatch),
    /// Change the stream's image (`settings` message).
    Settings(Settings),
    /// Fetch the scene's summary, objects, instances and lights again (HTTP).
    RefreshScene,
    /// Edit the scene: a batch of commands, as `POST /scenes/{scene}/commands` takes them
    /// (`commands` message).
    Commands(Value),
    /// Change the scene's clock: the fields of `PUT /scenes/{scene}/clock` (HTTP); the
    /// clock's new state comes back as [`Event::Clock`](crate::net::Event::Clock).
    Clock(Value),
    /// Light the scene with an image file on this machine: upload it as a texture
    /// (`POST /scenes/{scene}/textures`), make it the map of `light` (a `set_light` of light
    /// `id`, or an `add_light` where there is none), and fetch the scene again (HTTP).
    EnvironmentImage {
        /// A Radiance HDR, PNG or JPEG file, latitude-longitude.
        path: std::path::PathBuf,
        /// The environment light to give the map to, if the scene has one.
        id: Option<u32>,
        /// The light as the API describes it (its `map` replaced by the upload's).
        light: Value,
    },
}

impl Request {
    /// The stream message this request sends, numbered `request`; `None` for requests answered
    /// over HTTP.
    pub fn message(&self, request: u64) -> Option<Value> {
        match self {
            Request::Camera(camera) => Some(json!({ "type": "camera", "request": request, "camera": camera })),
            Request::Settings(settings) => {
                let mut message = serde_json::to_value(settings).expect("settings serialise");
                message["type"] = json!("settings");
                message["request"] = json!(request);
                Some(message)
            }
            Request::Commands(commands) => Some(json!({ "type": "commands", "request": request, "commands": commands })),
            Request::RefreshScene | Request::EnvironmentImage { .. } | Request::Clock(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_read_as_the_protocol_writes_them() {
        let frame = r#"{"type": "frame", "seq": 7, "scene_version": 12, "width": 640, "height": 360, "integrator": "eyelight",
            "samples": 16, "pass_samples": 4, "pass_seconds": 0.021, "encode_seconds": 0.004,
            "rays": {"primary": 921600, "shadow": 0, "reflection": 0, "refraction": 0, "diffuse": 0, "total": 921600},
            "mrays_per_second": 11.2, "effects": ["multisampling"], "converged": false, "something_new": 1}"#;
        let ServerMessage::Frame(stats) = serde_json::from_str(frame).unwrap() else { panic!("a frame") };
        assert_eq!((stats.seq, stats.samples, stats.rays.total, stats.effects.as_slice()), (7, 16, 921600, &["multisampling".to_string()][..]));
        let error = r#"{"type": "error", "request": 3, "error": {"code": "unprocessable", "message": "too big", "field": "width"}}"#;
        assert!(matches!(serde_json::from_str(error).unwrap(), ServerMessage::Error { request: Some(3), error } if error.field.as_deref() == Some("width")));
    }

    #[test]
    fn requests_write_stream_messages() {
        let settings = Request::Settings(Settings { integrator: Some("path".into()), ..Settings::default() });
        assert_eq!(settings.message(4), Some(json!({ "type": "settings", "request": 4, "integrator": "path" })));
        let camera = Request::Camera(CameraPatch { eye: [0.0, 1.0, 5.0], target: [0.0; 3] });
        assert_eq!(camera.message(5), Some(json!({ "type": "camera", "request": 5, "camera": { "eye": [0.0, 1.0, 5.0], "target": [0.0, 0.0, 0.0] } })));
        let both = Settings { width: Some(640), height: Some(360), ..Settings::default() }.merged(Settings { width: Some(800), max_samples: Some(64), ..Settings::default() });
        assert_eq!(both.query(), "width=800&height=360&max_samples=64");
    }
}
