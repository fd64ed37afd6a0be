//! `index.html`: the report a person reads, written by `compare` and `sweep` beside their tables.
//!
//! One self-contained page, opened from the file system (no server, nothing fetched): the
//! style and the script are inlined from `report.css` and `report.js` beside this file, the
//! run's figures are a JSON block the script reads, and the images are the PNG files the run
//! wrote, referenced by relative paths. What it shows:
//!
//! - per scene (per swept value for `sweep`), the reference and every technique in a grid
//!   grouped by family, each with its FLIP map on demand and its key figures (masked FLIP,
//!   PSNR, frame time, speed-up against the exact tracer), at each error frame along the path;
//! - a comparison of any two images of a scene: a draggable split, flicker and toggle, a
//!   nearest-neighbour zoom into the same crop of both, and an exposure control that reads the
//!   HDR copies (`*.hdr.js`, see [`crate::images::write_hdr_script`]);
//! - the results table (sortable, filterable by scene and family, failures and NaN pixels
//!   highlighted), whose cells carry the CSV's own text in `data-v`;
//! - the plots as SVG ([`svg`]): the Pareto view per scene, or the sweep's figures;
//! - the failures, skipped techniques and importer notes, and what produced the page
//!   ([`Provenance`]).

use crate::plot as svg;

use crate::model::{ImageFrame, RunReport, WrittenImages};
use crate::plan::{ParamOwner, SweepInfo};
pub use crate::provenance::Provenance;
use crate::report::{ResultRow, csv_int, csv_num, times_list};
use crate::{file_name, technique_family as family};
use anyhow::{Context as _, Result};
use std::fmt::Write as _;
use std::path::Path;
use svg::{escape, short};

const STYLE: &str = include_str!("report.css");
const SCRIPT: &str = include_str!("report.js");

/// The figures under an image.
#[derive(Clone, Debug, Default, serde::Serialize)]
struct Figures {
    flip_masked: Option<f64>,
    flip: Option<f64>,
    psnr_db: Option<f64>,
    rmse: Option<f64>,
    frame_ms: Option<f64>,
    timer: String,
    speedup: Option<f64>,
    nan_pixels: Option<usize>,
}

/// A reference or a technique's result in a group.
#[derive(Clone, Debug, serde::Serialize)]
struct Entry {
    id: String,
    label: String,
    family: String,
    /// One per error frame the run wrote.
    frames: Vec<ImageFrame>,
    figures: Option<Figures>,
    error: Option<String>,
    /// The entry this one is compared against by default (its reference).
    reference: Option<usize>,
}

/// A scene of a compare run, or the swept values of a sweep.
#[derive(Clone, Debug, serde::Serialize)]
struct Group {
    title: String,
    anchor: String,
    times: Vec<f32>,
    entries: Vec<Entry>,
    #[serde(skip)]
    plots: Vec<String>,
    #[serde(skip)]
    legend: Vec<(String, String)>,
}

/// A figure that is a JSON number, or null (serde writes NaN and infinity as null too).
fn finite(v: Option<f64>) -> Option<f64> {
    v.filter(|v| v.is_finite())
}

fn figures(row: &ResultRow) -> Figures {
    Figures {
        flip_masked: finite(row.flip_mean_masked),
        flip: finite(row.flip_mean),
        psnr_db: row.psnr_db.filter(|v| !v.is_nan()).map(|v| v.min(999.0)),
        rmse: finite(row.rmse),
        frame_ms: finite(row.frame_ms_median),
        timer: row.timer.clone(),
        speedup: finite(row.speedup_vs_raytracer),
        nan_pixels: row.nan_pixels,
    }
}

/// The frames written for the first image matching `wanted` (empty when none was written).
fn frames_of(images: &[WrittenImages], wanted: impl Fn(&WrittenImages) -> bool) -> Vec<ImageFrame> {
    images
        .iter()
        .find(|w| wanted(w))
        .map(|w| w.frames.clone())
        .unwrap_or_default()
}

/// Every time any entry has a frame at, in order.
fn times_of(entries: &[Entry]) -> Vec<f32> {
    let mut times: Vec<f32> = entries
        .iter()
        .flat_map(|e| e.frames.iter().map(|f| f.time))
        .collect();
    times.sort_by(f32::total_cmp);
    times.dedup();
    times
}

