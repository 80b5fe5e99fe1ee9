//! Log-log plots of error against time, drawn with plotters into an RGB buffer and written as
//! PNG.
//!
//! Text needs a font, and plotters is built without system-font discovery (which would need
//! fontconfig): [`register_font`] loads a TrueType file if one of a few common ones exists.
//! Without one the plots are drawn without any text, and `report.md` says what they show, so a
//! report (and its test) never depends on the machine's fonts.

use std::path::Path;
use std::sync::OnceLock;

use plotters::prelude::*;

use crate::Error;
use crate::run::Knob;

/// Plot size in pixels.
const SIZE: (u32, u32) = (720, 540);

/// Sans-serif TrueType fonts looked for, in order (Debian's and Arch's DejaVu, Liberation).
const FONT_FILES: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
];

static FONT: OnceLock<Option<&'static str>> = OnceLock::new();

/// Registers the first font of a few common TrueType files that exists as plotters'
/// sans-serif, once per process; returns its path, or `None` if there is none (plots are then
/// drawn without text).
pub fn register_font() -> Option<&'static str> {
    *FONT.get_or_init(|| {
        FONT_FILES.into_iter().find(|path| {
            let Ok(bytes) = std::fs::read(path) else { return false };
            // plotters keeps registered fonts for the life of the process.
            plotters::style::register_font("sans-serif", FontStyle::Normal, Vec::leak(bytes)).is_ok()
        })
    })
}

/// Whether plots carry text: a font was registered by [`register_font`].
fn has_text() -> bool {
    FONT.get().copied().flatten().is_some()
}

/// The colour of a knob's line (report.md names them).
fn colour(id: &str) -> RGBColor {
    match id {
        "spp" => RGBColor(31, 90, 200),
        "depth" => RGBColor(210, 40, 40),
        "light-samples" => RGBColor(30, 150, 60),
        "roulette" => RGBColor(190, 40, 190),
        "adaptive" => RGBColor(240, 140, 20),
        "whitted-depth" => RGBColor(140, 90, 40),
        "distribution-spp" => RGBColor(20, 150, 150),
        "kernel" => RGBColor(140, 140, 140),
        _ => RGBColor(20, 20, 20),
    }
}

