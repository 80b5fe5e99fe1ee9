//! Plots of benchmark results, drawn with `plotters` into an RGB buffer and written as PNG.
//!
//! Text needs a font: plotters is built without system-font discovery (which would need
//! fontconfig), so [`register_system_font`] loads the first of a few common TrueType files.
//! Without one, plots are drawn without any text and the caller says in words what they show.

use std::error::Error;
use std::path::Path;

use plotters::prelude::*;

use crate::render::{ConvergenceRun, TAIL_POINTS};

/// Plot size in pixels.
const SIZE: (u32, u32) = (800, 600);

/// Sans-serif TrueType fonts looked for, in order (Debian's and Arch's DejaVu, Liberation).
const FONT_FILES: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
];

/// Registers the first of the system's sans-serif fonts this module looks for (DejaVu, then
/// Liberation) as plotters' sans-serif; returns whether there was one (without, plots must be
/// drawn without text).
pub fn register_system_font() -> bool {
    FONT_FILES.into_iter().any(|path| {
        let Ok(bytes) = std::fs::read(path) else { return false };
        // plotters keeps registered fonts for the life of the process.
        plotters::style::register_font("sans-serif", FontStyle::Normal, Vec::leak(bytes)).is_ok()
    })
}

/// Draws the path tracer's convergence on log-log axes, RMSE against samples per pixel: the
/// measured points joined by a solid blue line, and a dashed red line for the ideal 1/√spp through
/// the first point. With `text`, also a title (with the fitted slopes), axis labels and a legend.
/// Writes the plot to `path` as PNG.
pub fn convergence(path: &Path, run: &ConvergenceRun, text: bool) -> Result<(), Box<dyn Error>> {
    let points = &run.points;
    let first = points.first().ok_or("no convergence points to plot")?;
    let measured: Vec<(f64, f64)> = points.iter().map(|p| (p.spp as f64, p.rmse)).collect();
    let ideal: Vec<(f64, f64)> = points.iter().map(|p| (p.spp as f64, first.rmse / (p.spp as f64).sqrt())).collect();
    let ys = || measured.iter().chain(&ideal).map(|p| p.1);
    let (lo, hi) = (ys().fold(f64::INFINITY, f64::min), ys().fold(0.0, f64::max));
    let max_spp = measured.last().map_or(2.0, |p| p.0.max(2.0));
    let mut buffer = vec![0u8; SIZE.0 as usize * SIZE.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, SIZE).into_drawing_area();
        root.fill(&WHITE)?;
        let mut builder = ChartBuilder::on(&root);
        builder.margin(20);
        if text {
            builder
                .caption(
                    format!("Path tracer, Cornell room: RMSE vs spp (slope {:.2}, last {TAIL_POINTS} points {:.2})", run.slope, run.tail_slope),
                    ("sans-serif", 20),
                )
                .x_label_area_size(45)
                .y_label_area_size(70);
        }
        let (lo, hi) = (lo / 1.5, hi * 1.5);
        let mut chart = builder.build_cartesian_2d((1.0..max_spp).log_scale().base(2.0), (lo..hi).log_scale().with_key_points(ticks_125(lo, hi)))?;
        // Without label areas (no text), the grid is drawn but no label is.
        chart
            .configure_mesh()
            .x_desc("samples per pixel")
            .y_desc("RMSE against the reference (linear RGB)")
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_label_formatter(&|&y| format!("{y:.*}", (-y.log10().floor()).max(0.0) as usize))
            .draw()?;
        let blue = BLUE.stroke_width(2);
        chart
            .draw_series(LineSeries::new(measured.iter().copied(), blue))?
            .label("measured")
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], blue));
        chart.draw_series(measured.iter().map(|&p| Circle::new(p, 4, BLUE.filled())))?;
        let red = RED.stroke_width(2);
        chart
            .draw_series(DashedLineSeries::new(ideal.iter().copied(), 8, 6, red))?
            .label("ideal 1/sqrt(spp) from 1 spp")
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], red));
        if text {
            chart.configure_series_labels().position(SeriesLabelPosition::UpperRight).border_style(BLACK).background_style(WHITE).draw()?;
        }
        root.present()?;
    }
    image::save_buffer(path, &buffer, SIZE.0, SIZE.1, image::ExtendedColorType::Rgb8)?;
    Ok(())
}

/// The numbers 1, 2 and 5 times a power of ten in `[lo, hi]`: round ticks for a log axis.
fn ticks_125(lo: f64, hi: f64) -> Vec<f64> {
    let decades = lo.log10().floor() as i32..=hi.log10().ceil() as i32;
    decades.flat_map(|e| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(e))).filter(|v| (lo..=hi).contains(v)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::ConvergencePoint;

    #[test]
    fn log_ticks_are_one_two_five_per_decade() {
        assert_eq!(ticks_125(0.015, 0.6), vec![0.02, 0.05, 0.1, 0.2, 0.5]);
    }

    #[test]
    fn a_plot_without_text_needs_no_font() {
        let points = [1u32, 2, 4, 8].map(|spp| ConvergencePoint { spp, rmse: 0.2 / (spp as f64).sqrt(), seconds: spp as f64 }).to_vec();
        let run = ConvergenceRun { threads: 1, reference_spp: 64, reference_seconds: 1.0, points, slope: -0.5, tail_slope: -0.5 };
        let path = std::env::temp_dir().join(format!("raystage-bench-plot-{}.png", std::process::id()));
        convergence(&path, &run, false).unwrap();
        let decoded = image::open(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!((decoded.width(), decoded.height()), SIZE);
    }
}
