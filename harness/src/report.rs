//! Result rows and their three forms: CSV (every figure at full precision), JSON (the same plus
//! extra timer spans, skipped techniques and reference statistics) and a markdown table.
//!
//! Error figures are measured at several times along the camera path (the run's error
//! frames, [`crate::Frames::error_times`]): `rmse`, `flip_mean`, `flip_mean_masked` and
//! `flip_over_0_1_pct` are means over those times, `*_worst` the largest value at any of them,
//! `worst_time` the time of the largest masked FLIP (FLIP where no time has a mask), `psnr_db`
//! is that of the mean RMSE, `nan_pixels` the largest count in one frame and `masked_pixels`
//! the mask's size at time 0. `flip_mean_masked` is the mean over the frames whose mask is not
//! empty (a moving object may leave the view). JSON also has every time's figures
//! (`errors_at`).
//!
//! Missing figures (a technique that failed, no reference) are empty CSV cells and JSON
//! `null`. PSNR of identical images is infinite: `inf` in CSV and markdown, `"inf"` in JSON
//! (then `rmse` is 0; JSON has no infinity, see [`crate::json_float`]). `flip_mean_masked` is empty/`null` when the reference mask is empty.

use crate::json_float;
use crate::measure::TechniqueRun;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use truth::metrics::Metrics;

/// One (scene, technique[, parameter value]) result.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct ResultRow {
    pub scene: String,
    pub technique: String,
    /// Swept parameter name and value (sweep only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub param: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub value: Option<String>,
    pub width: u32,
    pub height: u32,
    /// Timed frames behind the median and p95.
    pub frames: u32,
    #[serde(with = "json_float::opt")]
    pub frame_ms_median: Option<f64>,
    #[serde(with = "json_float::opt")]
    pub frame_ms_p95: Option<f64>,
    /// Time of `prepare`, measured like the frames (same timer kind).
    #[serde(with = "json_float::opt")]
    pub prepare_ms: Option<f64>,
    /// Wall-clock time of `prepare` including submission and wait.
    #[serde(with = "json_float::opt")]
    pub prepare_wall_ms: Option<f64>,
    /// "gpu-timestamp", "wall" or "cpu" (see the README).
    pub timer: String,
    #[serde(with = "json_float::opt")]
    pub rmse: Option<f64>,
    #[serde(with = "json_float::opt")]
    pub psnr_db: Option<f64>,
    #[serde(with = "json_float::opt")]
    pub flip_mean: Option<f64>,
    #[serde(with = "json_float::opt")]
    pub flip_mean_masked: Option<f64>,
    #[serde(with = "json_float::opt")]
    pub flip_over_0_1_pct: Option<f64>,
    pub nan_pixels: Option<usize>,
    pub masked_pixels: Option<usize>,
    #[serde(with = "json_float::opt")]
    pub rmse_worst: Option<f64>,
    #[serde(with = "json_float::opt")]
    pub flip_mean_worst: Option<f64>,
    #[serde(with = "json_float::opt")]
    pub flip_mean_masked_worst: Option<f64>,
    /// Mean FLIP over the mask's silhouette band (`truth::metrics::silhouette_band`), mean
    /// over the error frames.
    #[serde(with = "json_float::opt")]
    pub flip_mean_silhouette: Option<f64>,
    /// The exact GPU ray tracer's median frame time on this scene in this run over this row's
    /// (`crate::pareto`): above 1, the technique is that many times faster than tracing the
    /// rays exactly. None without the tracer's row, for CPU-timed rows and failed rows.
    #[serde(with = "json_float::opt")]
    pub speedup_vs_raytracer: Option<f64>,
    /// Time of the worst error frame (largest masked FLIP, else largest FLIP).
    pub worst_time: Option<f32>,
    /// The times of the error frames.
    pub error_times: Vec<f32>,
    /// The figures of each error frame.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub errors_at: Vec<ErrorAt>,
    /// Extra named timer spans a technique recorded, median per frame (`regenerate_ms`), and
    /// those recorded during prepare (`prepare.build_ms`).
    pub spans_ms: BTreeMap<String, f64>,
    pub adapter: String,
    pub error: Option<String>,
    /// The row whose run measured this one (`Technique::contains`: `raytracer/whitted` from
    /// `raytracer/caustics`' eye pass), its images and times taken from that run's frames.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measured_with: Option<String>,
    /// Where the row's wall-clock time went (not a figure of the technique: the harness's own
    /// cost, for whoever makes the run faster).
    pub wall: RowWall,
}

