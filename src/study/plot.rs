//! `study.png`: the work-precision diagram, error against wall time on
//! log-log axes, drawn with plotters.

use crate::render::FONT_BYTES;
use plotters::prelude::*;
use std::sync::Once;

/// One point of the diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotPoint {
    /// The series it belongs to (one colour and line per series).
    pub series: String,
    /// Its label: the run's values of the varied keys that are not the series'.
    pub label: String,
    /// Time the run took (wall or CPU, as the axis says), in milliseconds.
    pub time_ms: f64,
    /// Trajectory error (length units).
    pub error: f64,
}

/// Draws the diagram as RGB8 pixels (`width * height * 3` bytes). Points
/// with a non-positive or non-finite time or error cannot be placed on
/// log axes and are left out; with none left, the axes are still drawn.
pub fn work_precision_plot(
    points: &[PlotPoint],
    title: &str,
    (time_axis, error_axis): (&str, &str),
    (width, height): (u32, u32),
) -> Result<Vec<u8>, String> {
    register_font();
    let shown: Vec<&PlotPoint> = points
        .iter()
        .filter(|p| {
            p.time_ms > 0.0 && p.error > 0.0 && p.time_ms.is_finite() && p.error.is_finite()
        })
        .collect();
    let (x_range, y_range) = log_ranges(&shown);
    let mut pixels = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(72)
            .build_cartesian_2d(x_range.log_scale(), y_range.log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(time_axis)
            .y_desc(error_axis)
            .x_label_formatter(&|x| tick(*x))
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| e.to_string())?;

        let mut series_names: Vec<&str> = Vec::new();
        for p in &shown {
            if !series_names.contains(&p.series.as_str()) {
                series_names.push(&p.series);
            }
        }
        for (i, name) in series_names.iter().enumerate() {
            let [r, g, b] = SERIES_COLOURS[i % SERIES_COLOURS.len()];
            let colour = RGBColor(r, g, b).to_rgba();
            let mut members: Vec<&PlotPoint> = shown
                .iter()
                .copied()
                .filter(|p| p.series == *name)
                .collect();
            members.sort_by(|a, b| a.time_ms.total_cmp(&b.time_ms));
            let line: Vec<(f64, f64)> = members.iter().map(|p| (p.time_ms, p.error)).collect();
            chart
                .draw_series(LineSeries::new(line.clone(), colour.stroke_width(2)))
                .map_err(|e| e.to_string())?
                .label(*name)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
            chart
                .draw_series(line.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                .map_err(|e| e.to_string())?;
            chart
                .draw_series(members.iter().map(|p| {
                    EmptyElement::at((p.time_ms, p.error))
                        + Text::new(p.label.clone(), (6, -14), ("sans-serif", 12))
                }))
                .map_err(|e| e.to_string())?;
        }
        if !series_names.is_empty() {
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 14))
                .draw()
                .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(pixels)
}

/// Strong colours that read on white (Tableau 10), one per series, in order.
const SERIES_COLOURS: [[u8; 3]; 10] = [
    [31, 119, 180],
    [214, 39, 40],
    [44, 160, 44],
    [255, 127, 14],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

/// A tick label of a wall time: at most three significant digits, no exponent.
fn tick(x: f64) -> String {
    if x >= 100.0 {
        format!("{x:.0}")
    } else if x >= 1.0 {
        format!("{}", (x * 10.0).round() / 10.0)
    } else {
        format!("{}", (x * 1000.0).round() / 1000.0)
    }
}

/// Axis ranges a little wider than the points, in whole decades' reach
/// (one decade around 1 when there are no points).
fn log_ranges(points: &[&PlotPoint]) -> (std::ops::Range<f64>, std::ops::Range<f64>) {
    let bounds = |values: Vec<f64>| {
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if lo.is_finite() && hi.is_finite() {
            // 20% margin on log axes; a single value gets a decade around it.
            let (lo, hi) = if hi / lo < 1.5 {
                (lo / 3.0, hi * 3.0)
            } else {
                (lo, hi)
            };
            (lo / 1.6)..(hi * 1.6)
        } else {
            0.1..10.0
        }
    };
    (
        bounds(points.iter().map(|p| p.time_ms).collect()),
        bounds(points.iter().map(|p| p.error).collect()),
    )
}

/// Gives plotters the font elasto ships (plotters has no fonts of its own
/// without system font lookup).
fn register_font() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        // The shipped font is valid; a failure would only lose the labels.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT_BYTES);
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(series: &str, label: &str, time_ms: f64, error: f64) -> PlotPoint {
        PlotPoint {
            series: series.into(),
            label: label.into(),
            time_ms,
            error,
        }
    }

    #[test]
    fn the_plot_draws_coloured_series_and_labels() {
        let points = [
            point("newton / backward-euler", "substeps=5", 10.0, 1e-1),
            point("newton / backward-euler", "substeps=20", 40.0, 2.5e-2),
            point("newton / bdf2", "substeps=5", 11.0, 1e-2),
            point("newton / bdf2", "substeps=20", 45.0, 6e-4),
            point("newton / bdf2", "failed", f64::NAN, 1.0),
        ];
        let (w, h) = (640, 480);
        let pixels = work_precision_plot(
            &points,
            "study",
            ("wall time (ms)", "trajectory error"),
            (w, h),
        )
        .unwrap();
        assert_eq!(pixels.len(), (w * h * 3) as usize);
        let white = pixels.chunks(3).filter(|p| p == &[255, 255, 255]).count();
        let dark = pixels
            .chunks(3)
            .filter(|p| p.iter().all(|&c| c < 80))
            .count();
        let coloured = pixels
            .chunks(3)
            .filter(|p| p.iter().max().unwrap() - p.iter().min().unwrap() > 80)
            .count();
        let total = (w * h) as usize;
        // Mostly background, with axes and text in black and two series in colour.
        assert!(white > total / 2, "{white} of {total} white");
        assert!(dark > 500, "{dark} dark pixels: axes and text");
        assert!(coloured > 200, "{coloured} coloured pixels: the series");
    }

    #[test]
    fn no_points_still_draws_axes() {
        let pixels = work_precision_plot(&[], "empty", ("time", "error"), (320, 240)).unwrap();
        assert!(pixels.chunks(3).any(|p| p.iter().all(|&c| c < 80)));
    }
}
