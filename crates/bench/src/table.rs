//! Human-readable tables of benchmark results.

use std::fmt::Write;

use crate::kernel::{Samples, SceneRun, Traced, median};
use crate::render::{ConvergenceRun, ShadingRun, System};

/// Median throughput of repeated runs over `n` rays.
fn mrays(runs: &[Traced], n: usize) -> f64 {
    median(&runs.iter().map(|r| n as f64 / r.seconds / 1e6).collect::<Vec<_>>())
}

/// One measured ray set: its name, its samples in a run, and its size.
struct RaySet {
    name: &'static str,
    runs: fn(&Samples) -> &[Traced],
    rays: usize,
}

/// The kernel benchmark of one scene as a table: one column per system (raystage, Embree, Embree
/// in robust mode) and the raystage/Embree ratio of each row against both (build: raystage's
/// time over Embree's, below 1 is faster; throughput: raystage's rate over Embree's, above 1 is
/// faster). The build is compared with Embree's MEDIUM build (binned SAH, like raystage's) and
/// its HIGH build (spatial splits, the tree Embree traces here), with raystage's tree's SAH cost
/// beside it.
pub fn kernel_table(run: &SceneRun) -> String {
    let mut out = String::new();
    let reps = run.runs.first().map_or(0, |r| r.2.build.len());
    let _ = writeln!(
        out,
        "scene {}: {} triangles, {}, median of {reps}",
        run.scene.name(),
        run.triangles,
        match run.sets {
            Some(_) => format!("{}x{} primary rays", crate::rays::WIDTH, crate::rays::HEIGHT),
            None => "builds only".to_string(),
        }
    );
    let sets: Vec<RaySet> = match &run.sets {
        Some(sets) => vec![
            RaySet { name: "primary", runs: |s| &s.primary, rays: sets.primary.len() },
            RaySet { name: "primary packets", runs: |s| &s.packets, rays: sets.packets.len() },
            RaySet { name: "primary 4x4", runs: |s| &s.groups, rays: sets.groups.len() },
            RaySet { name: "incoherent", runs: |s| &s.incoherent, rays: sets.incoherent.len() },
            RaySet { name: "bounce", runs: |s| &s.bounce, rays: sets.bounce.len() },
            RaySet { name: "shadow", runs: |s| &s.shadow, rays: sets.shadow.len() },
            RaySet { name: "shadow 4x4", runs: |s| &s.shadow_groups, rays: sets.shadow.len() },
        ],
        None => Vec::new(),
    };
    if let Some(w) = &run.walks {
        let _ = writeln!(out, "  raystage's walks per ray     nodes   leaves  triangles  (closest hit, single rays)");
        for (name, per) in [("primary", w.primary), ("incoherent", w.incoherent), ("bounce", w.bounce)] {
            let _ = writeln!(out, "  {name:<22} {:>11.2} {:>8.2} {:>10.2}", per.nodes, per.leaves, per.triangles);
        }
    }
    let mut thread_counts: Vec<usize> = run.runs.iter().map(|r| r.1).collect();
    thread_counts.sort_unstable();
    thread_counts.dedup();
    for threads in thread_counts {
        let find = |system: &str| run.runs.iter().find(|r| r.0 == system && r.1 == threads).map(|r| &r.2);
        let (ours, theirs, robust) = (find("raystage"), find("embree"), find("embree-robust"));
        let _ = writeln!(out, "  {threads} thread(s)              raystage      embree   ratio   robust   ratio");
        let row = |out: &mut String, name: &str, a: Option<f64>, b: Option<f64>, c: Option<f64>, unit: &str| {
            let fmt = |v: Option<f64>, width: usize| v.map_or(format!("{:>width$}", "-"), |v| format!("{v:>width$.3}"));
            let ratio = |b: Option<f64>| match (a, b) {
                (Some(a), Some(b)) if b > 0.0 => format!("{:>7}", format!("{:.2}x", a / b)),
                _ => format!("{:>7}", "-"),
            };
            let _ = writeln!(out, "  {name:<22} {} {} {} {} {}  {unit}", fmt(a, 9), fmt(b, 11), ratio(b), fmt(c, 8), ratio(c));
        };
        let build = |s: &Samples| median(&s.build);
        row(&mut out, "build", ours.map(build), run.medium_build(threads), None, "s (Embree MEDIUM: binned SAH)");
        row(&mut out, "build", ours.map(build), theirs.map(build), robust.map(build), "s (Embree HIGH: spatial splits)");
        if let Some((_, cost)) = run.sah_cost.iter().find(|(t, _)| *t == threads) {
            let _ = writeln!(out, "  {:<22} {cost:>9.3}  (raystage's tree: child boxes a random ray enters)", "SAH cost");
        }
        for set in &sets {
            let rate = |s: &Samples| mrays((set.runs)(s), set.rays);
            let unit = match set.name {
                "primary packets" => "Mrays/s (8 rays per call: rtcIntersect8)",
                "primary 4x4" => "Mrays/s (16 rays per call: rtcIntersect16; raystage: 2 packets)",
                "shadow" => "Mrays/s (1 ray per call: rtcOccluded1)",
                "shadow 4x4" => "Mrays/s (16 rays per call: rtcOccluded16; raystage: 2 packets)",
                _ => "Mrays/s (1 ray per call: rtcIntersect1)",
            };
            row(&mut out, set.name, ours.map(rate), theirs.map(rate), robust.map(rate), unit);
        }
        if let (Some(s), Some(all)) = (ours, &run.sets) {
            let single = |s: &Samples| mrays(&s.primary, all.primary.len());
            let packets = Some(mrays(&s.packets, all.packets.len()));
            row(&mut out, "raystage packets vs", packets, theirs.map(single), robust.map(single), "Mrays/s (Embree rtcIntersect1)");
        }
        for set in &sets {
            let checksum = |s: Option<&Samples>| {
                s.and_then(|s| (set.runs)(s).last().copied())
                    .map_or("-".to_string(), |t| format!("{} hits, sum t {:.1}", t.hits, t.tsum))
            };
            let _ = writeln!(
                out,
                "    {:<20} raystage {} | embree {} | robust {}",
                format!("{} checksum", set.name),
                checksum(ours),
                checksum(theirs),
                checksum(robust)
            );
        }
    }
    out
}

