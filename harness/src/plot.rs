//! `sweep.png`: error and frame time against a swept parameter, in two panels (top: mean FLIP
//! on the left axis and RMSE on the right axis; bottom: median frame time).
//!
//! Text (captions, axis labels, legend) needs a system font (found through fontconfig). When
//! none can be loaded, the plot is still written, without any text, and a warning is printed.
//! `HARNESS_PLOT_NO_TEXT=1` forces the text-free plot.

use anyhow::{Result, anyhow};
use plotters::prelude::*;
use std::path::Path;

/// One swept value and what was measured at it (None or NaN: not drawn).
#[derive(Clone, Debug, PartialEq)]
pub struct PlotPoint {
    pub value: String,
    pub flip_mean: Option<f64>,
    pub rmse: Option<f64>,
    pub frame_ms: Option<f64>,
}

/// Whether text was drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlotText {
    Drawn,
    /// No usable font (or text turned off): the plot has no text.
    Omitted,
}

fn err(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("plot: {e}")
}

/// Whether a sans-serif font can be loaded and measured.
pub fn fonts_available() -> bool {
    if std::env::var_os("HARNESS_PLOT_NO_TEXT").is_some_and(|v| !v.is_empty() && v != "0") {
        return false;
    }
    // Should the font loader panic (it unwraps in places), treat that as no font.
    std::panic::catch_unwind(|| ("sans-serif", 14).into_font().box_size("0.25 ms").is_ok())
        .unwrap_or(false)
}

/// Draws the sweep plot. X is the numeric value when every value is a number, else the values
/// in order as categories. Returns whether text was drawn; prints a warning when it was not
/// for lack of a font.
pub fn sweep_plot(path: &Path, title: &str, param: &str, points: &[PlotPoint]) -> Result<PlotText> {
    if fonts_available() {
        match draw(path, title, param, points, true) {
            Ok(()) => return Ok(PlotText::Drawn),
            Err(e) => eprintln!(
                "warning: cannot draw text in {} ({e:#}); writing it without text",
                path.display()
            ),
        }
    } else if std::env::var_os("HARNESS_PLOT_NO_TEXT").is_none() {
        eprintln!(
            "warning: no usable font found; {} is written without text",
            path.display()
        );
    }
    draw(path, title, param, points, false)?;
    Ok(PlotText::Omitted)
}

fn range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let max = values.filter(|v| v.is_finite()).fold(0.0f64, f64::max);
    0.0..if max > 0.0 { max * 1.1 } else { 1.0 }
}

fn finite(v: Option<f64>) -> Option<f64> {
    v.filter(|v| v.is_finite())
}

