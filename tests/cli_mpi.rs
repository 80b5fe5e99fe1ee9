//! `mpirun -n N raystage render … --mpi` end to end (built with the `mpi` feature): the image
//! is byte for byte the one a single process writes, whatever the number of ranks, for every
//! integrator, adaptive sampling, an animated demo at several frames and a glTF file; a rank
//! that cannot read the scene stops the whole job with an error instead of hanging it, and so
//! does a worker killed mid-frame.

#![cfg(feature = "mpi")]

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

mod common;

/// Longest a job may take before the test calls it hung.
const DEADLINE: Duration = Duration::from_secs(120);

/// Runs `command` to completion or the deadline (then kills it and fails the test).
fn finish(mut command: Command) -> Output {
    let mut child = command.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("the command starts");
    let start = Instant::now();
    while child.try_wait().expect("waiting works").is_none() {
        if start.elapsed() > DEADLINE {
            let _ = child.kill();
            panic!("{command:?} still runs after {DEADLINE:?}: hung");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output().expect("its output")
}

/// `raystage render ARGS --out OUT` in one process.
fn alone(args: &[&str], out: &PathBuf) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_raystage"));
    command.arg("render").args(args).arg("--out").arg(out);
    finish(command)
}

/// The same under `mpirun -n RANKS` with `--mpi`, one thread per rank (ranks × threads within
/// the machine's two cores), as root where the tests run as root.
fn ranks(n: u32, args: &[&str], out: &PathBuf) -> Output {
    let mut command = common::mpirun();
    command
        // Tagged output comes line by line, so that two ranks' lines do not interleave.
        .args(["--tag-output", "-n", &n.to_string()])
        .arg(env!("CARGO_BIN_EXE_raystage"))
        .arg("render")
        .args(args)
        .args(["--threads", "1", "--mpi", "--out"])
        .arg(out);
    finish(command)
}

fn out_path(name: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("cli_mpi-{}-{name}", std::process::id()));
    let _ = std::fs::remove_file(&path);
    path
}

/// Renders `args` alone and on `n` ranks and asserts the two files are the same bytes.
fn same_bytes(n: u32, args: &[&str], name: &str) {
    let (one, many) = (out_path(&format!("{name}-1.png")), out_path(&format!("{name}-{n}.png")));
    let output = alone(args, &one);
    assert!(output.status.success(), "{args:?} alone: {}", String::from_utf8_lossy(&output.stderr));
    let output = ranks(n, args, &many);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{args:?} on {n} ranks: {stdout}\n{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains(&format!("MPI: {n} ranks")), "rank 0 logs the job: {stdout}");
    // Lines come tagged with the rank by `--tag-output`.
    let timing = stdout.lines().find(|l| l.contains(&format!("MPI timing: {n} ranks x 1 threads; setup "))).unwrap_or_else(|| panic!("rank 0 logs the timing split: {stdout}"));
    assert_eq!(timing.split("share render s per rank ").nth(1).map(|rest| rest.split(':').next().unwrap().split_whitespace().count()), Some(n as usize), "one render time per rank: {timing}");
    assert!(timing.contains(" bytes gathered"), "{timing}");
    assert_eq!(stdout.matches(" rays (").count(), 1, "only rank 0 logs the frame: {stdout}");
    assert!(std::fs::read(&one).unwrap() == std::fs::read(&many).unwrap(), "{args:?}: {n} ranks wrote other bytes than one process");
}

#[test]
fn every_integrator_gives_the_same_bytes_on_two_and_three_ranks() {
    for integrator in ["eyelight", "whitted", "distribution", "path"] {
        for n in [2, 3] {
            let args = ["--demo", "materials", "--integrator", integrator, "--spp", "4", "--width", "72", "--height", "40"];
            same_bytes(n, &args, &format!("materials-{integrator}"));
        }
    }
}

#[test]
fn adaptive_sampling_an_animation_and_a_gltf_file_give_the_same_bytes() {
    let adaptive = ["--demo", "cornell", "--integrator", "path", "--spp", "64", "--noise-threshold", "0.1", "--width", "48", "--height", "48"];
    same_bytes(3, &adaptive, "adaptive");
    for frame in ["0", "7", "15"] {
        same_bytes(2, &["--demo", "robots", "--frame", frame, "--spp", "2", "--width", "64", "--height", "36"], &format!("robots-{frame}"));
    }
    let file = common::write_gltf();
    same_bytes(2, &[file.to_str().unwrap(), "--width", "40", "--height", "30"], "gltf");
}

