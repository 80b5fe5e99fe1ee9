//! `raystage view`: a scene and the viewer in one step. A server runs in-process on a free
//! loopback port with the scene as scene 1, and the viewer's window opens on it; closing the
//! window stops both.

use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result, ensure};
use raystage_server::{AppState, Config};

use crate::render::{Environment, SceneSource};

/// What to view.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewJob {
    /// The scene.
    pub scene: SceneSource,
    /// An environment light to add to the scene, or the default's turn and scale.
    pub environment: Environment,
    /// Whether a scene that nothing lights gets the default light (the studio for a glTF file
    /// without lights of its own, the sky for a demo).
    pub default_lights: bool,
    /// The integrator the stream starts with, or `None` for the server's choice for the scene.
    pub integrator: Option<String>,
    /// Samples per pixel the stream's image refines to, at first (`1..=` the server's
    /// [`Limits::max_spp`](raystage_server::Limits::max_spp)).
    pub max_samples: u32,
    /// Save a screenshot of the window here once the first frame is shown, then exit.
    pub screenshot: Option<PathBuf>,
}

/// Loads the scene, serves it on 127.0.0.1 (a free port) and opens the viewer on it; returns
/// when the window is closed.
pub fn view(job: &ViewJob, log: &mut impl Write) -> Result<()> {
    let config = Config::default();
    // Checked before the window opens, where the stream would refuse it.
    let max = config.limits.max_spp;
    ensure!((1..=max).contains(&job.max_samples), "--max-samples {} is not in 1..={max}", job.max_samples);
    let scene = job.scene.load(log, &job.environment, job.default_lights)?;
    let state = AppState::new(config);
    let id = state.add_scene(scene, job.scene.name()).map_err(|e| anyhow::anyhow!(e.detail.message))?;
    let runtime = tokio::runtime::Runtime::new().context("cannot start the server's threads")?;
    let listener = runtime.block_on(tokio::net::TcpListener::bind("127.0.0.1:0")).context("cannot listen on 127.0.0.1")?;
    let addr = listener.local_addr()?;
    // The server runs on the runtime's threads; the window needs the main thread.
    runtime.spawn(raystage_server::serve(listener, state, std::future::pending()));
    writeln!(log, "raystage serving http://{addr}/ (scene {id}: {}) for the viewer; closing the window stops it", job.scene.name())?;
    log.flush()?;
    let options = raystage_client::Options {
        server: format!("http://{addr}"),
        scene: Some(id),
        integrator: job.integrator.clone(),
        max_samples: job.max_samples,
        default_lights: job.default_lights,
        screenshot: job.screenshot.clone(),
        ..raystage_client::Options::default()
    };
    let outcome = raystage_client::run(options);
    // Renders in flight finish on the blocking pool; don't wait long for them.
    runtime.shutdown_timeout(Duration::from_secs(1));
    outcome.context("the viewer failed")
}