/// The groups of a compare run: one per scene, in the order they ran, the reference first,
/// then the techniques in the order they ran (families stay together: the registry lists them
/// so). The `reference` technique shows the ground truth's images (they are the same).
fn compare_groups(report: &RunReport) -> Vec<Group> {
    // Every scene has at least one reference record, even when its reference failed.
    let mut specs: Vec<&String> = report.references.iter().map(|r| &r.scene).collect();
    specs.dedup();
    let mut groups = Vec::new();
    for spec in specs {
        let dir_name = report.image_dirs.get(spec).cloned().unwrap_or_default();
        let truth = frames_of(&report.images, |w| {
            &w.scene == spec && w.technique.is_none()
        });
        let reference_error = report
            .references
            .iter()
            .find(|r| &r.scene == spec && r.error.is_some())
            .and_then(|r| r.error.clone());
        let mut entries = vec![Entry {
            id: "reference".into(),
            label: "reference (CPU ground truth)".into(),
            family: "reference".into(),
            frames: truth.clone(),
            figures: None,
            error: reference_error,
            reference: None,
        }];
        for row in report.rows.iter().filter(|r| &r.scene == spec) {
            let frames = match row.technique.as_str() {
                "reference" => truth.clone(),
                id => frames_of(&report.images, |w| {
                    &w.scene == spec && w.technique.as_deref() == Some(id)
                }),
            };
            entries.push(Entry {
                id: row.technique.clone(),
                label: row.technique.clone(),
                family: family(&row.technique).to_string(),
                frames,
                figures: Some(figures(row)),
                error: row.error.clone(),
                reference: Some(0),
            });
        }
        let pareto = report.pareto.iter().find(|p| &p.scene == spec);
        let plots: Vec<String> = pareto.and_then(svg::pareto).into_iter().collect();
        let legend = pareto
            .map(|p| {
                p.points
                    .iter()
                    .map(|q| {
                        let front = if q.on_front { ", on the front" } else { "" };
                        (
                            q.technique.clone(),
                            format!(
                                "{} ms, error {}{front}",
                                short(q.frame_ms),
                                short(q.measured_error)
                            ),
                        )
                    })
                    .collect()
            })
            .unwrap_or_default();
        groups.push(Group {
            title: spec.clone(),
            anchor: format!("scene-{}", file_name(&dir_name)),
            times: times_of(&entries),
            entries,
            plots,
            legend,
        });
    }
    groups
}

/// The one group of a sweep: its reference(s) and one entry per value.
fn sweep_group(report: &RunReport, sweep: &SweepInfo) -> Group {
    let family = family(sweep.technique.split(':').next().unwrap_or(""));
    let mut entries: Vec<Entry> = Vec::new();
    let reference_entry = |entries: &mut Vec<Entry>, value: Option<&String>| {
        let label = match value {
            Some(v) => format!("reference, {}={v}", sweep.param),
            None => "reference".into(),
        };
        entries.push(Entry {
            id: label.clone(),
            label,
            family: "reference".into(),
            frames: frames_of(&report.images, |w| {
                w.technique.is_none() && w.value.as_ref() == value
            }),
            figures: None,
            error: None,
            reference: None,
        });
        entries.len() - 1
    };
    let shared =
        (sweep.owner == ParamOwner::Technique).then(|| reference_entry(&mut entries, None));
    for row in &report.rows {
        let value = row.value.clone().unwrap_or_default();
        let reference = shared.unwrap_or_else(|| reference_entry(&mut entries, Some(&value)));
        let suffix = format!("{}={value}", sweep.param);
        entries.push(Entry {
            id: suffix.clone(),
            label: suffix,
            family: family.to_string(),
            frames: frames_of(&report.images, |w| {
                w.technique.is_some() && w.value.as_ref() == Some(&value)
            }),
            figures: Some(figures(row)),
            error: row.error.clone(),
            reference: Some(reference),
        });
    }
    let what = format!("{} on {}", sweep.technique, sweep.scene);
    let plots = sweep_plots(report, sweep);
    Group {
        title: format!("{what}, over {}", sweep.param),
        anchor: "sweep".into(),
        times: times_of(&entries),
        entries,
        plots,
        legend: Vec::new(),
    }
}

