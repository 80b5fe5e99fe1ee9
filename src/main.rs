//! The `raystage` command line. Parsing only: the commands live in the library.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use raystage::{RenderJob, SceneSource};
use raystage_demo::animated::Demo;

/// raystage: a ray-tracing rendering server.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render one frame of a glTF file or a built-in demo scene to a PNG file.
    Render {
        /// A glTF 2.0 file (.gltf or .glb) to render instead of a demo: seen through its first
        /// camera, or one that frames everything.
        #[arg(required_unless_present = "demo", conflicts_with = "demo")]
        scene: Option<PathBuf>,
        /// The demo scene: spheres (or sphere), soup, cornell, materials, robots, museum,
        /// museum-<triangles>, terrain.
        #[arg(long, value_parser = raystage::parse_demo)]
        demo: Option<Demo>,
        /// The frame of an animated demo.
        #[arg(long, default_value_t = 0)]
        frame: u32,
        // The scene time is a flag of the scene, as --frame is a demo's, not one of a frame's
        // settings (crates/render/src/settings.rs): posing edits the scene itself (instances
        // and vertices, and so the trees), which every frame rendered from it then shows,
        // while a frame's settings say how to render whatever scene it is given.
        /// Seconds into the glTF file's animation to render it at [default: 0].
        #[arg(long, conflicts_with_all = ["demo", "frames"])]
        time: Option<f32>,
        /// The animation of the glTF file to play: its name, its index, or `all` for every one
        /// together [default: the first].
        #[arg(long, conflicts_with = "demo")]
        animation: Option<String>,
        /// Seconds the shutter stays open from --time (or each frame's time): what the animation
        /// moves blurs along its motion, with the distribution or path integrator.
        #[arg(long, conflicts_with = "demo")]
        shutter: Option<f32>,
        /// Render frames FIRST..LAST (both included) of the glTF file's animation at --fps,
        /// frame n at n / fps seconds, from one import; --out is then a pattern with %d or %0Nd
        /// for the frame number (frame_%04d.png).
        #[arg(long, value_parser = raystage::parse_frames, conflicts_with = "demo")]
        frames: Option<(u32, u32)>,
        /// Frames per second of --frames.
        #[arg(long, default_value_t = 24.0, requires = "frames")]
        fps: f32,
        /// The image file to write: .png (sRGB, tone-mapped), .exr or .pfm (linear light).
        #[arg(long)]
        out: PathBuf,
        /// Threads for the BVH build and the render [default: one per core].
        #[arg(long)]
        threads: Option<usize>,
        #[command(flatten)]
        settings: raystage::FrameFlags,
        #[command(flatten)]
        lighting: Lighting,
        /// Also writes these channels of the first surface each pixel sees, comma-separated:
        /// depth, z, normal, albedo, instance, object, primitive. An EXR image holds them as
        /// named channels (depth.Z, normal.X, ..., instance.id); beside a PNG or PFM each goes
        /// to OUT-STEM.CHANNEL.pfm (depth and z always; the rest beside a PFM) or .png.
        #[arg(long, value_delimiter = ',')]
        channels: Vec<raystage_render::Channel>,
        /// Render on every rank of the MPI job this process was started in by `mpirun`: rank 0
        /// writes the image, the same bytes one process writes.
        #[cfg(feature = "mpi")]
        #[arg(long)]
        mpi: bool,
    },
    /// Serve the HTTP/JSON API: scenes, edits, PNG frames and a WebSocket stream.
    Serve {
        /// A glTF 2.0 file (.gltf or .glb) to load as scene 1.
        #[arg(conflicts_with = "demo")]
        scene: Option<PathBuf>,
        /// A demo scene to load as scene 1 (see `render --demo`).
        #[arg(long, value_parser = raystage::parse_demo)]
        demo: Option<Demo>,
        /// The address to listen on; anything but a loopback address needs a token.
        #[arg(long, default_value = "127.0.0.1:8080")]
        addr: std::net::SocketAddr,
        /// The bearer token every request must carry (`Authorization: Bearer <token>`).
        #[arg(long, env = "RAYSTAGE_TOKEN", hide_env_values = true)]
        token: Option<String>,
        /// Serve from every rank of the MPI job this process was started in by `mpirun`: rank 0
        /// serves the API, every other rank holds a replica of the scenes and renders its share
        /// of every frame.
        #[cfg(feature = "mpi")]
        #[arg(long)]
        mpi: bool,
        /// With --mpi: seconds rank 0 waits for a worker's answer before giving the workers up
        /// and serving alone.
        #[cfg(feature = "mpi")]
        #[arg(long, default_value_t = 90, value_parser = clap::value_parser!(u64).range(1..=86_400))]
        mpi_timeout: u64,
    },
    /// View a glTF file or a demo scene in a window: serves it on 127.0.0.1 (a free port) and
    /// opens the viewer on it. Left-drag orbits, right- or middle-drag pans, scroll zooms.
    View {
        /// A glTF 2.0 file (.gltf or .glb) to view.
        #[arg(required_unless_present = "demo", conflicts_with = "demo")]
        scene: Option<PathBuf>,
        /// The demo scene (see `render --demo`).
        #[arg(long, value_parser = raystage::parse_demo)]
        demo: Option<Demo>,
        /// How pixels are shaded at first (the viewer's panel changes it) [default: chosen for
        /// the scene as `render` chooses].
        #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(raystage_client::INTEGRATORS))]
        integrator: Option<String>,
        /// Samples per pixel the image refines to while nothing changes, at first (the
        /// viewer's panel changes it; at most the server's limit on samples per pixel).
        #[arg(long, default_value_t = 256)]
        max_samples: u32,
        /// Save a PNG screenshot of the window here once the first frame is shown, then exit.
        #[arg(long)]
        screenshot: Option<PathBuf>,
        #[command(flatten)]
        lighting: Lighting,
    },
    /// Measure what accuracy costs in time: render a converged reference of a scene, sweep
    /// each knob that trades accuracy for time, and write report.md, plots and images.
    Report {
        /// The scene: cornell, area-spheres, glass, spheres, or a .glb/.gltf file.
        #[arg(long, default_value = "cornell")]
        scene: String,
        /// The reference image, rendered elsewhere (.exr, .pfm or .npy of linear RGB) [default:
        /// a converged raystage render, which cannot show raystage's biases].
        #[arg(long)]
        reference: Option<PathBuf>,
        /// Image width [default: the reference's, else 160 on the long side at the camera's
        /// aspect].
        #[arg(long)]
        width: Option<u32>,
        /// Image height [default: as the width].
        #[arg(long)]
        height: Option<u32>,
        /// Renders per setting, interleaved, for medians, spreads and the bias/noise split.
        #[arg(long, default_value_t = 3)]
        repeats: u32,
        /// The target error (relative RMSE on 4x4 blocks) that times to target aim at.
        #[arg(long, default_value_t = 0.05)]
        target: f64,
        /// The directory to write the report into.
        #[arg(long, default_value = "report")]
        out: PathBuf,
        /// A tiny run (32 pixels on the long side, a 64-spp reference): seconds instead of
        /// minutes, too short to rank settings.
        #[arg(long)]
        quick: bool,
        /// Threads for the renders and builds [default: one per core].
        #[arg(long)]
        threads: Option<usize>,
    },
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Render {
            scene,
            demo,
            frame,
            time,
            animation,
            shutter,
            frames,
            fps,
            out,
            threads,
            settings,
            lighting,
            channels,
            #[cfg(feature = "mpi")]
            mpi,
        } => {
            let pose = (time.is_some() || animation.is_some() || shutter.is_some()).then(|| raystage::ScenePose { time: time.unwrap_or(0.0), animation, shutter });
            let scene = SceneSource::from_args(scene, demo, frame, pose).expect("clap requires a file or a demo");
            let frames = frames.map(|(first, last)| raystage::Sequence { first, last, fps });
            let mut settings = settings.patch();
            if lighting.no_default_lights {
                settings.default_lights = Some(false);
            }
            let job = RenderJob { scene, threads, settings, environment: lighting.environment(), out, channels, frames };
            #[cfg(feature = "mpi")]
            if mpi {
                return finish(raystage::Cluster::join().and_then(|cluster| raystage::render_scene_mpi(&job, &mut std::io::stdout().lock(), &cluster).map(|_| ())));
            }
            raystage::render_scene(&job, &mut std::io::stdout().lock()).map(|_| ())
        }
        Command::Serve {
            scene,
            demo,
            addr,
            token,
            #[cfg(feature = "mpi")]
            mpi,
            #[cfg(feature = "mpi")]
            mpi_timeout,
        } => {
            let job = raystage::ServeJob { addr, token, scene: SceneSource::from_args(scene, demo, 0, None) };
            #[cfg(feature = "mpi")]
            if mpi {
                let timeout = std::time::Duration::from_secs(mpi_timeout);
                return finish(raystage::Cluster::join().and_then(|cluster| raystage::serve_mpi(&job, &mut std::io::stdout().lock(), &cluster, timeout)));
            }
            raystage::serve(&job, &mut std::io::stdout().lock())
        }
        Command::View { scene, demo, integrator, max_samples, screenshot, lighting } => {
            let scene = SceneSource::from_args(scene, demo, 0, None).expect("clap requires a file or a demo");
            let (environment, default_lights) = (lighting.environment(), !lighting.no_default_lights);
            let job = raystage::ViewJob { scene, environment, default_lights, integrator, max_samples, screenshot };
            raystage::view(&job, &mut std::io::stdout().lock())
        }
        Command::Report { scene, reference, width, height, repeats, target, out, quick, threads } => {
            let job = raystage::ReportJob { scene, reference, width, height, repeats, target, out, quick, threads };
            raystage::run_report(&job, &mut std::io::stdout().lock()).map(|_| ())
        }
    };
    finish(result)
}

