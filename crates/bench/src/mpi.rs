//! One frame on several MPI ranks of this machine: `mpirun -n K raystage render …
//! --mpi` for a few rank counts, each rank given an equal part of the cores, against one process
//! rendering the same frame on all of them. The numbers come from rank 0's log: the summary line
//! (frame seconds, rays) and the `MPI timing:` line (setup, each rank's share render seconds,
//! the gather and its bytes). Every image is compared, byte for byte, with the one process's.
//!
//! The benchmark runs `raystage` as a separate program rather than linking it: MPI's ranks are
//! processes `mpirun` starts, and one process's figure must come from the same binary.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use raystage_render::Share;
use serde::Serialize;

use crate::cluster_model::{Encoding, Frame};
use crate::kernel::median;

/// What to measure.
#[derive(Clone, Debug)]
pub struct Config {
    /// The `raystage` binary, built with the `mpi` feature.
    pub raystage: PathBuf,
    /// Rank counts to run, each under `mpirun`.
    pub ranks: Vec<u32>,
    /// Cores to share among the ranks; the one-process baseline has them all as threads.
    pub cores: usize,
    /// The scene and frame: `raystage render` arguments before `--threads` and `--out`.
    pub render_args: Vec<String>,
    /// Runs of each configuration; the median frame is reported.
    pub reps: usize,
    /// Where the images go.
    pub dir: PathBuf,
}

/// Threads per rank: the cores shared equally, at least one (more ranks than cores
/// oversubscribe them).
pub fn threads_per_rank(ranks: u32, cores: usize) -> usize {
    (cores / ranks.max(1) as usize).max(1)
}

/// Rank 0's summary line of a frame: `WxH scene …: S s on T threads (…), R rays (…) at M
/// Mrays/s -> out`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Summary {
    pub width: u32,
    pub height: u32,
    /// Rank 0's seconds rendering (its share, under MPI: the gather is not in it).
    pub seconds: f64,
    pub threads: usize,
    /// Rays of the whole frame, every rank's.
    pub rays: u64,
    pub mrays_per_s: f64,
}

/// Rank 0's `MPI timing:` line.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Timing {
    pub ranks: u32,
    pub threads: usize,
    /// Loading the scene and the vote that every rank has it.
    pub setup_s: f64,
    /// Each rank's seconds rendering its share, by rank.
    pub render_s: Vec<f64>,
    /// Rank 0 finishing its share to holding every share.
    pub gather_s: f64,
    /// Bytes rank 0 received.
    pub bytes: u64,
}

impl Timing {
    /// The slowest rank's render seconds over the fastest's.
    pub fn max_over_min(&self) -> f64 {
        let min = self.render_s.iter().copied().fold(f64::INFINITY, f64::min);
        self.render_s.iter().copied().fold(0.0, f64::max) / min
    }
}

/// The word after the first `marker` in `line`.
fn word_after<'a>(line: &'a str, marker: &str) -> Option<&'a str> {
    line.split_once(marker)?.1.split_whitespace().next()
}

/// The word before the first `marker` in `line`.
fn word_before<'a>(line: &'a str, marker: &str) -> Option<&'a str> {
    line.split_once(marker)?.0.split_whitespace().next_back()
}

/// Parses the summary line `raystage render` logs for a frame; `None` for any other line.
pub fn parse_summary(line: &str) -> Option<Summary> {
    if !line.contains(" Mrays/s -> ") {
        return None;
    }
    let (width, height) = line.split_whitespace().next()?.split_once('x')?;
    Some(Summary {
        width: width.parse().ok()?,
        height: height.parse().ok()?,
        seconds: word_before(line, " s on ")?.parse().ok()?,
        threads: word_after(line, " s on ")?.parse().ok()?,
        rays: word_before(line, " rays (")?.parse().ok()?,
        mrays_per_s: word_before(line, " Mrays/s")?.parse().ok()?,
    })
}

/// Parses rank 0's `MPI timing: K ranks x T threads; setup S s (load + vote); share render s per
/// rank A B …: …; gather G s on rank 0; N bytes gathered`; `None` for any other line.
pub fn parse_timing(line: &str) -> Option<Timing> {
    let rest = line.strip_prefix("MPI timing: ")?;
    let per_rank = rest.split_once("share render s per rank ")?.1.split_once(':')?.0;
    Some(Timing {
        ranks: rest.split_whitespace().next()?.parse().ok()?,
        threads: word_after(rest, " ranks x ")?.parse().ok()?,
        setup_s: word_after(rest, "setup ")?.parse().ok()?,
        render_s: per_rank.split_whitespace().map(str::parse).collect::<Result<_, _>>().ok()?,
        gather_s: word_after(rest, "; gather ")?.parse().ok()?,
        bytes: word_before(rest, " bytes gathered")?.parse().ok()?,
    })
}

