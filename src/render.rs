//! `raystage render`: load a scene (a built-in demo or a glTF file), render one frame with a
//! progress bar, write a PNG.

use std::fs::File;
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail, ensure};
use glam::Vec3;
use indicatif::{ProgressBar, ProgressStyle};
use raystage_demo::animated::Demo;
use raystage_render::{Channel, Film, FrameSettings, FrameStats, Integrator, OutputFormat, Progressive, RenderSettings, SettingsPatch, Share};
use raystage_scene::{Image, Light, Scene};

use crate::animate::{ScenePose, Sequence};

/// Largest accepted image width or height in pixels.
pub const MAX_DIMENSION: u32 = 16_384;

/// Largest accepted number of render threads.
pub const MAX_THREADS: usize = 1024;

/// Image width where none is given: a full-HD image, as a command renders a picture to keep (a
/// server's frames are previews, smaller).
pub const DEFAULT_WIDTH: u32 = 1920;

/// Image height where none is given (see [`DEFAULT_WIDTH`]).
pub const DEFAULT_HEIGHT: u32 = 1080;

/// Samples per pixel at most where the path tracer is chosen for a scene and no sample count is
/// given (adaptive sampling stops most tiles well before).
pub const AUTO_SAMPLES: u32 = 256;

/// The noise threshold of [`AUTO_SAMPLES`]: each pixel's standard error below 2 % of its
/// brightness, where noise stops being visible in an 8-bit image.
pub const AUTO_NOISE_THRESHOLD: f32 = 0.02;

/// Where a scene comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneSource {
    /// A built-in demo scene, at a frame of its animation (0 for the first; still scenes
    /// ignore it).
    Demo {
        /// The demo.
        demo: Demo,
        /// The frame.
        frame: u32,
    },
    /// A glTF 2.0 file (`.gltf` or `.glb`), seen through its camera or, if it has none, one
    /// that frames everything, posed at a moment of its animations if `pose` says (else at time
    /// 0 of its first).
    File {
        /// The file.
        path: PathBuf,
        /// When and which animation.
        pose: Option<ScenePose>,
    },
}

impl SceneSource {
    /// The scene a command line names: a file (posed as `pose` says), or a demo at a frame;
    /// `None` for neither.
    pub fn from_args(file: Option<PathBuf>, demo: Option<Demo>, frame: u32, pose: Option<ScenePose>) -> Option<SceneSource> {
        file.map(|path| SceneSource::File { path, pose }).or(demo.map(|demo| SceneSource::Demo { demo, frame }))
    }

    /// Builds or reads the scene, lit by `environment` if it names a source. Else, with
    /// `default_lights`, a glTF file that brings no lights of its own (`KHR_lights_punctual`) is
    /// lit by the studio environment, turned and scaled as `environment` says, as glTF viewers
    /// light such a file, whatever emitting surfaces it has (a demo keeps the renderer's
    /// default, the sky where nothing lights it). A file's notes (what it had that was left out)
    /// and the studio go to `log`.
    pub fn load(&self, log: &mut impl Write, environment: &Environment, default_lights: bool) -> Result<Scene> {
        let (mut scene, unlit_file) = match self {
            SceneSource::Demo { demo, frame } => (demo.scene(*frame).context("cannot build the demo scene")?, false),
            SceneSource::File { path, pose } => {
                let import = raystage_gltf_import::read_file(path, &raystage_gltf_import::Limits::default())
                    .with_context(|| format!("cannot import {}", path.display()))?;
                for note in import.notes() {
                    writeln!(log, "note: {}: {note}", path.display())?;
                }
                let unlit = import.lights().is_empty();
                let mut scene = import.into_scene().with_context(|| format!("cannot import {}", path.display()))?;
                if let Some(pose) = pose {
                    crate::animate::pose(&mut scene, pose, log, &self.name())?;
                }
                (scene, unlit)
            }
        };
        match &environment.source {
            Some(source) => add_environment(&mut scene, source, environment)?,
            None if unlit_file && default_lights => {
                add_environment(&mut scene, &EnvironmentSource::Studio, environment)?;
                writeln!(
                    log,
                    "note: {}: no lights of its own: the studio environment lights it, as glTF viewers do (--environment replaces it, --no-default-lights turns it off)",
                    self.name()
                )?;
            }
            None => {}
        }
        Ok(scene)
    }

    /// The name in logs: the demo's, or the file's.
    pub fn name(&self) -> String {
        match self {
            SceneSource::Demo { demo, .. } => demo.name(),
            SceneSource::File { path, .. } => path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned()),
        }
    }
}

