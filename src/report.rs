//! `raystage report`: the accuracy report of a scene, with a progress bar while it runs.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result, ensure};
use indicatif::{ProgressBar, ProgressStyle};
use raystage_report::{Options, Progress, Report, SceneSource};

use crate::render::MAX_THREADS;

/// What to report on and where.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportJob {
    /// A built-in scene's name (`cornell`, `area-spheres`, `glass`, `spheres`) or a `.glb` file.
    pub scene: String,
    /// The directory to write `report.md`, the plots and the images into (created if needed).
    pub out: PathBuf,
    /// A tiny run (32×24, a 64-spp reference) instead of the full one.
    pub quick: bool,
    /// Threads for the renders and builds, `1..=MAX_THREADS`; `None` for one per core.
    pub threads: Option<usize>,
}

/// An indicatif bar fed by the report's progress; drawn only when stderr is a terminal.
struct Bar(ProgressBar);

impl Progress for Bar {
    fn start(&mut self, total: u64) {
        self.0.set_length(total);
    }

    fn advance(&mut self, units: u64, what: &str) {
        self.0.set_message(what.to_string());
        self.0.inc(units);
    }
}

/// Runs `job`: makes the report (drawing a progress bar on stderr), writes it, and logs where
/// it went to `log`. Plots carry text if a system font is found.
pub fn run_report(job: &ReportJob, log: &mut impl Write) -> Result<Report> {
    let source = SceneSource::parse(&job.scene)?;
    let options = if job.quick { Options::quick(source) } else { Options::full(source) };
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(threads) = job.threads {
        ensure!((1..=MAX_THREADS).contains(&threads), "--threads must be between 1 and {MAX_THREADS}, got {threads}");
        pool = pool.num_threads(threads);
    }
    let pool = pool.build().context("cannot start the render threads")?;
    let bar = ProgressBar::new(0).with_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% {msg}").expect("a valid template"),
    );
    let mut progress = Bar(bar.clone());
    let report = pool.install(|| raystage_report::run(&options, &mut progress));
    bar.finish_and_clear();
    let report = report?;
    let font = raystage_report::register_font();
    let files = raystage_report::write(&report, &job.out)?;
    writeln!(
        log,
        "{} at {}x{} on {} threads: reference {} spp in {:.1} s; {} files in {}{}",
        report.scene,
        report.width,
        report.height,
        report.threads,
        options.reference_spp,
        report.reference_seconds,
        files.len(),
        job.out.display(),
        if font.is_some() { "" } else { " (no font found: plots without text, see report.md)" }
    )?;
    for knob in &report.knobs {
        if let Some(best) = knob.best_trade() {
            writeln!(log, "  {}: best trade {} (RMSE {:.4}, {:.3} s)", knob.name, best.setting, best.errors.rmse, best.seconds)?;
        }
    }
    Ok(report)
}
