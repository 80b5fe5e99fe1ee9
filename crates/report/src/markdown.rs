//! `report.md`: a table per knob and readings computed from its numbers, never fixed sentences:
//! fits with their point count and R², levels that converge or do not, a best trade only where
//! the difference exceeds the spread of the measurements.

use std::fmt::Write;

use crate::metrics::BLOCK;
use crate::reference::ReferenceSource;
use crate::run::{BvhRow, Knob, Report, Row};
use crate::timing::Spread;

/// Formats seconds with a sensible unit.
fn time(seconds: f64) -> String {
    if seconds >= 1.0 {
        format!("{seconds:.2} s")
    } else if seconds >= 1e-3 {
        format!("{:.1} ms", seconds * 1e3)
    } else {
        format!("{:.0} µs", seconds * 1e6)
    }
}

/// A time's median ± half its range.
fn time_spread(s: &Spread) -> String {
    format!("{} ± {}", time(s.median()), time(s.half_range()))
}

/// A fraction as a percentage.
fn percent(x: f64) -> String {
    if x.abs() >= 0.1 { format!("{:.0} %", x * 100.0) } else { format!("{:.1} %", x * 100.0) }
}

/// A least-squares line through `(ln x, ln y)`: y ∝ x^slope.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Fit {
    pub slope: f64,
    pub intercept: f64,
    pub r2: f64,
    pub points: usize,
}

impl Fit {
    /// Fits the points with positive coordinates; `None` with fewer than two or no spread in x.
    pub(crate) fn log_log(points: &[(f64, f64)]) -> Option<Fit> {
        let pts: Vec<(f64, f64)> = points.iter().filter(|p| p.0 > 0.0 && p.1 > 0.0).map(|p| (p.0.ln(), p.1.ln())).collect();
        if pts.len() < 2 {
            return None;
        }
        let n = pts.len() as f64;
        let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
        let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
        let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let syy: f64 = pts.iter().map(|p| (p.1 - my).powi(2)).sum();
        if sxx <= 0.0 {
            return None;
        }
        let slope = sxy / sxx;
        let r2 = if syy > 0.0 { (sxy * sxy / (sxx * syy)).min(1.0) } else { 1.0 };
        Some(Fit { slope, intercept: my - slope * mx, r2, points: pts.len() })
    }

    /// The x at which the line reaches `y`.
    fn solve(&self, y: f64) -> Option<f64> {
        (self.slope != 0.0).then(|| ((y.ln() - self.intercept) / self.slope).exp())
    }
}

/// What the measurements of one knob allow us to say about the trade.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Verdict {
    /// A quick run: timings too short to rank.
    NotRanked,
    /// Neither the error nor the time tells the settings apart.
    NoEffect,
    /// The images are equally accurate and this setting is faster beyond the spread.
    Faster(usize),
    /// No setting reaches the target error: bias alone exceeds it.
    Unreachable,
    /// One setting reaches the target soonest, beyond the spread of the others.
    Best(usize),
    /// These settings reach the target in times whose spreads overlap.
    Tie(Vec<usize>),
}

/// Whether the rows' images agree within the spread of their errors (times aside).
fn same_error(rows: &[Row]) -> bool {
    rows.iter().all(|a| rows.iter().all(|b| a.error().overlaps(&b.error()) && a.level().overlaps(&b.level())))
}

pub(crate) fn verdict(knob: &Knob, target: f64, quick: bool) -> Verdict {
    if quick {
        return Verdict::NotRanked;
    }
    // A knob that does not change the image is a matter of time alone, never a trade.
    if knob.rows.len() > 1 && same_error(&knob.rows) {
        let rows = &knob.rows;
        let fastest = (0..rows.len()).min_by(|&a, &b| rows[a].wall.median().total_cmp(&rows[b].wall.median())).expect("rows");
        let apart = rows.iter().enumerate().all(|(i, r)| i == fastest || rows[fastest].wall.max() < r.wall.min());
        return if apart { Verdict::Faster(fastest) } else { Verdict::NoEffect };
    }
    let mut reachable: Vec<(usize, Spread)> = knob.rows.iter().enumerate().filter_map(|(i, r)| Some((i, r.time_to(target)?))).collect();
    if reachable.is_empty() {
        return Verdict::Unreachable;
    }
    reachable.sort_by(|a, b| a.1.median().total_cmp(&b.1.median()));
    let (best, best_time) = &reachable[0];
    let mut tied: Vec<usize> = reachable[1..].iter().filter(|(_, t)| t.min() <= best_time.max()).map(|(i, _)| *i).collect();
    if tied.is_empty() {
        return Verdict::Best(*best);
    }
    tied.insert(0, *best);
    Verdict::Tie(tied)
}