fn draw(path: &Path, title: &str, param: &str, points: &[PlotPoint], text: bool) -> Result<()> {
    let axis = XAxis::of(points);
    let (x0, x1) = axis.range;
    let xs = &axis.xs;
    let category = |x: &f64| axis.category(x);
    let xy = |f: fn(&PlotPoint) -> Option<f64>| -> Vec<(f64, f64)> {
        xs.iter()
            .zip(points)
            .filter_map(|(&x, p)| finite(f(p)).map(|y| (x, y)))
            .collect()
    };
    let flip = xy(|p| p.flip_mean);
    let rmse = xy(|p| p.rmse);
    let time = xy(|p| p.frame_ms);
    let label_area = |n: u32| if text { n } else { 4 };

    let root = BitMapBackend::new(path, (960, 720)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let root = if text {
        root.titled(title, ("sans-serif", 22)).map_err(err)?
    } else {
        root
    };
    let (top, bottom) = root.split_vertically(root.dim_in_pixel().1 / 2);
    let flip_colour = RGBColor(200, 40, 40);
    let rmse_colour = RGBColor(40, 80, 200);

    // Top panel: error.
    let mut chart = ChartBuilder::on(&top)
        .margin(12)
        .x_label_area_size(label_area(40))
        .y_label_area_size(label_area(70))
        .right_y_label_area_size(label_area(70))
        .build_cartesian_2d(x0..x1, range(flip.iter().map(|p| p.1)))
        .map_err(err)?
        .set_secondary_coord(x0..x1, range(rmse.iter().map(|p| p.1)));
    {
        let mut mesh = chart.configure_mesh();
        if text {
            mesh.x_desc(param).y_desc("FLIP mean");
            if axis.categorical {
                mesh.x_label_formatter(&category)
                    .x_labels(axis.labels.len().max(2));
            }
        } else {
            mesh.x_labels(0).y_labels(0);
        }
        mesh.draw().map_err(err)?;
    }
    {
        let mut secondary = chart.configure_secondary_axes();
        if text {
            secondary.y_desc("RMSE (linear)");
        } else {
            secondary.x_labels(0).y_labels(0);
        }
        secondary.draw().map_err(err)?;
    }
    let flip_series = chart
        .draw_series(LineSeries::new(flip.clone(), flip_colour.stroke_width(2)))
        .map_err(err)?;
    if text {
        flip_series.label("FLIP mean (left)").legend(move |(x, y)| {
            PathElement::new(vec![(x, y), (x + 20, y)], flip_colour.stroke_width(2))
        });
    }
    chart
        .draw_series(
            flip.iter()
                .map(|&p| Circle::new(p, 4, flip_colour.filled())),
        )
        .map_err(err)?;
    let rmse_series = chart
        .draw_secondary_series(LineSeries::new(rmse.clone(), rmse_colour.stroke_width(2)))
        .map_err(err)?;
    if text {
        rmse_series.label("RMSE (right)").legend(move |(x, y)| {
            PathElement::new(vec![(x, y), (x + 20, y)], rmse_colour.stroke_width(2))
        });
    }
    chart
        .draw_secondary_series(
            rmse.iter()
                .map(|&p| Circle::new(p, 4, rmse_colour.filled())),
        )
        .map_err(err)?;
    if text {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(err)?;
    }

    draw_time_panel(&bottom, &axis, &time, param, text)?;
    root.present().map_err(err)?;
    Ok(())
}

/// The x axis both panels share: where each point sits (its value, or its index when some
/// value is not a number: a categorical parameter), the padded range, and the labels.
struct XAxis {
    xs: Vec<f64>,
    range: (f64, f64),
    labels: Vec<String>,
    categorical: bool,
}

impl XAxis {
    fn of(points: &[PlotPoint]) -> Self {
        let numeric: Option<Vec<f64>> = points
            .iter()
            .map(|p| p.value.parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect();
        let categorical = numeric.is_none();
        let xs: Vec<f64> = numeric.unwrap_or_else(|| (0..points.len()).map(|i| i as f64).collect());
        let (mut x0, mut x1) = xs
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        if !x0.is_finite() {
            (x0, x1) = (0.0, 1.0);
        }
        let pad = if x1 > x0 { (x1 - x0) * 0.05 } else { 0.5 };
        Self {
            xs,
            range: (x0 - pad, x1 + pad),
            labels: points.iter().map(|p| p.value.clone()).collect(),
            categorical,
        }
    }

    /// The label of a category's position (empty between categories).
    fn category(&self, x: &f64) -> String {
        let i = x.round();
        if (x - i).abs() < 1e-6 && i >= 0.0 {
            self.labels.get(i as usize).cloned().unwrap_or_default()
        } else {
            String::new()
        }
    }
}

/// The bottom panel: median frame time (no right axis; the margin keeps x aligned with the
/// top panel's).
fn draw_time_panel(
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    axis: &XAxis,
    time: &[(f64, f64)],
    param: &str,
    text: bool,
) -> Result<()> {
    let (x0, x1) = axis.range;
    let categorical = axis.categorical;
    let category = |x: &f64| axis.category(x);
    let label_area = |n: u32| if text { n } else { 4 };
    let time_colour = RGBColor(30, 140, 60);
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .margin_right(12 + label_area(70))
        .x_label_area_size(label_area(40))
        .y_label_area_size(label_area(70))
        .build_cartesian_2d(x0..x1, range(time.iter().map(|p| p.1)))
        .map_err(err)?;
    {
        let mut mesh = chart.configure_mesh();
        if text {
            mesh.x_desc(param).y_desc("frame ms (median)");
            if categorical {
                mesh.x_label_formatter(&category)
                    .x_labels(axis.labels.len().max(2));
            }
        } else {
            mesh.x_labels(0).y_labels(0);
        }
        mesh.draw().map_err(err)?;
    }
    chart
        .draw_series(LineSeries::new(time.to_vec(), time_colour.stroke_width(2)))
        .map_err(err)?;
    chart
        .draw_series(
            time.iter()
                .map(|&p| Circle::new(p, 4, time_colour.filled())),
        )
        .map_err(err)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn points(values: &[&str]) -> Vec<PlotPoint> {
        values
            .iter()
            .enumerate()
            .map(|(i, v)| PlotPoint {
                value: v.to_string(),
                flip_mean: Some(0.1 / (i + 1) as f64),
                rmse: if i == 1 { None } else { Some(0.05 * i as f64) },
                frame_ms: Some(1.0 + i as f64),
            })
            .collect()
    }

    #[test]
    fn plots_are_written_with_and_without_text() {
        let dir = std::env::temp_dir().join(format!("harness-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (name, pts) in [
            ("numeric.png", points(&["1", "2", "4", "8"])),
            ("categorical.png", points(&["mirror", "gold", "glass-1.5"])),
            ("single.png", points(&["3"])),
            ("empty.png", vec![]),
        ] {
            let path = dir.join(name);
            sweep_plot(&path, "t", "p", &pts).unwrap();
            let img = image::open(&path).unwrap();
            assert_eq!((img.width(), img.height()), (960, 720));
            draw(&path, "t", "p", &pts, false).unwrap();
            assert!(image::open(&path).is_ok());
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
