//! Rendering frames for requests: settings checked against the limits, the render on a
//! blocking thread (it runs on the rayon pool, never on the reactor), the PNG encoded there too.

use std::sync::Arc;
use std::sync::atomic::AtomicU32;
use std::time::Duration;

use raystage_render::{Cancel, Filter, Integrator, Look, MAX_DEPTH, RenderSettings};
use raystage_scene::{Background, Scene};
use serde::Deserialize;
use utoipa::{IntoParams, ToSchema};

use crate::cluster::Accumulator;
use crate::config::Limits;
use crate::error::{ApiError, ApiResult};
use crate::state::{AppState, SceneSlot};
use crate::stats::FrameReport;

/// Bytes a frame takes per pixel while it renders: the sums of its samples (three `f32`) and
/// its sRGB rows on their way to the PNG.
pub(crate) const FRAME_BYTES_PER_PIXEL: u64 = 12 + 4;

/// Bytes a stream's image takes per pixel while the stream is open: the sums of its samples and
/// of their squares (for the noise estimate), the film of the frame being encoded, its sRGB
/// rows and its PNG.
pub(crate) const STREAM_BYTES_PER_PIXEL: u64 = 12 + 4 + 12 + 3 + 3;

/// The integrators by name, for the API description (the query keeps the string, parsed by
/// [`parse_integrator`] with an error naming the field).
#[derive(ToSchema)]
#[serde(rename_all = "lowercase")]
#[allow(dead_code, reason = "a schema only: the names the API accepts")]
pub(crate) enum IntegratorName {
    /// The eye-light preview.
    Eyelight,
    /// Whitted's ray tracing.
    Whitted,
    /// Cook's distribution ray tracing.
    Distribution,
    /// Path tracing.
    Path,
}

/// The PNG tone curves by name, for the API description.
#[derive(ToSchema)]
#[serde(rename_all = "lowercase")]
#[allow(dead_code, reason = "a schema only: the names the API accepts")]
pub(crate) enum ToneMapName {
    /// Clamp to [0, 1] (the default).
    Clamp,
    /// The same as `clamp`.
    None,
    /// Khronos PBR Neutral.
    Neutral,
}

/// What frame to render.
#[derive(Clone, Debug, Default, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub struct FrameQuery {
    /// Width in pixels; default 640.
    #[param(minimum = 1)]
    pub width: Option<u32>,
    /// Height in pixels; default 360.
    #[param(minimum = 1)]
    pub height: Option<u32>,
    /// Samples per pixel; default 1.
    #[param(minimum = 1)]
    pub spp: Option<u32>,
    /// `eyelight`, `whitted`, `distribution` or `path`; default `whitted` if anything lights
    /// the scene (the default sky does unless `default_lights` is false), else `eyelight`.
    #[param(value_type = Option<IntegratorName>)]
    pub integrator: Option<String>,
    /// What camera rays that hit nothing show: `sky`, `black` or `R,G,B`; default the
    /// environment light if the scene has one, else the scene's choice, else the sky where the
    /// default lights the scene, else black.
    pub background: Option<String>,
    /// Whether a scene that nothing lights (no light, no emitting surface) is lit by the
    /// default sky; default true.
    pub default_lights: Option<bool>,
    /// Longest path in segments, the camera ray included, or deepest recursion: 1 to 64;
    /// default 6.
    #[param(minimum = 1, maximum = 64)]
    pub max_depth: Option<u32>,
    /// Whether the path tracer may end paths early by Russian roulette; default true.
    pub russian_roulette: Option<bool>,
    /// The pixel filter: `box`, `gaussian` or `gaussian:RADIUS`; default `box`.
    pub filter: Option<String>,
    /// Seed of the sample sequences; default 0.
    pub seed: Option<u32>,
    /// Adaptive sampling: tiles stop taking samples once each pixel's standard error is below
    /// this fraction of its brightness, in (0, 1]; default none (every pixel gets `spp`).
    #[param(exclusive_minimum = 0, maximum = 1)]
    pub noise_threshold: Option<f32>,
    /// Exposure in stops: the image is scaled by 2 to this power; default 0.
    pub exposure: Option<f32>,
    /// The PNG's tone curve: `clamp` (the default) or `neutral` (Khronos PBR Neutral).
    #[param(value_type = Option<ToneMapName>)]
    pub tonemap: Option<String>,
}