/// The dynamic benchmark of one scene as a table: one column per system, medians per frame,
/// and raystage's frame times relative to each other system's, the median of the frames' ratios
/// (below 1 means raystage is faster).
pub fn dynamic_table(scene: &str, triangles: u64, instances: usize, frames: usize, threads: usize, runs: &[crate::dynamic::SystemRun]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "scene {scene}: {instances} instances, {triangles} triangles after instancing; {}x{} primary + shadow rays; medians over frames 1..={frames}; {threads} thread(s)",
        crate::dynamic::WIDTH,
        crate::dynamic::HEIGHT
    );
    let reports: Vec<_> = runs.iter().map(|r| r.report(scene, threads, triangles, instances)).collect();
    let _ = write!(out, "  {:<22}", "");
    for r in &reports {
        let _ = write!(out, "{:>22}", r.system);
    }
    let _ = writeln!(out);
    type Column = fn(&crate::dynamic::DynamicReport) -> f64;
    let rows: [(&str, Column); 6] = [
        ("first frame ms", |r| r.first_frame_ms),
        ("update ms / frame", |r| r.update_ms),
        ("trace ms / frame", |r| r.trace_ms),
        ("frame ms", |r| r.frame_ms),
        ("frames / s", |r| r.fps),
        ("Mrays / s (tracing)", |r| r.mrays),
    ];
    for (name, get) in rows {
        let _ = write!(out, "  {name:<22}");
        for r in &reports {
            let _ = write!(out, "{:>22.3}", get(r));
        }
        let _ = writeln!(out);
    }
    // Each raystage run against the Embree runs that hand rays over the same way, frame by
    // frame (they took turns).
    let packets = |r: &crate::dynamic::SystemRun| r.system.ends_with("-packets");
    for ours in runs.iter().filter(|r| r.system.starts_with("raystage")) {
        for theirs in runs.iter().filter(|r| !r.system.starts_with("raystage") && packets(r) == packets(ours)) {
            let ratio = |of: fn(&crate::dynamic::FrameTime) -> f64| crate::dynamic::paired_ratio(ours, theirs, of);
            let _ = writeln!(
                out,
                "  {} / {}: frame time {:.2}x, update {:.2}x, trace {:.2}x (medians of the frames' ratios)",
                ours.system,
                theirs.system,
                ratio(|f| f.update + f.trace),
                ratio(|f| f.update),
                ratio(|f| f.trace)
            );
        }
    }
    out
}