/// The wall-clock seconds one row of a run took, by step (`results.csv`'s `wall_*_s`).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct RowWall {
    /// A fresh device and the scene uploaded to it, the technique made, its parameters set and
    /// its `prepare`.
    #[serde(with = "json_float::num")]
    pub prepare_s: f64,
    /// Warm-up, timed and error frames, read-backs included.
    #[serde(with = "json_float::num")]
    pub frames_s: f64,
    /// The error figures and FLIP maps against the references.
    #[serde(with = "json_float::num")]
    pub metrics_s: f64,
    /// The row's images, and the tables and JSON rewritten after it.
    #[serde(with = "json_float::num")]
    pub write_s: f64,
}

impl RowWall {
    pub fn total_s(&self) -> f64 {
        self.prepare_s + self.frames_s + self.metrics_s + self.write_s
    }
}

/// The error figures of one error frame.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(from = "ErrorAtJson", into = "ErrorAtJson")]
pub struct ErrorAt {
    pub time: f32,
    pub metrics: Metrics,
}

impl ErrorAt {
    pub fn new(time: f32, metrics: &Metrics) -> Self {
        ErrorAt {
            time,
            metrics: *metrics,
        }
    }
}

/// [`ErrorAt`] as JSON: the time and the metrics side by side, NaN as `null` and infinity as
/// `"inf"` ([`json_float`]), so that a run's JSON reads back to the same figures.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
struct ErrorAtJson {
    time: f32,
    #[serde(with = "json_float::num")]
    rmse: f64,
    #[serde(with = "json_float::num")]
    psnr_db: f64,
    #[serde(with = "json_float::num")]
    flip_mean: f64,
    #[serde(with = "json_float::num")]
    flip_mean_masked: f64,
    #[serde(with = "json_float::num")]
    flip_mean_silhouette: f64,
    #[serde(with = "json_float::num")]
    flip_over_0_1_pct: f64,
    nan_pixels: usize,
    masked_pixels: usize,
}

impl From<ErrorAtJson> for ErrorAt {
    fn from(j: ErrorAtJson) -> Self {
        ErrorAt {
            time: j.time,
            metrics: Metrics {
                rmse: j.rmse,
                psnr_db: j.psnr_db,
                flip_mean: j.flip_mean,
                flip_mean_masked: j.flip_mean_masked,
                flip_mean_silhouette: j.flip_mean_silhouette,
                flip_over_0_1_pct: j.flip_over_0_1_pct,
                nan_pixels: j.nan_pixels,
                masked_pixels: j.masked_pixels,
            },
        }
    }
}

impl From<ErrorAt> for ErrorAtJson {
    fn from(e: ErrorAt) -> Self {
        let m = e.metrics;
        ErrorAtJson {
            time: e.time,
            rmse: m.rmse,
            psnr_db: m.psnr_db,
            flip_mean: m.flip_mean,
            flip_mean_masked: m.flip_mean_masked,
            flip_mean_silhouette: m.flip_mean_silhouette,
            flip_over_0_1_pct: m.flip_over_0_1_pct,
            nan_pixels: m.nan_pixels,
            masked_pixels: m.masked_pixels,
        }
    }
}

/// Mean of the non-NaN values (NaN when there are none).
fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values
        .filter(|v| !v.is_nan())
        .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if n == 0 { f64::NAN } else { sum / n as f64 }
}

