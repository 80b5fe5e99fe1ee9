//! `report.md`: a table per knob and a reading of it, computed from the numbers.

use std::fmt::Write;

use crate::run::{BvhRow, Knob, Report, Row};

/// Formats seconds with a sensible unit.
fn time(seconds: f64) -> String {
    if seconds >= 1.0 { format!("{seconds:.2} s") } else { format!("{:.1} ms", seconds * 1e3) }
}

/// Least-squares slope of `ln y` against `ln x`.
fn log_slope(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points.iter().filter(|p| p.0 > 0.0 && p.1 > 0.0).map(|p| (p.0.ln(), p.1.ln())).collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

fn table(out: &mut String, rows: &[Row]) {
    out.push_str("| setting | time | rays | Mrays/s | RMSE | relative MSE | mean abs. error | MSE × time |\n");
    out.push_str("|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for r in rows {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.2} | {:.4} | {:.4} | {:.4} | {:.3e} |",
            r.setting,
            time(r.seconds),
            r.rays,
            r.rays as f64 / r.seconds.max(1e-9) * 1e-6,
            r.errors.rmse,
            r.errors.rel_mse,
            r.errors.mae,
            r.inefficiency()
        );
    }
    out.push('\n');
}

/// What the numbers of one knob say, in a sentence or three.
fn reading(knob: &Knob) -> String {
    let rows = &knob.rows;
    let (Some(best), Some(accurate)) = (knob.best_trade(), knob.most_accurate()) else { return String::new() };
    let mut s = format!(
        "Best trade (lowest MSE × time): **{}** ({:.3e}); most accurate: **{}** (RMSE {:.4}, {}).",
        best.setting,
        best.inefficiency(),
        accurate.setting,
        accurate.errors.rmse,
        time(accurate.seconds)
    );
    match knob.id {
        "spp" => {
            let pts: Vec<(f64, f64)> = rows.iter().filter_map(|r| Some((r.setting.split(' ').next()?.parse::<f64>().ok()?, r.errors.rmse))).collect();
            let times: Vec<(f64, f64)> = rows.iter().filter_map(|r| Some((r.setting.split(' ').next()?.parse::<f64>().ok()?, r.seconds))).collect();
            if let (Some(e), Some(t)) = (log_slope(&pts), log_slope(&times)) {
                let _ = write!(
                    s,
                    " RMSE falls as spp^{e:.2} (an unbiased estimator's ideal is spp^−0.5) while time grows as spp^{t:.2}, so MSE × time stays within a factor {:.1} across the sweep: more samples buy accuracy at a fixed exchange rate, and the choice is only how much error the picture can show.",
                    rows.iter().map(Row::inefficiency).fold(0.0, f64::max) / rows.iter().map(Row::inefficiency).fold(f64::INFINITY, f64::min)
                );
            }
        }
        "depth" => {
            let lowest = rows.iter().min_by(|a, b| a.errors.rmse.total_cmp(&b.errors.rmse));
            if let (Some(lowest), Some(deepest)) = (lowest, rows.last())
                && deepest.errors.rmse > 1.1 * lowest.errors.rmse
            {
                let _ = write!(
                    s,
                    " The error is lowest at **{}** and grows beyond it (RMSE {:.4} at {}): at this sample count the long paths (light focused through glass, found only by chance) add more noise than the light they recover, so a shorter path's bias costs less than a longer one's variance until the sample count rises.",
                    lowest.setting, deepest.errors.rmse, deepest.setting
                );
            } else if let Some(deepest) = rows.last() {
                let enough = rows.iter().find(|r| r.errors.rmse <= deepest.errors.rmse * 1.1);
                if let Some(enough) = enough {
                    let _ = write!(
                        s,
                        " From **{}** on the error is within 10 % of the deepest setting's (the rest is sample noise); shallower paths lose light (RMSE {:.4} at {}), deeper ones cost {:.0} % more time for nothing visible.",
                        enough.setting,
                        rows[0].errors.rmse,
                        rows[0].setting,
                        (deepest.seconds / enough.seconds - 1.0) * 100.0
                    );
                }
            }
        }
        "light-samples" => {
            if let (Some(one), Some(most)) = (rows.first(), rows.last()) {
                let _ = write!(
                    s,
                    " {} cut RMSE by {:.0} % against {} at {:.2}× the time; the ratio of MSE × time, {:.2}, says whether extra shadow rays are cheaper than extra camera samples (below 1: they are).",
                    most.setting,
                    (1.0 - most.errors.rmse / one.errors.rmse) * 100.0,
                    one.setting,
                    most.seconds / one.seconds,
                    most.inefficiency() / one.inefficiency()
                );
            }
        }
        "roulette" => {
            if let [on, off] = &rows[..] {
                let _ = write!(
                    s,
                    " Roulette on takes {:.0} % of the time of roulette off, for {:.2}× its MSE: MSE × time {:.2}× (below 1: roulette pays).",
                    on.seconds / off.seconds * 100.0,
                    on.errors.mse() / off.errors.mse(),
                    on.inefficiency() / off.inefficiency()
                );
            }
        }
        "integrator" => {
            if let Some(fastest) = rows.iter().min_by(|a, b| a.seconds.total_cmp(&b.seconds)) {
                let _ = write!(
                    s,
                    " The fastest, **{}** ({}), has RMSE {:.4}. Only the path tracer converges to the reference: the others leave out light (indirect light, area-light and glossy effects) and their error does not fall with more samples, so for them MSE × time measures speed more than quality.",
                    fastest.setting,
                    time(fastest.seconds),
                    fastest.errors.rmse
                );
            }
        }
        _ => {}
    }
    s
}