/// Each scene's tracing throughput relative to `baseline`'s (the still sphere grid), system by
/// system: the target asks terrain for at least 0.7 of the sphere grid's Mrays/s
/// (docs/performance.md, "Dynamic scenes"). Scenes or systems without a baseline run are left
/// out.
pub fn throughput_against(baseline: &str, reports: &[crate::dynamic::DynamicReport]) -> String {
    let mut out = String::new();
    let scenes = reports.iter().map(|r| r.scene.as_str()).filter(|&s| s != baseline);
    let mut seen: Vec<&str> = Vec::new();
    for scene in scenes {
        if seen.contains(&scene) {
            continue;
        }
        seen.push(scene);
        let ratios: Vec<String> = reports
            .iter()
            .filter(|r| r.scene == scene)
            .filter_map(|r| {
                let base = reports.iter().find(|b| b.scene == baseline && b.system == r.system)?;
                Some(format!("{} {:.2}x", r.system, r.mrays / base.mrays))
            })
            .collect();
        if !ratios.is_empty() {
            let _ = writeln!(out, "{scene} Mrays/s / {baseline}'s: {}", ratios.join(", "));
        }
    }
    out
}

/// The shading measurements as a table: median time per frame of the bare kernel and of each
/// rendered frame, its ratio to the kernel's (median of the repetitions' ratios) and the rays it
/// traced; then the ratios with targets (docs/performance.md, "Shading"), and whether specialised
/// and general shading gave the same image.
pub fn shading_table(run: &ShadingRun) -> String {
    let mut out = String::new();
    let reps = run.samples.first().map_or(0, |(_, m)| m.len());
    let _ = writeln!(
        out,
        "shading: sphere grid, {} triangles, {}x{}, one point light (the whitted-area frames: an area light); {} thread(s), median of {reps}; object trees built once beforehand ({:.3} s)",
        run.triangles,
        crate::rays::WIDTH,
        crate::rays::HEIGHT,
        run.threads,
        run.object_build_seconds
    );
    let _ = writeln!(out, "  {:<20} {:>9} {:>10} {:>13} {:>13} {:>9}", "system", "ms", "vs kernel", "primary rays", "shadow rays", "Mrays/s");
    for system in System::ALL {
        let (seconds, rays) = (run.median_seconds(system), run.rays(system));
        let _ = writeln!(
            out,
            "  {:<20} {:>9.1} {:>9.2}x {:>13} {:>13} {:>9.1}",
            system.name(),
            seconds * 1e3,
            run.ratio(system, System::Kernel),
            rays.primary,
            rays.shadow,
            rays.total() as f64 / seconds / 1e6
        );
    }
    let _ = writeln!(out, "  eyelight / kernel:     {:.2}x (target <= 1.2)", run.ratio(System::EyeLight, System::Kernel));
    let _ = writeln!(out, "  point light / kernel:  {:.2}x (target <= 2.2)", run.ratio(System::Whitted, System::Kernel));
    let general = run.ratio(System::AreaGeneral, System::AreaSpecialised);
    let _ = writeln!(out, "specialisation: whitted, purely diffuse scene under an area light (every hit through the recursion)");
    let _ = writeln!(out, "  general / specialised: {general:.3}x (target <= 1.05: reflection and refraction code costs a diffuse scene at most 5 %)");
    let d = run.specialisation_difference;
    if d.differing == 0 {
        let _ = writeln!(out, "  images identical: yes (every pixel bit-identical)");
    } else {
        let _ = writeln!(out, "  images identical: NO ({} pixels differ, by up to {})", d.differing, d.largest);
    }
    out
}

/// The path tracer's convergence as a table: RMSE against the reference and the cumulative
/// render time at each sample count, beside the ideal 1/sqrt(spp) from the first point, and the
/// fitted log-log slope.
pub fn convergence_table(run: &ConvergenceRun) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "convergence: Cornell room, path tracing, {}x{}, {} thread(s); reference {} spp of another seed ({:.1} s)",
        crate::render::CONVERGENCE_WIDTH,
        crate::render::CONVERGENCE_HEIGHT,
        run.threads,
        run.reference_spp,
        run.reference_seconds
    );
    let _ = writeln!(out, "  {:>6} {:>10} {:>10} {:>9}", "spp", "RMSE", "ideal", "seconds");
    let first = run.points.first().map_or(0.0, |p| p.rmse);
    for p in &run.points {
        let _ = writeln!(out, "  {:>6} {:>10.5} {:>10.5} {:>9.2}", p.spp, p.rmse, first / (p.spp as f64).sqrt(), p.seconds);
    }
    let _ = writeln!(
        out,
        "  log-log slope: {:.3} over all, {:.3} over the last {} counts (Monte Carlo: -0.5)",
        run.slope,
        run.tail_slope,
        crate::render::TAIL_POINTS
    );
    out
}