/// A sweep's figures against the swept value (FLIP, masked FLIP, RMSE, frame time): the
/// report's plots of the sweep and `sweep.svg`.
pub fn sweep_plots(report: &RunReport, sweep: &SweepInfo) -> Vec<String> {
    let series = |f: fn(&ResultRow) -> Option<f64>| -> Vec<(String, Option<f64>)> {
        report
            .rows
            .iter()
            .map(|r| (r.value.clone().unwrap_or_default(), f(r)))
            .collect()
    };
    let what = format!("{} on {}", sweep.technique, sweep.scene);
    [
        ("FLIP (mean)", series(|r| r.flip_mean)),
        ("FLIP over the mask (mean)", series(|r| r.flip_mean_masked)),
        ("RMSE (mean)", series(|r| r.rmse)),
        ("frame time, ms (median)", series(|r| r.frame_ms_median)),
    ]
    .into_iter()
    .filter_map(|(figure, points)| {
        svg::sweep(&format!("{what}: {figure}"), &sweep.param, figure, &points)
    })
    .collect()
}

/// A column of the results table: its CSV name (the `data-col` the test matches against
/// results.csv), its heading and how to read a row.
struct Column {
    csv: &'static str,
    heading: &'static str,
    numeric: bool,
    /// The CSV's text of the cell (its `data-v`) and what the page shows.
    cell: fn(&ResultRow) -> (String, String),
}

fn num_cell(v: Option<f64>) -> (String, String) {
    let text = csv_num(v);
    let shown = match v {
        Some(v) if v.is_nan() => "NaN".into(),
        Some(v) if v.is_infinite() => "inf".into(),
        Some(v) => short(v),
        None => "–".into(),
    };
    (text, shown)
}

fn text_cell(s: &str) -> (String, String) {
    (s.to_string(), s.to_string())
}

/// A text column: `cell` of the row as the CSV writes it and as shown.
macro_rules! text_column {
    ($csv:literal, $heading:literal, |$r:ident| $text:expr) => {
        Column {
            csv: $csv,
            heading: $heading,
            numeric: false,
            cell: |$r| text_cell($text),
        }
    };
}

/// A numeric column of an `Option<f64>` field of the row.
macro_rules! number_column {
    ($csv:literal, $heading:literal, $field:ident) => {
        Column {
            csv: $csv,
            heading: $heading,
            numeric: true,
            cell: |r| num_cell(r.$field),
        }
    };
}

const COLUMNS: &[Column] = &[
    text_column!("scene", "scene", |r| &r.scene),
    text_column!("technique", "technique", |r| &r.technique),
    text_column!("param", "parameter", |r| r.param.as_deref().unwrap_or("")),
    text_column!("value", "value", |r| r.value.as_deref().unwrap_or("")),
    Column {
        csv: "frames",
        heading: "frames",
        numeric: true,
        cell: |r| text_cell(&r.frames.to_string()),
    },
    number_column!("frame_ms_median", "frame ms (median)", frame_ms_median),
    number_column!("frame_ms_p95", "p95 ms", frame_ms_p95),
    number_column!("prepare_ms", "prepare ms", prepare_ms),
    text_column!("timer", "timer", |r| &r.timer),
    number_column!(
        "speedup_vs_raytracer",
        "speed-up vs ray tracer",
        speedup_vs_raytracer
    ),
    number_column!("flip_mean_masked", "FLIP masked", flip_mean_masked),
    number_column!(
        "flip_mean_masked_worst",
        "FLIP masked worst",
        flip_mean_masked_worst
    ),
    Column {
        csv: "worst_time",
        heading: "worst t",
        numeric: true,
        // The CSV writes the f32 as it reads back (`0.6666667`), not widened to f64.
        cell: |r| match r.worst_time {
            Some(t) => (t.to_string(), short(f64::from(t))),
            None => (String::new(), "–".into()),
        },
    },
    number_column!("flip_mean", "FLIP", flip_mean),
    number_column!(
        "flip_mean_silhouette",
        "FLIP silhouette",
        flip_mean_silhouette
    ),
    number_column!("flip_over_0_1_pct", "FLIP>0.1 %", flip_over_0_1_pct),
    number_column!("rmse", "RMSE", rmse),
    number_column!("psnr_db", "PSNR dB", psnr_db),
    Column {
        csv: "nan_pixels",
        heading: "NaN px",
        numeric: true,
        cell: |r| {
            let t = csv_int(r.nan_pixels);
            (t.clone(), if t.is_empty() { "–".into() } else { t })
        },
    },
    text_column!("error_times", "error times", |r| &times_list(
        &r.error_times
    )),
    text_column!("error", "error", |r| r.error.as_deref().unwrap_or("")),
];

