//! `raystage render FILE` end to end: a glTF file written by the test (no binary assets), the
//! binary renders it through the file's camera, and the PNG shows the file's colours.

use std::process::Command;

mod common;

use common::{temp, write_gltf};

#[test]
fn renders_a_gltf_file_framed_by_an_automatic_camera() {
    let (file, out) = (write_gltf(), temp("triangle.png"));
    let output = Command::new(env!("CARGO_BIN_EXE_raystage"))
        .args(["render", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--width", "48", "--height", "48", "--spp", "4"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "stdout: {stdout}\nstderr: {}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("48x48 ") && stdout.contains("triangle.gltf (1 triangles), whitted at 4 spp [shadows, multisampling]"), "{stdout}");
    let image = image::open(&out).unwrap().to_rgba8();
    assert_eq!(image.get_pixel(24, 26).0, [0, 255, 0, 255], "the triangle fills the middle of the frame");
    assert_ne!(image.get_pixel(2, 2).0, [0, 255, 0, 255], "but not the corner");
}

#[test]
fn a_file_and_a_demo_together_or_a_missing_file_are_errors() {
    let out = temp("never.png");
    let run = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_raystage")).args(args).output().unwrap();
    let both = run(&["render", "scene.glb", "--demo", "cornell", "--out", out.to_str().unwrap()]);
    assert!(!both.status.success() && String::from_utf8_lossy(&both.stderr).contains("cannot be used with"));
    let neither = run(&["render", "--out", out.to_str().unwrap()]);
    assert!(!neither.status.success());
    let missing = run(&["render", "/nonexistent/scene.glb", "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&missing.stderr);
    assert!(!missing.status.success() && stderr.contains("cannot import /nonexistent/scene.glb"), "{stderr}");
}
