//! Writing a run's output folder from the report model ([`RunReport`]), as often as the engine
//! asks: after every row the tables that hold it (`results.csv` and `results.json`; `sweep.*`
//! for a sweep), after every scene everything (the markdown table, `index.html`, the plots),
//! so that a run stopped at any point leaves every finished row readable. Each file is written
//! to a temporary name and renamed over the old one: a reader (or a crash) never sees half a
//! file.
//!
//! The images of a row are written once, by [`write_row_images`] and
//! [`write_reference_images`], which return the files for the report's `images`.

use crate::measure::ErrorFrame;
use crate::model::{ImageFrame, RunReport};
use crate::report::ResultRow;
use crate::{images, report, time_suffix};
use anyhow::{Context as _, Result, anyhow};
use std::path::{Path, PathBuf};

/// A run's output folder and the stem of its tables (`results` or `sweep`).
pub struct Output {
    pub dir: PathBuf,
    pub stem: &'static str,
}

impl Output {
    pub fn new(dir: &Path, stem: &'static str) -> Self {
        Output {
            dir: dir.to_path_buf(),
            stem,
        }
    }

    /// The path of the table file with `extension` (`results.csv`).
    pub fn table(&self, extension: &str) -> PathBuf {
        self.dir.join(format!("{}.{extension}", self.stem))
    }

    fn swept(report: &RunReport) -> bool {
        report.sweep().is_some()
    }

    /// The CSV and JSON tables: what every finished row is in at once.
    pub fn write_rows(&self, report: &RunReport) -> Result<()> {
        write_text(
            &self.table("csv"),
            &report::to_csv(&report.rows, Self::swept(report)),
        )?;
        let json = serde_json::to_string_pretty(report)
            .map_err(|e| anyhow!("cannot encode the results: {e}"))?;
        write_text(&self.table("json"), &json)
    }

    /// Everything but the sweep's plot: the tables, the markdown table, `wall.md` and
    /// `index.html`.
    pub fn write_all(&self, report: &RunReport) -> Result<()> {
        self.write_rows(report)?;
        write_text(&self.table("md"), &results_markdown(report))?;
        write_text(&self.dir.join("wall.md"), &wall_markdown(report))?;
        crate::html::write_page(&self.dir, report)
    }

    /// A sweep's `sweep.svg` (nothing for a compare), drawn once at the end of the run: the
    /// report's figures of the sweep one under the other.
    pub fn write_sweep_plot(&self, report: &RunReport) -> Result<()> {
        let Some(sweep) = report.sweep() else {
            return Ok(());
        };
        let figures = crate::html::sweep_plots(report, sweep);
        write_text(
            &self.dir.join("sweep.svg"),
            &crate::plot::file(&figures, &[]),
        )
    }
}

/// One scene's speed-ups, points and plot (`out/pareto/<dir_name>.svg`, written when the
/// tracer and at least one other technique were measured): what `compare` does after each
/// scene, and `harness pareto` for the rows of earlier runs. A plot that cannot be written is a
/// warning (returned), not an error.
pub fn write_pareto_scene(
    out: &Path,
    scene: &str,
    dir_name: &str,
    rows: &mut [ResultRow],
    adapter: &str,
) -> Result<(crate::pareto::ParetoScene, Option<String>)> {
    crate::pareto::set_speedups(rows);
    let mut points = crate::pareto::scene_points(scene, rows);
    let mut warning = None;
    if points.yardstick_ms.is_some() && points.points.len() > 1 {
        let file = format!("pareto/{dir_name}.svg");
        match write_pareto_plot(&out.join(&file), adapter, &points) {
            Ok(()) => points.plot = Some(file),
            Err(e) => warning = Some(format!("{scene}: {e:#}")),
        }
    }
    Ok((points, warning))
}

/// The scene's Pareto view as an SVG file: the report's figure (frame time on a log scale
/// across, error up, the front as a red staircase, the tracer in blue, each point numbered),
/// then the numbers' legend with the adapter.
fn write_pareto_plot(path: &Path, adapter: &str, scene: &crate::pareto::ParetoScene) -> Result<()> {
    let figure = crate::plot::pareto(scene)
        .ok_or_else(|| anyhow!("no technique with a frame time and an error"))?;
    let mut legend = crate::plot::pareto_legend(scene);
    legend.push(format!("measured on {adapter}"));
    let text = crate::plot::file(&[figure], &legend);
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| anyhow!("cannot create {}: {e}", dir.display()))?;
    }
    std::fs::write(path, text).map_err(|e| anyhow!("cannot write {}: {e}", path.display()))
}

