//! `raystage report` end to end: a quick report of the Cornell room, its files and tables.

use std::path::PathBuf;
use std::process::{Command, Output};

mod common;

use common::write_gltf;

fn raystage(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raystage")).args(args).output().expect("the raystage binary runs")
}

#[test]
fn a_quick_report_writes_tables_plots_and_images() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("cli_report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let output = raystage(&["report", "--quick", "--scene", "cornell", "--threads", "2", "--out", dir.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "stdout: {stdout}\nstderr: {}", String::from_utf8_lossy(&output.stderr));
    // The first line says what the report measures against.
    assert!(stdout.starts_with("Accuracy report: cornell, against raystage's own path tracer at 64 spp"), "{stdout}");
    assert!(stdout.contains("cornell at 32x24 on 2 threads, 3 renders per setting"), "{stdout}");
    assert!(stdout.contains("Samples per pixel: not ranked: a quick run's timings are too short"), "{stdout}");

    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for heading in [
        "# Accuracy report: cornell",
        "## Summary",
        "## Samples per pixel",
        "## Adaptive sampling",
        "## Path depth",
        "## Shadow rays per area light",
        "## Russian roulette",
        "## Integrator",
        "## Whitted recursion depth",
        "## Distribution samples per pixel",
        "## Shading kernel",
        "## BVH build quality",
    ] {
        assert!(md.contains(heading), "report.md lacks {heading}:\n{md}");
    }
    for row in ["| 1 spp |", "| 4 spp |", "| depth 2 |", "| 2 per light |", "| roulette off |", "| eyelight |", "| path |", "| sah |", "| fast |"] {
        assert!(md.contains(row), "report.md lacks the row {row}");
    }
    assert!(md.contains("Verdict: not ranked"), "a verdict per knob");
    assert!(!md.contains("NaN") && !md.contains("inf |"), "every number is finite:\n{md}");

    for plot in ["error_vs_time.png", "spp.png", "adaptive.png", "depth.png", "light-samples.png", "roulette.png", "integrator.png", "whitted-depth.png", "kernel.png"] {
        let image = image::open(dir.join(plot)).unwrap().to_rgb8();
        assert_eq!(image.dimensions(), (720, 540), "{plot}");
        assert!(image.pixels().any(|p| p.0 != [255, 255, 255]), "{plot} is blank");
    }
    let strip = image::open(dir.join("strip.png")).unwrap();
    // The reference, three spp settings and three other integrators, 32 wide with 4-pixel gaps.
    assert_eq!((strip.width(), strip.height()), (7 * 32 + 6 * 4, 24));
    assert_eq!(image::open(dir.join("reference.png")).unwrap().width(), 32);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_gltf_file_is_reported_on_through_its_camera() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("cli_report-gltf-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let file = write_gltf();
    let output = raystage(&["report", "--quick", "--scene", file.to_str().unwrap(), "--threads", "2", "--out", dir.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "stdout: {stdout}\nstderr: {}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("triangle.gltf at 32x24 on 2 threads"), "{stdout}");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("the glTF scene ") && md.contains("## Samples per pixel"), "{md}");
    // The unlit green triangle fills the middle of the reference.
    let reference = image::open(dir.join("reference.png")).unwrap().to_rgba8();
    assert_eq!(reference.get_pixel(16, 13).0, [0, 255, 0, 255]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_external_reference_sets_the_size_and_is_named_first() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("cli_report-external-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // A flat grey 24×24 image as another renderer might write it.
    let mut pfm = b"PF\n24 24\n-1.0\n".to_vec();
    pfm.extend(std::iter::repeat_n(0.2f32.to_le_bytes(), 24 * 24 * 3).flatten());
    let reference = dir.join("grey.pfm");
    std::fs::write(&reference, &pfm).unwrap();
    let out = dir.join("report");
    let output = raystage(&["report", "--quick", "--scene", "area-spheres", "--reference", reference.to_str().unwrap(), "--threads", "2", "--out", out.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "stdout: {stdout}\nstderr: {}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.starts_with("Accuracy report: area-spheres, against the external image ") && stdout.contains("grey.pfm"), "{stdout}");
    assert!(stdout.contains("area-spheres at 24x24"), "{stdout}");

    let output = raystage(&["report", "--quick", "--scene", "area-spheres", "--reference", reference.to_str().unwrap(), "--width", "32", "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success() && stderr.contains("the reference is 24x24"), "{stderr}");
    let output = raystage(&["report", "--quick", "--scene", "area-spheres", "--repeats", "2", "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success() && stderr.contains("--repeats must be at least 3"), "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unknown_scenes_and_missing_files_are_errors() {
    let output = raystage(&["report", "--quick", "--scene", "teapot", "--out", env!("CARGO_TARGET_TMPDIR")]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("unknown scene `teapot`: expected cornell, area-spheres, glass, spheres or a .glb or .gltf file"), "{stderr}");
    let output = raystage(&["report", "--quick", "--scene", "/nonexistent/room.glb", "--out", env!("CARGO_TARGET_TMPDIR")]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("cannot import /nonexistent/room.glb"), "{stderr}");
}
