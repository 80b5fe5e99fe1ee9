//! Rendering frames for requests: settings checked against the limits, the render on a
//! blocking thread (it runs on the rayon pool, never on the reactor), the PNG encoded there too.

use std::sync::Arc;
use std::sync::atomic::AtomicU32;
use std::time::Duration;

use raystage_render::{Cancel, FrameSettings, RenderSettings, SettingsPatch};
use raystage_scene::Scene;
use serde::Deserialize;
use utoipa::{IntoParams, ToSchema};

use crate::cluster::Accumulator;
use crate::config::Limits;
use crate::error::{ApiError, ApiResult};
use crate::state::{AppState, SceneSlot};
use crate::turns::Client;
use crate::stats::{FrameReport, scene_time};

/// Bytes a frame takes per pixel while it renders: the sums of its samples (three `f32`) and
/// its sRGB rows on their way to the PNG.
pub(crate) const FRAME_BYTES_PER_PIXEL: u64 = 12 + 4;

/// Bytes a stream's image takes per pixel while the stream is open: the sums of its samples and
/// of their squares (for the noise estimate), the film of the frame being encoded, its sRGB
/// rows and its PNG.
pub(crate) const STREAM_BYTES_PER_PIXEL: u64 = 12 + 4 + 12 + 3 + 3;

/// The integrators by name, for the API description (the query keeps the string, parsed by
/// [`FrameSettings::apply`] with an error naming the field).
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

/// Makes a type the API takes a frame's settings in from the list of them
/// ([`raystage_render::frame_settings!`]): the type's own fields first, then every setting as an
/// optional field, described as the list describes it, its limits in `#[param(...)]` (a query)
/// or `#[schema(...)]` (a body) as the brackets after the type's name say. Its `patch` is the
/// settings it sets but the sample count, which each type names its own way.
macro_rules! settings_type {
    (
        $(#[$meta:meta])* pub struct $type:ident [$limits:ident] { $($own:tt)* }
        $( $(#[doc = $doc:literal])* $name:ident: $setting:ty [$($limit:tt)*] {$($flag:tt)*}, )*
    ) => {
        $(#[$meta])*
        pub struct $type {
            $($own)*
            $( $(#[doc = $doc])* #[$limits($($limit)*)] pub $name: Option<$setting>, )*
        }

        impl $type {
            /// The settings it sets, but the sample count.
            pub(crate) fn patch(&self) -> raystage_render::SettingsPatch {
                raystage_render::SettingsPatch { $($name: self.$name.clone(),)* ..raystage_render::SettingsPatch::default() }
            }
        }
    };
}
pub(crate) use settings_type;

raystage_render::frame_settings!(settings_type! {
    /// What frame to render.
    #[derive(Clone, Debug, Default, Deserialize, IntoParams)]
    #[serde(deny_unknown_fields)]
    #[into_params(parameter_in = Query)]
    pub struct FrameQuery [param] {
        /// Samples per pixel; default 1.
        #[param(minimum = 1)]
        pub spp: Option<u32>,
    }
});

impl FrameQuery {
    /// The frame the query asks for, checked (422 naming the parameter out of range); the
    /// integrator is chosen once the scene is seen.
    pub(crate) fn check(&self, limits: &Limits) -> ApiResult<FrameSettings> {
        let mut frame = FrameSettings::default();
        frame.apply(&SettingsPatch { samples_per_pixel: self.spp, ..self.patch() }).map_err(|e| setting_error(e, "spp"))?;
        check_limits(&frame.render, "spp", limits)?;
        Ok(frame)
    }
}

/// A setting the renderer refused, as the API reports it: 422 naming the parameter, the sample
/// count by the name `samples` that the request gave it.
pub(crate) fn setting_error(e: raystage_render::Error, samples: &str) -> ApiError {
    let field = match e {
        raystage_render::Error::Setting { field: "samples_per_pixel", .. } => Some(samples),
        raystage_render::Error::Setting { field, .. } => Some(field),
        _ => None,
    };
    ApiError::unprocessable(field.map(Into::into), e.to_string())
}

/// Checks a frame's size and samples (called `samples` in the request) against the server's
/// limits (422 naming the parameter).
pub(crate) fn check_limits(settings: &RenderSettings, samples: &str, limits: &Limits) -> ApiResult<()> {
    let max = limits.max_dimension;
    for (name, value) in [("width", settings.width), ("height", settings.height)] {
        if !(1..=max).contains(&value) {
            return Err(ApiError::unprocessable(Some(name.into()), format!("{name} {value} is not in 1..={max}")));
        }
    }
    let (width, height, spp) = (settings.width, settings.height, settings.samples_per_pixel);
    if !(1..=limits.max_spp).contains(&spp) {
        return Err(ApiError::unprocessable(Some(samples.into()), format!("{samples} {spp} is not in 1..={}", limits.max_spp)));
    }
    let total = width as u64 * height as u64 * spp as u64;
    if total > limits.max_frame_samples {
        return Err(ApiError::unprocessable(
            Some(samples.into()),
            format!("{width}×{height} at {spp} spp is {total} samples, more than the limit of {}", limits.max_frame_samples),
        ));
    }
    Ok(())
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
/// when the render stops; `client`'s turn comes as [`crate::turns`] shares them.
pub(crate) async fn render_png(
    state: &AppState,
    slot: &Arc<SceneSlot>,
    client: Client,
    snapshot: Option<(Arc<Scene>, u64)>,
    frame: FrameSettings,
    rows_done: Arc<AtomicU32>,
) -> ApiResult<Rendered> {
    let bytes = frame.render.width as u64 * frame.render.height as u64 * FRAME_BYTES_PER_PIXEL;
    let cluster = state.cluster().filter(|c| c.ranks() > 1).cloned();
    let scene_id = slot.id;
    let rendered = on_a_turn(state, slot, client, snapshot, bytes, move |scene, version, cancel| {
        let settings = frame.for_scene(&scene);
        let Some(cluster) = cluster else {
            let (png, stats, rendered, encoded) = crate::png::render_png(&scene.frame(), &settings, frame.look, cancel, &rows_done)?;
            let mut report = FrameReport::new(&settings, &stats, encoded, version, scene_time(&scene));
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
        let png = crate::png::encode(&accumulator.film(), frame.look)?;
        let mut report = FrameReport::new(&settings, &stats, start.elapsed().as_secs_f64() - rendered, version, scene_time(&scene));
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
/// reserved (refused at once if they cannot be) and `client`'s turn to render has come. `work` should
/// stop when its cancel token says so: when the returned future is dropped (the client hung up,
/// a render job was deleted) or past [`Limits::max_render_seconds`] (503). Either way the turn
/// and the memory go to the next render only once the work has stopped.
pub(crate) async fn on_a_turn<T: Send + 'static>(
    state: &AppState,
    slot: &Arc<SceneSlot>,
    client: Client,
    snapshot: Option<(Arc<Scene>, u64)>,
    bytes: u64,
    work: impl FnOnce(Arc<Scene>, u64, &Cancel) -> ApiResult<T> + Send + 'static,
) -> ApiResult<T> {
    // Before waiting for a turn: work that cannot have its memory fails at once.
    let memory = state.reserve_render_memory(bytes)?;
    let turn = state.render_permit(client).await;
    let (scene, version) = match snapshot {
        Some(snapshot) => snapshot,
        None => {
            // A clock that cannot move the scene pauses itself: the frame then shows the
            // scene as it is.
            let _ = slot.follow_clock(state).await;
            slot.snapshot().await
        }
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