fn bvh_reading(rows: &[BvhRow]) -> String {
    let (Some(sah), Some(fast)) = (rows.iter().find(|r| r.quality == "sah"), rows.iter().find(|r| r.quality == "fast")) else {
        return String::new();
    };
    let per_ray = |r: &BvhRow| r.trace_seconds / r.rays.max(1) as f64;
    let mut s = format!(
        "The SAH build takes {:.2}× the fast build's time and traces {:.2}× as fast; both return the same closest hit for every ray ({} differ).",
        sah.build_seconds / fast.build_seconds.max(1e-12),
        fast.trace_seconds / sah.trace_seconds.max(1e-12),
        fast.mismatches
    );
    let saved = per_ray(fast) - per_ray(sah);
    let extra = sah.build_seconds - fast.build_seconds;
    if saved > 0.0 && extra > 0.0 {
        let _ = write!(
            s,
            " SAH pays for its longer build after {:.2e} rays ({:.1} frames of these {} rays): **{}** is the better trade here.",
            extra / saved,
            extra / saved / sah.rays as f64,
            sah.rays,
            if sah.total_seconds() <= fast.total_seconds() { "sah" } else { "fast" }
        );
    } else {
        let better = if sah.total_seconds() <= fast.total_seconds() { "sah" } else { "fast" };
        let _ = write!(s, " On this scene **{better}** has the lower build-plus-trace time.");
    }
    s
}

/// The whole report as markdown.
pub fn markdown(report: &Report) -> String {
    let mut out = String::new();
    let o = &report.options;
    let _ = writeln!(out, "# Accuracy report: {}\n", report.scene);
    let _ = writeln!(
        out,
        "Scene: {} ({} triangles). {}×{} pixels, {} threads. Reference: path tracer, {} spp, depth {}, Russian roulette on, its own seed ({}). \
         Errors are over every pixel and channel of the linear radiance against the reference, whose own noise (about 1/{} of the {}-spp image's MSE) is included. \
         Times are wall-clock times of one render each, after the reference has built every BVH.\n",
        report.description,
        report.triangles,
        report.width,
        report.height,
        report.threads,
        o.reference_spp,
        o.max_depth,
        time(report.reference_seconds),
        o.reference_spp / o.spp.last().copied().unwrap_or(1).max(1),
        o.spp.last().copied().unwrap_or(1)
    );
    out.push_str("![error against time](error_vs_time.png)\n\n");
    out.push_str(
        "`error_vs_time.png`: RMSE against wall time on log-log axes, one line per knob in sweep order \
         (blue: samples per pixel; red: path depth; green: shadow rays per light; magenta crosses: Russian roulette on and off; \
         black crosses: the integrators). Lower left is better; each knob also has its own plot, `<knob>.png`. \
         `strip.png` shows, left to right: ",
    );
    out.push_str(&report.images.iter().map(|(what, _)| what.as_str()).collect::<Vec<_>>().join("; "));
    out.push_str(".\n\n![images](strip.png)\n\n");

    out.push_str("## Summary\n\n| knob | best trade (lowest MSE × time) | its RMSE | its time | most accurate |\n|---|---|---:|---:|---|\n");
    for knob in &report.knobs {
        if let (Some(best), Some(acc)) = (knob.best_trade(), knob.most_accurate()) {
            let _ = writeln!(out, "| {} | {} | {:.4} | {} | {} |", knob.name, best.setting, best.errors.rmse, time(best.seconds), acc.setting);
        }
    }
    if let Some(winner) = report.bvh.iter().min_by(|a, b| a.total_seconds().total_cmp(&b.total_seconds())) {
        let _ = writeln!(out, "| BVH builder | {} (build + trace {}) | same hits | | |", winner.quality, time(winner.total_seconds()));
    }
    out.push('\n');

    for knob in &report.knobs {
        let _ = writeln!(out, "## {}\n\nFixed: {}.\n", knob.name, knob.fixed);
        table(&mut out, &knob.rows);
        let _ = writeln!(out, "{}\n", reading(knob));
    }

    let _ = writeln!(
        out,
        "## BVH build quality\n\nThe scene's {} triangles baked into one mesh, built by each builder (best of three) and traced with the same {} rays \
         ({} jittered camera rays per pixel and one diffuse bounce from each hit), closest hit, all threads.\n",
        report.triangles,
        report.bvh.first().map_or(0, |r| r.rays),
        o.bvh_rays_per_pixel
    );
    out.push_str("| builder | build | trace | Mrays/s | build + trace | nodes + leaves | hits differing |\n|---|---:|---:|---:|---:|---:|---:|\n");
    for r in &report.bvh {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.2} | {} | {} | {} |",
            r.quality,
            time(r.build_seconds),
            time(r.trace_seconds),
            r.rays as f64 / r.trace_seconds.max(1e-9) * 1e-6,
            time(r.total_seconds()),
            r.nodes,
            r.mismatches
        );
    }
    let _ = writeln!(out, "\n{}", bvh_reading(&report.bvh));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slopes_of_power_laws() {
        let pts: Vec<(f64, f64)> = [1.0f64, 2.0, 4.0, 8.0].iter().map(|&x| (x, 3.0 / x.sqrt())).collect();
        assert!((log_slope(&pts).unwrap() + 0.5).abs() < 1e-12);
        assert_eq!(log_slope(&pts[..1]), None);
    }
}