/// The verdict in a phrase, for the summary and the readings.
fn verdict_phrase(knob: &Knob, verdict: &Verdict, target: f64) -> String {
    let name = |i: usize| knob.rows[i].setting.clone();
    let t = percent(target);
    match verdict {
        Verdict::NotRanked => "not ranked: a quick run's timings are too short to rank settings".into(),
        Verdict::NoEffect => "no effect: every setting's error, brightness and time agree within their spread".into(),
        Verdict::Faster(i) => format!(
            "no effect on the image (every setting's error and brightness agree within their spread); **{}** is the fastest, beyond the spread ({})",
            name(*i),
            time_spread(&knob.rows[*i].wall)
        ),
        Verdict::Unreachable => format!("no setting reaches {t}: the bias alone exceeds it"),
        Verdict::Best(i) => {
            let ttt = knob.rows[*i].time_to(target).expect("a best trade reaches the target");
            format!("best trade **{}**: it reaches {t} in {} (the others need longer, beyond the spread)", name(*i), time_spread(&ttt))
        }
        Verdict::Tie(rows) => {
            format!("tie between {}: their times to reach {t} overlap within the spread", rows.iter().map(|&i| format!("**{}**", name(i))).collect::<Vec<_>>().join(", "))
        }
    }
}

fn table(out: &mut String, rows: &[Row], target: f64) {
    let _ = writeln!(
        out,
        "| setting | wall time | CPU time | rays | rel. error ({BLOCK}×{BLOCK}) | per pixel | bias | noise | mean R / G / B | time to {} |",
        percent(target)
    );
    out.push_str("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for r in rows {
        let e = r.error();
        let pixel = Spread { samples: r.errors.iter().map(|e| e.relative_pixels).collect() };
        let ratios: Vec<String> = (0..3).map(|c| format!("{:.3}", r.mean_ratio(c).median())).collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {:.4} ± {:.4} | {:.4} | {:.4} | {:.4} | {} ± {:.3} | {} |",
            r.setting,
            time_spread(&r.wall),
            time_spread(&r.cpu),
            r.rays,
            e.median(),
            e.half_range(),
            pixel.median(),
            r.split.bias,
            r.split.noise,
            ratios.join(" / "),
            r.level().half_range(),
            r.time_to(target).map_or("not reachable".to_string(), |t| time_spread(&t)),
        );
    }
    out.push('\n');
}

/// The fit of the main error against a numeric knob value.
fn error_fit(rows: &[Row]) -> Option<Fit> {
    Fit::log_log(&rows.iter().filter_map(|r| Some((r.value?, r.error().median()))).collect::<Vec<_>>())
}

/// How the image's brightness settles along an ordered sweep (depths): from which setting on
/// the level stays within the larger of 0.1 % and twice its own spread of the last setting's.
fn convergence(rows: &[Row], unit: &str) -> String {
    let Some(last) = rows.last() else { return String::new() };
    let level = |r: &Row| r.level().median();
    let tolerance = rows.iter().map(|r| 2.0 * r.level().half_range()).fold(0.001, f64::max);
    let settled = (0..rows.len()).find(|&i| rows[i..].iter().all(|r| (level(r) / level(last) - 1.0).abs() <= tolerance));
    let mut s = format!(
        "{} keeps {} of the light of {}.",
        rows[0].setting,
        percent(level(&rows[0]) / level(last).max(1e-30)),
        last.setting
    );
    match settled {
        Some(i) if i + 1 < rows.len() => {
            let cost = if rows[i].wall.overlaps(&last.wall) {
                "no time the measurements can tell".to_string()
            } else {
                format!("{} more time", percent(last.wall.median() / rows[i].wall.median().max(1e-12) - 1.0))
            };
            let _ = write!(
                s,
                " Beyond **{}** the image's mean changes by less than {} (the measurements' resolution): light past {} {unit} is negligible in this scene, and the deeper settings cost {cost} for it.",
                rows[i].setting,
                percent(tolerance),
                rows[i].value.map_or_else(|| rows[i].setting.clone(), |v| format!("{v}")),
            );
        }
        _ => {
            let prev = &rows[rows.len().saturating_sub(2)];
            let _ = write!(
                s,
                " The mean still changes by {} between {} and {}: light travels further than the sweep reaches; a higher maximum would be brighter.",
                percent(level(last) / level(prev).max(1e-30) - 1.0),
                prev.setting,
                last.setting
            );
        }
    }
    s
}