/// Makes [`FrameFlags`] from the list of a frame's settings
/// ([`raystage_render::frame_settings!`]): every setting a flag as the list's braces say (`skip`
/// for none), and `--spp`.
macro_rules! frame_flags {
    ($( $(#[doc = $doc:literal])* $name:ident: $setting:ty [$($limit:tt)*] {$($flag:tt)*}, )*) => {
        /// `raystage render`'s flags for a frame's settings.
        #[derive(clap::Args, Clone, Debug, Default, PartialEq)]
        pub struct FrameFlags {
            /// Samples per pixel [default: 1; where the path tracer is chosen for the scene, up
            /// to 256 with adaptive sampling to a noise threshold of 0.02].
            #[arg(long)]
            pub spp: Option<u32>,
            $( $(#[doc = $doc])* #[arg($($flag)*)] pub $name: Option<$setting>, )*
        }

        impl FrameFlags {
            /// The settings the flags set.
            pub fn patch(&self) -> SettingsPatch {
                SettingsPatch { samples_per_pixel: self.spp, $($name: self.$name.clone(),)* }
            }
        }
    };
}

raystage_render::frame_settings!(frame_flags! {});

/// What to render and where to write it.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderJob {
    /// The scene.
    pub scene: SceneSource,
    /// Threads for the BVH build and the render, `1..=MAX_THREADS`; `None` for one per core.
    pub threads: Option<usize>,
    /// The frame's settings as given; the rest are the renderer's defaults but the size,
    /// [`DEFAULT_WIDTH`] × [`DEFAULT_HEIGHT`] (each side `1..=MAX_DIMENSION`). With no
    /// integrator, [`Integrator::default_for`] the scene; with no samples per pixel, one, or,
    /// where the path tracer is chosen for the scene (neither named), [`AUTO_SAMPLES`] with
    /// adaptive sampling to [`AUTO_NOISE_THRESHOLD`] unless a threshold is given: a clean
    /// picture from a command with no options.
    pub settings: SettingsPatch,
    /// An environment light to add to the scene, or the default's turn and scale.
    pub environment: Environment,
    /// The image file to write (created or replaced): `.png` (sRGB, tone-mapped), `.exr` or
    /// `.pfm` (linear, as rendered), told by the extension.
    pub out: PathBuf,
    /// Channels to write beside it ([`channel_path`] names their files).
    pub channels: Vec<Channel>,
    /// A sequence of frames of the file's animation to render instead of one frame: `out` is
    /// then a pattern (see [`crate::animate::Sequence`]).
    pub frames: Option<Sequence>,
}

/// Where channel `channel` of an image written to `out` (a PNG or PFM: an EXR holds its
/// channels) goes, and whether as PFM (else PNG): `frame.png` → `frame.depth.pfm`,
/// `frame.normal.png`. Depths are floats whatever the image; the rest follow it: 8-bit beside a
/// PNG, floats beside a PFM.
fn channel_path(out: &std::path::Path, channel: Channel) -> (PathBuf, bool) {
    let linear = !matches!(OutputFormat::from_path(out), Ok(OutputFormat::Png));
    let pfm = linear || channel.is_distance();
    let stem = out.file_stem().map_or_else(|| "frame".into(), |s| s.to_string_lossy().into_owned());
    (out.with_file_name(format!("{stem}.{}.{}", channel.name(), if pfm { "pfm" } else { "png" })), pfm)
}

/// An environment light as the command line asks for it.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// Where its light comes from; `None` for the default (the studio for a glTF file without
    /// lights of its own, else nothing).
    pub source: Option<EnvironmentSource>,
    /// Turns it about the up axis (+y) by this many degrees.
    pub rotate_degrees: f32,
    /// Scales its radiance.
    pub intensity: f32,
}

impl Default for Environment {
    /// The default environment, neither turned nor scaled.
    fn default() -> Environment {
        Environment { source: None, rotate_degrees: 0.0, intensity: 1.0 }
    }
}

/// Light from all around: one radiance, a latitude-longitude image, or the studio.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvironmentSource {
    /// The same radiance from every direction, linear RGB.
    Uniform(Vec3),
    /// An equirectangular image (Radiance HDR, OpenEXR, PNG or JPEG), its top row straight up.
    Image(PathBuf),
    /// The neutral studio raystage makes ([`raystage_scene::studio_environment`]).
    Studio,
}

/// Parses `R,G,B` (three numbers) or one number as a non-negative linear colour.
fn parse_colour(text: &str) -> Option<Vec3> {
    raystage_scene::parse_color(text).filter(|c| c.is_finite() && c.min_element() >= 0.0)
}

/// Parses `--environment`: `studio`, a radiance (`R,G,B` or one number) or an image file's
/// path.
pub fn parse_environment(text: &str) -> Result<EnvironmentSource> {
    if text == "studio" {
        return Ok(EnvironmentSource::Studio);
    }
    if let Some(colour) = parse_colour(text) {
        return Ok(EnvironmentSource::Uniform(colour));
    }
    let path = PathBuf::from(text);
    let known = ["hdr", "exr", "png", "jpg", "jpeg"];
    match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase) {
        Some(ext) if known.contains(&ext.as_str()) => Ok(EnvironmentSource::Image(path)),
        _ => bail!("`{text}` is neither `studio`, a radiance (R,G,B or one number, not negative) nor an image file (.hdr, .exr, .png, .jpg)"),
    }
}

