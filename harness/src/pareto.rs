//! Error against time, per scene: every technique's frame time beside the exact GPU ray
//! tracer's (`speedup_vs_raytracer`), and the Pareto front of error and frame time
//! (`pareto/<scene>.svg`, drawn by `plot` as the report's view is; the data in
//! `results.json`'s `pareto`).
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

/// The technique every row's speed-up is measured against.
pub const YARDSTICK: &str = "raytracer/caustics";

/// One technique on one scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
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
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
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

/// The rows of a `results.json` written by `compare` (the fields the Pareto view reads), and
/// the adapter's name.
pub fn rows_from_json(text: &str) -> Result<(String, Vec<ResultRow>)> {
    let v: serde_json::Value =
        serde_json::from_str(text).map_err(|e| anyhow!("not a results.json: {e}"))?;
    let rows = v
        .get("rows")
        .and_then(|r| r.as_array())
        .ok_or_else(|| anyhow!("not a results.json of compare: it has no rows"))?;
    let text_of =
        |r: &serde_json::Value, k: &str| r.get(k).and_then(|x| x.as_str()).map(String::from);
    let num = |r: &serde_json::Value, k: &str| r.get(k).and_then(|x| x.as_f64());
    let rows = rows
        .iter()
        .map(|r| ResultRow {
            scene: text_of(r, "scene").unwrap_or_default(),
            technique: text_of(r, "technique").unwrap_or_default(),
            frame_ms_median: num(r, "frame_ms_median"),
            flip_mean: num(r, "flip_mean"),
            flip_mean_masked: num(r, "flip_mean_masked"),
            timer: text_of(r, "timer").unwrap_or_default(),
            error: text_of(r, "error"),
            ..Default::default()
        })
        .collect();
    let adapter = v
        .get("adapter")
        .and_then(|a| a.get("name"))
        .and_then(|n| n.as_str())
        .unwrap_or("unknown adapter")
        .to_string();
    Ok((adapter, rows))
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
}
