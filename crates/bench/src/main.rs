//! `raystage-bench`: command-line front end of the benchmark harness.

use clap::{Parser, Subcommand};
use raystage_bench::{kernel, table};
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
    },
}

fn main() {
    match Cli::parse().command {
        Command::Kernel { scene, threads, reps, json } => {
            let scenes = match scene.as_str() {
                "all" => StandardScene::ALL.to_vec(),
                name => match StandardScene::from_name(name) {
                    Some(s) => vec![s],
                    None => {
                        eprintln!("error: unknown scene `{name}` (expected sphere, soup or all)");
                        std::process::exit(2);
                    }
                },
            };
            if !cfg!(feature = "embree") {
                eprintln!("note: built without the `embree` feature; only raystage is measured");
            }
            for s in scenes {
                let run = kernel::run(s, threads.max(1), reps, |line| eprintln!("{line}"));
                if json {
                    for r in run.reports() {
                        println!("{}", serde_json::to_string(&r).expect("report serialises"));
                    }
                } else {
                    print!("{}", table::kernel_table(&run));
                }
            }
        }
    }
}
