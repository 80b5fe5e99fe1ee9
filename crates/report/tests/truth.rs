//! The report tells the truth: an external reference's bias shows and is called bias, knobs
//! that change nothing are never a trade, readings name only what the scene has, the image
//! follows the camera's aspect, and a quick run ranks nothing.

use std::path::PathBuf;

use raystage_render::{Film, Integrator, OutputFormat, RenderSettings, render};
use raystage_report::{BuiltinScene, Options, ReferenceSource, Report, SceneSource, markdown, run};

fn temp(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("report-truth-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn report(options: &Options) -> Report {
    run(options, &mut ()).unwrap_or_else(|e| panic!("the report runs: {e}"))
}

fn knob<'a>(report: &'a Report, id: &str) -> &'a raystage_report::Knob {
    report.knobs.iter().find(|k| k.id == id).unwrap_or_else(|| panic!("knob {id} in {:?}", report.knobs.iter().map(|k| k.id).collect::<Vec<_>>()))
}

/// The area-lit spheres converged (2048 spp) at the quick report's size and depth, scaled by
/// `scale`, written as PFM.
fn external_reference(scale: f32, name: &str) -> PathBuf {
    let scene = BuiltinScene::AreaSpheres.scene().unwrap();
    let settings = RenderSettings { width: 32, height: 24, integrator: Integrator::Path, samples_per_pixel: 2048, max_depth: 8, seed: 0xC0FFEE, ..RenderSettings::default() };
    let (film, _) = render(&scene.frame(), &settings).unwrap();
    let scaled = Film::from_pixels(32, 24, film.pixels().iter().map(|p| *p * scale).collect());
    let path = temp(name);
    std::fs::write(&path, scaled.encode(OutputFormat::Pfm, Default::default()).unwrap()).unwrap();
    path
}

fn bias_options(reference: PathBuf) -> Options {
    Options {
        reference: ReferenceSource::External(reference),
        spp: vec![16, 64, 256],
        ..Options::quick(SceneSource::Builtin(BuiltinScene::AreaSpheres))
    }
}

#[test]
fn a_reference_five_percent_dark_shows_as_bias_and_the_true_one_as_noise() {
    let dark = report(&bias_options(external_reference(0.95, "dark.pfm")));
    let row = knob(&dark, "spp").rows.last().unwrap();
    let level = row.level();
    assert!((level.median() - 1.0 / 0.95).abs() < 0.01 + 3.0 * level.half_range(), "mean ratio {level:?}, expected 1/0.95");
    for c in 0..3 {
        assert!((row.mean_ratio(c).median() - 1.0 / 0.95).abs() < 0.02, "channel {c}: {:?}", row.mean_ratio(c));
    }
    assert!(row.split.bias > 0.03 && row.split.bias_share() > 0.5, "the error is mostly bias: {:?}", row.split);
    let md = markdown(&dark);
    assert!(md.lines().next().unwrap().contains("against the external image") && md.contains("dark.pfm"), "{md}");

    let truth = report(&bias_options(external_reference(1.0, "true.pfm")));
    let row = knob(&truth, "spp").rows.last().unwrap();
    assert!((row.level().median() - 1.0).abs() < 0.01 + 3.0 * row.level().half_range(), "{:?}", row.level());
    assert!(row.split.bias_share() < 0.3, "the error is mostly noise: {:?}", row.split);
}

#[test]
fn a_reference_of_another_size_or_kind_is_a_clear_error() {
    let reference = external_reference(1.0, "sized.pfm");
    let options = Options { width: Some(64), ..bias_options(reference) };
    let err = run(&options, &mut ()).unwrap_err().to_string();
    assert!(err.contains("the reference is 32x24"), "{err}");
    let bogus = temp("bogus.exr");
    std::fs::write(&bogus, b"not an image").unwrap();
    let err = run(&bias_options(bogus), &mut ()).unwrap_err().to_string();
    assert!(err.starts_with("cannot read the reference"), "{err}");
}