/// One run of a frame: one process, or `mpirun` with some ranks.
#[derive(Clone, Debug, Serialize)]
pub struct Run {
    /// Ranks; `None` for one process without MPI.
    pub ranks: Option<u32>,
    pub threads: usize,
    /// Rank 0's render start to holding the whole frame: its render seconds plus the gather.
    pub frame_s: f64,
    /// The fastest `frame_s` of the configuration's runs: on a machine shared with other work,
    /// the nearest to an idle machine's.
    pub fastest_frame_s: f64,
    /// Wall seconds of the whole command, start-up, scene load and image writing included.
    pub wall_s: f64,
    pub summary: Summary,
    /// Under MPI, rank 0's timing line.
    pub timing: Option<Timing>,
    /// Whether the image is byte for byte the one-process image.
    pub same_bytes: bool,
    /// The image's size in bytes.
    pub png_bytes: u64,
}

impl Run {
    /// Rays of the frame over its seconds (rank 0's render and gather).
    pub fn mrays_per_s(&self) -> f64 {
        self.summary.rays as f64 / self.frame_s / 1e6
    }
}

/// Every configuration's median run, the one-process baseline first.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub cores: usize,
    pub render_args: Vec<String>,
    pub runs: Vec<Run>,
}

impl Report {
    /// The one-process run.
    pub fn baseline(&self) -> &Run {
        &self.runs[0]
    }

    /// Whether every run's image is the baseline's, byte for byte.
    pub fn all_same_bytes(&self) -> bool {
        self.runs.iter().all(|r| r.same_bytes)
    }

    /// The baseline's frame of `measured_spp` samples per pixel scaled to 1920×1080 by pixel
    /// count and to `spp` samples per pixel, at its measured core-seconds per pixel, on nodes of
    /// `cores_per_node` cores. The cost is taken as proportional to the samples: each sample of
    /// a path tracer is a path of its own, nothing cached between them.
    ///
    /// The cost is the fastest baseline frame's, not the median's: a cluster node renders alone,
    /// and on a machine shared with other work the median can be twice the idle cost, which would
    /// make the gather look cheaper beside the render than it is.
    pub fn model_frame(&self, measured_spp: u32, spp: u32, cores_per_node: usize) -> Frame {
        let base = self.baseline();
        let pixels = f64::from(base.summary.width) * f64::from(base.summary.height);
        let per_sample = base.fastest_frame_s * base.threads as f64 / pixels / f64::from(measured_spp.max(1));
        Frame { pixels: 1920.0 * 1080.0, spp, core_seconds_per_pixel: per_sample * f64::from(spp), cores_per_node }
    }

    /// The encodings the model compares: the measured bytes per gathered pixel (f32 RGB, what
    /// is sent today, with the counts and timings each rank adds), f16 RGB, 8-bit sRGB, and 8-bit
    /// sRGB deflated as the baseline's PNG is (its file size over its raw RGB8 bytes: a
    /// measured lossless ratio, headers included).
    pub fn encodings(&self) -> Vec<Encoding> {
        let base = self.baseline();
        let (w, h) = (base.summary.width, base.summary.height);
        let f32_rgb = self
            .runs
            .iter()
            .filter_map(|r| Some((r.timing.as_ref()?.bytes, sent_pixels(w, h, r.ranks?))))
            .filter(|&(_, pixels)| pixels > 0)
            .max_by_key(|&(_, pixels)| pixels)
            .map_or(12.0, |(bytes, pixels)| bytes as f64 / pixels as f64);
        let deflated = base.png_bytes as f64 / (f64::from(w) * f64::from(h));
        vec![
            Encoding { name: "f32 RGB".into(), bytes_per_pixel: f32_rgb },
            Encoding { name: "f16 RGB".into(), bytes_per_pixel: 6.0 },
            Encoding { name: "sRGB8".into(), bytes_per_pixel: 3.0 },
            Encoding { name: "sRGB8 deflate".into(), bytes_per_pixel: deflated },
        ]
    }
}

/// Pixels of a `width`×`height` frame that ranks other than 0 render, out of `ranks`: those
/// that cross the network to rank 0.
pub fn sent_pixels(width: u32, height: u32, ranks: u32) -> u64 {
    (1..ranks).map(|index| Share { index, count: ranks }.pixel_count(width, height) as u64).sum()
}

/// Runs `command` once, returning its standard output and wall seconds, or why it failed.
fn run_command(mut command: Command) -> Result<(String, f64), String> {
    let start = Instant::now();
    let output = command.output().map_err(|e| format!("cannot run {command:?}: {e}"))?;
    let wall = start.elapsed().as_secs_f64();
    if !output.status.success() {
        return Err(format!("{command:?} failed ({}): {}", output.status, String::from_utf8_lossy(&output.stderr)));
    }
    Ok((String::from_utf8_lossy(&output.stdout).into_owned(), wall))
}

