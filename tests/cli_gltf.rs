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
    // A file without lights is lit by the studio, so it is path traced (see below).
    assert!(stdout.contains("48x48 ") && stdout.contains("triangle.gltf (1 triangles), path at 4 spp ["), "{stdout}");
    let image = image::open(&out).unwrap().to_rgba8();
    assert_eq!(image.get_pixel(24, 26).0, [0, 255, 0, 255], "the triangle fills the middle of the frame");
    assert_ne!(image.get_pixel(2, 2).0, [0, 255, 0, 255], "but not the corner");
}

#[test]
fn the_summary_counts_the_triangles_that_instances_repeat() {
    // The grove as gltfpack -mi writes it: one tree repeated 24 times by EXT_mesh_gpu_instancing.
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/crates/demo/assets/instanced/grove.instanced.glb");
    let out = temp("grove.png");
    let output = Command::new(env!("CARGO_BIN_EXE_raystage"))
        .args(["render", file, "--out", out.to_str().unwrap(), "--width", "32", "--height", "32", "--spp", "1"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "stdout: {stdout}\nstderr: {}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("grove.instanced.glb (34 triangles, 770 placed by 25 instances), "), "{stdout}");
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
    // A file that is not glTF: the reason once, not once per level of the error's chain.
    let broken = temp("broken.gltf");
    std::fs::write(&broken, b"{\"asset\": {}}").unwrap();
    let broken = run(&["render", broken.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&broken.stderr);
    assert!(!broken.status.success() && stderr.matches("missing field `version`").count() == 1, "{stderr}");
}

/// A grey, fairly rough square facing +z with a small emitting triangle beside it (as
/// DamagedHelmet has glowing decals), written as `name.gltf` with its buffer beside it; with
/// `lamp`, a `KHR_lights_punctual` point light in front of it too.
fn write_decorated_square(name: &str, lamp: bool) -> std::path::PathBuf {
    let mut buffer = Vec::new();
    let square = [[-1.0f32, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]];
    let decal = [[1.1f32, -0.1, 0.0], [1.3, -0.1, 0.0], [1.2, 0.1, 0.0]];
    for p in square.iter().chain(&decal) {
        p.iter().for_each(|c| buffer.extend(c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        buffer.extend(i.to_le_bytes());
    }
    let bin = temp(&format!("{name}.bin"));
    std::fs::write(&bin, &buffer).unwrap();
    let (extensions, light_node, light_ref) = if lamp {
        (
            r#""extensionsUsed": ["KHR_lights_punctual"], "extensions": { "KHR_lights_punctual": { "lights": [{ "type": "point", "intensity": 20 }] } },"#,
            r#", { "translation": [0, 0, 2], "extensions": { "KHR_lights_punctual": { "light": 0 } } }"#,
            ", 1",
        )
    } else {
        ("", "", "")
    };
    let document = format!(
        r#"{{
            "asset": {{ "version": "2.0" }}, {extensions}
            "buffers": [{{ "byteLength": {}, "uri": "{}" }}],
            "bufferViews": [{{ "buffer": 0, "byteLength": 48 }}, {{ "buffer": 0, "byteOffset": 48, "byteLength": 36 }}, {{ "buffer": 0, "byteOffset": 84, "byteLength": 12 }}],
            "accessors": [
                {{ "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0] }},
                {{ "bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3", "min": [1.1, -0.1, 0], "max": [1.3, 0.1, 0] }},
                {{ "bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR" }}
            ],
            "materials": [
                {{ "pbrMetallicRoughness": {{ "baseColorFactor": [0.6, 0.6, 0.6, 1], "metallicFactor": 0, "roughnessFactor": 0.8 }} }},
                {{ "pbrMetallicRoughness": {{ "baseColorFactor": [0, 0, 0, 1] }}, "emissiveFactor": [1, 0.5, 0] }}
            ],
            "meshes": [{{ "primitives": [{{ "attributes": {{ "POSITION": 0 }}, "indices": 2, "material": 0 }}, {{ "attributes": {{ "POSITION": 1 }}, "material": 1 }}] }}],
            "nodes": [{{ "mesh": 0 }}{light_node}],
            "scenes": [{{ "nodes": [0{light_ref}] }}]
        }}"#,
        buffer.len(),
        bin.file_name().unwrap().to_str().unwrap()
    );
    let path = temp(&format!("{name}.gltf"));
    std::fs::write(&path, document).unwrap();
    path
}

/// Runs `raystage render FILE --out OUT ARGS...` at 64 × 64; returns its standard output and the
/// mean sRGB brightness (0 to 255) of the middle of the image, where the square is.
fn render_square(file: &std::path::Path, name: &str, args: &[&str]) -> (String, f64) {
    let out = temp(&format!("{name}.png"));
    let output = Command::new(env!("CARGO_BIN_EXE_raystage"))
        .args(["render", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--width", "64", "--height", "64"])
        .args(args)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(output.status.success(), "stdout: {stdout}\nstderr: {}", String::from_utf8_lossy(&output.stderr));
    let image = image::open(&out).unwrap().to_rgb8();
    let middle: Vec<f64> = (24..40).flat_map(|y| (24..40).map(move |x| (x, y))).flat_map(|(x, y)| image.get_pixel(x, y).0).map(f64::from).collect();
    (stdout, middle.iter().sum::<f64>() / middle.len() as f64)
}

/// A glTF file without lights of its own is lit by the studio environment whatever emitting
/// surfaces it has, path traced to a noise threshold, and about as bright as under a uniform
/// environment of radiance 1; `--no-default-lights` leaves it to its decal (dark), and a file
/// with its own lamp gets no studio.
#[test]
fn a_gltf_file_without_lights_is_lit_by_the_studio() {
    let file = write_decorated_square("decorated", false);
    let (stdout, studio) = render_square(&file, "studio", &[]);
    assert!(stdout.contains("no lights of its own: the studio environment lights it"), "{stdout}");
    assert!(stdout.contains("path at 256 spp") && stdout.contains("adaptive sampling"), "{stdout}");
    let (_, uniform) = render_square(&file, "uniform", &["--environment", "1", "--integrator", "path", "--spp", "64"]);
    assert!((studio / uniform - 1.0).abs() < 0.25, "the studio gives {studio:.1}, a uniform environment {uniform:.1}");
    let (stdout, dark) = render_square(&file, "dark", &["--no-default-lights"]);
    assert!(!stdout.contains("studio") && dark < 0.5 * uniform, "without the default the decal alone lights it: {dark:.1}\n{stdout}");
    let (stdout, _) = render_square(&write_decorated_square("lamp", true), "lamp", &[]);
    assert!(!stdout.contains("studio") && stdout.contains("whitted at 1 spp"), "{stdout}");
}

/// Two unlit green unit squares seen from +z by the file's camera: the left one still, the
/// right one moved down by 1 over the first second by the file's animation `drop`. Written as
/// `name.gltf` with its buffer beside it.
fn write_animated_squares(name: &str) -> std::path::PathBuf {
    let mut buffer = Vec::new();
    for f in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0] {
        buffer.extend(f.to_le_bytes());
    }
    // Keyframe times, then translations of the right square.
    for f in [0.0f32, 1.0, 0.5, -0.5, 0.0, 0.5, -1.5, 0.0] {
        buffer.extend(f.to_le_bytes());
    }
    let bin = temp(&format!("{name}.bin"));
    std::fs::write(&bin, &buffer).unwrap();
    let document = serde_json::json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["KHR_materials_unlit"],
        "buffers": [{ "byteLength": buffer.len(), "uri": bin.file_name().unwrap().to_str().unwrap() }],
        "bufferViews": [{ "buffer": 0, "byteLength": 72 }, { "buffer": 0, "byteOffset": 72, "byteLength": 8 }, { "buffer": 0, "byteOffset": 80, "byteLength": 24 }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] },
            { "bufferView": 1, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1] },
            { "bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC3" }
        ],
        "materials": [{ "pbrMetallicRoughness": { "baseColorFactor": [0, 1, 0, 1] }, "extensions": { "KHR_materials_unlit": {} } }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "material": 0 }] }],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1 } }],
        "nodes": [
            { "mesh": 0, "translation": [-1.5, -0.5, 0] },
            { "mesh": 0, "translation": [0.5, -0.5, 0] },
            { "camera": 0, "translation": [0, 0, 5] }
        ],
        "animations": [{ "name": "drop", "channels": [{ "sampler": 0, "target": { "node": 1, "path": "translation" } }], "samplers": [{ "input": 1, "output": 2 }] }],
        "scenes": [{ "nodes": [0, 1, 2] }]
    });
    let path = temp(&format!("{name}.gltf"));
    std::fs::write(&path, document.to_string()).unwrap();
    path
}