/// A square glTF camera (aspect 1) looking at a grey quad lit by one directional light, nothing
/// behind it: no glass, no mirror, no area light, and nothing for a bounce to reach.
fn write_lit_quad() -> PathBuf {
    let mut buffer = Vec::new();
    for p in [[-1.0f32, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]] {
        p.iter().for_each(|c| buffer.extend(c.to_le_bytes()));
    }
    for i in [0u32, 1, 2, 0, 2, 3] {
        buffer.extend(i.to_le_bytes());
    }
    let bin = temp("quad.bin");
    std::fs::write(&bin, &buffer).unwrap();
    let document = format!(
        r#"{{
            "asset": {{ "version": "2.0" }},
            "extensionsUsed": ["KHR_lights_punctual"],
            "extensions": {{ "KHR_lights_punctual": {{ "lights": [{{ "type": "directional", "intensity": 2.0 }}] }} }},
            "buffers": [{{ "byteLength": 72, "uri": "{}" }}],
            "bufferViews": [{{ "buffer": 0, "byteLength": 48 }}, {{ "buffer": 0, "byteOffset": 48, "byteLength": 24 }}],
            "accessors": [
                {{ "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0] }},
                {{ "bufferView": 1, "componentType": 5125, "count": 6, "type": "SCALAR" }}
            ],
            "materials": [{{ "pbrMetallicRoughness": {{ "baseColorFactor": [0.6, 0.6, 0.6, 1], "metallicFactor": 0, "roughnessFactor": 1 }} }}],
            "meshes": [{{ "primitives": [{{ "attributes": {{ "POSITION": 0 }}, "indices": 1, "material": 0 }}] }}],
            "cameras": [{{ "type": "perspective", "perspective": {{ "yfov": 0.8, "aspectRatio": 1.0, "znear": 0.1 }} }}],
            "nodes": [
                {{ "mesh": 0 }},
                {{ "camera": 0, "translation": [0, 0, 3] }},
                {{ "extensions": {{ "KHR_lights_punctual": {{ "light": 0 }} }}, "rotation": [-0.2, 0.1, 0, 0.97] }}
            ],
            "scenes": [{{ "nodes": [0, 1, 2] }}]
        }}"#,
        bin.file_name().unwrap().to_str().unwrap()
    );
    let path = temp("quad.gltf");
    std::fs::write(&path, document).unwrap();
    path
}

#[test]
fn readings_name_only_what_the_scene_has_and_the_image_keeps_its_aspect() {
    let quad = report(&Options::quick(SceneSource::Gltf(write_lit_quad())));
    assert_eq!((quad.width, quad.height), (32, 32), "the camera's aspect ratio of 1");
    let md = markdown(&quad);
    // (The "Left out" lines name what the scene lacks, by design: they say why a knob is out.)
    for word in ["glass", "caustic", "refract"] {
        assert!(!md.to_lowercase().contains(word), "`{word}` in the report of a lit quad:\n{md}");
    }
    let left_out: Vec<&str> = quad.left_out.iter().map(|l| l.name).collect();
    assert!(left_out.contains(&"Shadow rays per area light") && left_out.contains(&"Distribution samples"), "{left_out:?}");
    assert!(md.contains("left out: the scene has no area light"), "{md}");
    assert!(quad.knobs.iter().all(|k| k.id != "light-samples" && k.id != "distribution-spp"));

    // The Cornell room has glass and an area light: its report sweeps both knobs.
    let cornell = report(&Options::quick(SceneSource::Builtin(BuiltinScene::Cornell)));
    assert!(cornell.knobs.iter().any(|k| k.id == "whitted-depth") && cornell.knobs.iter().any(|k| k.id == "light-samples"));
    assert!(cornell.effects.refraction);
    assert_eq!((cornell.width, cornell.height), (32, 24), "no camera aspect: 4:3");
}

#[test]
fn a_knob_that_changes_nothing_is_never_a_best_trade() {
    // Depth 2 and 4 on the lit quad: every bounce escapes into the black, so the images are the
    // same; so are the two shading kernels' everywhere.
    let options = Options { depths: vec![2, 4], quick: false, ..Options::quick(SceneSource::Gltf(write_lit_quad())) };
    let quad = report(&options);
    let md = markdown(&quad);
    for id in ["depth", "kernel"] {
        let k = knob(&quad, id);
        assert_eq!(k.rows[0].errors, k.rows[1].errors, "{id}: the same images");
        let section = md.split(&format!("## {}\n", k.name)).nth(1).unwrap().split("\n## ").next().unwrap();
        assert!(section.contains("no effect") && !section.contains("best trade"), "{id}:\n{section}");
    }
}

#[test]
fn a_quick_run_says_its_timings_rank_nothing() {
    let quick = report(&Options::quick(SceneSource::Builtin(BuiltinScene::AreaSpheres)));
    let md = markdown(&quick);
    assert!(md.contains("Quick run: its timings are too short to rank settings"), "{md}");
    assert!(!md.contains("best trade **"), "{md}");
    // Every setting was rendered three times, interleaved, and timed in wall and CPU time.
    for k in &quick.knobs {
        for r in &k.rows {
            assert_eq!((r.wall.samples.len(), r.cpu.samples.len(), r.errors.len()), (3, 3, 3), "{}: {}", k.id, r.setting);
        }
    }
    let spp = knob(&quick, "spp");
    let total = |r: &raystage_report::Row| r.split.bias.hypot(r.split.noise);
    assert!(spp.rows.windows(2).all(|w| total(&w[1]) < total(&w[0])), "error falls with samples: {:?}", spp.rows.iter().map(|r| r.split).collect::<Vec<_>>());
    assert!(md.contains("Error ∝ spp^") && md.contains("R² "), "{md}");
}