/// The path-tracing benchmark's table: every render's time and error, each system's time to
/// 1 % and raystage's ratio to it, and raystage's thread scaling.
pub fn pathtrace_table(report: &crate::pathtrace::Report, targets: &[crate::pathtrace::TimeToTarget]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "path tracing: {} at {}x{}, reference {}", report.scene, report.size, report.size, report.reference);
    let _ = writeln!(out, "  {:<20} {:>6} {:>10} {:>10} {:>22}", "system", "spp", "seconds", "RMSE", "channel means / ref");
    for p in &report.points {
        let [r, g, b] = p.channel_ratio;
        let _ = writeln!(out, "  {:<20} {:>6} {:>10.3} {:>10.5}   {r:.4} {g:.4} {b:.4}", p.system, p.spp, p.seconds, p.rmse);
    }
    let _ = writeln!(out, "time to a relative RMSE:");
    for t in targets {
        let seconds = t.seconds.map_or("not reached".to_string(), |s| format!("{s:.3} s{}", if t.extrapolated { " (extrapolated)" } else { "" }));
        let ratio = t.raystage_ratio.map_or(String::new(), |r| format!("   raystage / this: {r:.2}x"));
        let _ = writeln!(out, "  {:>3} %  {:<20} {seconds}{ratio}", t.target * 100.0, t.system);
    }
    let s = &report.scaling;
    let _ = writeln!(
        out,
        "raystage thread scaling at {} spp: {:.3} s on 1 thread, {:.3} s on {}: {:.2}x; {} tasks a frame",
        s.spp, s.one_thread_s, s.threads_s, s.threads, s.speedup, s.tasks
    );
    out
}

/// The scaling benchmark: one row per integrator, scene and thread count.
pub fn scaling_table(points: &[crate::scaling::Point]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<13} {:<8} {:>9} {:>4} {:>7} {:>10} {:>8} {:>8} {:>10} {:>9} {:>6} {:>8}",
        "integrator", "scene", "size", "spp", "threads", "frame s", "speedup", "effic.", "1st frame", "build s", "tasks", "largest"
    );
    for p in points {
        let _ = writeln!(
            out,
            "{:<13} {:<8} {:>9} {:>4} {:>7} {:>10.3} {:>7.2}x {:>8.2} {:>10.3} {:>9.3} {:>6} {:>7.2}%",
            p.integrator,
            p.scene,
            format!("{}x{}", p.width, p.height),
            p.spp,
            p.threads,
            p.frame_s,
            p.speedup,
            p.efficiency,
            p.first_frame_s,
            p.build_s,
            p.tasks,
            100.0 * p.largest_task_share
        );
    }
    out
}

/// The MPI runs as a table: per configuration (one process first) the median frame, rank 0's
/// render plus gather, and the fastest, the median's rays per second, its speed against one process, the slowest rank's
/// share render over the fastest's, the gather and what it received; then whether every image
/// was the one process's.
pub fn mpi_table(report: &crate::mpi::Report) -> String {
    let mut out = String::new();
    let base = report.baseline();
    let _ = writeln!(
        out,
        "MPI on this machine: raystage render {} on {} cores; {}x{}, median of the runs; frame = rank 0's render + gather",
        report.render_args.join(" "),
        report.cores,
        base.summary.width,
        base.summary.height
    );
    let _ = writeln!(
        out,
        "  {:>5} {:>7} {:>8} {:>8} {:>7} {:>8} {:>8} {:>10} {:>8} {:>11}",
        "ranks", "threads", "frame s", "fastest", "wall s", "Mrays/s", "vs one", "max/min", "gather s", "gathered MB"
    );
    for run in &report.runs {
        let timing = run.timing.as_ref();
        let _ = writeln!(
            out,
            "  {:>5} {:>7} {:>8.3} {:>8.3} {:>7.3} {:>8.2} {:>7.2}x {:>10} {:>8} {:>11}",
            run.ranks.map_or("alone".to_string(), |k| k.to_string()),
            run.threads,
            run.frame_s,
            run.fastest_frame_s,
            run.wall_s,
            run.mrays_per_s(),
            base.frame_s / run.frame_s,
            timing.map_or("-".to_string(), |t| format!("{:.2}", t.max_over_min())),
            timing.map_or("-".to_string(), |t| format!("{:.3}", t.gather_s)),
            timing.map_or("-".to_string(), |t| format!("{:.2}", t.bytes as f64 / 1e6)),
        );
    }
    let same = if report.all_same_bytes() { "every run's PNG is byte for byte the one process's" } else { "SOME PNGs DIFFER from the one process's (see the log)" };
    let _ = writeln!(out, "  {same}");
    out
}

