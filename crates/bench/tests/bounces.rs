//! The bounce benchmark's rays and orders, small: every bounce's rays start on the surface the
//! previous ray hit and leave on the side it came from, sorting only reorders them (each ray
//! hits what it hit before, bit for bit), and a whole run counts its walks and makes a page.

use glam::Vec3;
use raystage_bench::bounces::{BounceScene, Cells, Config, Sorted, World, bounce_name, run, same_hits, sort};
use raystage_bench::kernel::build_raystage;
use raystage_bench::page;
use raystage_bench::stamp::{Stamp, StampLine};
use raystage_kernel::{Bvh8, Ray};

fn room(size: u32) -> (World, Bvh8) {
    let world = BounceScene::Room.world(size).expect("the room imports");
    let (bvh, _) = build_raystage(&world.mesh, 2);
    (world, bvh)
}

#[test]
fn bounces_start_on_the_surface_they_leave_and_leave_on_the_side_the_ray_came_from() {
    let (world, bvh) = room(64);
    assert_eq!(world.primary.len(), 64 * 64);
    let bounces = world.bounces(&bvh, 3);
    assert_eq!(bounces.len(), 4);
    let mut light_hits = 0;
    for k in 1..bounces.len() {
        let parents = &bounces[k - 1];
        // Each ray of bounce k continues one path that hit a surface the path goes on from.
        let continuing: Vec<(&Ray, u32, f32)> =
            parents.iter().filter_map(|r| bvh.intersect(r).map(|h| (r, h.prim, h.t))).filter(|(_, prim, _)| !world.ends_paths[*prim as usize]).collect();
        light_hits += parents.iter().filter_map(|r| bvh.intersect(r)).filter(|h| world.ends_paths[h.prim as usize]).count();
        assert_eq!(bounces[k].len(), continuing.len(), "{}: one ray per continuing hit", bounce_name(k));
        assert!(!bounces[k].is_empty() && bounces[k].len() <= parents.len());
        let mut cosines = 0.0;
        for (ray, &(parent, prim, t)) in bounces[k].iter().zip(&continuing) {
            assert!((ray.dir.length() - 1.0).abs() < 1e-5, "{ray:?}: a unit direction");
            let [a, b, c] = world.mesh.triangle(prim);
            let mut n = (b - a).cross(c - a).normalize();
            if n.dot(parent.dir) > 0.0 {
                n = -n;
            }
            // On the side the parent came from, just off its hit point.
            let hit = parent.origin + parent.dir * t;
            let off = ray.origin - hit;
            assert!(off.length() < 2e-4 && off.dot(n) > 0.5e-4, "{ray:?} starts {off:?} from its parent's hit (normal {n:?})");
            assert!(ray.dir.dot(n) > 0.0, "{ray:?} leaves into the surface (normal {n:?})");
            cosines += f64::from(ray.dir.dot(n));
            // Back along the normal, the surface it left is right there.
            let back = bvh.intersect(&Ray::new(ray.origin, -n)).expect("the surface behind the ray");
            assert!((back.t - off.dot(n)).abs() < 1e-5, "{ray:?}: behind it {back:?}, not the plane of triangle {prim}");
        }
        // Cosine-distributed about the normal: the cosine's mean is 2/3 (its standard deviation
        // is 0.24, so over these thousands of rays the mean's is under 0.006).
        let mean = cosines / bounces[k].len() as f64;
        assert!((mean - 2.0 / 3.0).abs() < 0.02, "{}: mean cosine {mean}", bounce_name(k));
    }
    // The camera sees the light, so paths that end there were left out above.
    assert!(light_hits > 0);
    assert!(world.ends_paths.iter().filter(|&&e| e).count() == 2, "the light is one quad");
}