/// Whether a row's bias is within what its estimate can resolve (or below 0.5 %).
fn unbiased(row: &Row) -> bool {
    row.resolved_bias() <= 0.005
}

/// What the numbers of one knob say.
fn reading(knob: &Knob) -> String {
    let rows = &knob.rows;
    let mut s = String::new();
    match knob.id {
        "spp" | "distribution-spp" => {
            if let Some(fit) = error_fit(rows) {
                let _ = write!(s, "Error ∝ spp^{:.2} (fit over {} points, R² {:.2}; an unbiased estimator's is spp^−0.5).", fit.slope, fit.points, fit.r2);
            }
            if let Some(last) = rows.last() {
                let _ = write!(
                    s,
                    " At {} the error is {} bias and {} noise ({} of its square is bias).",
                    last.setting,
                    percent(last.split.bias),
                    percent(last.split.noise),
                    percent(last.split.bias_share())
                );
                let times = Fit::log_log(&rows.iter().map(|r| (r.wall.median(), r.error().median())).collect::<Vec<_>>());
                if let Some(fit) = times.filter(|f| f.slope < 0.0) {
                    let longest = rows.iter().map(|r| r.wall.median()).fold(0.0, f64::max);
                    let costs: Vec<String> = [0.1, 0.05, 0.02, 0.01]
                        .into_iter()
                        .map(|t| {
                            if last.resolved_bias() >= 0.9 * t {
                                format!("{} is out of reach (bias floor {})", percent(t), percent(last.resolved_bias()))
                            } else {
                                let seconds = fit.solve(t).unwrap_or(f64::INFINITY);
                                format!("{} costs {}{}", percent(t), time(seconds), if seconds > 1.5 * longest { " (extrapolated)" } else { "" })
                            }
                        })
                        .collect();
                    let _ = write!(s, " On the fit of error against wall time (R² {:.2}): {}.", fit.r2, costs.join("; "));
                }
            }
        }
        "adaptive" => {
            if let Some(off) = rows.iter().find(|r| r.value.is_none()) {
                for r in rows.iter().filter(|r| r.value.is_some()) {
                    if r.rays >= off.rays {
                        let _ = write!(s, "{}: no tile met the threshold, every pixel took every sample. ", r.setting);
                        continue;
                    }
                    let _ = write!(
                        s,
                        "{}: {:.0} % of the rays, {:.2}× the time of {} for {:.2}× its error. ",
                        r.setting,
                        r.rays as f64 / off.rays.max(1) as f64 * 100.0,
                        r.wall.median() / off.wall.median().max(1e-12),
                        off.setting,
                        r.error().median() / off.error().median().max(1e-30)
                    );
                }
            }
        }
        "depth" | "whitted-depth" => s = convergence(rows, if knob.id == "depth" { "bounces" } else { "recursion levels" }),
        "light-samples" => {
            if let (Some(one), Some(most)) = (rows.first(), rows.last()) {
                let ratio = (most.split.noise / one.split.noise.max(1e-30)).powi(2) * most.wall.median() / one.wall.median().max(1e-12);
                let _ = write!(
                    s,
                    "{}: noise {:.2}× that of {} at {:.2}× the time, so noise² × time is {ratio:.2}×: {}.",
                    most.setting,
                    most.split.noise / one.split.noise.max(1e-30),
                    one.setting,
                    most.wall.median() / one.wall.median().max(1e-12),
                    if ratio < 1.0 { "in this scene extra shadow rays remove noise more cheaply than extra camera samples" } else { "in this scene extra camera samples remove noise more cheaply than extra shadow rays" }
                );
            }
        }
        "roulette" => {
            if let [on, off] = &rows[..] {
                let _ = write!(
                    s,
                    "Roulette on: {:.2}× the time of roulette off, noise {:.2}×, bias {} against {} ({}).",
                    on.wall.median() / off.wall.median().max(1e-12),
                    on.split.noise / off.split.noise.max(1e-30),
                    percent(on.split.bias),
                    percent(off.split.bias),
                    if unbiased(on) == unbiased(off) { "the same within the estimate" } else { "they differ" }
                );
            }
        }
        "integrator" => {
            let describe = |r: &Row| {
                format!("{}: mean {:.3}× the reference, bias {} ({} of its error²)", r.setting, r.level().median(), percent(r.split.bias), percent(r.split.bias_share()))
            };
            let _ = write!(s, "{}.", rows.iter().map(describe).collect::<Vec<_>>().join("; "));
            let (close, far): (Vec<&Row>, Vec<&Row>) = rows.iter().partition(|r| unbiased(r));
            let names = |rs: &[&Row]| rs.iter().map(|r| r.setting.as_str()).collect::<Vec<_>>().join(", ");
            if !close.is_empty() {
                let _ = write!(s, " Within the estimate's resolution, {} agree{} with the reference.", names(&close), if close.len() == 1 { "s" } else { "" });
            }
            if !far.is_empty() {
                let _ = write!(s, " {} {} a bias that more samples will not remove.", names(&far), if far.len() == 1 { "has" } else { "have" });
            }
        }
        "kernel" => {
            let identical = rows.windows(2).all(|w| w[0].errors == w[1].errors);
            let _ = write!(
                s,
                "The two kernels' images are {}; the specialised one takes {:.2}× the general one's time.",
                if identical { "identical" } else if same_error(rows) { "equally accurate" } else { "different (a bug: they should be identical)" },
                rows[0].wall.median() / rows.get(1).map_or(1.0, |r| r.wall.median()).max(1e-12)
            );
        }
        _ => {}
    }
    s
}

