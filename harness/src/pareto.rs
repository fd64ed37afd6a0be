//! Error against time, per scene: every technique's frame time beside the exact GPU ray
//! tracer's (`speedup_vs_raytracer`), and the Pareto front of error and frame time
//! (`pareto/<scene>.png`, the data in `results.json`'s `pareto`).
//!
//! The yardstick is [`YARDSTICK`] (`raytracer/caustics`: the reference's whole image traced on
//! the same adapter in the same run). A row's speed-up is the yardstick's median frame time
//! over the row's: 10 means ten times faster than tracing the rays exactly. Rows timed on the
//! CPU (the reference) and rows without a frame time get none.
//!
//! The error of a point is the mean masked FLIP (FLIP over the scene's special pixels), or the
//! whole image's FLIP on a scene whose mask is empty; the tracer is drawn at error 0 (it is
//! exact up to its photon noise, whose measured FLIP stays in the row and in the data). A point
//! is on the front when no other point is both at most as slow and at most as wrong, and
//! better in one of the two.

use crate::report::ResultRow;
use anyhow::{Result, anyhow};
use plotters::prelude::*;
use std::path::Path;

/// The technique every row's speed-up is measured against.
pub const YARDSTICK: &str = "raytracer/caustics";

/// One technique on one scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ParetoPoint {
    pub technique: String,
    pub frame_ms: f64,
    /// The error drawn (0 for the yardstick).
    pub error: f64,
    /// The error measured (the yardstick's photon noise included).
    pub measured_error: f64,
    pub on_front: bool,
}

/// A scene's points.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ParetoScene {
    pub scene: String,
    /// `flip_mean_masked`, or `flip_mean` where the scene's mask is empty.
    pub error_metric: String,
    pub yardstick_ms: Option<f64>,
    pub points: Vec<ParetoPoint>,
    /// The plot, relative to the output folder.
    pub plot: Option<String>,
}

/// Sets `speedup_vs_raytracer` on every GPU-timed row of `rows` (one scene's rows) from the
/// yardstick's row among them.
pub fn set_speedups(rows: &mut [ResultRow]) {
    let yardstick = rows
        .iter()
        .find(|r| r.technique == YARDSTICK && r.error.is_none())
        .and_then(|r| r.frame_ms_median)
        .filter(|ms| *ms > 0.0);
    for r in rows.iter_mut() {
        r.speedup_vs_raytracer = match (yardstick, r.frame_ms_median) {
            (Some(y), Some(ms)) if ms > 0.0 && r.timer != "cpu" && r.error.is_none() => {
                Some(y / ms)
            }
            _ => None,
        };
    }
}

/// The points of one scene's rows (rows with a frame time and an error, GPU-timed).
pub fn scene_points(scene: &str, rows: &[ResultRow]) -> ParetoScene {
    let masked = rows
        .iter()
        .any(|r| r.flip_mean_masked.is_some_and(|v| v.is_finite()));
    let error_of = |r: &ResultRow| {
        if masked {
            r.flip_mean_masked
        } else {
            r.flip_mean
        }
    };
    let mut points: Vec<ParetoPoint> = rows
        .iter()
        .filter(|r| r.timer != "cpu" && r.error.is_none())
        .filter_map(|r| {
            let ms = r.frame_ms_median.filter(|v| v.is_finite() && *v > 0.0)?;
            let measured = error_of(r).filter(|v| v.is_finite())?;
            let error = if r.technique == YARDSTICK {
                0.0
            } else {
                measured
            };
            Some(ParetoPoint {
                technique: r.technique.clone(),
                frame_ms: ms,
                error,
                measured_error: measured,
                on_front: false,
            })
        })
        .collect();
    mark_front(&mut points);
    ParetoScene {
        scene: scene.to_string(),
        error_metric: if masked {
            "flip_mean_masked"
        } else {
            "flip_mean"
        }
        .into(),
        yardstick_ms: points
            .iter()
            .find(|p| p.technique == YARDSTICK)
            .map(|p| p.frame_ms),
        points,
        plot: None,
    }
}

/// Marks the points no other point dominates.
pub fn mark_front(points: &mut [ParetoPoint]) {
    let dominated: Vec<bool> = points
        .iter()
        .map(|p| {
            points.iter().any(|q| {
                q.frame_ms <= p.frame_ms
                    && q.error <= p.error
                    && (q.frame_ms < p.frame_ms || q.error < p.error)
            })
        })
        .collect();
    for (p, d) in points.iter_mut().zip(dominated) {
        p.on_front = !d;
    }
}

fn err(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("pareto plot: {e}")
}

