//! Human-readable tables of benchmark results.

use std::fmt::Write;

use crate::kernel::{SceneRun, Traced, median};

fn mrays(runs: &[Traced], n: usize) -> f64 {
    median(&runs.iter().map(|r| n as f64 / r.seconds / 1e6).collect::<Vec<_>>())
}

/// The kernel benchmark of one scene as a table: one column per system and thread count, and the
/// raystage/Embree ratio where both were measured (higher is better for raystage except for build
/// time, where the ratio is raystage's time over Embree's).
pub fn kernel_table(run: &SceneRun) -> String {
    let mut out = String::new();
    let reps = run.runs.first().map_or(0, |r| r.2.build.len());
    let _ = writeln!(
        out,
        "scene {}: {} triangles, {}x{} primary rays, median of {reps}",
        run.scene.name(),
        run.triangles,
        crate::rays::WIDTH,
        crate::rays::HEIGHT
    );
    let thread_counts: Vec<usize> = {
        let mut t: Vec<usize> = run.runs.iter().map(|r| r.1).collect();
        t.sort_unstable();
        t.dedup();
        t
    };
    for threads in thread_counts {
        let ours = run.runs.iter().find(|r| r.0 == "raystage" && r.1 == threads).map(|r| &r.2);
        let theirs = run.runs.iter().find(|r| r.0 == "embree" && r.1 == threads).map(|r| &r.2);
        let _ = writeln!(out, "  {threads} thread(s)            raystage        embree   ratio");
        let row = |out: &mut String, name: &str, a: Option<f64>, b: Option<f64>, unit: &str| {
            let fmt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
            let ratio = match (a, b) {
                (Some(a), Some(b)) if b > 0.0 => format!("{:.2}x", a / b),
                _ => "-".to_string(),
            };
            let _ = writeln!(out, "  {name:<20} {:>9} {:>13} {ratio:>7}  {unit}", fmt(a), fmt(b));
        };
        row(&mut out, "build", ours.map(|s| median(&s.build)), theirs.map(|s| median(&s.build)), "s (Embree HIGH)");
        if let Some((_, m)) = run.embree_medium_build.iter().find(|(t, _)| *t == threads) {
            row(&mut out, "build vs MEDIUM", ours.map(|s| median(&s.build)), Some(*m), "s (Embree MEDIUM)");
        }
        let sets = [
            ("primary", run.sets.primary.len(), 0),
            ("incoherent", run.sets.incoherent.len(), 1),
            ("bounce", run.sets.bounce.len(), 2),
        ];
        for (name, n, which) in sets {
            let pick = |s: &crate::kernel::Samples| match which {
                0 => s.primary.clone(),
                1 => s.incoherent.clone(),
                _ => s.bounce.clone(),
            };
            row(&mut out, name, ours.map(|s| mrays(&pick(s), n)), theirs.map(|s| mrays(&pick(s), n)), "Mrays/s");
            let sum = |s: Option<&crate::kernel::Samples>| {
                s.and_then(|s| pick(s).last().copied()).map_or("-".to_string(), |t| format!("{} hits, sum t {:.1}", t.hits, t.tsum))
            };
            let _ = writeln!(out, "  {:<20} raystage {} | embree {}", format!("  {name} checksum"), sum(ours), sum(theirs));
        }
    }
    out
}