/// Largest non-NaN value (NaN when there are none).
fn worst(values: impl Iterator<Item = f64>) -> f64 {
    values.filter(|v| !v.is_nan()).fold(f64::NAN, f64::max)
}

impl ResultRow {
    /// A row with identity fields only (the rest filled by [`ResultRow::with_run`] and
    /// [`ResultRow::with_errors_along`], or an error).
    pub fn new(scene: &str, technique: &str, size: crate::Size, adapter: &str) -> Self {
        ResultRow {
            scene: scene.to_string(),
            technique: technique.to_string(),
            width: size.width,
            height: size.height,
            adapter: adapter.to_string(),
            ..Default::default()
        }
    }

    pub fn with_run(mut self, run: &TechniqueRun) -> Self {
        self.frames = run.frame.samples as u32;
        let timed = run.frame.samples > 0;
        self.frame_ms_median = timed.then_some(run.frame.median_ms);
        self.frame_ms_p95 = timed.then_some(run.frame.p95_ms);
        self.prepare_ms = Some(run.prepare_ms);
        self.prepare_wall_ms = Some(run.prepare_wall_ms);
        self.timer = run.timer.clone();
        self.spans_ms = run.spans_ms.clone();
        self
    }

    /// Means and worst values over the error frames (see the module documentation).
    pub fn with_errors_along(mut self, at: Vec<ErrorAt>) -> Self {
        let Some(first) = at.first() else {
            return self;
        };
        let rmse = mean(at.iter().map(|e| e.metrics.rmse));
        self.rmse = Some(rmse);
        // Identical images: infinite PSNR; no finite pixel at all (RMSE NaN): NaN, never inf.
        self.psnr_db = Some(if rmse == 0.0 {
            f64::INFINITY
        } else {
            20.0 * (1.0 / rmse).log10()
        });
        self.flip_mean = Some(mean(at.iter().map(|e| e.metrics.flip_mean)));
        self.flip_mean_masked = Some(mean(at.iter().map(|e| e.metrics.flip_mean_masked)));
        self.flip_mean_silhouette = Some(mean(at.iter().map(|e| e.metrics.flip_mean_silhouette)));
        self.flip_over_0_1_pct = Some(mean(at.iter().map(|e| e.metrics.flip_over_0_1_pct)));
        self.nan_pixels = at.iter().map(|e| e.metrics.nan_pixels).max();
        self.masked_pixels = Some(first.metrics.masked_pixels);
        self.rmse_worst = Some(worst(at.iter().map(|e| e.metrics.rmse)));
        self.flip_mean_worst = Some(worst(at.iter().map(|e| e.metrics.flip_mean)));
        self.flip_mean_masked_worst = Some(worst(at.iter().map(|e| e.metrics.flip_mean_masked)));
        let key = |e: &ErrorAt| match e.metrics.flip_mean_masked.is_nan() {
            true => e.metrics.flip_mean,
            false => e.metrics.flip_mean_masked,
        };
        let masked = at.iter().any(|e| !e.metrics.flip_mean_masked.is_nan());
        self.worst_time = at
            .iter()
            .filter(|e| !masked || !e.metrics.flip_mean_masked.is_nan())
            .max_by(|a, b| key(a).total_cmp(&key(b)))
            .map(|e| e.time);
        self.error_times = at.iter().map(|e| e.time).collect();
        self.errors_at = at;
        self
    }

    pub fn with_error(mut self, error: impl Into<String>) -> Self {
        self.error = Some(error.into());
        self
    }
}