/// How a frame is set up beyond its size and integrator: what a render needs to match another
/// renderer's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Setup {
    pub background: Option<Background>,
    pub default_lights: bool,
    pub max_depth: u32,
    pub russian_roulette: bool,
    pub filter: Filter,
    pub seed: u32,
    pub noise_threshold: Option<f32>,
    /// How the PNG is graded.
    pub look: Look,
}

impl Default for Setup {
    fn default() -> Setup {
        let s = RenderSettings::default();
        Setup {
            background: s.background,
            default_lights: s.default_lights,
            max_depth: s.max_depth,
            russian_roulette: s.russian_roulette,
            filter: s.filter,
            seed: s.seed,
            noise_threshold: s.noise_threshold,
            look: Look::default(),
        }
    }
}

/// A frame request checked against the limits; the integrator is chosen once the scene is seen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FrameRequest {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub integrator: Option<Integrator>,
    pub setup: Setup,
}

impl FrameQuery {
    /// Checks the query (422 naming the parameter out of range).
    pub(crate) fn check(&self, limits: &Limits) -> ApiResult<FrameRequest> {
        let request = FrameRequest {
            width: self.width.unwrap_or(640),
            height: self.height.unwrap_or(360),
            spp: self.spp.unwrap_or(1),
            integrator: self.integrator.as_deref().map(parse_integrator).transpose()?,
            setup: self.setup_over(Setup::default())?,
        };
        request.check(limits)?;
        Ok(request)
    }
}

impl FrameQuery {
    /// `base` with what the query sets replaced (422 naming the parameter that is wrong). The
    /// stream applies its changes this way too, over its current setup.
    pub(crate) fn setup_over(&self, base: Setup) -> ApiResult<Setup> {
        let wrong = |field: &str, message: String| ApiError::unprocessable(Some(field.into()), message);
        let d = base;
        let max_depth = self.max_depth.unwrap_or(d.max_depth);
        if !(1..=MAX_DEPTH).contains(&max_depth) {
            return Err(wrong("max_depth", format!("max_depth {max_depth} is not in 1..={MAX_DEPTH}")));
        }
        if let Some(threshold) = self.noise_threshold.filter(|t| !(*t > 0.0 && *t <= 1.0)) {
            return Err(wrong("noise_threshold", format!("noise_threshold {threshold} is not in (0, 1]")));
        }
        let exposure = self.exposure.unwrap_or(d.look.exposure);
        if !exposure.is_finite() {
            return Err(wrong("exposure", format!("exposure {exposure} is not a number of stops")));
        }
        let tone_map = self.tonemap.as_deref().map(str::parse).transpose().map_err(|e: raystage_render::Error| wrong("tonemap", e.to_string()))?;
        Ok(Setup {
            look: Look { exposure, tone_map: tone_map.unwrap_or(d.look.tone_map) },
            noise_threshold: self.noise_threshold.or(d.noise_threshold),
            background: self
                .background
                .as_deref()
                .map(str::parse)
                .transpose()
                .map_err(|e: raystage_scene::SceneError| wrong("background", e.to_string()))?
                .or(d.background),
            default_lights: self.default_lights.unwrap_or(d.default_lights),
            max_depth,
            russian_roulette: self.russian_roulette.unwrap_or(d.russian_roulette),
            filter: self.filter.as_deref().map(str::parse).transpose().map_err(|e: raystage_render::Error| wrong("filter", e.to_string()))?.unwrap_or(d.filter),
            seed: self.seed.unwrap_or(d.seed),
        })
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
            integrator: self.integrator.unwrap_or_else(|| Integrator::default_for(scene, self.setup.default_lights)),
            background: self.setup.background,
            default_lights: self.setup.default_lights,
            max_depth: self.setup.max_depth,
            russian_roulette: self.setup.russian_roulette,
            filter: self.setup.filter,
            seed: self.setup.seed,
            noise_threshold: self.setup.noise_threshold,
            ..RenderSettings::default()
        }
    }
}

/// A rendered frame.
pub(crate) struct Rendered {
    /// The PNG.
    pub png: Vec<u8>,
    /// What it cost.
    pub report: FrameReport,
}