/// The results table: one row per result, `data-v` the CSV's text of each cell.
fn results_table(rows: &[ResultRow], swept: bool) -> String {
    let columns: Vec<&Column> = COLUMNS
        .iter()
        .filter(|c| swept || !matches!(c.csv, "param" | "value"))
        .collect();
    let mut html = String::from(r#"<table id="results-table"><thead><tr>"#);
    for c in &columns {
        let _ = write!(
            html,
            r#"<th data-col="{}" data-kind="{}" title="sort by {}">{}</th>"#,
            c.csv,
            if c.numeric { "num" } else { "text" },
            escape(c.heading),
            escape(c.heading)
        );
    }
    html.push_str("</tr></thead><tbody>");
    for r in rows {
        let mut class = Vec::new();
        if r.error.is_some() {
            class.push("failed");
        }
        if r.nan_pixels.is_some_and(|n| n > 0) {
            class.push("has-nan");
        }
        let _ = write!(
            html,
            r#"<tr data-scene="{}" data-family="{}" class="{}">"#,
            escape(&r.scene),
            escape(family(&r.technique)),
            class.join(" ")
        );
        for c in &columns {
            let (value, shown) = (c.cell)(r);
            let bad = match c.csv {
                "nan_pixels" => r.nan_pixels.is_some_and(|n| n > 0),
                "error" => r.error.is_some(),
                _ => shown == "NaN",
            };
            let _ = write!(
                html,
                r#"<td data-v="{}"{}>{}</td>"#,
                escape(&value),
                if bad { r#" class="bad""# } else { "" },
                escape(&shown)
            );
        }
        html.push_str("</tr>");
    }
    html.push_str("</tbody></table>");
    html
}

/// The filters above the table: scenes and families, from the rows.
fn table_filters(rows: &[ResultRow]) -> String {
    let mut scenes: Vec<&str> = rows.iter().map(|r| r.scene.as_str()).collect();
    scenes.dedup();
    let mut families: Vec<&str> = rows.iter().map(|r| family(&r.technique)).collect();
    families.sort();
    families.dedup();
    let options = |all: &str, values: &[&str]| {
        let mut s = format!(r#"<option value="">{all}</option>"#);
        for v in values {
            let _ = write!(s, r#"<option value="{0}">{0}</option>"#, escape(v));
        }
        s
    };
    format!(
        r#"<div class="filters"><label>scene <select id="filter-scene">{}</select></label> <label>family <select id="filter-family">{}</select></label> <label><input type="checkbox" id="filter-failed"> failures and NaN only</label> <span id="row-count"></span></div>"#,
        options("every scene", &scenes),
        options("every family", &families)
    )
}

/// A list section (failures, skipped, notes); empty when there is nothing to list.
fn list_section(id: &str, title: &str, class: &str, items: &[String]) -> String {
    if items.is_empty() {
        return String::new();
    }
    let mut s = format!(r#"<section id="{id}" class="{class}"><h2>{title}</h2><ul>"#);
    for item in items {
        let _ = write!(s, "<li>{}</li>", escape(item));
    }
    s.push_str("</ul></section>");
    s
}

/// A definition list of (term, value) pairs.
fn definitions(pairs: &[(&str, String)]) -> String {
    let mut s = String::from("<dl>");
    for (term, value) in pairs {
        let _ = write!(
            s,
            "<dt>{}</dt><dd><code>{}</code></dd>",
            escape(term),
            escape(value)
        );
    }
    s.push_str("</dl>");
    s
}

/// The static part of a group's section; the script fills the grid and the comparison.
fn group_section(index: usize, group: &Group) -> String {
    let mut s = format!(
        r#"<section class="group" id="{}" data-group="{index}"><h2>{}</h2><div class="group-controls"></div><div class="grid"></div><div class="compare"></div>"#,
        escape(&group.anchor),
        escape(&group.title)
    );
    if !group.plots.is_empty() {
        s.push_str(r#"<div class="plots">"#);
        for plot in &group.plots {
            let _ = write!(s, "<figure>{plot}</figure>");
        }
        if !group.legend.is_empty() {
            s.push_str(r#"<ol class="legend">"#);
            for (technique, text) in &group.legend {
                let _ = write!(s, "<li><b>{}</b> {}</li>", escape(technique), escape(text));
            }
            s.push_str("</ol>");
        }
        s.push_str("</div>");
    }
    s.push_str("</section>");
    s
}

/// The JSON block the script reads.
fn data_block(groups: &[Group]) -> Result<String> {
    let json = serde_json::to_string(&serde_json::json!({ "groups": groups }))
        .context("cannot encode the report's data")?;
    // `<` only occurs inside JSON strings, where `\u003c` means the same: no `</script>` or
    // `<!--` can end or confuse the script element.
    Ok(format!(
        r#"<script type="application/json" id="report-data">{}</script>"#,
        json.replace('<', "\\u003c")
    ))
}

/// Everything a page is made of.
struct Page<'a> {
    title: String,
    summary: String,
    groups: Vec<Group>,
    rows: &'a [ResultRow],
    swept: bool,
    problems: Vec<String>,
    skipped: Vec<String>,
    notes: Vec<String>,
    provenance: Vec<(&'static str, String)>,
}

impl Page<'_> {
    fn html(&self) -> Result<String> {
        let mut nav = String::new();
        for g in &self.groups {
            let _ = write!(
                nav,
                r##"<a href="#{}">{}</a> "##,
                escape(&g.anchor),
                escape(&g.title)
            );
        }
        let mut body = format!(
            r##"<header><h1>{}</h1><p class="summary">{}</p><nav>{nav}<a href="#results">results table</a> <a href="#provenance">how this page was made</a></nav></header>"##,
            escape(&self.title),
            escape(&self.summary)
        );
        body.push_str(&list_section(
            "failures",
            &format!("Failures ({})", self.problems.len()),
            "failures",
            &self.problems,
        ));
        body.push_str(&list_section("notes", "Scene notes", "notes", &self.notes));
        for (i, g) in self.groups.iter().enumerate() {
            body.push_str(&group_section(i, g));
        }
        let _ = write!(
            body,
            r#"<section id="results"><h2>Results</h2>{}{}<p class="hint">Click a heading to sort; the cells hold the CSV's numbers (hover for the full value).</p></section>"#,
            table_filters(self.rows),
            results_table(self.rows, self.swept)
        );
        // Most skips are techniques that do not apply to a scene: listed, folded, after the
        // table.
        if !self.skipped.is_empty() {
            let _ = write!(
                body,
                r#"<section id="skipped" class="skipped"><details><summary>Skipped: {} (scene, technique) pairs, with the reason</summary><ul>"#,
                self.skipped.len()
            );
            for item in &self.skipped {
                let _ = write!(body, "<li>{}</li>", escape(item));
            }
            body.push_str("</ul></details></section>");
        }
        let _ = write!(
            body,
            r#"<section id="provenance"><h2>How this page was made</h2>{}</section>"#,
            definitions(&self.provenance)
        );
        Ok(format!(
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width\"><title>{}</title><style>{STYLE}{plot_style}</style></head><body>{body}{}<script>{SCRIPT}</script></body></html>\n",
            escape(&self.title),
            data_block(&self.groups)?,
            plot_style = svg::PLOT_STYLE,
        ))
    }
}

/// Writes `out/index.html` for a run: a compare's page, or a sweep's.
pub fn write_page(out: &Path, report: &RunReport) -> Result<()> {
    let page = match report.sweep() {
        Some(sweep) => sweep_page(report, sweep),
        None => compare_page(report),
    };
    write(out, &page)
}

/// The problems a page lists first: errors, panics and rows with NaN pixels.
fn problems(report: &RunReport) -> Vec<String> {
    let mut problems = report.errors.clone();
    problems.extend(report.panics.iter().map(|p| format!("panic: {p}")));
    problems.extend(
        report
            .rows
            .iter()
            .filter(|r| r.nan_pixels.is_some_and(|n| n > 0))
            .map(|r| {
                format!(
                    "{} / {}: {} NaN or infinite pixels (magenta in the comparison)",
                    r.scene,
                    r.technique,
                    r.nan_pixels.unwrap_or(0)
                )
            }),
    );
    problems
}

/// What a shard's page says of itself.
fn shard_note(report: &RunReport) -> String {
    match report.shard {
        Some(shard) => format!(", shard {shard} of the plan"),
        None => String::new(),
    }
}

fn compare_page(report: &RunReport) -> Page<'_> {
    let groups = compare_groups(report);
    Page {
        title: "harness compare".into(),
        summary: format!(
            "{} scenes, {} results, {} failures, {} skipped (listed under the table), at {} on {}{}",
            groups.len(),
            report.rows.len(),
            report.errors.len(),
            report.skipped.len(),
            report.size,
            report.adapter.name,
            shard_note(report)
        ),
        groups,
        rows: &report.rows,
        swept: false,
        problems: problems(report),
        skipped: report
            .skipped
            .iter()
            .map(|s| format!("{} / {}: {}", s.scene, s.technique, s.reason))
            .collect(),
        notes: report.scene_notes.clone(),
        provenance: report.provenance.rows(
            &report.adapter,
            &report.size,
            format!(
                "{} timed (fewer where the timed budget ran out: see each row), {} warm-up, {} error frames along the path",
                report.frames, report.warmup, report.error_frames
            ),
        ),
    }
}

fn sweep_page<'a>(report: &'a RunReport, sweep: &SweepInfo) -> Page<'a> {
    let group = sweep_group(report, sweep);
    Page {
        title: format!("harness sweep: {}", group.title),
        summary: format!(
            "{} values of {} ({} parameter), {} failures, at {} on {}{}",
            report.rows.len(),
            sweep.param,
            match sweep.owner {
                ParamOwner::Technique => "technique",
                ParamOwner::Scene => "scene",
            },
            report.errors.len(),
            report.size,
            report.adapter.name,
            shard_note(report)
        ),
        groups: vec![group],
        rows: &report.rows,
        swept: true,
        problems: problems(report),
        skipped: Vec::new(),
        notes: report.scene_notes.clone(),
        provenance: report.provenance.rows(
            &report.adapter,
            &report.size,
            format!("{} timed, {} warm-up", report.frames, report.warmup),
        ),
    }
}

fn write(out: &Path, page: &Page) -> Result<()> {
    let path = out.join("index.html");
    std::fs::write(&path, page.html()?).with_context(|| format!("cannot write {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_cells_hold_the_csv_text_and_mark_failures() {
        let mut ok = ResultRow::new("s", "fam/a", crate::Size::new(4, 4), "x");
        ok.flip_mean_masked = Some(0.012_345_678_9);
        ok.psnr_db = Some(f64::INFINITY);
        ok.nan_pixels = Some(3);
        let failed =
            ResultRow::new("s", "fam/b", crate::Size::new(4, 4), "x").with_error("it <broke>");
        let html = results_table(&[ok, failed], false);
        assert!(
            html.contains(r#"<td data-v="0.0123456789">0.01235</td>"#),
            "{html}"
        );
        assert!(html.contains(r#"<td data-v="inf">inf</td>"#));
        assert!(html.contains(r#"<td data-v="3" class="bad">3</td>"#));
        assert!(html.contains(r#"class="has-nan""#) && html.contains(r#"class="failed""#));
        assert!(html.contains("it &lt;broke&gt;") && !html.contains("<broke>"));
        assert!(!html.contains(r#"data-col="param""#));
        assert_eq!(html.matches("<tr data-scene").count(), 2);
    }

    #[test]
    fn the_data_block_cannot_end_its_script_element() {
        let group = Group {
            title: "x</script><!--<script>".into(),
            anchor: "a".into(),
            times: vec![0.0],
            entries: Vec::new(),
            plots: Vec::new(),
            legend: Vec::new(),
        };
        let block = data_block(&[group]).unwrap();
        assert_eq!(block.matches('<').count(), 2, "{block}");
        assert!(block.ends_with("</script>") && block.contains(r"x\u003c/script>"));
    }

    #[test]
    fn families_are_the_id_before_the_slash() {
        assert_eq!(family("envmap/classic"), "envmap");
        assert_eq!(family("reference"), "reference");
    }
}