/// The cluster model as tables, one per link: per node count, each node's render, then for each
/// encoding the gather in ms, frames per second and efficiency (speedup over nodes), and the
/// efficiency with the gather overlapping the render; `*` marks efficiencies at or above
/// [`crate::cluster_model::GOOD_EFFICIENCY`].
pub fn cluster_model_table(frame: &crate::cluster_model::Frame, encodings: &[crate::cluster_model::Encoding], links: &[crate::cluster_model::Link]) -> String {
    use crate::cluster_model::{GOOD_EFFICIENCY, NODES, predict};
    let mut out = String::new();
    let _ = writeln!(
        out,
        "cluster model: 1920x1080 at {} spp, {:.3e} core-s per pixel (one process's fastest frame) on nodes of {} cores: {:.3} s per frame on one node",
        frame.spp,
        frame.core_seconds_per_pixel,
        frame.cores_per_node,
        frame.one_node_s()
    );
    let _ = writeln!(out, "  per encoding: gather ms, frames/s, efficiency, efficiency with the gather overlapping the render; * efficiency >= {GOOD_EFFICIENCY}");
    let mark = |e: f64| format!("{e:.2}{}", if e >= GOOD_EFFICIENCY { "*" } else { " " });
    for link in links {
        let _ = writeln!(out, "  {} ({:.3} GB/s, {:.0} us per message, serialised into node 0)", link.name, link.bytes_per_s / 1e9, link.latency_s * 1e6);
        let _ = write!(out, "  {:>5} {:>8}", "nodes", "render s");
        for e in encodings {
            let _ = write!(out, " | {:<25}", format!("{} {:.2} B/px", e.name, e.bytes_per_pixel));
        }
        let _ = writeln!(out);
        for nodes in NODES {
            let _ = write!(out, "  {nodes:>5} {:>8.3}", frame.one_node_s() / f64::from(nodes));
            for e in encodings {
                let p = predict(frame, nodes, link, e);
                let _ = write!(out, " | {:>7.1} {:>6.2} {} {}", p.gather_s * 1e3, p.frames_per_s, mark(p.efficiency), mark(p.overlapped_efficiency));
            }
            let _ = writeln!(out);
        }
    }
    // The padding of the last column and unmarked figures would end lines in spaces.
    out.lines().map(|line| format!("{}\n", line.trim_end())).collect()
}

/// The bounce benchmark of one scene as a table: per bounce, its rays, the share that hit and
/// raystage's walk per ray; then each system's Mrays/s on one thread in each order, with the
/// sorting's time added in brackets, and the time to sort.
pub fn bounces_table(run: &crate::bounces::SceneRun) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "bounces: {}, {} triangles; one ray per call on one thread (Embree: rtcIntersect1); Mrays/s tracing alone (with the sorting's time)",
        run.scene.name(),
        run.triangles
    );
    let _ = writeln!(out, "  {:<9} {:>8} {:>6} {:>7} {:>7} {:>9}", "bounce", "rays", "hits", "nodes", "leaves", "triangles");
    for w in &run.walks {
        let p = &w.per_ray;
        let _ = writeln!(out, "  {:<9} {:>8} {:>5.1}% {:>7.2} {:>7.2} {:>9.2}", w.bounce, w.rays, 100.0 * w.hit_share, p.nodes, p.leaves, p.triangles);
    }
    for w in &run.walks {
        let _ = writeln!(out, "  {}:", w.bounce);
        for t in run.traces.iter().filter(|t| t.bounce == w.bounce) {
            let with_sort = t.mrays_with_sort.map_or(String::new(), |r| format!(" ({r:.2})"));
            let sort =
                run.sorting.iter().find(|s| s.bounce == t.bounce && s.order == t.order).map_or(String::new(), |s| format!(", sorting {:.2} ms", s.sort_ms));
            let _ = writeln!(out, "    {:<9} {:<18} {:>7.2}{with_sort}  {:.2}x as made{sort}", t.system, t.order, t.mrays, t.vs_as_made);
        }
    }
    out
}