/// Parses `on` or `off`.
pub fn parse_switch(text: &str) -> Result<bool> {
    match text {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => bail!("expected on or off, got `{text}`"),
    }
}

/// Adds an environment light of `source` to `scene`, turned and scaled as `environment` says.
fn add_environment(scene: &mut Scene, source: &EnvironmentSource, environment: &Environment) -> Result<()> {
    let intensity = environment.intensity;
    ensure!(intensity.is_finite() && intensity >= 0.0, "--environment-intensity must be a number not below 0, got {intensity}");
    let image = match source {
        EnvironmentSource::Uniform(radiance) => {
            scene.add_light(Light::Environment { radiance: *radiance * intensity, map: None, rotate_degrees: 0.0 })?;
            return Ok(());
        }
        EnvironmentSource::Image(path) => {
            let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
            Image::decode(&bytes).with_context(|| format!("cannot decode {}", path.display()))?
        }
        EnvironmentSource::Studio => raystage_scene::studio_environment(),
    };
    scene.add_environment_map(image, Vec3::splat(intensity), environment.rotate_degrees)?;
    Ok(())
}

/// What a render cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderReport {
    /// Triangles in the scene.
    pub triangles: usize,
    /// Threads used.
    pub threads: usize,
    /// The frame's statistics, lazy BVH builds included.
    pub frame: FrameStats,
    /// Seconds to load the scene and, on several ranks, agree that every rank has it.
    pub setup_seconds: f64,
}

/// Parses a demo scene name (see [`Demo::NAMES`]).
pub fn parse_demo(name: &str) -> Result<Demo> {
    match Demo::from_name(name) {
        Some(demo) => Ok(demo),
        None => bail!("unknown demo scene `{name}`: expected {}", Demo::NAMES),
    }
}

/// Runs `job`: loads the scene, renders the frame (object trees are built lazily, by the first
/// rays that need them) and writes the PNG, logging a one-line summary to `log`. A render of
/// several samples per pixel shows a progress bar on a terminal.
///
/// The job is checked first and the output file created before any work, so that bad arguments
/// and unwritable paths fail at once rather than after the render.
pub fn render_scene(job: &RenderJob, log: &mut impl Write) -> Result<RenderReport> {
    match &job.frames {
        Some(sequence) => crate::animate::render_sequence(job, sequence, log),
        None => render_on(job, log, &Alone),
    }
}

/// The processes a frame is rendered by: this one alone, or every rank of an MPI job
/// (`crate::Cluster`), each rendering its share of the frame.
pub(crate) trait Ranks {
    /// Whether this process writes the image and the log (rank 0).
    fn is_root(&self) -> bool;
    /// This process's share of the frame.
    fn share(&self) -> Share;
    /// Every process's `result`, agreed: all go on, or all stop with an error.
    fn agree(&self, result: Result<()>) -> Result<()>;
    /// The shares' images put together, with the frame's statistics and mean samples per
    /// pixel: on the root; `None` elsewhere.
    fn gather(&self, film: Film, stats: FrameStats, mean_samples: f64) -> Result<Option<(Film, FrameStats, f64)>>;
}

/// One process, the whole frame.
struct Alone;

impl Ranks for Alone {
    fn is_root(&self) -> bool {
        true
    }

    fn share(&self) -> Share {
        Share::WHOLE
    }

    fn agree(&self, result: Result<()>) -> Result<()> {
        result
    }

