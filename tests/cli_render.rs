//! `raystage render` end to end: run the binary, decode the PNG it writes, look at its pixels.

use std::path::PathBuf;
use std::process::{Command, Output};

mod common;

fn raystage(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raystage")).args(args).output().expect("the raystage binary runs")
}

/// A fresh path for an output file in Cargo's temporary directory for integration tests.
fn out_path(name: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("cli_render-{}-{name}", std::process::id()));
    let _ = std::fs::remove_file(&path);
    path
}

/// Runs a command that must fail and returns its error output.
fn failure(args: &[&str]) -> String {
    let output = raystage(args);
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!output.status.success(), "{args:?} succeeded");
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    stderr
}

#[test]
fn renders_the_sphere_grid_to_png() {
    let out = out_path("spheres.png");
    let output = raystage(&[
        "render",
        "--demo",
        "spheres",
        "--out",
        out.to_str().unwrap(),
        "--width",
        "160",
        "--height",
        "90",
        "--threads",
        "2",
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "stdout: {stdout}\nstderr: {}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("160x90 sphere (1000002 triangles), whitted at 1 spp [shadows]: ") && stdout.contains(" on 2 threads "), "{stdout}");
    assert!(stdout.contains("(14400 primary, ") && stdout.contains(" shadow) at "), "{stdout}");

    let image = image::open(&out).unwrap().to_rgba8();
    assert_eq!(image.dimensions(), (160, 90));
    let rgb = |x, y| {
        let p = image.get_pixel(x, y).0;
        [p[0] as i32, p[1] as i32, p[2] as i32]
    };
    let saturation = |p: [i32; 3]| p.iter().max().unwrap() - p.iter().min().unwrap();

    let sky = rgb(80, 0);
    assert!(sky[2] > sky[0], "the top row is blue-ish sky: {sky:?}");
    // The front-row sphere left of the centre line (purple in the palette).
    let sphere = rgb(70, 69);
    assert!(saturation(sphere) > 60, "a coloured sphere at (70, 69): {sphere:?}");
    // The bottom row is lit grey ground; the spheres cast dark grey shadows on it higher up.
    let bottom: Vec<[i32; 3]> = (0..160).map(|x| rgb(x, 89)).collect();
    assert!(bottom.iter().all(|&p| saturation(p) < 8 && p[0] > 150), "lit grey ground along the bottom: {bottom:?}");
    let shadowed = (40..90).flat_map(|y| (0..160).map(move |x| (x, y))).filter(|&(x, y)| {
        let p = rgb(x, y);
        saturation(p) < 8 && p[0] < 90
    });
    assert!(shadowed.count() > 50, "shadows on the ground");

    let mut colours: Vec<_> = image.pixels().map(|p| p.0).collect();
    colours.sort_unstable();
    colours.dedup();
    assert!(colours.len() > 100, "only {} distinct colours", colours.len());
    assert!(image.pixels().all(|p| p.0[3] == 255), "opaque");
}

#[test]
fn path_traces_the_cornell_room_with_the_effects_it_needs() {
    let out = out_path("cornell.png");
    let output = raystage(&[
        "render", "--demo", "cornell", "--integrator", "path", "--spp", "4", "--width", "32", "--height", "24", "--out", out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "stderr: {}", String::from_utf8_lossy(&output.stderr));
    assert!(
        stdout.contains("path at 4 spp [shadows, reflection, refraction, transparent-shadows, area-lights, global-illumination, multisampling]"),
        "{stdout}"
    );
    assert_eq!(image::open(&out).unwrap().to_rgba8().dimensions(), (32, 24));
    let stderr = failure(&["render", "--demo", "cornell", "--integrator", "radiosity", "--out", out.to_str().unwrap()]);
    assert!(stderr.contains("unknown integrator `radiosity`: expected eyelight, whitted, distribution or path"), "{stderr}");
    let stderr = failure(&["render", "--demo", "cornell", "--spp", "0", "--out", out.to_str().unwrap()]);
    assert!(stderr.contains("samples_per_pixel is out of range: 0 is not in 1..=65536"), "{stderr}");
}

#[test]
fn an_unknown_demo_is_an_error() {
    let out = out_path("never.png");
    let stderr = failure(&["render", "--demo", "teapot", "--out", out.to_str().unwrap()]);
    assert!(stderr.contains("unknown demo scene `teapot`: expected spheres, sphere, soup, cornell, materials, robots, museum"), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn zero_and_absurd_resolutions_are_errors() {
    let out = out_path("never.png");
    let out = out.to_str().unwrap();
    let stderr = failure(&["render", "--demo", "soup", "--out", out, "--width", "0"]);
    assert!(stderr.contains("--width must be between 1 and 16384, got 0"), "{stderr}");
    let stderr = failure(&["render", "--demo", "soup", "--out", out, "--height", "16385"]);
    assert!(stderr.contains("--height must be between 1 and 16384, got 16385"), "{stderr}");
    let stderr = failure(&["render", "--demo", "soup", "--out", out, "--width=-3"]);
    assert!(stderr.contains("invalid value '-3' for '--width <WIDTH>'"), "{stderr}");
    let stderr = failure(&["render", "--demo", "soup", "--out", out, "--threads", "0"]);
    assert!(stderr.contains("--threads must be between 1 and 1024, got 0"), "{stderr}");
    assert!(!PathBuf::from(out).exists());
}

#[test]
fn an_unwritable_output_is_an_error() {
    let stderr = failure(&["render", "--demo", "soup", "--out", "/nonexistent-raystage-dir/frame.png"]);
    assert!(stderr.contains("cannot create /nonexistent-raystage-dir/frame.png"), "{stderr}");
    let dir = env!("CARGO_TARGET_TMPDIR");
    let stderr = failure(&["render", "--demo", "soup", "--out", dir]);
    assert!(stderr.contains(&format!("cannot write {dir}: its name must end in .png, .exr or .pfm")), "{stderr}");
}

/// The options that set a render up like another renderer's: environment, backdrop, default
/// lights, path length, filter, roulette and seed, each reaching the image or its summary.
#[test]
fn lighting_options_reach_the_image() {
    let render = |name: &str, extra: &[&str]| {
        let out = out_path(name);
        let mut args = vec!["render", "--demo", "spheres", "--out", out.to_str().unwrap(), "--width", "64", "--height", "36", "--threads", "2"];
        args.extend_from_slice(extra);
        let output = raystage(&args);
        let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
        assert!(output.status.success(), "{extra:?}: {stdout}{}", String::from_utf8_lossy(&output.stderr));
        (image::open(&out).unwrap().to_rgb8(), stdout)
    };
    // The sky shows above the spheres (the demo's own backdrop); a red background replaces it.
    let (sky, _) = render("sky.png", &[]);
    let top = |image: &image::RgbImage| image.get_pixel(32, 0).0;
    assert!(top(&sky)[2] > 150, "{:?}", top(&sky));
    let (red, _) = render("red.png", &["--background", "1,0,0"]);
    assert_eq!(top(&red), [255, 0, 0]);
    // An environment light shows behind the scene, over the demo's own backdrop.
    let (green, _) = render("green.png", &["--environment", "0,1,0"]);
    assert_eq!(top(&green), [0, 255, 0]);
    // A uniform environment adds light: the image brightens.
    let (lit, stdout) = render("environment.png", &["--environment", "0.5", "--background", "black", "--integrator", "path", "--spp", "4", "--max-depth", "3", "--filter", "gaussian:1", "--russian-roulette", "off", "--seed", "7", "--noise-threshold", "0.5"]);
    let sum = |image: &image::RgbImage| image.pixels().map(|p| p.0.iter().map(|&c| c as u64).sum::<u64>()).sum::<u64>();
    assert!(sum(&lit) > sum(&red) - 255 * 64, "the environment lights the spheres");
    assert!(stdout.contains("path at 4 spp [shadows, area-lights") && stdout.contains("adaptive sampling: 4.0 samples per pixel on average, of 4"), "{stdout}");

    for (args, expected) in [
        (&["--environment", "nowhere.xyz"][..], "nor an image file"),
        (&["--environment", "-1"][..], "nor an image file"),
        (&["--background", "blue"][..], "not sky, black or a colour"),
        (&["--filter", "tent"][..], "not box, gaussian"),
        (&["--max-depth", "0"][..], "max_depth"),
        (&["--russian-roulette", "maybe"][..], "expected on or off"),
        (&["--noise-threshold", "2"][..], "noise_threshold"),
        (&["--environment", "missing.hdr"][..], "cannot read missing.hdr"),
        (&["--tonemap", "aces"][..], "not clamp (or none) or neutral"),
    ] {
        let out = out_path("bad.png");
        let mut all = vec!["render", "--demo", "spheres", "--out", out.to_str().unwrap(), "--width", "8", "--height", "8"];
        all.extend_from_slice(args);
        let stderr = failure(&all);
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
}

/// A glTF file with neither lights nor emitting materials is lit by the default light, the
/// studio glTF viewers give such a file, and the log says so; `--no-default-lights` leaves it to
/// the eye-light preview (nothing lights it; not even the renderer's default sky).
#[test]
fn a_scene_nothing_lights_gets_the_default_light_unless_told_not_to() {
    let file = common::write_gltf();
    let out = out_path("defaulted.png");
    let args = ["render", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--width", "16", "--height", "16"];
    let output = raystage(&args);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success() && stdout.contains("the studio environment lights it") && stdout.contains("path at 256 spp"), "{stdout}");
    let mut dark = args.to_vec();
    dark.push("--no-default-lights");
    let output = raystage(&dark);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success() && !stdout.contains("studio") && !stdout.contains("default sky") && stdout.contains("eyelight"), "{stdout}");
}

/// The output's extension chooses its format: linear OpenEXR and PFM keep light above white,
/// the PNG is exposed and tone-mapped, and an extension raystage cannot write is an error
/// before any rendering.
#[test]
fn the_extension_chooses_the_format() {
    let render = |name: &str, extra: &[&str]| {
        let out = out_path(name);
        let mut args = vec!["render", "--demo", "cornell", "--out", out.to_str().unwrap(), "--width", "16", "--height", "12", "--threads", "2"];
        args.extend_from_slice(extra);
        let output = raystage(&args);
        assert!(output.status.success(), "{name}: {}", String::from_utf8_lossy(&output.stderr));
        std::fs::read(&out).unwrap()
    };
    let exr = image::load_from_memory(&render("frame.exr", &["--exposure", "2"])).unwrap().to_rgb32f();
    assert!(exr.pixels().any(|p| p.0[0] > 1.0), "the exposed light is kept above 1");
    assert!(render("frame.pfm", &[]).starts_with(b"PF\n16 12\n"));
    let (plain, neutral) = (render("plain.png", &[]), render("neutral.png", &["--tonemap", "neutral", "--exposure", "-1"]));
    assert_ne!(plain, neutral);
    assert!(image::load_from_memory(&neutral).is_ok());
    let out = out_path("frame.tiff");
    let stderr = failure(&["render", "--demo", "cornell", "--out", out.to_str().unwrap(), "--width", "8", "--height", "8"]);
    assert!(stderr.contains("its name must end in .png, .exr or .pfm"), "{stderr}");
    assert!(!out.exists(), "nothing written");
}

#[test]
fn channels_are_written_beside_the_image() {
    let out = out_path("channels.png");
    let args = ["render", "--demo", "cornell", "--width", "40", "--height", "30", "--integrator", "eyelight", "--channels", "depth,normal,instance", "--out"];
    let output = raystage(&[&args[..], &[out.to_str().unwrap()]].concat());
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let beside = |name: &str| out.with_file_name(out.file_name().unwrap().to_str().unwrap().replace(".png", name));
    let depth = std::fs::read(beside(".depth.pfm")).unwrap();
    assert!(depth.starts_with(b"Pf\n40 30\n-1.0\n") && depth.len() == 14 + 40 * 30 * 4, "{}", depth.len());
    // The room's back wall, straight ahead: a positive, finite distance.
    let centre = 14 + ((30 - 1 - 15) * 40 + 20) * 4;
    let d = f32::from_le_bytes(depth[centre..centre + 4].try_into().unwrap());
    assert!(d.is_finite() && d > 0.0, "{d}");
    let normal = image::open(beside(".normal.png")).unwrap().to_rgb8();
    assert_eq!(normal.dimensions(), (40, 30));
    assert!(image::open(beside(".instance.png")).is_ok());
    // Beside a linear PFM, every channel is floats.
    let pfm = out_path("channels.pfm");
    let output = raystage(&["render", "--demo", "cornell", "--width", "8", "--height", "6", "--integrator", "eyelight", "--channels", "albedo", "--out", pfm.to_str().unwrap()]);
    assert!(output.status.success());
    assert!(std::fs::read(pfm.with_file_name(pfm.file_name().unwrap().to_str().unwrap().replace(".pfm", ".albedo.pfm"))).unwrap().starts_with(b"PF\n8 6\n"));

    // An OpenEXR image holds its channels, named as compositors group them.
    let exr = out_path("channels.exr");
    let args = ["render", "--demo", "cornell", "--width", "8", "--height", "6", "--integrator", "eyelight", "--channels", "depth,normal,instance", "--out"];
    assert!(raystage(&[&args[..], &[exr.to_str().unwrap()]].concat()).status.success());
    let image = exr::prelude::read_all_flat_layers_from_file(&exr).unwrap();
    let names: Vec<String> = image.layer_data[0].channel_data.list.iter().map(|c| c.name.to_string()).collect();
    assert_eq!(names, ["B", "G", "R", "depth.Z", "instance.id", "normal.X", "normal.Y", "normal.Z"]);
    let centre = 3 * 8 + 4;
    let depth = &image.layer_data[0].channel_data.list[3].sample_data;
    assert!(matches!(depth, exr::prelude::FlatSamples::F32(d) if d[centre].is_finite() && d[centre] > 0.0), "{depth:?}");
    assert!(matches!(&image.layer_data[0].channel_data.list[4].sample_data, exr::prelude::FlatSamples::U32(ids) if ids[centre] == 0), "the room's instance");

    let stderr = failure(&["render", "--demo", "cornell", "--channels", "colour", "--out", out.to_str().unwrap()]);
    assert!(stderr.contains("depth, z, normal, albedo, instance, object or primitive"), "{stderr}");
}