/// Draws the scene's points: frame time (log scale) across, error up, the front as a staircase
/// and every point named (when a font is available: see `plot`).
pub fn draw(path: &Path, title: &str, scene: &ParetoScene) -> Result<()> {
    let text = crate::plot::fonts_available();
    if scene.points.is_empty() {
        return Err(anyhow!("no technique with a frame time and an error"));
    }
    let (lo, hi) = scene
        .points
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), p| {
            (a.min(p.frame_ms), b.max(p.frame_ms))
        });
    let (x0, x1) = (lo / 2.0, hi * 2.0);
    let top = scene.points.iter().map(|p| p.error).fold(0.0f64, f64::max);
    let y1 = if top > 0.0 { top * 1.15 } else { 1.0 };
    let root = BitMapBackend::new(path, (1100, 760)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let root = if text {
        root.titled(title, ("sans-serif", 22)).map_err(err)?
    } else {
        root
    };
    let label_area = |n: u32| if text { n } else { 4 };
    let mut chart = ChartBuilder::on(&root)
        .margin(16)
        .x_label_area_size(label_area(44))
        .y_label_area_size(label_area(70))
        .build_cartesian_2d((x0..x1).log_scale(), 0.0..y1)
        .map_err(err)?;
    {
        let mut mesh = chart.configure_mesh();
        if text {
            mesh.x_desc("frame time, ms (median, log scale)").y_desc(
                match scene.error_metric.as_str() {
                    "flip_mean_masked" => "FLIP over the mask (mean along the path)",
                    _ => "FLIP (mean along the path)",
                },
            );
        } else {
            mesh.x_labels(0).y_labels(0);
        }
        mesh.draw().map_err(err)?;
    }
    let front_colour = RGBColor(200, 40, 40);
    let other = RGBColor(110, 110, 110);
    let tracer = RGBColor(40, 80, 200);
    let mut front: Vec<&ParetoPoint> = scene.points.iter().filter(|p| p.on_front).collect();
    front.sort_by(|a, b| a.frame_ms.total_cmp(&b.frame_ms));
    let mut stairs = Vec::new();
    for (i, p) in front.iter().enumerate() {
        if i > 0 {
            stairs.push((p.frame_ms, front[i - 1].error));
        }
        stairs.push((p.frame_ms, p.error));
    }
    chart
        .draw_series(LineSeries::new(stairs, front_colour.stroke_width(2)))
        .map_err(err)?;
    for p in &scene.points {
        let colour = if p.technique == YARDSTICK {
            tracer
        } else if p.on_front {
            front_colour
        } else {
            other
        };
        chart
            .draw_series(std::iter::once(Circle::new(
                (p.frame_ms, p.error),
                5,
                colour.filled(),
            )))
            .map_err(err)?;
        if text {
            let name = p.technique.clone();
            chart
                .draw_series(std::iter::once(Text::new(
                    name,
                    (p.frame_ms, p.error),
                    ("sans-serif", 13).into_font().color(&colour),
                )))
                .map_err(err)?;
        }
    }
    root.present().map_err(err)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(t: &str, ms: f64, e: f64) -> ParetoPoint {
        ParetoPoint {
            technique: t.into(),
            frame_ms: ms,
            error: e,
            measured_error: e,
            on_front: false,
        }
    }

    #[test]
    fn the_front_keeps_exactly_the_undominated_points() {
        let mut p = vec![
            point("exact", 100.0, 0.0),
            point("fast", 1.0, 0.3),
            point("middle", 10.0, 0.1),
            point("worse", 20.0, 0.2), // slower and worse than middle
            point("tie", 10.0, 0.1),   // equal to middle: neither dominates
        ];
        mark_front(&mut p);
        let front: Vec<&str> = p
            .iter()
            .filter(|p| p.on_front)
            .map(|p| p.technique.as_str())
            .collect();
        assert_eq!(front, ["exact", "fast", "middle", "tie"]);
    }

    #[test]
    fn speedups_are_against_the_tracer_of_the_same_scene() {
        let row = |t: &str, ms: f64, timer: &str| ResultRow {
            technique: t.into(),
            frame_ms_median: Some(ms),
            timer: timer.into(),
            ..Default::default()
        };
        let mut rows = vec![
            row("reference", 5000.0, "cpu"),
            row(YARDSTICK, 40.0, "gpu-timestamp"),
            row("raster", 2.0, "gpu-timestamp"),
        ];
        set_speedups(&mut rows);
        assert_eq!(rows[0].speedup_vs_raytracer, None);
        assert_eq!(rows[1].speedup_vs_raytracer, Some(1.0));
        assert_eq!(rows[2].speedup_vs_raytracer, Some(20.0));
        let mut alone = vec![row("raster", 2.0, "gpu-timestamp")];
        set_speedups(&mut alone);
        assert_eq!(alone[0].speedup_vs_raytracer, None);
    }

    #[test]
    fn plots_are_written() {
        let rows = vec![
            ResultRow {
                technique: YARDSTICK.into(),
                frame_ms_median: Some(40.0),
                flip_mean_masked: Some(0.002),
                timer: "gpu-timestamp".into(),
                ..Default::default()
            },
            ResultRow {
                technique: "raster".into(),
                frame_ms_median: Some(2.0),
                flip_mean_masked: Some(0.4),
                timer: "gpu-timestamp".into(),
                ..Default::default()
            },
        ];
        let scene = scene_points("test", &rows);
        assert_eq!(scene.points[0].error, 0.0);
        assert_eq!(scene.points[0].measured_error, 0.002);
        assert!(scene.points.iter().all(|p| p.on_front));
        let path = std::env::temp_dir().join("harness-pareto-test.png");
        draw(&path, "test", &scene).unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 1000);
    }
}