/// Where the run's wall-clock time went (`wall.md`): what made the run, then the time by
/// family and by scene, then per scene its references and rows, per row its steps (prepare,
/// frames, metrics, writing). The harness's own cost, for whoever makes the run faster; not a
/// figure of any technique.
pub fn wall_markdown(report: &RunReport) -> String {
    let mut out = String::from("# Where the run's wall-clock time went\n\n");
    out.push_str(&provenance_markdown(report));
    out.push_str(&wall_totals(report));
    out.push_str("\n## By family\n\n");
    out.push_str(&wall_by_family(report));
    out.push_str("\n## By scene\n\n");
    out.push_str(&wall_by_scene(report));
    out.push_str("\n## Per row\n\n");
    out.push_str(&wall_per_row(report));
    out
}

/// A row's name in `wall.md`: its technique, the swept value, or the row whose frames it was
/// measured in.
fn wall_row_name(r: &ResultRow) -> String {
    match (&r.value, &r.measured_with) {
        (Some(v), _) => format!("{} {}={v}", r.technique, r.param.as_deref().unwrap_or("")),
        (None, Some(with)) => format!("{} (in {with}'s frames)", r.technique),
        (None, None) => r.technique.clone(),
    }
}

fn wall_totals(report: &RunReport) -> String {
    let rows_s: f64 = report.rows.iter().map(|r| r.wall.total_s()).sum();
    let references_s: f64 = report.scene_walls.iter().map(|w| w.reference_s).sum();
    let close_s: f64 = report.scene_walls.iter().map(|w| w.close_s).sum();
    format!(
        "\n{} rows: {rows_s:.1} s; references: {references_s:.1} s; Pareto views and files \
         after each scene: {close_s:.1} s; together {:.1} s (the process's start, its device and \
         the scenes' loading are outside it)\n",
        report.rows.len(),
        rows_s + references_s + close_s
    )
}

/// Seconds per step summed over `rows`, and their total.
fn summed_walls<'a>(rows: impl Iterator<Item = &'a ResultRow>) -> (usize, [f64; 5]) {
    let mut n = 0;
    let mut s = [0.0; 5];
    for r in rows {
        n += 1;
        let w = r.wall;
        for (acc, v) in
            s.iter_mut()
                .zip([w.prepare_s, w.frames_s, w.metrics_s, w.write_s, w.total_s()])
        {
            *acc += v;
        }
    }
    (n, s)
}

fn wall_by_family(report: &RunReport) -> String {
    let all_s = summed_walls(report.rows.iter()).1[4].max(1e-9);
    let mut families: Vec<&str> = report
        .rows
        .iter()
        .map(|r| crate::technique_family(&r.technique))
        .collect();
    families.sort_unstable();
    families.dedup();
    let mut sums: Vec<(&str, usize, [f64; 5])> = families
        .into_iter()
        .map(|family| {
            let rows = report
                .rows
                .iter()
                .filter(|r| crate::technique_family(&r.technique) == family);
            let (n, s) = summed_walls(rows);
            (family, n, s)
        })
        .collect();
    sums.sort_by(|a, b| b.2[4].total_cmp(&a.2[4]));
    let mut out = String::from(
        "| family | rows | prepare s | frames s | metrics s | write s | total s | share of rows |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for (family, n, s) in sums {
        out.push_str(&format!(
            "| {family} | {n} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.0} % |\n",
            s[0],
            s[1],
            s[2],
            s[3],
            s[4],
            100.0 * s[4] / all_s
        ));
    }
    out
}

fn wall_by_scene(report: &RunReport) -> String {
    let mut out = String::from(
        "| scene | references s | rows | rows s | files s | total s |\n| --- | --- | --- | --- | --- | --- |\n",
    );
    for wall in &report.scene_walls {
        let (n, s) = summed_walls(report.rows.iter().filter(|r| r.scene == wall.scene));
        out.push_str(&format!(
            "| {} | {:.1} | {n} | {:.1} | {:.1} | {:.1} |\n",
            wall.scene,
            wall.reference_s,
            s[4],
            wall.close_s,
            wall.reference_s + s[4] + wall.close_s
        ));
    }
    out
}