/// The command rendering `config`'s frame into `out`: one process on every core, or `ranks`
/// ranks under `mpirun`, sharing them.
fn frame_command(config: &Config, ranks: Option<u32>, out: &Path) -> (Command, usize) {
    let threads = ranks.map_or(config.cores.max(1), |k| threads_per_rank(k, config.cores));
    let mut command = match ranks {
        None => Command::new(&config.raystage),
        Some(k) => {
            let mut command = Command::new("mpirun");
            // Open MPI refuses root without these; benchmark machines often run as root.
            command.env("OMPI_ALLOW_RUN_AS_ROOT", "1").env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
            // Open MPI binds each rank to one core by default, which would leave a rank's
            // other threads idle; more ranks than cores must be allowed to measure them.
            command.args(["--oversubscribe", "--bind-to", "none", "-n", &k.to_string()]).arg(&config.raystage);
            command
        }
    };
    command.arg("render").args(&config.render_args).args(["--threads", &threads.to_string(), "--out"]).arg(out);
    if ranks.is_some() {
        command.arg("--mpi");
    }
    (command, threads)
}

/// Runs one frame of `config` and parses rank 0's log; `reference` is the baseline image.
fn run_once(config: &Config, ranks: Option<u32>, rep: usize, reference: Option<&[u8]>) -> Result<(Run, Vec<u8>), String> {
    let name = ranks.map_or("alone".to_string(), |k| format!("ranks{k}"));
    let out = config.dir.join(format!("mpi-{name}-{rep}.png"));
    let (command, threads) = frame_command(config, ranks, &out);
    let (stdout, wall_s) = run_command(command)?;
    let summary = stdout.lines().find_map(parse_summary).ok_or_else(|| format!("no summary line in the log of {name}: {stdout}"))?;
    let timing = stdout.lines().find_map(parse_timing);
    if ranks.is_some() && timing.is_none() {
        return Err(format!("no `MPI timing:` line in the log of {name} (is {} built with --features mpi?): {stdout}", config.raystage.display()));
    }
    let png = std::fs::read(&out).map_err(|e| format!("cannot read {}: {e}", out.display()))?;
    let frame_s = summary.seconds + timing.as_ref().map_or(0.0, |t| t.gather_s);
    let run = Run {
        ranks,
        threads,
        frame_s,
        fastest_frame_s: frame_s,
        wall_s,
        summary,
        same_bytes: reference.is_none_or(|r| r == png.as_slice()),
        png_bytes: png.len() as u64,
        timing,
    };
    Ok((run, png))
}

/// The run of median frame seconds, with the fastest of them and whether all of them wrote the
/// reference's bytes.
fn median_run(mut runs: Vec<Run>) -> Run {
    let same = runs.iter().all(|r| r.same_bytes);
    let seconds: Vec<f64> = runs.iter().map(|r| r.frame_s).collect();
    let m = median(&seconds);
    let mut run = runs.swap_remove(seconds.iter().position(|&s| s == m).expect("the median is one of them"));
    run.same_bytes = same;
    run.fastest_frame_s = seconds.iter().copied().fold(f64::INFINITY, f64::min);
    run
}

