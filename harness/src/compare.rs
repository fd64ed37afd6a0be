//! `harness compare`: every supported (scene, technique) pair against the reference.
//!
//! Writes, under the output folder:
//!
//! - `results.csv`, `results.json`, `results.md` (see [`crate::report`]);
//! - `images/<scene>/<technique>.png` and `.exr` (the error frame: default view, time 0),
//!   `images/<scene>/<technique>.flip.png` (FLIP error map, magma colour map),
//!   `images/<scene>/reference.png` and `.exr`;
//! - `.cache/` with the references (see [`crate::cache`]).
//!
//! `<scene>` and `<technique>` are made file names by [`crate::file_name`] (`/` becomes `__`).
//! A technique whose `supports(scene)` is false is skipped quietly; one whose required
//! features the adapter lacks is skipped with the reason printed; both are listed under
//! `skipped` in `results.json`. A technique that fails (an error, a GPU validation error or a
//! panic) gets a row with the error and the run goes on. If the reference fails, the rows of
//! that scene have timings but no error figures, and the reason is in `results.json`.

use crate::cache::{self, RefView};
use crate::report::{self, AdapterJson, ResultRow, Skipped};
use crate::run::{self, TechniqueRun};
use crate::{
    Env, Frames, Reference, ReferenceStats, Size, backend, file_name, images, scene_dir_name,
};
use anyhow::{Context as _, Result, anyhow};
use scene::{GpuScene, Scene, Technique};
use std::path::{Path, PathBuf};

/// What to compare.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    pub out: PathBuf,
    /// Scene specs (built-in or paths); every built-in scene when empty.
    pub scenes: Vec<String>,
    /// Technique ids or families; every registered technique when `None`.
    pub techniques: Option<Vec<String>>,
    pub size: Size,
    pub frames: Frames,
}

/// How a scene's reference went.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ReferenceInfo {
    pub scene: String,
    pub cached: bool,
    pub stats: Option<ReferenceStats>,
    pub masked_pixels: usize,
    pub error: Option<String>,
}

/// Everything a compare run produced (also written to `results.json`).
#[derive(Clone, Debug, serde::Serialize)]
pub struct CompareReport {
    pub adapter: AdapterJson,
    pub size: String,
    pub frames: u32,
    pub warmup: u32,
    pub rows: Vec<ResultRow>,
    pub skipped: Vec<Skipped>,
    pub references: Vec<ReferenceInfo>,
    /// Every error of the run, one line each ("scene / technique: message").
    pub errors: Vec<String>,
    #[serde(skip)]
    pub markdown: String,
}

/// A one-line message of a caught panic.
pub(crate) fn panic_message(payload: Box<dyn std::any::Any + Send>) -> String {
    let text = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into());
    format!("panicked: {}", text.lines().next().unwrap_or(""))
}

/// The result of one technique on one scene, as the runners share it.
pub(crate) struct Outcome {
    pub row: ResultRow,
    pub run: Option<TechniqueRun>,
    pub flip: Option<scene::metrics::FlipMap>,
}