fn render_args(args: &[&str]) -> std::process::Output {
    let output = Command::new(env!("CARGO_BIN_EXE_raystage")).args(args).output().unwrap();
    assert!(output.status.success(), "stdout: {}\nstderr: {}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    output
}

#[test]
fn time_poses_the_animation_where_it_moves_and_nowhere_else() {
    let file = write_animated_squares("squares");
    let images: Vec<image::RgbaImage> = ["0", "1.0"]
        .iter()
        .map(|time| {
            let out = temp(&format!("squares-{time}.png"));
            let args = ["render", file.to_str().unwrap(), "--time", time, "--out", out.to_str().unwrap(), "--width", "64", "--height", "64", "--integrator", "eyelight"];
            let stdout = String::from_utf8_lossy(&render_args(&args).stdout).into_owned();
            assert!(stdout.contains(&format!("squares.gltf: posed at {:.3} s of animation 0 `drop` (1.000 s long)", time.parse::<f32>().unwrap())), "{stdout}");
            image::open(&out).unwrap().to_rgba8()
        })
        .collect();
    let green = [0, 255, 0, 255];
    // The camera sees 2.1 units either side of the centre over 32 pixels: the right square's
    // centre is at (1, 0) at time 0, at (1, −1) at time 1.
    assert_eq!((images[0].get_pixel(47, 32).0, images[1].get_pixel(47, 47).0), (green, green));
    assert_ne!(images[1].get_pixel(47, 32).0, green, "the right square left its place at time 1");
    assert_ne!(images[0].get_pixel(47, 47).0, green, "and was not there yet at time 0");
    assert_eq!(images[0].get_pixel(17, 32).0, green, "the left square is seen");
    for (x, y, p) in images[0].enumerate_pixels().filter(|(x, ..)| *x < 32) {
        assert_eq!(p, images[1].get_pixel(x, y), "the still half is the same at ({x}, {y})");
    }
}

#[test]
fn frames_render_a_sequence_from_one_import() {
    let file = write_animated_squares("sequence");
    let pattern = temp("sequence_%03d.png");
    let args = ["render", file.to_str().unwrap(), "--frames", "1..3", "--fps", "2", "--animation", "drop", "--out", pattern.to_str().unwrap(), "--width", "32", "--height", "32", "--integrator", "eyelight"];
    let stdout = String::from_utf8_lossy(&render_args(&args).stdout).into_owned();
    for n in 1..=3 {
        let frame = pattern.with_file_name(pattern.file_name().unwrap().to_str().unwrap().replace("%03d", &format!("{n:03}")));
        assert!(frame.exists(), "{} missing; {stdout}", frame.display());
    }
    assert!(stdout.contains("frame 2 at 1.000 s: pose ") && stdout.contains("3 frames of ") && stdout.contains("sequence.gltf at 32x32") && stdout.contains("per frame: pose "), "{stdout}");
}

#[test]
fn an_unknown_animation_or_a_time_for_a_demo_is_an_error() {
    let file = write_animated_squares("unknown");
    let out = temp("unknown.png");
    let run = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_raystage")).args(args).output().unwrap();
    let unknown = run(&["render", file.to_str().unwrap(), "--animation", "jump", "--out", out.to_str().unwrap(), "--width", "8", "--height", "8"]);
    let stderr = String::from_utf8_lossy(&unknown.stderr);
    assert!(!unknown.status.success() && stderr.contains("no animation `jump`: the file has 0 `drop` (1.000 s)"), "{stderr}");
    let demo = run(&["render", "--demo", "cornell", "--time", "1", "--out", out.to_str().unwrap()]);
    assert!(!demo.status.success() && String::from_utf8_lossy(&demo.stderr).contains("cannot be used with"));
}

/// `--shutter` blurs what the animation moves along its motion: over a shutter open from 0 to
/// 1 s the right square covers its place at time 0 for half the interval and its place at time
/// 1 for the other half, so both show between the square and what is behind it; the still
/// square stays sharp. (Without the animation's motion, the blurred image would be the crisp one
/// at time 0.)
#[test]
fn shutter_blurs_what_the_animation_moves() {
    let file = write_animated_squares("blurred");
    let render = |name: &str, extra: &[&str]| {
        let out = temp(&format!("blurred-{name}.png"));
        let mut args = vec!["render", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--width", "64", "--height", "64", "--integrator", "path", "--spp", "64"];
        args.extend_from_slice(extra);
        render_args(&args);
        image::open(&out).unwrap().to_rgba8()
    };
    let (at_0, at_1, blurred) = (render("0", &["--time", "0"]), render("1", &["--time", "1"]), render("blur", &["--time", "0", "--shutter", "1"]));
    for (x, y) in [(47, 32), (47, 47)] {
        // Red: none in the green square, much in the grey studio behind it.
        let (a, b, c) = (at_0.get_pixel(x, y)[0], at_1.get_pixel(x, y)[0], blurred.get_pixel(x, y)[0]);
        let (low, high) = (a.min(b), a.max(b));
        assert!(high - low > 100, "the square moves across ({x}, {y}): {a} and {b}");
        assert!(c > low + 30 && c < high - 30, "({x}, {y}) is blurred between {low} and {high}: {c}");
    }
    assert_eq!(blurred.get_pixel(17, 32), at_0.get_pixel(17, 32), "the still square stays sharp");
}
