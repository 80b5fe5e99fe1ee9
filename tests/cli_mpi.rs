//! `mpirun -n N raystage render … --mpi` end to end (built with the `mpi` feature): the image
//! is byte for byte the one a single process writes, whatever the number of ranks, for every
//! integrator, adaptive sampling, an animated demo at several frames and a glTF file; a rank
//! that cannot read the scene stops the whole job with an error instead of hanging it.

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
    let mut command = Command::new("mpirun");
    command
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        // Tagged output comes line by line, so that two ranks' lines do not interleave.
        .args(["--oversubscribe", "--tag-output", "-n", &n.to_string()])
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