/// The CSV columns, in order (sweep adds `param,value` after `technique`).
pub const CSV_COLUMNS: &[&str] = &[
    "scene",
    "technique",
    "width",
    "height",
    "frames",
    "frame_ms_median",
    "frame_ms_p95",
    "prepare_ms",
    "timer",
    "rmse",
    "psnr_db",
    "flip_mean",
    "flip_mean_masked",
    "flip_over_0_1_pct",
    "nan_pixels",
    "masked_pixels",
    "rmse_worst",
    "flip_mean_worst",
    "flip_mean_masked_worst",
    "worst_time",
    "error_times",
    "flip_mean_silhouette",
    "speedup_vs_raytracer",
    "adapter",
    "error",
    "wall_prepare_s",
    "wall_frames_s",
    "wall_metrics_s",
    "wall_write_s",
];

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// A number for CSV: full precision, `inf`/`-inf`, empty for NaN or missing.
pub(crate) fn csv_num(v: Option<f64>) -> String {
    match v {
        Some(v) if v.is_nan() => String::new(),
        Some(v) if v.is_infinite() => if v > 0.0 { "inf" } else { "-inf" }.to_string(),
        Some(v) => format!("{v}"),
        None => String::new(),
    }
}

/// Seconds of wall clock to the millisecond (they are the harness's cost, not a figure).
fn wall_s(seconds: f64) -> String {
    format!("{seconds:.3}")
}

pub(crate) fn csv_int(v: Option<usize>) -> String {
    v.map(|v| v.to_string()).unwrap_or_default()
}

/// CSV text of rows (header included). `with_param` adds the sweep's `param,value` columns.
pub fn to_csv(rows: &[ResultRow], with_param: bool) -> String {
    let mut out = String::new();
    let mut header: Vec<&str> = CSV_COLUMNS.to_vec();
    if with_param {
        header.splice(2..2, ["param", "value"]);
    }
    out.push_str(&header.join(","));
    out.push('\n');
    for r in rows {
        let mut f: Vec<String> = vec![csv_field(&r.scene), csv_field(&r.technique)];
        if with_param {
            f.push(csv_field(r.param.as_deref().unwrap_or("")));
            f.push(csv_field(r.value.as_deref().unwrap_or("")));
        }
        f.extend([
            r.width.to_string(),
            r.height.to_string(),
            r.frames.to_string(),
            csv_num(r.frame_ms_median),
            csv_num(r.frame_ms_p95),
            csv_num(r.prepare_ms),
            csv_field(&r.timer),
            csv_num(r.rmse),
            csv_num(r.psnr_db),
            csv_num(r.flip_mean),
            csv_num(r.flip_mean_masked),
            csv_num(r.flip_over_0_1_pct),
            csv_int(r.nan_pixels),
            csv_int(r.masked_pixels),
            csv_num(r.rmse_worst),
            csv_num(r.flip_mean_worst),
            csv_num(r.flip_mean_masked_worst),
            r.worst_time.map(|t| t.to_string()).unwrap_or_default(),
            csv_field(&times_list(&r.error_times)),
            csv_num(r.flip_mean_silhouette),
            csv_num(r.speedup_vs_raytracer),
            csv_field(&r.adapter),
            csv_field(r.error.as_deref().unwrap_or("")),
            wall_s(r.wall.prepare_s),
            wall_s(r.wall.frames_s),
            wall_s(r.wall.metrics_s),
            wall_s(r.wall.write_s),
        ]);
        out.push_str(&f.join(","));
        out.push('\n');
    }
    out
}

/// Error-frame times as one field: `0;1;2`.
pub(crate) fn times_list(times: &[f32]) -> String {
    times
        .iter()
        .map(|t| t.to_string())
        .collect::<Vec<_>>()
        .join(";")
}

fn md_num(v: Option<f64>, decimals: usize) -> String {
    match v {
        Some(v) if v.is_nan() => "-".into(),
        Some(v) if v.is_infinite() => if v > 0.0 { "inf" } else { "-inf" }.into(),
        Some(v) => format!("{v:.decimals$}"),
        None => "-".into(),
    }
}

