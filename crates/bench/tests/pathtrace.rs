//! The path-tracing benchmark end to end on its two scenes, small: without Mitsuba (a Python
//! that does not exist), it measures raystage against a reference of its own, and reports each
//! scene's renders, times to every target error and thread scaling.

use raystage_bench::pathtrace::{Config, PathScene, TARGETS, run};

#[test]
fn both_scenes_are_measured_and_timed_to_every_target() {
    let dir = std::env::temp_dir().join(format!("raystage-pathtrace-test-{}", std::process::id()));
    let config = Config {
        scenes: vec![(PathScene::Room, 16), (PathScene::Spheres, 16)],
        spp: vec![4, 16],
        reference_spp: 64,
        threads: 2,
        variants: vec!["scalar_rgb".into()],
        python: "/nonexistent/python3".into(),
        dir: dir.clone(),
    };
    let reports = run(&config, |_| {}).expect("the benchmark runs without Mitsuba");
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(reports.iter().map(|r| r.scene).collect::<Vec<_>>(), ["room", "spheres"]);
    for report in &reports {
        assert_eq!(report.reference, "raystage at 64 spp");
        assert_eq!(report.points.iter().map(|p| (p.system.as_str(), p.scene, p.spp)).collect::<Vec<_>>(), [("raystage", report.scene, 4), ("raystage", report.scene, 16)]);
        // More samples, less error; at 16 spp the means agree with the reference's within the
        // noise (on 16×16 pixels of the room, 4-5 % standard deviation over 40 seeds, the
        // lowest 0.87; at 2 spp 16 %, the lowest 0.73).
        assert!(report.points[1].rmse < report.points[0].rmse, "{:?}", report.points);
        let p = &report.points[1];
        assert!(p.channel_ratio.iter().all(|r| (0.8..1.25).contains(r)), "{p:?}");
        let targets = report.times_to_target();
        assert_eq!(targets.iter().map(|t| t.target).collect::<Vec<_>>(), TARGETS);
        assert!(targets.iter().all(|t| t.scene == report.scene && t.system == "raystage"));
        assert_eq!(report.scaling.scene, report.scene);
    }
}

/// The large scene is the room with its ten quads of blocks traded for a million triangles of
/// spheres, every one of them with area (the poles' rows are fans, not degenerate quads).
#[test]
fn the_spheres_room_holds_a_million_triangles() {
    let import = |json: String| raystage_gltf_import::read(json.as_bytes(), None, &raystage_gltf_import::Limits::default()).unwrap().into_scene().unwrap();
    let (room, spheres) = (import(raystage_demo::cornell_box::gltf()), import(raystage_demo::cornell_box::spheres_gltf()));
    let triangles = |scene: &raystage_scene::Scene| scene.object_ids().map(|id| scene.mesh(id).unwrap().indices.len()).sum::<usize>();
    assert_eq!(triangles(&spheres) + 10 * 2, triangles(&room) + 36 * 27_888);
    let degenerate = spheres.object_ids().flat_map(|id| {
        let mesh = spheres.mesh(id).unwrap();
        (0..mesh.indices.len() as u32).filter(move |&t| {
            let [a, b, c] = mesh.triangle(t);
            (b - a).cross(c - a).length() == 0.0
        })
    });
    assert_eq!(degenerate.count(), 0);
}
