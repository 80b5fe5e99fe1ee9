//! Frame statistics as JSON: what a frame computed and what it cost.

use raystage_render::{FrameStats, RenderSettings};
use raystage_scene::Scene;
use serde::Serialize;
use utoipa::ToSchema;

/// Rays traced, by kind.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, ToSchema)]
pub struct RaysJson {
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

/// A rendered frame (or a stream's pass): its settings, effects, rays and times.
#[derive(Clone, Debug, PartialEq, Serialize, ToSchema)]
pub struct FrameReport {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The integrator.
    pub integrator: String,
    /// Samples per pixel this render added.
    pub samples_per_pixel: u32,
    /// Samples per pixel in the image (progressive streams accumulate).
    pub accumulated_samples: u32,
    /// The effects simulated (only what the scene calls for).
    pub effects: Vec<String>,
    /// Whether nothing in the scene gave light, so the renderer's default sky lit it.
    pub default_lights: bool,
    /// Samples that came out NaN or infinite (a bug; they went into the image as black).
    pub non_finite_samples: u64,
    /// Rays traced.
    pub rays: RaysJson,
    /// Wall-clock seconds of the render, lazy tree builds included.
    pub render_seconds: f64,
    /// Seconds spent building or refitting object trees (within `render_seconds`).
    pub build_seconds: f64,
    /// Seconds the PNG took beyond the render (a frame is compressed band by band while it
    /// renders; a stream's frame once its pass is done).
    pub encode_seconds: f64,
    /// Tracing rate, not counting tree builds.
    pub mrays_per_second: f64,
    /// The scene version rendered.
    pub scene_version: u64,
    /// The animation time the scene was posed at (see `/scenes/{scene}/clock`); absent for a
    /// scene never posed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene_time: Option<f64>,
    /// Where the frame's (or pass's) time went across a cluster's ranks (`raystage serve
    /// --mpi`); absent where one process rendered it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cluster: Option<ClusterTimes>,
}

/// Where a frame's (or pass's) time went across the ranks of a cluster, as rank 0 saw it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, ToSchema)]
pub struct ClusterTimes {
    /// Ranks that rendered it.
    pub ranks: u32,
    /// Sending the pass to the workers.
    pub send_seconds: f64,
    /// Rank 0's own share.
    pub render_seconds: f64,
    /// From rank 0's share done to every share in: waiting for the slowest rank, and the
    /// transfer.
    pub gather_seconds: f64,
    /// The workers' longest share.
    pub slowest_share_seconds: f64,
    /// Bytes of pixels gathered from the workers.
    pub gathered_bytes: u64,
}

impl FrameReport {
    /// The report of a render with `settings` that produced `stats`.
    pub fn new(settings: &RenderSettings, stats: &FrameStats, encode_seconds: f64, scene_version: u64, scene_time: Option<f64>) -> FrameReport {
        let r = stats.rays;
        FrameReport {
            width: settings.width,
            height: settings.height,
            integrator: settings.integrator.name().to_string(),
            samples_per_pixel: stats.samples_per_pixel,
            accumulated_samples: stats.accumulated_samples,
            effects: stats.effects.names().into_iter().map(String::from).collect(),
            default_lights: stats.default_lights,
            non_finite_samples: stats.non_finite,
            rays: RaysJson { primary: r.primary, shadow: r.shadow, reflection: r.reflection, refraction: r.refraction, diffuse: r.diffuse, total: r.total() },
            render_seconds: stats.seconds,
            build_seconds: stats.work.build_seconds,
            encode_seconds,
            mrays_per_second: stats.mrays_per_second(),
            scene_version,
            scene_time,
            cluster: None,
        }
    }
}

/// The animation time `scene` shows, as frames report it.
pub fn scene_time(scene: &Scene) -> Option<f64> {
    scene.posed().map(|(_, time)| f64::from(time))
}
