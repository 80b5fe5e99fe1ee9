//! `raystage report`: the accuracy report of a scene, with a progress bar while it runs.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result, ensure};
use indicatif::{ProgressBar, ProgressStyle};
use raystage_report::{Options, Progress, ReferenceSource, Report, SceneSource};

use crate::render::MAX_THREADS;

/// What to report on and where.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportJob {
    /// A built-in scene's name (`cornell`, `area-spheres`, `glass`, `spheres`) or a `.glb` file.
    pub scene: String,
    /// An image rendered elsewhere to measure against; `None` for a converged raystage render.
    pub reference: Option<PathBuf>,
    /// Image width, if given.
    pub width: Option<u32>,
    /// Image height, if given.
    pub height: Option<u32>,
    /// Renders per setting (at least 3).
    pub repeats: u32,
    /// The target error that times to target aim at.
    pub target: f64,
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
    let defaults = if job.quick { Options::quick(source) } else { Options::full(source) };
    let reference = job.reference.clone().map_or(defaults.reference.clone(), ReferenceSource::External);
    let options = Options { reference, width: job.width, height: job.height, repeats: job.repeats, target: job.target, ..defaults };
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
    writeln!(log, "{}", raystage_report::title(&report))?;
    writeln!(
        log,
        "{} at {}x{} on {} threads, {} renders per setting; {} files in {}{}",
        report.scene,
        report.width,
        report.height,
        report.threads,
        options.repeats,
        files.len(),
        job.out.display(),
        if font.is_some() { "" } else { " (no font found: plots without text, see report.md)" }
    )?;
    for line in raystage_report::summary_lines(&report) {
        writeln!(log, "  {line}")?;
    }
    Ok(report)
}