#[test]
fn sorting_only_reorders_the_rays_and_each_ray_hits_what_it_hit_before() {
    let (world, bvh) = room(64);
    let rays = &world.bounces(&bvh, 2)[2];
    let cells = Cells::over(&bvh.bounds());
    for batch in [100, 1024, rays.len()] {
        let sorted = sort(rays, &cells, batch);
        let hits = same_hits(&bvh, rays, &sorted).expect("the same hits");
        assert!(hits > rays.len() / 2, "{hits} of {} rays hit", rays.len());
        // Each batch holds the rays it held, by key.
        for (b, chunk) in sorted.order.chunks(batch).enumerate() {
            let mut indices: Vec<u32> = chunk.to_vec();
            indices.sort_unstable();
            assert_eq!(indices, ((b * batch) as u32..(b * batch + chunk.len()) as u32).collect::<Vec<_>>());
            let keys: Vec<u32> = chunk.iter().map(|&i| cells.key(&rays[i as usize])).collect();
            assert!(keys.is_sorted(), "batch {b} of {batch} out of order");
        }
        if batch == rays.len() {
            assert_ne!(sorted.order, (0..rays.len() as u32).collect::<Vec<_>>(), "all sorted, the rays move");
        }
    }
    // The check catches a ray twice, a ray in the wrong place, and a changed ray.
    let good = sort(rays, &cells, rays.len());
    let mut twice = Sorted { order: good.order.clone(), rays: good.rays.clone() };
    twice.order[1] = twice.order[0];
    assert!(same_hits(&bvh, rays, &twice).is_err());
    let mut swapped = Sorted { order: good.order.clone(), rays: good.rays.clone() };
    swapped.order.swap(0, 1);
    assert!(same_hits(&bvh, rays, &swapped).is_err());
    let mut moved = Sorted { order: good.order.clone(), rays: good.rays };
    moved.rays[0].origin += Vec3::splat(1e-3);
    assert!(same_hits(&bvh, rays, &moved).is_err());
}

#[test]
fn sort_keys_put_the_origin_cell_first_and_the_octant_last() {
    let (_, bvh) = room(4);
    let bounds = bvh.bounds();
    let cells = Cells::over(&bounds);
    let at = |p: Vec3, d: Vec3| cells.key(&Ray::new(p, d));
    let corner = bounds.min + Vec3::splat(1e-3);
    // The same cell: only the octant tells the rays apart, in the lowest three bits.
    assert_eq!(at(corner, Vec3::X) >> 3, at(corner, -Vec3::ONE.normalize()) >> 3);
    assert_eq!(at(corner, Vec3::new(1.0, 1.0, 1.0).normalize()) & 7, 0);
    assert_eq!(at(corner, Vec3::new(-1.0, -1.0, -1.0).normalize()) & 7, 7);
    // The far corner's cell comes last; an origin outside the bounds goes to the nearest cell.
    assert!(at(bounds.max - Vec3::splat(1e-3), Vec3::X) > at(corner, -Vec3::X));
    assert_eq!(at(bounds.min - Vec3::ONE, Vec3::X), at(corner, Vec3::X));
}

#[test]
fn a_run_counts_every_bounce_and_its_report_makes_a_page() {
    let config = Config { scenes: vec![BounceScene::Room], size: 32, bounces: 2, batches: vec![256], reps: 1, build_threads: 2 };
    let runs = run(&config, |_| {}).expect("the benchmark runs");
    let [run] = &runs[..] else { panic!("one scene, one run") };
    assert_eq!(run.triangles, 32);
    assert_eq!(run.walks.iter().map(|w| w.bounce.as_str()).collect::<Vec<_>>(), ["primary", "bounce 1", "bounce 2"]);
    for w in &run.walks {
        let p = &w.per_ray;
        assert!(p.nodes >= 1.0 && p.leaves > 0.0 && p.triangles >= p.leaves, "{w:?}");
        assert!(w.hit_share > 0.0 && w.hit_share <= 1.0, "{w:?}");
    }
    // Each bounce in three orders, per system; sorted orders with their sorting times.
    let systems = if cfg!(feature = "embree") { 2 } else { 1 };
    assert_eq!(run.traces.len(), 3 * 3 * systems);
    assert_eq!(run.sorting.len(), 3 * 2);
    for t in &run.traces {
        assert!(t.mrays > 0.0 && t.vs_as_made > 0.0 && t.hits > 0, "{t:?}");
        assert_eq!(t.mrays_with_sort.is_some(), t.order != "as made", "{t:?}");
        // Every order and system finds the same hits.
        let first = run.traces.iter().find(|f| f.bounce == t.bounce).expect("a first trace");
        assert_eq!((t.rays, t.hits), (first.rays, first.hits), "{t:?}");
    }
    let mut report = vec![serde_json::to_string(&StampLine { stamp: Stamp::now(&["bounces".into(), "--json".into()]) }).unwrap()];
    report.extend(run.walks.iter().map(|w| serde_json::to_string(w).unwrap()));
    report.extend(run.traces.iter().map(|t| serde_json::to_string(t).unwrap()));
    report.extend(run.sorting.iter().map(|s| serde_json::to_string(s).unwrap()));
    let page = page::render(&report.join("\n")).expect("a page");
    for expected in [
        "# `bounces` benchmark",
        "## walks",
        "| measurement | scene | scene_triangles | bounce | rays | hit_share | nodes | leaves | triangles |",
        "## results",
        "| raystage | room | bounce 2 | sorted in 256 |",
        "## sorting",
    ] {
        assert!(page.contains(expected), "missing {expected:?} in\n{page}");
    }
}
