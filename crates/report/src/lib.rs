//! # raystage-report
//!
//! The accuracy report (`raystage report`, docs/guide/accuracy-report.md): what each knob that
//! trades accuracy for time costs and buys, told truthfully. For one scene it measures against a
//! reference — an image from another renderer (`.exr`, `.pfm`, `.npy`), where raystage's biases
//! show, or a converged raystage render, and says which — and sweeps one knob at a time, only
//! the knobs that apply to the scene (samples per pixel, adaptive sampling, path depth, Russian
//! roulette, shadow rays per area light, the integrator, Whitted depth, distribution samples,
//! the shading kernel), saying why the others are left out. Every setting is rendered several
//! times, interleaved with the others, so that each time is a median with a spread (wall and
//! CPU) and each error splits into bias and noise; errors are relative, on the pixels that are
//! not emitters, per 4×4 block and per pixel, with per-channel mean ratios. The readings are
//! computed from the numbers (fits with R², where the image stops changing, the time to reach
//! a target error), and a best trade is named only where it beats the others beyond their
//! spread. The BVH builders are compared at the kernel level.
//!
//! [`run`] computes a [`Report`]; [`write()`] turns it into `report.md`, log-log plots of error
//! against time with error bars, and a strip of the images side by side.
//!
//! Not in here: the renderer and kernel it measures, and the command line (the `raystage`
//! binary parses arguments and shows progress through [`Progress`]).

mod markdown;
mod metrics;
mod plot;
mod reference;
mod run;
mod scenes;
mod strip;
mod timing;

pub use markdown::{markdown, summary_lines, title};
pub use metrics::{BLOCK, Comparison, Errors, Split};
pub use plot::{error_plot, register_font};
pub use reference::{ReferenceSource, read_image};
pub use run::{BvhRow, Knob, LeftOut, Options, Progress, Report, Row, run};
pub use scenes::{BuiltinScene, SceneSource};
pub use strip::strip;
pub use timing::Spread;

use std::path::{Path, PathBuf};

/// What can go wrong making a report.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene could not be built.
    #[error("cannot build the scene: {0}")]
    Scene(#[from] raystage_scene::SceneError),
    /// The renderer refused the settings.
    #[error("cannot render: {0}")]
    Render(#[from] raystage_render::Error),
    /// The glTF file could not be read or imported.
    #[error("cannot import {path}: {source}")]
    Import {
        /// The file.
        path: PathBuf,
        /// Why.
        source: raystage_gltf_import::ImportError,
    },
    /// The scene named is not one the report knows how to load.
    #[error("{0}")]
    Unsupported(String),
    /// The reference image could not be read.
    #[error("cannot read the reference {path}: {message}")]
    Reference {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// Writing an output file failed.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Drawing a plot or encoding an image failed.
    #[error("cannot draw {path}: {message}")]
    Draw {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

/// The files [`write()`] makes in its directory.
pub const FILES: [&str; 4] = ["report.md", "error_vs_time.png", "strip.png", "reference.png"];

/// Writes the report into `dir` (created if needed): `report.md`, `error_vs_time.png` (every
/// knob's relative error against wall time, log-log), one plot per knob (`<knob>.png`), `strip.png` (the
/// reference and the settings' images side by side) and `reference.png`. Plots carry text only
/// if a font was registered ([`register_font`]); `report.md` says what they show either way.
/// Returns the files written.
pub fn write(report: &Report, dir: &Path) -> Result<Vec<PathBuf>, Error> {
    std::fs::create_dir_all(dir).map_err(|source| Error::Write { path: dir.to_owned(), source })?;
    let mut written = Vec::new();
    let md = dir.join("report.md");
    std::fs::write(&md, markdown(report)).map_err(|source| Error::Write { path: md.clone(), source })?;
    written.push(md);
    let all = dir.join("error_vs_time.png");
    error_plot(&all, &report.knobs.iter().collect::<Vec<_>>(), "Error against time, every knob")?;
    written.push(all);
    for knob in &report.knobs {
        let path = dir.join(format!("{}.png", knob.id));
        error_plot(&path, &[knob], &format!("{}: error against time", knob.name))?;
        written.push(path);
    }
    let strip_path = dir.join("strip.png");
    strip(&strip_path, &report.images.iter().map(|(_, film)| film).collect::<Vec<_>>())?;
    written.push(strip_path);
    let reference = dir.join("reference.png");
    report.reference.write_png(&reference).map_err(|e| Error::Draw { path: reference.clone(), message: e.to_string() })?;
    written.push(reference);
    Ok(written)
}
