//! The `raystage` command line. Parsing only: the commands live in the library.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use raystage::RenderJob;
use raystage_demo::animated::Demo;
use raystage_render::Integrator;

/// raystage: a ray-tracing rendering server.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render one frame of a built-in demo scene to a PNG file.
    Render {
        /// The demo scene: spheres (or sphere), soup, cornell, materials, robots, museum,
        /// museum-<triangles>, terrain.
        #[arg(long, value_parser = raystage::parse_demo)]
        demo: Demo,
        /// The frame of an animated demo.
        #[arg(long, default_value_t = 0)]
        frame: u32,
        /// The PNG file to write.
        #[arg(long)]
        out: PathBuf,
        /// Image width in pixels.
        #[arg(long, default_value_t = 1920)]
        width: u32,
        /// Image height in pixels.
        #[arg(long, default_value_t = 1080)]
        height: u32,
        /// Threads for the BVH build and the render [default: one per core].
        #[arg(long)]
        threads: Option<usize>,
        /// How pixels are shaded: eyelight, whitted, distribution or path [default: whitted if
        /// the scene has lights, else eyelight].
        #[arg(long, value_parser = raystage::parse_integrator)]
        integrator: Option<Integrator>,
        /// Samples per pixel.
        #[arg(long, default_value_t = 1)]
        spp: u32,
    },
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Render { demo, frame, out, width, height, threads, integrator, spp } => {
            let job = RenderJob { demo, frame, width, height, threads, integrator, samples: spp, out };
            raystage::render_demo(&job, &mut std::io::stdout().lock())
        }
    };
    match result {
        Ok(_) => ExitCode::SUCCESS,
        Err(err) => {
            // `{:#}` prints the cause chain on one line, like clap's own errors.
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