/// Renders a frame of `slot` and encodes it, waiting for a turn to render first, counting the
/// rows finished in `rows_done`: the scene as `snapshot` holds it if given (a job renders the
/// scene as it was when it started), else as it is when the turn comes. See [`on_a_turn`] for
/// when the render stops.
pub(crate) async fn render_png(
    state: &AppState,
    slot: &Arc<SceneSlot>,
    snapshot: Option<(Arc<Scene>, u64)>,
    request: FrameRequest,
    rows_done: Arc<AtomicU32>,
) -> ApiResult<Rendered> {
    let bytes = request.width as u64 * request.height as u64 * FRAME_BYTES_PER_PIXEL;
    let cluster = state.cluster().filter(|c| c.ranks() > 1).cloned();
    let scene_id = slot.id;
    let rendered = on_a_turn(state, slot, snapshot, bytes, move |scene, version, cancel| {
        let settings = request.settings(&scene);
        let Some(cluster) = cluster else {
            let (png, stats, rendered, encoded) = crate::png::render_png(&scene.frame(), &settings, request.setup.look, cancel, &rows_done)?;
            let mut report = FrameReport::new(&settings, &stats, encoded, version);
            // The whole render, with the film's allocation and resolve, which the frame
            // statistics leave out.
            report.render_seconds = rendered;
            return Ok(Rendered { png, report });
        };
        // Across the cluster: one pass of every sample, gathered, then encoded (a worker's rows
        // arrive together, so encoding cannot overlap the render here).
        let start = std::time::Instant::now();
        let mut accumulator = Accumulator::new(settings, Some(&cluster)).map_err(crate::png::render_error)?;
        let stats = accumulator.add(scene_id, &scene.frame(), version, settings.samples_per_pixel, true, cancel).map_err(crate::png::render_error)?;
        let rendered = start.elapsed().as_secs_f64();
        rows_done.store(settings.height, std::sync::atomic::Ordering::Relaxed);
        let png = crate::png::encode(&accumulator.film(), request.setup.look)?;
        let mut report = FrameReport::new(&settings, &stats, start.elapsed().as_secs_f64() - rendered, version);
        report.render_seconds = rendered;
        report.cluster = accumulator.times();
        Ok(Rendered { png, report })
    })
    .await?;
    *slot.last_frame.lock().unwrap_or_else(|e| e.into_inner()) = Some(rendered.report.clone());
    Ok(rendered)
}

/// Runs `work` on a snapshot of `slot` (`snapshot` if given, else the scene as it is when the
/// turn comes) and its version, on a blocking thread, once `bytes` of memory for images are
/// reserved (refused at once if they cannot be) and a turn to render has come. `work` should
/// stop when its cancel token says so: when the returned future is dropped (the client hung up,
/// a render job was deleted) or past [`Limits::max_render_seconds`] (503). Either way the turn
/// and the memory go to the next render only once the work has stopped.
pub(crate) async fn on_a_turn<T: Send + 'static>(
    state: &AppState,
    slot: &Arc<SceneSlot>,
    snapshot: Option<(Arc<Scene>, u64)>,
    bytes: u64,
    work: impl FnOnce(Arc<Scene>, u64, &Cancel) -> ApiResult<T> + Send + 'static,
) -> ApiResult<T> {
    // Before waiting for a turn: work that cannot have its memory fails at once.
    let memory = state.reserve_render_memory(bytes)?;
    let turn = state.render_permit().await;
    let (scene, version) = match snapshot {
        Some(snapshot) => snapshot,
        None => slot.snapshot().await,
    };
    let cancel = CancelOnDrop(Cancel::new());
    let token = cancel.0.clone();
    let task = tokio::task::spawn_blocking(move || {
        let _running = turn.running();
        let _memory = memory;
        work(scene, version, &token)
        // The turn is dropped here, when the work has stopped, and not when the client goes.
    });
    within_budget(&state.config().limits, task).await?
}

/// Waits for a render's blocking task for at most [`Limits::max_render_seconds`]: past it, 503
/// naming the limit. The caller's [`CancelOnDrop`] then stops the render as it returns.
pub(crate) async fn within_budget<T>(limits: &Limits, work: tokio::task::JoinHandle<T>) -> ApiResult<T> {
    let budget = limits.max_render_seconds;
    match tokio::time::timeout(Duration::from_secs(budget), work).await {
        Ok(joined) => joined.map_err(|e| ApiError::internal(format!("a render failed: {e}"))),
        Err(_) => Err(ApiError::render_budget(
            "max_render_seconds",
            format!("the render ran past the server's limit of {budget} s: ask for fewer pixels or samples, or a faster integrator"),
        )),
    }
}

/// Cancels a render when dropped: held by whatever waits for the render (a request's future,
/// a stream's loop), so that the render stops as soon as nobody waits for it, whichever way
/// the waiting ends (the client hung up and hyper dropped the future, a budget ran out, a
/// stream closed).
pub(crate) struct CancelOnDrop(pub Cancel);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.cancel();
    }
}
