//! `raystage-client`: the viewer, on a running server. Parsing only: the viewer is
//! [`raystage_client::run`].

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;

/// raystage's viewer: shows a scene's frame stream and moves its camera with the mouse
/// (left-drag orbits, right- or middle-drag pans, scroll zooms).
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    /// The server, as http://host:port.
    #[arg(long, default_value = "http://127.0.0.1:8080")]
    server: String,
    /// The scene to show [default: the first the server lists].
    #[arg(long)]
    scene: Option<u32>,
    /// The server's bearer token.
    #[arg(long, env = "RAYSTAGE_TOKEN", hide_env_values = true)]
    token: Option<String>,
    /// The integrator: eyelight, whitted, distribution or path [default: the server's choice].
    #[arg(long)]
    integrator: Option<String>,
    /// Samples per pixel the image refines to.
    #[arg(long, default_value_t = 256)]
    max_samples: u32,
    /// Save a PNG screenshot of the window here once the first frame is shown, then exit.
    #[arg(long, env = "RAYSTAGE_CLIENT_SCREENSHOT")]
    screenshot: Option<PathBuf>,
    /// Seconds to keep streaming after the first frame before the screenshot.
    #[arg(long, default_value_t = 0.0, requires = "screenshot")]
    screenshot_delay: f64,
    /// The window's width in points.
    #[arg(long, default_value_t = 1280.0)]
    width: f32,
    /// The window's height in points.
    #[arg(long, default_value_t = 760.0)]
    height: f32,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let options = raystage_client::Options {
        server: cli.server,
        scene: cli.scene,
        token: cli.token,
        integrator: cli.integrator,
        max_samples: cli.max_samples,
        screenshot: cli.screenshot,
        screenshot_delay: cli.screenshot_delay,
        window_size: [cli.width, cli.height],
        ..raystage_client::Options::default()
    };
    match raystage_client::run(options) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