/// The worst masked FLIP with its time (`0.0123 (t 1)`); `-` when no frame had a mask.
fn md_worst(r: &ResultRow) -> String {
    match (r.flip_mean_masked_worst, r.worst_time) {
        (Some(v), Some(t)) if !v.is_nan() => format!("{v:.4} (t {t})"),
        _ => "-".into(),
    }
}

/// `12.3x` (three significant figures), `-` for none.
fn md_speedup(v: Option<f64>) -> String {
    match v {
        Some(v) if v.is_finite() && v >= 100.0 => format!("{v:.0}x"),
        Some(v) if v.is_finite() && v >= 10.0 => format!("{v:.1}x"),
        Some(v) if v.is_finite() => format!("{v:.2}x"),
        _ => "-".into(),
    }
}

fn md_cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// A markdown table of rows (`with_param` adds the sweep's parameter columns).
pub fn to_markdown(rows: &[ResultRow], with_param: bool) -> String {
    let mut out = String::new();
    let mut header = vec!["scene", "technique"];
    if with_param {
        header.extend(["param", "value"]);
    }
    header.extend([
        "frame ms (median)",
        "p95",
        "prepare ms",
        "timer",
        "RMSE",
        "PSNR dB",
        "FLIP",
        "FLIP masked",
        "FLIP masked worst (t)",
        "FLIP silhouette",
        "FLIP>0.1 %",
        "speed-up vs ray tracer",
        "NaN px",
        "error",
    ]);
    let _ = writeln!(out, "| {} |", header.join(" | "));
    let _ = writeln!(out, "|{}", " --- |".repeat(header.len()));
    for r in rows {
        let mut cells = vec![md_cell(&r.scene), md_cell(&r.technique)];
        if with_param {
            cells.push(md_cell(r.param.as_deref().unwrap_or("")));
            cells.push(md_cell(r.value.as_deref().unwrap_or("")));
        }
        cells.extend([
            md_num(r.frame_ms_median, 3),
            md_num(r.frame_ms_p95, 3),
            md_num(r.prepare_ms, 3),
            md_cell(&r.timer),
            md_num(r.rmse, 4),
            md_num(r.psnr_db, 2),
            md_num(r.flip_mean, 4),
            md_num(r.flip_mean_masked, 4),
            md_worst(r),
            md_num(r.flip_mean_silhouette, 4),
            md_num(r.flip_over_0_1_pct, 2),
            md_speedup(r.speedup_vs_raytracer),
            r.nan_pixels
                .map(|n| n.to_string())
                .unwrap_or_else(|| "-".into()),
            md_cell(r.error.as_deref().unwrap_or("")),
        ]);
        let _ = writeln!(out, "| {} |", cells.join(" | "));
    }
    out
}

/// The adapter as written to JSON.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AdapterJson {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    pub is_software: bool,
    /// Whether frame spans are GPU timestamps ("gpu-timestamp") or wall clock ("wall").
    pub timer_kind: String,
}

impl AdapterJson {
    pub fn of(ctx: &gpu::Context) -> Self {
        let s = &ctx.summary;
        let timer = gpu::GpuTimer::new(ctx, 1);
        AdapterJson {
            name: s.name.clone(),
            backend: s.backend.clone(),
            device_type: s.device_type.clone(),
            driver: s.driver.clone(),
            is_software: s.is_software,
            timer_kind: timer.kind().label().to_string(),
        }
    }
}