fn wall_per_row(report: &RunReport) -> String {
    let mut out = String::from(
        "| scene | row | prepare s | frames s | metrics s | write s | total s |\n| --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for wall in &report.scene_walls {
        out.push_str(&format!(
            "| {} | references | | | | | {:.2} |\n",
            wall.scene, wall.reference_s
        ));
        for r in report.rows.iter().filter(|r| r.scene == wall.scene) {
            let w = r.wall;
            out.push_str(&format!(
                "| {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |\n",
                r.scene,
                wall_row_name(r),
                w.prepare_s,
                w.frames_s,
                w.metrics_s,
                w.write_s,
                w.total_s()
            ));
        }
        out.push_str(&format!(
            "| {} | Pareto view, files written | | | | | {:.2} |\n",
            wall.scene, wall.close_s
        ));
    }
    out
}

/// What made the run, as a markdown list: command line, commit, date, adapter, size, frames,
/// reference, drivers.
fn provenance_markdown(report: &RunReport) -> String {
    let frames = format!(
        "{} timed, {} warm-up, {} error frames",
        report.frames, report.warmup, report.error_frames
    );
    report
        .provenance
        .markdown(&report.adapter, &report.size, frames)
}

/// `results.md`: what made the run, then the markdown table, so that a copy of the file says
/// where its figures come from.
pub fn results_markdown(report: &RunReport) -> String {
    let title = if report.sweep().is_some() {
        "Sweep"
    } else {
        "Results"
    };
    format!(
        "# {title}\n\n{}\n{}",
        provenance_markdown(report),
        markdown(report)
    )
}

/// The rows of `report` whose technique is one of `techniques` (an id with or without its
/// parameters, or a family: every id under it), written as `results.md` writes a run: what
/// made the run, a line saying which rows `command` picked from which file, then the table. A
/// crate's evidence is regenerated this way from a run's `results.json` instead of being
/// copied by hand. A technique that no row has is an error naming the ones there are.
pub fn selected_markdown(
    report: &RunReport,
    techniques: &[String],
    file: &str,
    command: &str,
) -> Result<String> {
    if let Some(t) = techniques
        .iter()
        .find(|t| !report.rows.iter().any(|r| technique_is(&r.technique, t)))
    {
        let there: std::collections::BTreeSet<&str> = report
            .rows
            .iter()
            .map(|r| r.technique.split(':').next().unwrap_or_default())
            .collect();
        let there: Vec<&str> = there.into_iter().collect();
        anyhow::bail!(
            "no row of {file} is of \"{t}\"; its rows are of {}",
            there.join(", ")
        );
    }
    let rows: Vec<ResultRow> = report
        .rows
        .iter()
        .filter(|r| techniques.iter().any(|t| technique_is(&r.technique, t)))
        .cloned()
        .collect();
    let title = if report.sweep().is_some() {
        "Sweep"
    } else {
        "Results"
    };
    Ok(format!(
        "# {title}\n\n{}- rows: those of {}, picked from {file} by `{command}`\n\n{}",
        provenance_markdown(report),
        techniques.join(", "),
        report::to_markdown(&rows, report.sweep().is_some())
    ))
}

/// Whether a row's technique label (`id` or `id:name=value,...`) is `wanted`: that id, that
/// label, or a variant of that family.
fn technique_is(label: &str, wanted: &str) -> bool {
    let id = label.split(':').next().unwrap_or_default();
    label == wanted || id == wanted || id.starts_with(&format!("{wanted}/"))
}

/// The markdown table of a report.
pub fn markdown(report: &RunReport) -> String {
    report::to_markdown(&report.rows, report.sweep().is_some())
}

/// Writes `text` to `path` through a temporary file renamed over it.
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let temporary = path.with_file_name(format!(".{name}.partial"));
    std::fs::write(&temporary, text)
        .with_context(|| format!("cannot write {}", temporary.display()))?;
    std::fs::rename(&temporary, path).with_context(|| format!("cannot write {}", path.display()))
}

/// The file stem of an error frame's images: `stem` at the first time, `stem.t<time>` after.
pub fn frame_stem(stem: &str, index: usize, time: f32) -> String {
    match index {
        0 => stem.to_string(),
        _ => format!("{stem}{}", time_suffix(time)),
    }
}

