//! `raystage-bench`: command-line front end of the benchmark harness.

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use raystage_bench::kernel::Api;
use raystage_bench::stamp::{Stamp, StampLine};
use raystage_bench::{animation, bounces, cluster_model, dynamic, kernel, mpi, page, pathtrace, plot, render, rtrps, scaling, table};
use raystage_demo::animated::{Animation, Baked, Museum, Robots, Still, Terrain};
use raystage_demo::StandardScene;

#[derive(Parser)]
#[command(version, about = "raystage benchmarks, side by side with Embree 3 (feature `embree`)")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Build time and single-ray throughput on the probe's standard scenes.
    Kernel {
        /// `sphere`, `soup` or `all`.
        #[arg(long, default_value = "sphere")]
        scene: String,
        /// Thread count of the multi-threaded measurements (1-thread figures are always measured).
        #[arg(long, default_value_t = std::thread::available_parallelism().map_or(1, |n| n.get()))]
        threads: usize,
        /// Repetitions; medians are reported.
        #[arg(long, default_value_t = 3)]
        reps: usize,
        /// Print one JSON object per system, scene and thread count instead of tables.
        #[arg(long)]
        json: bool,
        /// Measure the builds only (raystage, Embree MEDIUM and HIGH taking turns), no rays.
        #[arg(long)]
        build_only: bool,
    },
    /// Animated scenes updated and traced frame by frame (robots, museum, terrain).
    Dynamic {
        /// `robots`, `museum`, `terrain` or `all`.
        #[arg(long, default_value = "all")]
        scene: String,
        /// Moving triangles of the museum (default: 1024, 4096, 16384 and 65536 in turn).
        #[arg(long)]
        triangles: Option<usize>,
        /// Frames after the first.
        #[arg(long, default_value_t = 20)]
        frames: u32,
        /// Threads tracing (and building).
        #[arg(long, default_value_t = 1)]
        threads: usize,
        /// Print one JSON object per system and scene instead of tables.
        #[arg(long)]
        json: bool,
    },
    /// RTRPS (seed 004): bounding spheres culled per 16x16 tile instead of the top-level tree,
    /// in turns with raystage on the animated demos' primary rays, hits checked ray by ray.
    Rtrps {
        /// `robots`, `museum` or `all`.
        #[arg(long, default_value = "all")]
        scene: String,
        /// Moving triangles of the museum.
        #[arg(long, default_value_t = 16384)]
        triangles: usize,
        /// Frames after the first.
        #[arg(long, default_value_t = 20)]
        frames: u32,
        /// Threads tracing.
        #[arg(long, default_value_t = 1)]
        threads: usize,
    },
    /// Shading costs: eye-light and point-light frames against the bare kernel,
    /// specialised against general shading, and the path tracer's convergence.
    Render {
        /// Threads of every measurement.
        #[arg(long, default_value_t = std::thread::available_parallelism().map_or(1, |n| n.get()))]
        threads: usize,
        /// Repetitions of the shading measurements; medians are reported.
        #[arg(long, default_value_t = 3)]
        reps: usize,
        /// Samples per pixel of the convergence reference (its own error adds to the RMSE at the
        /// highest counts: raise it for a cleaner tail, at about 25 ms per sample on 2 cores).
        #[arg(long, default_value_t = 2048)]
        reference_spp: u32,
        /// Highest sample count compared with the reference (powers of two from 1).
        #[arg(long, default_value_t = 256)]
        max_spp: u32,
        /// Where to write the convergence plot (PNG).
        #[arg(long, default_value = "convergence.png")]
        plot: PathBuf,
        /// Print one JSON object per measurement instead of tables.
        #[arg(long)]
        json: bool,
    },
    /// The path tracer against Mitsuba 3 on the classic Cornell box and on the same room with a
    /// million triangles of spheres: time and error at each sample count, both systems in turns
    /// on the same threads, and each one's time to 5 %, 2 % and 1 % relative RMSE.
    Pathtrace {
        /// `room`, `spheres` or `all`.
        #[arg(long, default_value = "all")]
        scene: String,
        /// Image side in pixels of the room (a multiple of 4).
        #[arg(long, default_value_t = 256)]
        size: u32,
        /// Image side in pixels of the room with spheres (a multiple of 4).
        #[arg(long, default_value_t = 128)]
        spheres_size: u32,
        /// Sample counts to compare, comma-separated.
        #[arg(long, default_value = "16,32,64,128,256,512,1024", value_delimiter = ',')]
        spp: Vec<u32>,
        /// Samples per pixel of Mitsuba's reference.
        #[arg(long, default_value_t = 8192)]
        reference_spp: u32,
        /// Threads of every render.
        #[arg(long, default_value_t = std::thread::available_parallelism().map_or(1, |n| n.get()))]
        threads: usize,
        /// Mitsuba variants to time, comma-separated (llvm_ad_rgb needs LLVM 19:
        /// DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so).
        #[arg(long, default_value = "scalar_rgb", value_delimiter = ',')]
        variants: Vec<String>,
        /// The Python interpreter that has the `mitsuba` package.
        #[arg(long, default_value = "python3")]
        python: String,
        /// Where to write the scene, the reference and Mitsuba's images.
        #[arg(long, default_value = "pathtrace")]
        dir: PathBuf,
        /// Print one JSON object per render, then one per system's time to 1 %.
        #[arg(long)]
        json: bool,
    },
    /// A path tracer's rays bounce by bounce (camera rays, then diffuse bounces), traced one by
    /// one on one thread as made and sorted by where they start (origin cell, then octant), with
    /// the walk's nodes, leaves and triangles per ray: Bikker's tables per bounce (seed 003).
    Bounces {
        /// `room`, `spheres`, `sphere-grid` or `all`.
        #[arg(long, default_value = "all")]
        scene: String,
        /// Image side in pixels: one camera ray per pixel.
        #[arg(long, default_value_t = 512)]
        size: u32,
        /// Bounces after the camera rays.
        #[arg(long, default_value_t = 4)]
        bounces: u32,
        /// Batch sizes the rays are sorted in, comma-separated (all of a bounce's rays sorted at
        /// once is measured too).
        #[arg(long, default_value = "4096,65536", value_delimiter = ',')]
        batches: Vec<usize>,
        /// Repetitions; the best is reported.
        #[arg(long, default_value_t = 3)]
        reps: usize,
        /// Print one JSON object per measurement instead of tables.
        #[arg(long)]
        json: bool,
    },
    /// Frame time against threads (1, 2, 4, … up to `--threads`) for every integrator on the
    /// sphere grid at 1920x1080 and the Cornell room at 256x256: speedup, lazy build time, and
    /// the tasks a frame offers with the largest one's share of the work.
    Scaling {
        /// Most threads.
        #[arg(long, default_value_t = std::thread::available_parallelism().map_or(1, |n| n.get()))]
        threads: usize,
        /// `spheres`, `room` or `all`.
        #[arg(long, default_value = "all")]
        scene: String,
        /// Integrators, comma-separated (eyelight, whitted, distribution, path).
        #[arg(long, default_value = "eyelight,whitted,distribution,path", value_delimiter = ',')]
        integrators: Vec<String>,
        /// Warm frames per measurement; the best is reported.
        #[arg(long, default_value_t = 2)]
        reps: usize,
        /// Print one JSON object per integrator, scene and thread count instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// One frame on 1, 2, 3, 4 MPI ranks of this machine (`mpirun … raystage render --mpi`)
    /// against one process on all cores: frame time, rank 0's gather and the ranks' imbalance,
    /// the images compared byte for byte; then a model of the frame on 1 to 32 nodes over 10 GbE
    /// and 1 GbE.
    Mpi {
        /// Rank counts, comma-separated.
        #[arg(long, default_value = "1,2,3,4", value_delimiter = ',')]
        ranks: Vec<u32>,
        /// Cores shared among the ranks (each gets cores/ranks threads, at least one).
        #[arg(long, default_value_t = std::thread::available_parallelism().map_or(1, |n| n.get()))]
        cores: usize,
        /// The `raystage` binary, built with `--features mpi` (default: the one beside this one).
        #[arg(long)]
        raystage: Option<PathBuf>,
        /// Demo scene.
        #[arg(long, default_value = "cornell")]
        demo: String,
        /// Integrator.
        #[arg(long, default_value = "path")]
        integrator: String,
        /// Image width.
        #[arg(long, default_value_t = 640)]
        width: u32,
        /// Image height.
        #[arg(long, default_value_t = 360)]
        height: u32,
        /// Samples per pixel (the default makes a frame of a few seconds on 2 cores).
        #[arg(long, default_value_t = 16)]
        spp: u32,
        /// Runs of each configuration; the median frame is reported.
        #[arg(long, default_value_t = 3)]
        reps: usize,
        /// Cores of each node in the cluster model.
        #[arg(long, default_value_t = 16)]
        cores_per_node: usize,
        /// Samples per pixel of the cluster model's frames, comma-separated (default: the
        /// measured frame's, then 1, an interactive frame's).
        #[arg(long, value_delimiter = ',')]
        model_spp: Option<Vec<u32>>,
        /// Where to write the images.
        #[arg(long, default_value = "mpi")]
        dir: PathBuf,
        /// Print the runs and the model's predictions as JSON objects, one per line.
        #[arg(long)]
        json: bool,
    },
    /// A skinned glTF asset played frame by frame: evaluation, skinning, tree update and the
    /// eye-light preview at 1280x720 per frame; with Embree (feature `embree`) the same
    /// skinned vertices refitted and rebuilt, and the same primary rays traced.
    Animation {
        /// `rigged` (RiggedSimple), `tube` (a generated 99,840-triangle skinned tube) or a
        /// .glb/.gltf file, comma-separated.
        #[arg(long, default_value = "rigged,tube", value_delimiter = ',')]
        assets: Vec<String>,
        /// Thread counts, comma-separated.
        #[arg(long, default_value = "1,2", value_delimiter = ',')]
        threads: Vec<usize>,
        /// Frames after the first (at 24 frames per second).
        #[arg(long, default_value_t = 24)]
        frames: u32,
        /// Print one JSON object per system, asset and thread count instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// A Markdown performance page from a `--json` report: the run's stamp (machine, commit,
    /// date), then its records as tables, with the first system's figures over each other's.
    Page {
        /// The report, one JSON object per line as `--json` prints it (`-` for standard input).
        report: PathBuf,
    },
}

impl Command {
    /// Whether the run prints a JSON report (which then starts with the run's stamp).
    fn json(&self) -> bool {
        match self {
            Command::Kernel { json, .. }
            | Command::Bounces { json, .. }
            | Command::Dynamic { json, .. }
            | Command::Render { json, .. }
            | Command::Pathtrace { json, .. }
            | Command::Scaling { json, .. }
            | Command::Mpi { json, .. }
            | Command::Animation { json, .. } => *json,
            Command::Page { .. } | Command::Rtrps { .. } => false,
        }
    }
}

fn main() {
    let cli = Cli::parse();
    if cli.command.json() {
        // First, so that every report says what it was measured on (see `page`).
        let args: Vec<String> = std::env::args().skip(1).collect();
        println!("{}", serde_json::to_string(&StampLine { stamp: Stamp::now(&args) }).expect("stamps serialise"));
    }
    match cli.command {
        Command::Animation { assets, threads, frames, json } => {
            if !cfg!(feature = "embree") {
                eprintln!("note: built without the `embree` feature; only raystage is measured");
            }
            let mut reports = Vec::new();
            for name in &assets {
                let asset = animation::Asset::from_name(name).unwrap_or_else(|| fail(&format!("unknown asset `{name}` (expected rigged, tube or a .glb/.gltf file)")));
                for &threads in &threads {
                    let runs = animation::run(&asset, threads.max(1), frames.max(1)).unwrap_or_else(|e| fail(&e));
                    if json {
                        for r in &runs {
                            println!("{}", serde_json::to_string(r).expect("report serialises"));
                        }
                    }
                    reports.extend(runs);
                }
            }
            if !json {
                print!("{}", animation::table(&reports));
            }
        }
        Command::Page { report } => {
            let text = if report.as_os_str() == "-" {
                std::io::read_to_string(std::io::stdin())
            } else {
                std::fs::read_to_string(&report)
            };
            let text = text.unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", report.display())));
            match page::render(&text) {
                Ok(page) => print!("{page}"),
                Err(e) => fail(&format!("{}: {e}", report.display())),
            }
        }
        Command::Mpi { ranks, cores, raystage, demo, integrator, width, height, spp, reps, cores_per_node, model_spp, dir, json } => {
            let raystage = raystage.unwrap_or_else(|| {
                let bench = std::env::current_exe().unwrap_or_else(|e| fail(&format!("cannot find this executable: {e}")));
                bench.with_file_name("raystage")
            });
            let render_args = ["--demo", &demo, "--integrator", &integrator, "--width", &width.to_string(), "--height", &height.to_string(), "--spp", &spp.to_string()]
                .map(String::from)
                .to_vec();
            let config = mpi::Config { raystage, ranks, cores: cores.max(1), render_args, reps, dir };
            let report = mpi::run(&config, |line| eprintln!("{line}")).unwrap_or_else(|e| {
                eprintln!("error: {e}");
                std::process::exit(1);
            });
            let mut model_spp = model_spp.unwrap_or_else(|| vec![spp, 1]);
            model_spp.dedup();
            let frames: Vec<_> = model_spp.iter().map(|&s| report.model_frame(spp, s, cores_per_node.max(1))).collect();
            let encodings = report.encodings();
            let links = [cluster_model::TEN_GBE, cluster_model::ONE_GBE];
            if json {
                for run in &report.runs {
                    println!("{}", serde_json::to_string(run).expect("report serialises"));
                }
                for frame in &frames {
                    for link in &links {
                        for e in &encodings {
                            for nodes in cluster_model::NODES {
                                let p = cluster_model::predict(frame, nodes, link, e);
                                println!("{}", serde_json::json!({ "link": link, "encoding": e, "frame": frame, "prediction": p }));
                            }
                        }
                    }
                }
            } else {
                print!("{}", table::mpi_table(&report));
                for frame in &frames {
                    print!("{}", table::cluster_model_table(frame, &encodings, &links));
                }
            }
        }
        Command::Bounces { scene, size, bounces: count, batches, reps, json } => {
            let scenes = match scene.as_str() {
                "all" => bounces::BounceScene::ALL.to_vec(),
                name => match bounces::BounceScene::from_name(name) {
                    Some(s) => vec![s],
                    None => fail(&format!("unknown scene `{name}` (expected room, spheres, sphere-grid or all)")),
                },
            };
            if !cfg!(feature = "embree") {
                eprintln!("note: built without the `embree` feature; only raystage is measured");
            }
            let build_threads = std::thread::available_parallelism().map_or(1, |n| n.get());
            let config = bounces::Config { scenes, size: size.max(1), bounces: count, batches, reps, build_threads };
            let runs = bounces::run(&config, |line| eprintln!("{line}")).unwrap_or_else(|e| {
                eprintln!("error: {e}");
                std::process::exit(1);
            });
            for run in &runs {
                if json {
                    for w in &run.walks {
                        println!("{}", serde_json::to_string(w).expect("report serialises"));
                    }
                    for t in &run.traces {
                        println!("{}", serde_json::to_string(t).expect("report serialises"));
                    }
                    for s in &run.sorting {
                        println!("{}", serde_json::to_string(s).expect("report serialises"));
                    }
                } else {
                    print!("{}", table::bounces_table(run));
                }
            }
        }
        Command::Scaling { threads, scene, integrators, reps, json } => {
            let scenes = match scene.as_str() {
                "all" => scaling::BenchScene::ALL.to_vec(),
                name => match scaling::BenchScene::from_name(name) {
                    Some(s) => vec![s],
                    None => fail(&format!("unknown scene `{name}` (expected spheres, room or all)")),
                },
            };
            let integrators = integrators
                .iter()
                .map(|name| raystage_render::Integrator::from_name(name).unwrap_or_else(|| fail(&format!("unknown integrator `{name}`"))))
                .collect();
            let config = scaling::Config { threads: scaling::thread_counts(threads.max(1)), scenes, integrators, reps };
            let points = scaling::run(&config, |line| eprintln!("{line}"));
            if json {
                for p in &points {
                    println!("{}", serde_json::to_string(p).expect("report serialises"));
                }
            } else {
                print!("{}", table::scaling_table(&points));
            }
        }
        Command::Pathtrace { scene, size, spheres_size, spp, reference_spp, threads, variants, python, dir, json } => {
            let sized = |scene: pathtrace::PathScene| {
                let side = if scene == pathtrace::PathScene::Spheres { spheres_size } else { size };
                (scene, side.max(4) / 4 * 4)
            };
            let scenes = match scene.as_str() {
                "all" => pathtrace::PathScene::ALL.map(sized).to_vec(),
                name => match pathtrace::PathScene::from_name(name) {
                    Some(scene) => vec![sized(scene)],
                    None => fail(&format!("unknown scene `{name}` (expected room, spheres or all)")),
                },
            };
            let config = pathtrace::Config { scenes, spp, reference_spp, threads: threads.max(1), variants, python, dir };
            let reports = match pathtrace::run(&config, |line| eprintln!("{line}")) {
                Ok(reports) => reports,
                Err(e) => {
                    eprintln!("error: {e}");
                    std::process::exit(1);
                }
            };
            for report in &reports {
                let targets = report.times_to_target();
                if json {
                    for p in &report.points {
                        println!("{}", serde_json::to_string(p).expect("report serialises"));
                    }
                    for t in &targets {
                        println!("{}", serde_json::to_string(t).expect("report serialises"));
                    }
                    println!("{}", serde_json::to_string(&report.scaling).expect("report serialises"));
                } else {
                    print!("{}", table::pathtrace_table(report, &targets));
                }
            }
        }
        Command::Render { threads, reps, reference_spp, max_spp, plot: plot_path, json } => {
            let threads = threads.max(1);
            let shading = render::run_shading(threads, reps, |line| eprintln!("{line}"));
            let materials = render::run_material_cost(threads, reps, |line| eprintln!("{line}"));
            let convergence = render::run_convergence(threads, reference_spp.max(1), max_spp.max(1), |line| eprintln!("{line}"));
            let text = plot::register_system_font();
            if let Err(e) = plot::convergence(&plot_path, &convergence, text) {
                eprintln!("error: cannot write the plot {}: {e}", plot_path.display());
                std::process::exit(1);
            }
            let (lines, specialisation) = shading.reports();
            if json {
                for r in &lines {
                    println!("{}", serde_json::to_string(r).expect("report serialises"));
                }
                println!("{}", serde_json::to_string(&specialisation).expect("report serialises"));
                for r in convergence.reports() {
                    println!("{}", serde_json::to_string(&r).expect("report serialises"));
                }
                for m in &materials {
                    println!("{}", serde_json::to_string(m).expect("report serialises"));
                }
            } else {
                print!("{}", table::shading_table(&shading));
                for m in &materials {
                    println!(
                        "material cost, {} at {}x{}, {} spp: Diffuse {:.1} ms, PhysicallyBased {:.1} ms: {:.2}x",
                        m.integrator, m.width, m.height, m.spp, m.diffuse_ms, m.physically_based_ms, m.ratio
                    );
                }
                print!("{}", table::convergence_table(&convergence));
            }
            let mut note = format!("convergence plot: {}", plot_path.display());
            if !text {
                note += " (no font found, so no text: log-log axes, x samples per pixel from 1, y RMSE; \
                         solid blue with dots: measured; dashed red: ideal 1/sqrt(spp) from the first point)";
            }
            // Standard output stays one JSON object per line with --json.
            if json {
                eprintln!("{note}");
            } else {
                println!("{note}");
            }
        }
        Command::Dynamic { scene, triangles, frames, threads, json } => {
            let museum_sizes = triangles.map_or(vec![1024, 4096, 16384, 65536], |n| vec![n]);
            let animations: Vec<Box<dyn Animation>> = match scene.as_str() {
                "robots" => vec![Box::new(Robots)],
                "museum" => museum_sizes.iter().map(|&n| Box::new(Museum::new(n)) as Box<dyn Animation>).collect(),
                // The sphere grid is the baseline of terrain's throughput target; baked, the
                // terrain shows what its geometry costs without the instancing.
                "terrain" => vec![Box::new(Terrain), Box::new(Baked::new(&Terrain)), Box::new(Still(StandardScene::Spheres))],
                "all" => {
                    let mut all: Vec<Box<dyn Animation>> = vec![Box::new(Robots)];
                    all.extend(museum_sizes.iter().map(|&n| Box::new(Museum::new(n)) as Box<dyn Animation>));
                    all.push(Box::new(Terrain));
                    all.push(Box::new(Baked::new(&Terrain)));
                    all.push(Box::new(Still(StandardScene::Spheres)));
                    all
                }
                other => fail(&format!("unknown scene `{other}` (expected robots, museum, terrain or all)")),
            };
            if !cfg!(feature = "embree") {
                eprintln!("note: built without the `embree` feature; only raystage is measured");
            }
            let mut reports = Vec::new();
            for animation in animations {
                let name = animation.name();
                let mut runs = Vec::new();
                for api in [Api::Single, Api::Packets] {
                    // The systems that hand rays over the same way take turns frame by frame.
                    let threads = threads.max(1);
                    let mut systems: Vec<Box<dyn dynamic::System + '_>> = vec![Box::new(dynamic::Raystage::new(animation.as_ref(), threads, api))];
                    #[cfg(feature = "embree")]
                    {
                        use raystage_bench::embree::Quality;
                        let moving = animation.objects().iter().any(|o| o.kind == raystage_scene::ObjectKind::Unstructured);
                        let qualities = if moving { vec![Quality::Low, Quality::Refit] } else { vec![Quality::Low] };
                        for q in qualities {
                            systems.push(Box::new(dynamic::Embree::new(animation.as_ref(), threads, q, false, api)));
                        }
                        // Embree with raystage's guarantees (see `Scene::build_robust`).
                        systems.push(Box::new(dynamic::Embree::new(animation.as_ref(), threads, Quality::Low, true, api)));
                    }
                    let names: Vec<String> = systems.iter().map(|s| s.name()).collect();
                    eprintln!("{name}: {} in turns", names.join(", "));
                    runs.extend(dynamic::run_in_turns(&mut systems, frames));
                }
                let triangles = dynamic::instanced_triangles(animation.as_ref());
                let instances = animation.instances(0).len();
                if json {
                    for r in &runs {
                        println!("{}", serde_json::to_string(&r.report(&name, threads, triangles, instances)).expect("report serialises"));
                    }
                } else {
                    print!("{}", table::dynamic_table(&name, triangles, instances, frames as usize, threads, &runs));
                }
                reports.extend(runs.iter().map(|r| r.report(&name, threads, triangles, instances)));
            }
            if !json {
                print!("{}", table::throughput_against(StandardScene::Spheres.name(), &reports));
            }
        }
        Command::Rtrps { scene, triangles, frames, threads } => {
            let animations: Vec<Box<dyn Animation>> = match scene.as_str() {
                "robots" => vec![Box::new(Robots)],
                "museum" => vec![Box::new(Museum::new(triangles))],
                "all" => vec![Box::new(Robots), Box::new(Museum::new(triangles))],
                other => fail(&format!("unknown scene `{other}` (expected robots, museum or all)")),
            };
            let load = || std::fs::read_to_string("/proc/loadavg").unwrap_or_default().split_whitespace().take(3).collect::<Vec<_>>().join(" ");
            println!("load average before: {}", load());
            let mut differ = 0;
            for animation in animations {
                let (runs, tally) = rtrps::compare(animation.as_ref(), threads.max(1), frames);
                print!("{}", rtrps::table(&animation.name(), animation.instances(0).len(), threads.max(1), &runs, &tally));
                differ += tally.mismatches.get();
            }
            println!("load average after: {}", load());
            if differ > 0 {
                fail(&format!("{differ} rays' RTRPS hits differ from raystage's"));
            }
        }
        Command::Kernel { scene, threads, reps, json, build_only } => {
            let scenes = match scene.as_str() {
                "all" => StandardScene::ALL.to_vec(),
                name => match StandardScene::from_name(name) {
                    Some(s) => vec![s],
                    None => fail(&format!("unknown scene `{name}` (expected sphere, soup or all)")),
                },
            };
            if !cfg!(feature = "embree") {
                eprintln!("note: built without the `embree` feature; only raystage is measured");
            }
            for s in scenes {
                let run = kernel::run(s, threads.max(1), reps, build_only, |line| eprintln!("{line}"));
                if json {
                    for r in run.reports() {
                        println!("{}", serde_json::to_string(&r).expect("report serialises"));
                    }
                    for r in run.walk_reports() {
                        println!("{}", serde_json::to_string(&r).expect("report serialises"));
                    }
                } else {
                    print!("{}", table::kernel_table(&run));
                }
            }
        }
    }
}

/// Prints `message` as an error and exits with the status of a usage error.
fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    std::process::exit(2);
}