/// SAH against the fast build, build plus trace, with the tie rule of the knobs.
fn bvh_reading(rows: &[BvhRow]) -> String {
    let (Some(sah), Some(fast)) = (rows.iter().find(|r| r.quality == "sah"), rows.iter().find(|r| r.quality == "fast")) else {
        return String::new();
    };
    let total = |r: &BvhRow| Spread { samples: r.build.samples.iter().zip(&r.trace.samples).map(|(b, t)| b + t).collect() };
    let (st, ft) = (total(sah), total(fast));
    let mut s = format!(
        "The SAH build takes {:.2}× the fast build's time and traces {:.2}× as fast; both return the same closest hit for every ray ({} differ).",
        sah.build.median() / fast.build.median().max(1e-12),
        fast.trace.median() / sah.trace.median().max(1e-12),
        fast.mismatches
    );
    if st.overlaps(&ft) {
        let _ = write!(s, " Build plus one trace of these {} rays: a tie ({} against {}).", sah.rays, time_spread(&st), time_spread(&ft));
    } else {
        let better = if st.median() < ft.median() { "sah" } else { "fast" };
        let _ = write!(s, " Build plus one trace of these {} rays: **{better}** is faster ({} against {}).", sah.rays, time_spread(&st), time_spread(&ft));
    }
    let saved = (fast.trace.median() - sah.trace.median()) / sah.rays.max(1) as f64;
    let extra = sah.build.median() - fast.build.median();
    if saved > 0.0 && extra > 0.0 {
        let _ = write!(s, " SAH pays for its longer build after {:.2e} rays.", extra / saved);
    }
    s
}

/// The one-line verdict of each knob, for the command line's summary.
pub fn summary_lines(report: &Report) -> Vec<String> {
    report
        .knobs
        .iter()
        .map(|k| format!("{}: {}", k.name, verdict_phrase(k, &verdict(k, report.options.target, report.options.quick), report.options.target).replace("**", "")))
        .collect()
}