/// A technique that did not run on a scene, and why.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Skipped {
    pub scene: String,
    pub technique: String,
    pub reason: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_and_markdown_write_missing_and_infinite_values_sensibly() {
        let mut row = ResultRow::new(
            "cornell-sphere:material=a,b",
            "x/y",
            crate::Size::new(4, 2),
            "llvmpipe",
        );
        row.psnr_db = Some(f64::INFINITY);
        row.rmse = Some(0.0);
        row.flip_mean_masked = Some(f64::NAN);
        row.error = Some("said \"no\"".into());
        let csv = to_csv(std::slice::from_ref(&row), false);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines[0], CSV_COLUMNS.join(","));
        assert_eq!(
            lines[1],
            "\"cornell-sphere:material=a,b\",x/y,4,2,0,,,,,0,inf,,,,,,,,,,,,,llvmpipe,\"said \"\"no\"\"\",0.000,0.000,0.000,0.000"
        );
        let swept = to_csv(std::slice::from_ref(&row), true);
        assert!(swept.starts_with("scene,technique,param,value,width"));
        let md = to_markdown(std::slice::from_ref(&row), false);
        assert!(md.contains("| inf |") && md.lines().count() == 3, "{md}");
        let json = serde_json::to_value(&row).unwrap();
        assert_eq!(json["psnr_db"], "inf");
        assert!(json["flip_mean_masked"].is_null());
        assert_eq!(json["rmse"], 0.0);
        assert!(json.get("param").is_none());
        let back: ResultRow = serde_json::from_str(&json.to_string()).unwrap();
        assert_eq!(
            to_csv(&[back], false),
            csv,
            "JSON reads back to the same table"
        );
    }

    #[test]
    fn errors_along_the_path_give_means_and_the_worst_time() {
        let at = |time: f32, rmse, flip, masked| ErrorAt {
            time,
            metrics: Metrics {
                rmse,
                psnr_db: 0.0,
                flip_mean: flip,
                flip_mean_masked: masked,
                flip_mean_silhouette: masked,
                flip_over_0_1_pct: 10.0 * flip,
                nan_pixels: (time * 2.0) as usize,
                masked_pixels: 7,
            },
        };
        let row = ResultRow::new("s", "t", crate::Size::new(4, 4), "a").with_errors_along(vec![
            at(0.0, 0.1, 0.02, 0.01),
            at(1.0, 0.4, 0.01, 0.07),
            at(2.0, 0.1, 0.03, f64::NAN),
        ]);
        assert!((row.rmse.unwrap() - 0.2).abs() < 1e-12);
        assert!((row.psnr_db.unwrap() - 20.0 * 5f64.log10()).abs() < 1e-9);
        assert!((row.flip_mean.unwrap() - 0.02).abs() < 1e-12);
        assert!((row.flip_mean_masked.unwrap() - 0.04).abs() < 1e-12);
        assert_eq!(row.rmse_worst, Some(0.4));
        assert_eq!(row.flip_mean_worst, Some(0.03));
        assert_eq!(row.flip_mean_masked_worst, Some(0.07));
        assert_eq!(row.worst_time, Some(1.0));
        assert_eq!(row.nan_pixels, Some(4));
        assert_eq!(row.error_times, vec![0.0, 1.0, 2.0]);
        let md = to_markdown(std::slice::from_ref(&row), false);
        assert!(md.contains("| 0.0700 (t 1) |"), "{md}");
        let csv = to_csv(std::slice::from_ref(&row), false);
        assert!(csv.contains(",0.4,0.03,0.07,1,0;1;2,"), "{csv}");
        assert!((row.flip_mean_silhouette.unwrap() - 0.04).abs() < 1e-12);
        // Without a mask the worst time is the largest whole-image FLIP's.
        let row = ResultRow::new("s", "t", crate::Size::new(4, 4), "a").with_errors_along(vec![
            at(0.0, 0.1, 0.02, f64::NAN),
            at(1.0, 0.4, 0.05, f64::NAN),
        ]);
        assert_eq!(row.worst_time, Some(1.0));
        assert!(
            to_markdown(&[row], false).contains("| - |"),
            "no masked FLIP to show"
        );
        // No finite pixel at all: RMSE and PSNR are NaN (not the inf of identical images).
        let row = ResultRow::new("s", "t", crate::Size::new(4, 4), "a")
            .with_errors_along(vec![at(0.0, f64::NAN, f64::NAN, f64::NAN)]);
        assert!(row.rmse.unwrap().is_nan() && row.psnr_db.unwrap().is_nan());
    }
}