/// Runs one technique on an uploaded scene at the row's size, measures it against
/// `reference`, and fills the row. Errors and panics end up in the row.
pub(crate) fn measure(
    env: &Env,
    technique: &mut dyn Technique,
    gpu_scene: &mut GpuScene,
    reference: Option<&Reference>,
    frames: Frames,
    row: ResultRow,
    on_frame: &mut dyn FnMut(&str),
) -> Outcome {
    let size = Size::new(row.width, row.height);
    // The `reference` technique is the ground truth itself: instead of rendering it again for
    // every warm-up and timed frame (seconds each on the CPU), its row reuses the (cached)
    // ground-truth image and reports the CPU time that image took as one frame.
    if technique.id() == "reference" {
        if let Some(r) = reference {
            let ms = r.stats.seconds * 1e3;
            let run = TechniqueRun {
                image: r.image.clone(),
                timer: "cpu".into(),
                frame: gpu::TimeStats {
                    median_ms: ms,
                    p95_ms: ms,
                    samples: 1,
                },
                prepare_ms: 0.0,
                prepare_wall_ms: 0.0,
                spans_ms: Default::default(),
            };
            let (m, map) = scene::metrics::compare(&run.image, &r.image, Some(&r.mask));
            let row = row.with_run(&run).with_metrics(&m);
            return Outcome {
                row,
                run: Some(run),
                flip: Some(map),
            };
        }
    }
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        run::run_technique(env.ctx, technique, gpu_scene, size, frames, on_frame)
    }));
    let run = match result {
        Ok(Ok(run)) => run,
        Ok(Err(e)) => {
            return Outcome {
                row: row.with_error(format!("{e:#}")),
                run: None,
                flip: None,
            };
        }
        Err(p) => {
            return Outcome {
                row: row.with_error(panic_message(p)),
                run: None,
                flip: None,
            };
        }
    };
    let mut row = row.with_run(&run);
    let mut flip = None;
    if let Some(r) = reference {
        let view = scene::View {
            camera: gpu_scene.scene.camera,
            time: 0.0,
            width: size.width,
            height: size.height,
        };
        let truth = technique.ground_truth(&gpu_scene.scene, &view, &r.image);
        let (m, map) = scene::metrics::compare(
            &run.image,
            truth.as_ref().unwrap_or(&r.image),
            Some(&r.mask),
        );
        row = row.with_metrics(&m);
        flip = Some(map);
    }
    Outcome {
        row,
        run: Some(run),
        flip,
    }
}

/// Writes a technique's images: `<stem>.png`, `<stem>.exr` and `<stem>.flip.png`.
pub(crate) fn write_outcome_images(dir: &Path, stem: &str, outcome: &Outcome) -> Result<()> {
    if let Some(run) = &outcome.run {
        images::write_png(&dir.join(format!("{stem}.png")), &run.image)?;
        images::write_exr(&dir.join(format!("{stem}.exr")), &run.image)?;
    }
    if let Some(map) = &outcome.flip {
        images::write_png_rgb8(
            &dir.join(format!("{stem}.flip.png")),
            map.width,
            map.height,
            &map.to_magma_rgb8(),
        )?;
    }
    Ok(())
}

/// Loads every scene spec first, so a bad one fails before any GPU work.
pub(crate) fn load_scenes(specs: &[String]) -> Result<Vec<(String, Scene)>> {
    specs
        .iter()
        .map(|s| crate::load_scene(s).map(|scene| (s.clone(), scene)))
        .collect()
}

/// The reference of a scene's default view at time 0, through the cache.
pub(crate) fn scene_reference(
    env: &Env,
    out: &Path,
    spec: &str,
    scene: &Scene,
    size: Size,
) -> Result<(Reference, bool)> {
    let view = RefView {
        spec,
        scene,
        camera: scene.camera,
        time: 0.0,
        size,
    };
    cache::reference(&out.join(".cache"), env.ground_truth, &view)
}