/// Runs the baseline and every rank count in turns, `config.reps` rounds, logging each run:
/// a load that comes and goes on a shared machine then falls on every configuration alike.
pub fn run(config: &Config, log: impl Fn(&str)) -> Result<Report, String> {
    std::fs::create_dir_all(&config.dir).map_err(|e| format!("cannot create {}: {e}", config.dir.display()))?;
    let configurations: Vec<Option<u32>> = std::iter::once(None).chain(config.ranks.iter().map(|&k| Some(k))).collect();
    let mut reference: Option<Vec<u8>> = None;
    let mut runs: Vec<Vec<Run>> = vec![Vec::new(); configurations.len()];
    for rep in 0..config.reps.max(1) {
        for (&ranks, reps) in configurations.iter().zip(&mut runs) {
            let (run, png) = run_once(config, ranks, rep, reference.as_deref())?;
            log(&format!(
                "{} x {} threads: frame {:.3} s, wall {:.3} s{}{}",
                run.ranks.map_or("1 process".to_string(), |k| format!("{k} ranks")),
                run.threads,
                run.frame_s,
                run.wall_s,
                run.timing.as_ref().map_or(String::new(), |t| format!(", gather {:.3} s, render max/min {:.2}", t.gather_s, t.max_over_min())),
                if run.same_bytes { "" } else { ", OTHER BYTES than one process" }
            ));
            reference.get_or_insert(png);
            reps.push(run);
        }
    }
    Ok(Report { cores: config.cores, render_args: config.render_args.clone(), runs: runs.into_iter().map(median_run).collect() })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SUMMARY: &str = "640x360 cornell (36 triangles), path at 16 spp [diffuse, shadows]: 3.125 s on 2 threads (lazy BVH builds 0.001 s of it), 16465581 rays (3686400 primary, 6000000 shadow) at 5.3 Mrays/s -> /tmp/a.png";
    const TIMING: &str = "MPI timing: 3 ranks x 1 threads; setup 0.012 s (load + vote); share render s per rank 2.000 2.500 2.250: min 2.000, max 2.500, imbalance 1.111 (max/mean); gather 0.510 s on rank 0; 1843248 bytes gathered";

    #[test]
    fn the_summary_line_parses() {
        let s = parse_summary(SUMMARY).unwrap();
        assert_eq!(s, Summary { width: 640, height: 360, seconds: 3.125, threads: 2, rays: 16465581, mrays_per_s: 5.3 });
        assert_eq!(parse_summary("MPI: 2 ranks, each rendering its share of the frame's bands of tiles on 1 threads"), None);
        assert_eq!(parse_summary(TIMING), None);
    }

    #[test]
    fn the_timing_line_parses() {
        let t = parse_timing(TIMING).unwrap();
        assert_eq!(t, Timing { ranks: 3, threads: 1, setup_s: 0.012, render_s: vec![2.0, 2.5, 2.25], gather_s: 0.51, bytes: 1843248 });
        assert_eq!(t.max_over_min(), 1.25);
        assert_eq!(parse_timing(SUMMARY), None);
        assert_eq!(parse_timing("MPI timing: 3 ranks x 1 threads; setup 0.012 s"), None);
    }

    #[test]
    fn the_model_scales_the_measured_frame_and_its_gathered_bytes() {
        let summary = parse_summary(SUMMARY).unwrap();
        let run = |ranks, frame_s, timing| Run { ranks, threads: 2, frame_s, fastest_frame_s: frame_s, wall_s: frame_s, summary, timing, same_bytes: true, png_bytes: 640 * 360 * 2 };
        let timing = Timing { bytes: 12 * sent_pixels(640, 360, 3) + 128, ..parse_timing(TIMING).unwrap() };
        let mut base = run(None, 5.0, None);
        base.fastest_frame_s = 4.0;
        let report = Report { cores: 2, render_args: Vec::new(), runs: vec![base, run(Some(3), 3.0, Some(timing))] };
        // The fastest frame: 8 core-seconds over 640×360 pixels at 16 spp; the model's frame is 1080p at 1 spp.
        let frame = report.model_frame(16, 1, 16);
        assert_eq!((frame.pixels, frame.spp, frame.cores_per_node), (1920.0 * 1080.0, 1, 16));
        assert!((frame.core_seconds_per_pixel - 8.0 / (640.0 * 360.0) / 16.0).abs() < 1e-15);
        assert!((frame.one_node_s() - 9.0 * 8.0 / 16.0 / 16.0).abs() < 1e-12, "1080p is 9 of these frames");
        let per_pixel: Vec<f64> = report.encodings().iter().map(|e| e.bytes_per_pixel).collect();
        assert!((per_pixel[0] - 12.0).abs() < 1e-3 && per_pixel[0] > 12.0, "the counts and timings add a little: {per_pixel:?}");
        assert_eq!(per_pixel[1..], [6.0, 3.0, 2.0]);
    }

    #[test]
    fn the_median_run_keeps_the_fastest_and_any_other_bytes() {
        let summary = parse_summary(SUMMARY).unwrap();
        let run = |frame_s, same_bytes| Run { ranks: Some(2), threads: 1, frame_s, fastest_frame_s: frame_s, wall_s: frame_s, summary, timing: None, same_bytes, png_bytes: 1 };
        let m = median_run(vec![run(3.0, true), run(1.0, true), run(2.0, false)]);
        assert_eq!((m.frame_s, m.fastest_frame_s, m.same_bytes), (2.0, 1.0, false));
    }

    #[test]
    fn ranks_share_the_cores() {
        assert_eq!([1, 2, 3, 4].map(|k| threads_per_rank(k, 2)), [2, 1, 1, 1]);
        assert_eq!([1, 2, 3, 4].map(|k| threads_per_rank(k, 16)), [16, 8, 5, 4]);
    }

    #[test]
    fn ranks_other_than_0_send_the_rest_of_the_frame() {
        assert_eq!(sent_pixels(640, 360, 1), 0);
        let all = 640 * 360;
        let own = Share { index: 0, count: 3 }.pixel_count(640, 360) as u64;
        assert_eq!(sent_pixels(640, 360, 3), all - own);
        assert!(own > 0 && own < all);
    }
}
