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
use crate::plot::{self, PlotPoint, PlotText};
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
        write_text(&self.table("md"), &markdown(report))?;
        write_text(&self.dir.join("wall.md"), &wall_markdown(report))?;
        crate::html::write_page(&self.dir, report)
    }

    /// A sweep's `sweep.png` (nothing for a compare), drawn once at the end of the run; notes
    /// in the report whether it has text.
    pub fn write_sweep_plot(&self, report: &mut RunReport) -> Result<()> {
        let Some(sweep) = report.sweep() else {
            return Ok(());
        };
        let points: Vec<PlotPoint> = report
            .rows
            .iter()
            .map(|r| PlotPoint {
                value: r.value.clone().unwrap_or_default(),
                flip_mean: r.flip_mean,
                rmse: r.rmse,
                frame_ms: r.frame_ms_median,
            })
            .collect();
        let title = format!(
            "{} on {} over {}",
            sweep.technique, sweep.scene, sweep.param
        );
        let text = plot::sweep_plot(&self.dir.join("sweep.png"), &title, &sweep.param, &points)?;
        report.plot_has_text = text == PlotText::Drawn;
        Ok(())
    }
}

/// Where the run's wall-clock time went (`wall.md`): per scene its references and rows, per
/// row its steps (prepare, frames, metrics, writing), then the totals. The harness's own cost,
/// for whoever makes the run faster; not a figure of any technique.
pub fn wall_markdown(report: &RunReport) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let (mut rows_s, mut references_s, mut close_s) = (0.0, 0.0, 0.0);
    let _ = writeln!(
        out,
        "| scene | row | prepare s | frames s | metrics s | write s | total s |\n| --- | --- | --- | --- | --- | --- | --- |"
    );
    for wall in &report.scene_walls {
        references_s += wall.reference_s;
        close_s += wall.close_s;
        let _ = writeln!(
            out,
            "| {} | references | | | | | {:.2} |",
            wall.scene, wall.reference_s
        );
        for r in report.rows.iter().filter(|r| r.scene == wall.scene) {
            let w = r.wall;
            rows_s += w.total_s();
            let name = match (&r.value, &r.measured_with) {
                (Some(v), _) => format!("{} {}={v}", r.technique, r.param.as_deref().unwrap_or("")),
                (None, Some(with)) => format!("{} (in {with}'s frames)", r.technique),
                (None, None) => r.technique.clone(),
            };
            let _ = writeln!(
                out,
                "| {} | {name} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
                r.scene,
                w.prepare_s,
                w.frames_s,
                w.metrics_s,
                w.write_s,
                w.total_s()
            );
        }
        let _ = writeln!(
            out,
            "| {} | Pareto view, files written | | | | | {:.2} |",
            wall.scene, wall.close_s
        );
    }
    let _ = writeln!(
        out,
        "\n{} rows: {rows_s:.1} s; references: {references_s:.1} s; Pareto views and files \
         after each scene: {close_s:.1} s; together {:.1} s",
        report.rows.len(),
        rows_s + references_s + close_s
    );
    out
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