    fn gather(&self, film: Film, stats: FrameStats, mean_samples: f64) -> Result<Option<(Film, FrameStats, f64)>> {
        Ok(Some((film, stats, mean_samples)))
    }
}

/// [`render_scene`] on every rank of an MPI job started by `mpirun`: each rank builds the scene
/// from the same job, renders its share of the frame on all its threads, and rank 0 puts the
/// frame together, writes the image (the very bytes one process writes) and logs; the other
/// ranks write and log nothing, and return `None`.
#[cfg(feature = "mpi")]
pub fn render_scene_mpi(job: &RenderJob, log: &mut impl Write, cluster: &crate::Cluster) -> Result<Option<RenderReport>> {
    ensure!(job.frames.is_none(), "--frames renders on one process: leave out --mpi");
    if cluster.rank() == 0 {
        let report = render_on(job, log, cluster)?;
        writeln!(log, "MPI: {} ranks, each rendering its share of the frame's tiles on {} threads", cluster.size(), report.threads)?;
        let gathered = cluster.gathered().context("rank 0 gathered the frame")?;
        writeln!(
            log,
            "MPI timing: {} ranks x {} threads; setup {:.3} s (load + vote); {gathered}",
            cluster.size(),
            report.threads,
            report.setup_seconds
        )?;
        Ok(Some(report))
    } else {
        render_on(job, &mut std::io::sink(), cluster).map(|_| None)
    }
}

/// The job's settings checked and the render threads started, before any work.
pub(crate) fn prepare(job: &RenderJob) -> Result<(FrameSettings, rayon::ThreadPool)> {
    let asked = &job.settings;
    for (name, value) in [("width", asked.width.unwrap_or(DEFAULT_WIDTH)), ("height", asked.height.unwrap_or(DEFAULT_HEIGHT))] {
        ensure!((1..=MAX_DIMENSION).contains(&value), "--{name} must be between 1 and {MAX_DIMENSION}, got {value}");
    }
    let mut given = FrameSettings { render: RenderSettings { width: DEFAULT_WIDTH, height: DEFAULT_HEIGHT, ..RenderSettings::default() }, ..FrameSettings::default() };
    given.apply(asked).context("bad render settings")?;
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(threads) = job.threads {
        ensure!((1..=MAX_THREADS).contains(&threads), "--threads must be between 1 and {MAX_THREADS}, got {threads}");
        pool = pool.num_threads(threads);
    }
    Ok((given, pool.build().context("cannot start the render threads")?))
}

/// The settings `scene` is rendered with: what was `given` and `asked`, the rest chosen for the
/// scene (see [`RenderJob::settings`]).
pub(crate) fn settings_for(given: &FrameSettings, asked: &SettingsPatch, scene: &Scene) -> RenderSettings {
    let chosen = given.for_scene(scene);
    let auto = asked.samples_per_pixel.is_none() && given.integrator.is_none() && chosen.integrator == Integrator::Path;
    match auto {
        true => RenderSettings { samples_per_pixel: AUTO_SAMPLES, noise_threshold: chosen.noise_threshold.or(Some(AUTO_NOISE_THRESHOLD)), ..chosen },
        false => chosen,
    }
}