/// Draws the relative error against wall time on log-log axes for `knobs`: per setting the
/// medians, with bars from the smallest to the largest measurement of each, joined by a line
/// for an ordered sweep; and writes it to `path` as PNG. With a font (see [`register_font`]),
/// also the title, axis labels, a legend and each point's setting.
pub fn error_plot(path: &Path, knobs: &[&Knob], title: &str) -> Result<(), Error> {
    let fail = |message: String| Error::Draw { path: path.to_owned(), message };
    let rows = || knobs.iter().flat_map(|k| k.rows.iter()).filter(|r| r.wall.min() > 0.0 && r.error().min() > 0.0);
    let (t0, t1) = rows().fold((f64::INFINITY, 0.0f64), |(lo, hi), r| (lo.min(r.wall.min()), hi.max(r.wall.max())));
    let (e0, e1) = rows().fold((f64::INFINITY, 0.0f64), |(lo, hi), r| (lo.min(r.error().min()), hi.max(r.error().max())));
    if !(t0.is_finite() && e0.is_finite()) {
        return Err(fail("no points to plot".into()));
    }
    // Pad the ranges so that points sit inside the frame, and keep them non-empty.
    let (t0, t1) = (t0 / 1.6, (t1 * 1.6).max(t0 * 4.0));
    let (e0, e1) = (e0 / 1.6, (e1 * 1.6).max(e0 * 4.0));
    let text = has_text();
    let mut buffer = vec![0u8; SIZE.0 as usize * SIZE.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(e.to_string()))?;
        let mut builder = ChartBuilder::on(&root);
        builder.margin(16);
        if text {
            builder.caption(title, ("sans-serif", 20)).x_label_area_size(45).y_label_area_size(70);
        }
        let mut chart = builder.build_cartesian_2d((t0..t1).log_scale(), (e0..e1).log_scale()).map_err(|e| fail(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("wall time (s)")
            .y_desc("relative error (4x4 blocks)")
            .x_labels(8)
            .y_labels(8)
            .x_label_formatter(&|x| format!("{x:.1e}"))
            .y_label_formatter(&|y| format!("{y:.1e}"))
            .draw()
            .map_err(|e| fail(e.to_string()))?;
        for knob in knobs {
            let c = colour(knob.id);
            let shown: Vec<&crate::run::Row> = knob.rows.iter().filter(|r| r.wall.min() > 0.0 && r.error().min() > 0.0).collect();
            let medians: Vec<(f64, f64)> = shown.iter().map(|r| (r.wall.median(), r.error().median())).collect();
            let series = if knob.ordered() {
                chart.draw_series(LineSeries::new(medians.iter().copied(), c.stroke_width(2)))
            } else {
                chart.draw_series(medians.iter().map(|&p| Cross::new(p, 7, c.stroke_width(2))))
            }
            .map_err(|e| fail(e.to_string()))?;
            if text {
                series.label(knob.name).legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], c.stroke_width(2)));
            }
            // The spread of each setting: its time's range across, its error's range up and down.
            let bars = shown.iter().flat_map(|r| {
                let (t, e) = (r.wall.median(), r.error().median());
                [
                    PathElement::new([(r.wall.min(), e), (r.wall.max(), e)], c.stroke_width(1)),
                    PathElement::new([(t, r.error().min()), (t, r.error().max())], c.stroke_width(1)),
                ]
            });
            chart.draw_series(bars).map_err(|e| fail(e.to_string()))?;
            chart.draw_series(medians.iter().map(|&p| Circle::new(p, 4, c.filled()))).map_err(|e| fail(e.to_string()))?;
            if text && (knobs.len() == 1 || !knob.ordered()) {
                chart
                    .draw_series(shown.iter().map(|r| {
                        EmptyElement::at((r.wall.median(), r.error().median())) + Text::new(r.setting.clone(), (7, -16), ("sans-serif", 13).into_font())
                    }))
                    .map_err(|e| fail(e.to_string()))?;
            }
        }
        if text {
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .border_style(BLACK)
                .background_style(WHITE.mix(0.85))
                .draw()
                .map_err(|e| fail(e.to_string()))?;
        }
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    image::save_buffer(path, &buffer, SIZE.0, SIZE.1, image::ExtendedColorType::Rgb8).map_err(|e| fail(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::{Errors, Split};
    use crate::run::Row;
    use crate::timing::Spread;

    /// Without a registered font nothing draws text, so this needs no font on the machine.
    #[test]
    fn a_plot_without_text_needs_no_font() {
        assert!(!has_text(), "no test registers a font");
        let rows = [1u32, 2, 4, 8]
            .iter()
            .map(|&spp| {
                let e = 0.2 / (spp as f64).sqrt();
                let errors = Errors { relative_blocks: e, relative_pixels: e, rmse: e, mean_ratio: [1.0; 3] };
                Row {
                    setting: format!("{spp} spp"),
                    value: Some(spp as f64),
                    wall: Spread { samples: vec![spp as f64 * 0.1, spp as f64 * 0.12, spp as f64 * 0.11] },
                    cpu: Spread { samples: vec![spp as f64 * 0.2; 3] },
                    rays: 100,
                    errors: vec![errors; 3],
                    split: Split { bias: 0.0, noise: e },
                }
            })
            .collect();
        let knob = Knob { id: "spp", name: "Samples per pixel", fixed: String::new(), rows };
        let path = std::env::temp_dir().join(format!("raystage-report-plot-{}.png", std::process::id()));
        error_plot(&path, &[&knob], "test").unwrap();
        let decoded = image::open(&path).unwrap().to_rgb8();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(decoded.dimensions(), SIZE);
        assert!(decoded.pixels().any(|p| p.0 == [31, 90, 200]), "the knob's line is drawn");
    }
}