/// Writes one error frame's PNG and HDR copy (and the EXR at the first time) as
/// `<out>/<rel_dir>/<stem>[.t<time>]`.
fn write_frame(
    out: &Path,
    rel_dir: &str,
    stem: &str,
    index: usize,
    time: f32,
    image: &gpu::HdrImage,
) -> Result<ImageFrame> {
    let name = format!("{rel_dir}/{}", frame_stem(stem, index, time));
    images::write_png(&out.join(format!("{name}.png")), image)?;
    images::write_hdr_script(&out.join(format!("{name}.hdr.js")), image)?;
    if index == 0 {
        images::write_exr(&out.join(format!("{name}.exr")), image)?;
    }
    Ok(ImageFrame {
        time,
        png: format!("{name}.png"),
        flip: None,
        hdr: format!("{name}.hdr.js"),
    })
}

/// Writes a technique's error frames under `<out>/<rel_dir>`: `<stem>.png`, `.hdr.js`, `.exr`
/// and `.flip.png` of the first, `<stem>.t<time>.png`, `.hdr.js` and `.flip.png` of the later
/// ones (the FLIP maps where `flips` has them); returns them.
pub fn write_row_images(
    out: &Path,
    rel_dir: &str,
    stem: &str,
    frames: &[ErrorFrame],
    flips: &[truth::metrics::FlipMap],
) -> Result<Vec<ImageFrame>> {
    let mut written = Vec::new();
    for (i, frame) in frames.iter().enumerate() {
        let mut files = write_frame(out, rel_dir, stem, i, frame.time, &frame.image)?;
        if let Some(map) = flips.get(i) {
            let flip = format!("{rel_dir}/{}.flip.png", frame_stem(stem, i, frame.time));
            images::write_png_rgb8(
                &out.join(&flip),
                map.width,
                map.height,
                &map.to_magma_rgb8(),
            )?;
            files.flip = Some(flip);
        }
        written.push(files);
    }
    Ok(written)
}

/// Writes the references' images under `<out>/<rel_dir>`: `<stem>.png`, `.hdr.js` and `.exr`
/// at the first time, `<stem>.t<time>.png` and `.hdr.js` after; returns them.
pub fn write_reference_images(
    out: &Path,
    rel_dir: &str,
    stem: &str,
    references: &[(f32, &gpu::HdrImage)],
) -> Result<Vec<ImageFrame>> {
    references
        .iter()
        .enumerate()
        .map(|(i, (time, image))| write_frame(out, rel_dir, stem, i, *time, image))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_technique_is_its_id_its_label_or_a_variant_of_its_family() {
        for (label, wanted) in [
            ("impostors/secant-4", "impostors/secant-4"),
            ("impostors/secant-4", "impostors"),
            ("impostors/secant-4:iterations=2", "impostors/secant-4"),
            (
                "impostors/secant-4:iterations=2",
                "impostors/secant-4:iterations=2",
            ),
            ("impostors/secant-4:iterations=2", "impostors"),
            ("raster", "raster"),
        ] {
            assert!(technique_is(label, wanted), "{label} is {wanted}");
        }
        for (label, wanted) in [
            ("impostors/secant-4", "impostor"),
            ("impostors/secant-4", "impostors/secant"),
            (
                "impostors/secant-4:iterations=2",
                "impostors/secant-4:iterations=4",
            ),
            ("raster", "raytracer"),
        ] {
            assert!(!technique_is(label, wanted), "{label} is not {wanted}");
        }
    }

    #[test]
    fn plots_are_written() {
        let rows = vec![
            ResultRow {
                technique: crate::pareto::YARDSTICK.into(),
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
        let scene = crate::pareto::scene_points("test", &rows);
        assert_eq!(scene.points[0].error, 0.0);
        assert_eq!(scene.points[0].measured_error, 0.002);
        assert!(scene.points.iter().all(|p| p.on_front));
        let path = std::env::temp_dir().join("harness-pareto-test/plot.svg");
        write_pareto_plot(&path, "test adapter", &scene).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        assert!(
            svg.starts_with("<?xml") && svg.ends_with("</svg>\n"),
            "{svg}"
        );
        for text in [
            "1 raytracer/caustics: 40 ms",
            "2 raster: 2 ms",
            "measured on test adapter",
        ] {
            assert!(svg.contains(text), "{text} missing: {svg}");
        }
        assert!(svg.contains("<style>") && svg.contains("class=\"front\""));
    }
}
