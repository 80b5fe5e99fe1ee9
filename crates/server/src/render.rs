//! Rendering frames for requests: settings checked against the limits, the render on a
//! blocking thread (it runs on the rayon pool, never on the reactor), the PNG encoded there too.

use std::sync::Arc;
use std::sync::atomic::AtomicU32;

use raystage_render::{FrameSettings, RenderSettings, SettingsPatch};
use raystage_scene::Scene;
use raystage_service::{AppState, Client, Error, FrameReport, Limits, Rendered, Result, SceneSlot, on_a_turn, scene_time};
use serde::Deserialize;
use utoipa::{IntoParams, ToSchema};

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
    pub(crate) fn check(&self, limits: &Limits) -> Result<FrameSettings> {
        let mut frame = FrameSettings::default();
        frame.apply(&SettingsPatch { samples_per_pixel: self.spp, ..self.patch() }).map_err(|e| setting_error(e, "spp"))?;
        check_limits(&frame.render, "spp", limits)?;
        Ok(frame)
    }
}

/// A setting the renderer refused, as the API reports it: 422 naming the parameter, the sample
/// count by the name `samples` that the request gave it.
pub(crate) fn setting_error(e: raystage_render::Error, samples: &str) -> Error {
    let field = match e {
        raystage_render::Error::Setting { field: "samples_per_pixel", .. } => Some(samples),
        raystage_render::Error::Setting { field, .. } => Some(field),
        _ => None,
    };
    Error::unprocessable(field.map(Into::into), e.to_string())
}

/// Checks a frame's size and samples (called `samples` in the request) against the server's
/// limits (422 naming the parameter).
pub(crate) fn check_limits(settings: &RenderSettings, samples: &str, limits: &Limits) -> Result<()> {
    let max = limits.max_dimension;
    for (name, value) in [("width", settings.width), ("height", settings.height)] {
        if !(1..=max).contains(&value) {
            return Err(Error::unprocessable(Some(name.into()), format!("{name} {value} is not in 1..={max}")));
        }
    }
    let (width, height, spp) = (settings.width, settings.height, settings.samples_per_pixel);
    if !(1..=limits.max_spp).contains(&spp) {
        return Err(Error::unprocessable(Some(samples.into()), format!("{samples} {spp} is not in 1..={}", limits.max_spp)));
    }
    let total = width as u64 * height as u64 * spp as u64;
    if total > limits.max_frame_samples {
        return Err(Error::unprocessable(
            Some(samples.into()),
            format!("{width}×{height} at {spp} spp is {total} samples, more than the limit of {}", limits.max_frame_samples),
        ));
    }
    Ok(())
}

/// Renders a frame of `slot` and encodes it, waiting for a turn to render first, counting the
/// rows finished in `rows_done`: the scene as `snapshot` holds it if given (a job renders the
/// scene as it was when it started), else as it is when the turn comes. See [`on_a_turn`] for
/// when the render stops; `client`'s turn comes as [`raystage_service::Client`] shares them.
pub(crate) async fn render_png(
    state: &AppState,
    slot: &Arc<SceneSlot>,
    client: Client,
    snapshot: Option<(Arc<Scene>, u64)>,
    frame: FrameSettings,
    rows_done: Arc<AtomicU32>,
) -> Result<Rendered> {
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
        let mut accumulator = cluster.accumulate(settings).map_err(crate::png::render_error)?;
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