/// The report's title line: the scene and, as the issue of every reading, the reference.
pub fn title(report: &Report) -> String {
    format!("Accuracy report: {}, against {}", report.scene, report.options.reference.describe())
}

/// The whole report as markdown.
pub fn markdown(report: &Report) -> String {
    let mut out = String::new();
    let o = &report.options;
    let _ = writeln!(out, "# {}\n", title(report));
    let _ = writeln!(
        out,
        "Scene: {} ({} triangles; effects under the path tracer: {}). {}×{} pixels ({}), {} threads.",
        report.description,
        report.triangles,
        report.effects.names().join(", "),
        report.width,
        report.height,
        report.size_from,
        report.threads,
    );
    match &o.reference {
        ReferenceSource::Converged { spp } => {
            let _ = writeln!(
                out,
                "Reference: raystage's path tracer, {spp} spp, depth {}, its own seed ({}): errors against it show noise and the other settings' departures from raystage's own converged image, not raystage's biases. Bring an image from another renderer with `--reference` to see those.",
                o.max_depth,
                time(report.reference_seconds)
            );
            if let Some(noise) = report.reference_noise {
                let _ = writeln!(out, "Its own noise, {} (from the spp sweep), is taken off every bias below.", percent(noise));
            }
        }
        ReferenceSource::External(path) => {
            let _ = writeln!(out, "Reference: {} (rendered elsewhere): every bias of raystage against it shows in the mean ratios and the bias column.", path.display());
        }
    }
    let _ = writeln!(
        out,
        "\nError: relative RMSE, each difference over the reference value plus ε (10 % of its mean), on {BLOCK}×{BLOCK} pixel block means and per pixel, over the {} of pixels that see neither an emitter nor the background. \
         Every setting was rendered {} times with independent seeds, interleaved with the other settings; times are the median ± half the range, \
         bias and noise split each render's error (bias² + noise² = its expected error²), and *time to {}* is the wall time at which more samples would bring the error to the target {} (noise falls as 1/√time, bias stays).{}\n",
        percent(report.measured_share),
        o.repeats,
        percent(o.target),
        percent(o.target),
        if o.quick { " **Quick run: its timings are too short to rank settings; no best trade is named.**" } else { "" }
    );
    out.push_str("![error against time](error_vs_time.png)\n\n");
    out.push_str(
        "`error_vs_time.png`: the relative error against wall time on log-log axes, medians with bars from the smallest to the largest measurement, one line per ordered knob \
         (blue: samples per pixel; red: path depth; green: shadow rays per light; orange: adaptive sampling; brown: Whitted depth; teal: distribution samples) and crosses for alternatives \
         (magenta: Russian roulette; black: the integrators; grey: the shading kernels). Lower left is better; each knob also has its own plot, `<knob>.png`. \
         `strip.png` shows, left to right: ",
    );
    out.push_str(&report.images.iter().map(|(what, _)| what.as_str()).collect::<Vec<_>>().join("; "));
    out.push_str(".\n\n![images](strip.png)\n\n");

    out.push_str("## Summary\n\n| knob | verdict |\n|---|---|\n");
    for knob in &report.knobs {
        let _ = writeln!(out, "| {} | {} |", knob.name, verdict_phrase(knob, &verdict(knob, o.target, o.quick), o.target));
    }
    for left in &report.left_out {
        let _ = writeln!(out, "| {} | left out: {} |", left.name, left.why);
    }
    out.push('\n');

    for knob in &report.knobs {
        let _ = writeln!(out, "## {}\n\nFixed: {}.\n", knob.name, knob.fixed);
        table(&mut out, &knob.rows, o.target);
        let _ = writeln!(out, "{} Verdict: {}.\n", reading(knob), verdict_phrase(knob, &verdict(knob, o.target, o.quick), o.target));
    }
    if !report.left_out.is_empty() {
        out.push_str("## Left out\n\n");
        for left in &report.left_out {
            let _ = writeln!(out, "- {}: {}.", left.name, left.why);
        }
        out.push('\n');
    }

    let _ = writeln!(
        out,
        "## BVH build quality\n\nThe scene's {} triangles baked into one mesh, built by each builder and traced with the same {} rays \
         ({} jittered camera rays per pixel and one diffuse bounce from each hit), closest hit, all threads; {} times each, interleaved.\n",
        report.triangles,
        report.bvh.first().map_or(0, |r| r.rays),
        o.bvh_rays_per_pixel,
        o.repeats
    );
    out.push_str("| builder | build | trace | Mrays/s | nodes + leaves | hits differing |\n|---|---:|---:|---:|---:|---:|\n");
    for r in &report.bvh {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.2} | {} | {} |",
            r.quality,
            time_spread(&r.build),
            time_spread(&r.trace),
            r.rays as f64 / r.trace.median().max(1e-9) * 1e-6,
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
    use crate::metrics::{Errors, Split};

    #[test]
    fn fits_of_power_laws() {
        let pts: Vec<(f64, f64)> = [1.0f64, 2.0, 4.0, 8.0].iter().map(|&x| (x, 3.0 / x.sqrt())).collect();
        let fit = Fit::log_log(&pts).unwrap();
        assert!((fit.slope + 0.5).abs() < 1e-12 && (fit.r2 - 1.0).abs() < 1e-12 && fit.points == 4);
        assert!((fit.solve(3.0 / 4.0).unwrap() - 16.0).abs() < 1e-9);
        assert_eq!(Fit::log_log(&pts[..1]), None);
    }

    fn row(setting: &str, walls: [f64; 3], error: f64, bias: f64) -> Row {
        let errors = Errors { relative_blocks: error, relative_pixels: error, rmse: error, mean_ratio: [1.0; 3] };
        Row {
            setting: setting.into(),
            value: None,
            wall: Spread { samples: walls.to_vec() },
            cpu: Spread { samples: walls.to_vec() },
            rays: 1,
            errors: vec![errors; 3],
            split: Split { bias, noise: (error * error - bias * bias).max(0.0).sqrt() },
        }
    }

    fn knob(rows: Vec<Row>) -> Knob {
        Knob { id: "light-samples", name: "Shadow rays per area light", fixed: String::new(), rows }
    }

    #[test]
    fn settings_that_change_nothing_are_no_effect_never_a_best_trade() {
        let k = knob(vec![row("1 per light", [1.0, 1.2, 1.1], 0.2, 0.0), row("2 per light", [1.1, 1.3, 1.0], 0.2, 0.0)]);
        assert_eq!(verdict(&k, 0.05, false), Verdict::NoEffect);
        assert!(!verdict_phrase(&k, &Verdict::NoEffect, 0.05).contains("best"));
        // The same images, one setting clearly faster: faster, still not a trade.
        let k = knob(vec![row("1 per light", [1.0, 1.2, 1.1], 0.2, 0.0), row("2 per light", [2.1, 2.3, 2.0], 0.2, 0.0)]);
        assert_eq!(verdict(&k, 0.05, false), Verdict::Faster(0));
        assert!(!verdict_phrase(&k, &Verdict::Faster(0), 0.05).contains("best"));
    }

    #[test]
    fn a_best_trade_needs_a_gap_beyond_the_spread() {
        // Same noise, times apart: the faster one reaches the target sooner, clearly.
        let apart = knob(vec![row("1 per light", [1.0, 1.1, 1.05], 0.2, 0.0), row("2 per light", [2.0, 2.1, 2.2], 0.1, 0.0)]);
        // 2 per light: a quarter of the noise² at twice the time reaches the target sooner.
        assert_eq!(verdict(&apart, 0.05, false), Verdict::Best(1));
        // Times overlapping and noise² × time equal: a tie.
        let close = knob(vec![row("1 per light", [1.0, 1.6, 1.2], 0.2, 0.0), row("2 per light", [4.0, 4.8, 4.4], 0.1, 0.0)]);
        assert_eq!(verdict(&close, 0.05, false), Verdict::Tie(vec![1, 0]));
        // Quick runs rank nothing; a bias above the target reaches nothing.
        assert_eq!(verdict(&apart, 0.05, true), Verdict::NotRanked);
        let biased = knob(vec![row("1 per light", [1.0, 1.1, 1.05], 0.11, 0.1), row("2 per light", [2.0, 2.1, 2.2], 0.105, 0.1)]);
        assert_eq!(verdict(&biased, 0.05, false), Verdict::Unreachable);
    }
}