/// Runs the comparison (see the module documentation) and writes every file.
pub fn run(env: &Env, opts: &CompareOptions) -> Result<CompareReport> {
    let all_ids: Vec<String> = (env.techniques)().iter().map(|t| t.id()).collect();
    let selected = crate::select_techniques(&all_ids, opts.techniques.as_deref())?;
    let specs = if opts.scenes.is_empty() {
        crate::builtin_scene_names()
    } else {
        opts.scenes.clone()
    };
    let scenes = load_scenes(&specs)?;
    env.ctx.check_size(opts.size.width, opts.size.height)?;
    std::fs::create_dir_all(&opts.out)
        .with_context(|| format!("cannot create {}", opts.out.display()))?;

    let adapter = AdapterJson::of(env.ctx);
    let adapter_name = env.ctx.summary.name.clone();
    let mut report = CompareReport {
        adapter,
        size: opts.size.to_string(),
        frames: opts.frames.timed,
        warmup: opts.frames.warmup,
        rows: Vec::new(),
        skipped: Vec::new(),
        references: Vec::new(),
        errors: Vec::new(),
        markdown: String::new(),
    };
    let bar = crate::progress_bar(env.progress, (scenes.len() * (selected.len() + 1)) as u64);
    let say = |bar: &indicatif::ProgressBar, line: String| bar.suspend(|| eprintln!("{line}"));

    for (spec, scene) in &scenes {
        let dir = opts.out.join("images").join(scene_dir_name(spec));
        bar.set_message(format!("{spec}: reference"));
        let reference = match scene_reference(env, &opts.out, spec, scene, opts.size) {
            Ok((r, cached)) => {
                images::write_png(&dir.join("reference.png"), &r.image)?;
                images::write_exr(&dir.join("reference.exr"), &r.image)?;
                report.references.push(ReferenceInfo {
                    scene: spec.clone(),
                    cached,
                    stats: Some(r.stats.clone()),
                    masked_pixels: r.mask.iter().filter(|&&m| m).count(),
                    error: None,
                });
                Some(r)
            }
            Err(e) => {
                let msg = format!("{spec} / reference: {e:#}");
                say(&bar, format!("error: {msg}"));
                report.errors.push(msg);
                report.references.push(ReferenceInfo {
                    scene: spec.clone(),
                    cached: false,
                    stats: None,
                    masked_pixels: 0,
                    error: Some(format!("{e:#}")),
                });
                None
            }
        };
        bar.inc(1);

        let techniques: Vec<Box<dyn Technique>> = (env.techniques)()
            .into_iter()
            .filter(|t| selected.contains(&t.id()))
            .collect();
        let mut gpu_scene: Option<GpuScene> = None;
        let mut upload_error: Option<String> = None;
        // Each technique is dropped (pipelines, maps) as soon as its row is measured: a
        // driver's shader cache then holds only the running technique's shaders. On lavapipe,
        // keeping every technique's pipelines alive made later techniques up to 10x slower
        // (llvmpipe evicts and recompiles shader variants once its cache is full).
        for mut technique in techniques {
            let id = technique.id();
            let row = ResultRow::new(spec, &id, opts.size, &adapter_name);
            if !technique.supports(scene) {
                report.skipped.push(Skipped {
                    scene: spec.clone(),
                    technique: id,
                    reason: "does not support this scene".into(),
                });
                bar.inc(1);
                continue;
            }
            if let Err(e) = env.ctx.require(technique.required_features()) {
                say(&bar, format!("skipped: {spec} / {id}: {e}"));
                report.skipped.push(Skipped {
                    scene: spec.clone(),
                    technique: id,
                    reason: e.to_string(),
                });
                bar.inc(1);
                continue;
            }
            if gpu_scene.is_none() && upload_error.is_none() {
                bar.set_message(format!("{spec}: uploading"));
                match backend::upload_scene(env.ctx, scene) {
                    Ok(s) => gpu_scene = Some(s),
                    Err(e) => {
                        let msg = format!("{spec} / upload: {e:#}");
                        say(&bar, format!("error: {msg}"));
                        report.errors.push(msg);
                        upload_error = Some(format!("scene upload failed: {e:#}"));
                    }
                }
            }
            let Some(gs) = gpu_scene.as_mut() else {
                report
                    .rows
                    .push(row.with_error(upload_error.clone().unwrap_or_default()));
                bar.inc(1);
                continue;
            };
            let mut on_frame = |step: &str| bar.set_message(format!("{spec} / {id}: {step}"));
            let outcome = measure(
                env,
                technique.as_mut(),
                gs,
                reference.as_ref(),
                opts.frames,
                row,
                &mut on_frame,
            );
            write_outcome_images(&dir, &file_name(&id), &outcome)?;
            if let Some(err) = &outcome.row.error {
                let msg = format!("{spec} / {id}: {err}");
                say(&bar, format!("error: {msg}"));
                report.errors.push(msg);
            } else if let Some(n) = outcome.row.nan_pixels.filter(|&n| n > 0) {
                say(
                    &bar,
                    format!("warning: {spec} / {id}: {n} NaN or infinite pixels"),
                );
            }
            report.rows.push(outcome.row);
            bar.inc(1);
        }
    }
    bar.finish_and_clear();

    report.markdown = report::to_markdown(&report.rows, false);
    write_text(
        &opts.out.join("results.csv"),
        &report::to_csv(&report.rows, false),
    )?;
    write_text(&opts.out.join("results.md"), &report.markdown)?;
    write_text(
        &opts.out.join("results.json"),
        &serde_json::to_string_pretty(&report)
            .map_err(|e| anyhow!("cannot encode results: {e}"))?,
    )?;
    Ok(report)
}

pub(crate) fn write_text(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}