#[test]
fn a_scene_no_rank_can_read_stops_every_rank_with_an_error() {
    let out = out_path("missing.png");
    let output = ranks(2, &["/nonexistent/scene.glb", "--width", "16", "--height", "16"], &out);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "the job fails");
    assert!(stderr.contains("error: rank 0: cannot import /nonexistent/scene.glb"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // Rank 0 cannot create the image; the other ranks learn it from the vote.
    let output = ranks(2, &["--demo", "cornell", "--width", "16", "--height", "16"], &PathBuf::from("/nonexistent/dir/out.png"));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success() && stderr.contains("error: rank 0: cannot create /nonexistent/dir/out.png"), "{stderr}");
    assert!(stderr.contains("1 of 2 MPI ranks failed"), "the other rank says why it stops: {stderr}");
}

/// The processes of this user running `raystage` whose MPI rank (Open MPI's
/// `OMPI_COMM_WORLD_RANK`, in their environment) is `rank` and whose job's output is `out`.
fn rank_pids(rank: u32, out: &std::path::Path) -> Vec<u32> {
    let Ok(entries) = std::fs::read_dir("/proc") else { return Vec::new() };
    let wanted_rank = format!("OMPI_COMM_WORLD_RANK={rank}");
    let out = out.to_string_lossy().into_owned();
    entries
        .filter_map(|e| e.ok()?.file_name().to_str()?.parse::<u32>().ok())
        .filter(|pid| {
            let cmdline = std::fs::read(format!("/proc/{pid}/cmdline")).unwrap_or_default();
            let environ = std::fs::read(format!("/proc/{pid}/environ")).unwrap_or_default();
            let has = |bytes: &[u8], s: &str| bytes.split(|&b| b == 0).any(|part| part == s.as_bytes());
            has(&cmdline, &out) && has(&environ, &wanted_rank) && cmdline.starts_with(env!("CARGO_BIN_EXE_raystage").as_bytes())
        })
        .collect()
}

/// A worker killed while the frame renders ends the job with an error naming it, within the
/// deadline, never a hang; no rank is left behind.
#[test]
fn a_worker_killed_mid_frame_ends_the_job_with_an_error() {
    let out = out_path("killed.png");
    let mut command = common::mpirun();
    command
        .args(["--tag-output", "-n", "2"])
        .arg(env!("CARGO_BIN_EXE_raystage"))
        // Minutes of path tracing: the worker is killed long before the frame could end.
        .args(["render", "--demo", "cornell", "--integrator", "path", "--spp", "4096", "--width", "256", "--height", "256", "--threads", "1", "--mpi", "--out"])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut job = command.spawn().expect("mpirun starts");
    let start = Instant::now();
    // Wait until both ranks run (rank 0 logs the job before the frame starts), then a moment
    // into the frame.
    let worker = loop {
        if let ([worker], [_]) = (rank_pids(1, &out).as_slice(), rank_pids(0, &out).as_slice()) {
            break *worker;
        }
        assert!(job.try_wait().unwrap().is_none(), "the job ended before its worker was killed");
        assert!(start.elapsed() < DEADLINE, "the ranks did not start within {DEADLINE:?}");
        std::thread::sleep(Duration::from_millis(50));
    };
    std::thread::sleep(Duration::from_secs(2));
    let root = rank_pids(0, &out);
    assert!(Command::new("kill").args(["-KILL", &worker.to_string()]).status().unwrap().success());
    let killed = Instant::now();
    while job.try_wait().unwrap().is_none() {
        if killed.elapsed() > DEADLINE {
            let _ = job.kill();
            panic!("the job still runs {DEADLINE:?} after its worker was killed: hung");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let output = job.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "the job reports the failure in its status: {stderr}");
    assert!(stderr.contains("rank 1") && stderr.contains("signal 9"), "mpirun names the lost rank and why: {stderr}");
    // Rank 0 creates the file before the frame, to know it can; a frame that did not finish
    // leaves it empty.
    assert!(std::fs::metadata(&out).map_or(0, |m| m.len()) == 0, "no image from a frame that did not finish");
    // Rank 0 is gone too, once the system has reaped it.
    let gone = |pid: &u32| std::fs::read_to_string(format!("/proc/{pid}/stat")).map_or(true, |stat| stat.contains(") Z "));
    let reaped = Instant::now();
    while !root.iter().all(gone) {
        assert!(reaped.elapsed() < Duration::from_secs(10), "rank 0 ({root:?}) still runs after the job ended");
        std::thread::sleep(Duration::from_millis(50));
    }
}