/// How `render` and `view` light a scene besides its own lights.
#[derive(clap::Args, Debug)]
struct Lighting {
    /// Light from all around the scene: studio (the neutral studio glTF viewers light a file
    /// with), a radiance (R,G,B or one number) or an equirectangular image (.hdr, .exr, .png,
    /// .jpg; its top row straight up), sampled by brightness [default: studio for a glTF file
    /// without lights of its own].
    #[arg(long, value_parser = raystage::parse_environment, allow_hyphen_values = true)]
    environment: Option<raystage::EnvironmentSource>,
    /// Turns the environment (the default studio too) about the up axis by this many degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    environment_rotate: f32,
    /// Scales the environment's radiance (the default studio's too).
    #[arg(long, default_value_t = 1.0)]
    environment_intensity: f32,
    /// Leave a scene that nothing lights dark: no studio for a glTF file without lights of its
    /// own, no sky for a demo that nothing lights.
    #[arg(long)]
    no_default_lights: bool,
}

impl Lighting {
    /// The environment the flags ask for (its source `None` for the default).
    fn environment(&self) -> raystage::Environment {
        raystage::Environment { source: self.environment.clone(), rotate_degrees: self.environment_rotate, intensity: self.environment_intensity }
    }
}

/// The exit status of a command, its error (if any) printed on standard error.
fn finish(result: anyhow::Result<()>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        #[cfg(feature = "mpi")]
        Err(err) if err.is::<raystage::Reported>() => ExitCode::FAILURE,
        Err(err) => {
            // `{:#}` prints the cause chain on one line, like clap's own errors.
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