/// [`render_scene`] by `ranks`; the report of a rank that is not the root is its own share's.
fn render_on(job: &RenderJob, log: &mut impl Write, ranks: &impl Ranks) -> Result<RenderReport> {
    let (given, pool) = prepare(job)?;
    let format = OutputFormat::from_path(&job.out)?;
    // What one rank can fail at alone is voted on, so that no rank waits for another that quit.
    let setup = Instant::now();
    let prepared = (|| {
        let out = if ranks.is_root() { Some(File::create(&job.out).with_context(|| format!("cannot create {}", job.out.display()))?) } else { None };
        let scene = job.scene.load(log, &job.environment, given.render.default_lights)?;
        Ok((out, scene))
    })();
    let (mut out, scene) = match prepared {
        Ok(prepared) => {
            ranks.agree(Ok(()))?;
            prepared
        }
        Err(e) => return Err(ranks.agree(Err(e)).expect_err("a failure is agreed as one")),
    };
    let setup_seconds = setup.elapsed().as_secs_f64();
    let settings = settings_for(&given, &job.settings, &scene);
    let look = given.look;
    let share = ranks.share();
    let (film, frame, mean_samples) = pool.install(|| render_with_progress(&scene, &settings, share)).context("bad render settings")?;
    let triangles = scene.object_ids().map(|id| scene.mesh(id).map_or(0, |m| m.indices.len())).sum();
    let Some((film, frame, mean_samples)) = ranks.gather(film, frame, mean_samples)? else {
        return Ok(RenderReport { triangles, threads: pool.current_num_threads(), frame, setup_seconds });
    };
    let channels = pool.install(|| raystage_render::render_channels(&scene.frame(), settings.width, settings.height, &job.channels))?;
    // An OpenEXR image holds its channels; other formats have them beside.
    let (encoded, beside) = match format {
        OutputFormat::Exr if !channels.is_empty() => (raystage_render::exr_with_channels(&film, look, &channels), Vec::new()),
        _ => (film.encode(format, look), channels),
    };
    let out = out.as_mut().expect("the root created the file");
    out.write_all(&encoded.context("cannot encode the image")?).with_context(|| format!("cannot write {}", job.out.display()))?;
    for image in beside {
        let (path, pfm) = channel_path(&job.out, image.channel);
        let bytes = if pfm { image.pfm() } else { image.png()? };
        std::fs::write(&path, bytes).with_context(|| format!("cannot write {}", path.display()))?;
        writeln!(log, "{} -> {}", image.channel.name(), path.display())?;
    }

    let report = RenderReport { triangles, threads: pool.current_num_threads(), frame, setup_seconds };
    // Where instances repeat objects (a forest of one tree), the triangles they place as well.
    let (instances, placed) = scene.instances().fold((0, 0), |(n, sum), (_, object, _)| (n + 1, sum + scene.mesh(object).map_or(0, |m| m.indices.len())));
    let repeated = if placed > triangles { format!(", {placed} placed by {instances} instances") } else { String::new() };
    if frame.default_lights {
        writeln!(log, "note: nothing in the scene gives light: the default sky lights it (--no-default-lights turns it off)")?;
    }
    if settings.noise_threshold.is_some() {
        writeln!(log, "adaptive sampling: {mean_samples:.1} samples per pixel on average, of {}", settings.samples_per_pixel)?;
    }
    if frame.non_finite > 0 {
        writeln!(log, "warning: {} samples came out NaN or infinite and went in as black", frame.non_finite)?;
    }
    writeln!(
        log,
        "{}x{} {} ({} triangles{}), {} at {} spp [{}]{}: {:.3} s on {} {} (lazy BVH builds {:.3} s of it), {} rays ({} primary, {} shadow) at {:.1} Mrays/s -> {}",
        settings.width,
        settings.height,
        job.scene.name(),
        triangles,
        repeated,
        settings.integrator.name(),
        settings.samples_per_pixel,
        frame.effects.names().join(", "),
        if frame.default_lights { ", default sky" } else { "" },
        frame.seconds,
        report.threads,
        if report.threads == 1 { "thread" } else { "threads" },
        frame.work.build_seconds,
        frame.rays.total(),
        frame.rays.primary,
        frame.rays.shadow,
        frame.mrays_per_second(),
        job.out.display()
    )?;
    Ok(report)
}

/// Renders `settings.samples_per_pixel` samples in passes (about a hundred at most), advancing
/// a progress bar on standard error after each (drawn only on a terminal); returns the PNG, the
/// statistics of the whole frame and the samples per pixel taken on average (fewer than asked
/// for where adaptive sampling stopped tiles early). The passes continue each pixel's sample sequence, so the
/// image is the one a single pass would give.
pub(crate) fn render_with_progress(scene: &Scene, settings: &RenderSettings, share: Share) -> Result<(Film, FrameStats, f64)> {
    let start = Instant::now();
    let mut progressive = Progressive::new(*settings)?.with_share(share)?;
    let total = settings.samples_per_pixel;
    let bar = ProgressBar::new(total as u64).with_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} samples per pixel, {eta} left").expect("a valid template"),
    );
    let frame = scene.frame();
    let per_pass = total.div_ceil(100);
    let mut stats: Option<FrameStats> = None;
    while progressive.samples() < total {
        let pass = progressive.add(&frame, per_pass.min(total - progressive.samples()));
        stats = Some(match stats {
            None => pass,
            Some(mut sum) => {
                sum.merge(&pass);
                sum
            }
        });
        bar.set_position(progressive.samples() as u64);
    }
    bar.finish_and_clear();
    let mut stats = stats.expect("at least one sample per pixel");
    stats.seconds = start.elapsed().as_secs_f64();
    Ok((progressive.film(), stats, progressive.mean_samples()))
}
