//! `harness compare`: every supported (scene, technique) pair against the reference.
//!
//! Writes, under the output folder:
//!
//! - `results.csv`, `results.json`, `results.md` (see [`crate::report`]);
//! - `images/<scene>/<technique>.png` and `.exr` (the first error frame: the camera path's
//!   view at time 0), `images/<scene>/<technique>.flip.png` (FLIP error map, magma colour
//!   map), `images/<scene>/reference.png` and `.exr`; the later error frames along the camera
//!   path as `<technique>.t<time>.png`, `<technique>.t<time>.flip.png` and
//!   `reference.t<time>.png` (`.t1`, see [`crate::time_suffix`]); beside every PNG its HDR copy
//!   `.hdr.js` (see [`images::write_hdr_script`]), all listed in the report's `images`;
//! - `index.html`, the report a person reads (see [`crate::html`]);
//! - `.cache/` with the references (see [`crate::cache`]).
//!
//! `<scene>` and `<technique>` are made file names by [`crate::file_name`] (`/` becomes `__`).
//! A technique whose `supports(scene)` is false is skipped quietly; one whose required
//! features the adapter lacks is skipped with the reason printed; both are listed under
//! `skipped` in `results.json`. A technique that fails (an error, a GPU validation error or a
//! panic) gets a row with the error and the run goes on. If the reference fails, the rows of
//! that scene have timings but no error figures, and the reason is in `results.json`.

use crate::cache::{self, RefView};
use crate::pareto::{self, ParetoScene};
use crate::report::{self, AdapterJson, ErrorAt, ResultRow, Skipped};
use crate::run::{self, ErrorFrame, TechniqueRun};
use crate::{
    Env, Frames, Reference, ReferenceStats, Size, backend, file_name, images, time_suffix,
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
    /// Technique ids or families; when `None`, every registered technique that is
    /// [`Technique::representative`], or every one with `all_variants`.
    pub techniques: Option<Vec<String>>,
    /// Run every variant of every family, not just the representative ones (ignored when
    /// `techniques` names them).
    pub all_variants: bool,
    pub size: Size,
    pub frames: Frames,
}

/// How a scene's reference at one error-frame time went.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ReferenceInfo {
    pub scene: String,
    pub time: f32,
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
    /// Error frames asked for per row (fewer on a scene whose path is shorter: see each
    /// row's `error_times`).
    pub error_frames: u32,
    pub rows: Vec<ResultRow>,
    pub skipped: Vec<Skipped>,
    pub references: Vec<ReferenceInfo>,
    /// Per scene spec: the folder under `images/` its images are in (unique within the run).
    pub image_dirs: std::collections::BTreeMap<String, String>,
    /// What the glTF importer supplied or repaired, per scene ("scene: note"): default
    /// lighting for a file without lights, replaced normals.
    pub scene_notes: Vec<String>,
    /// Every error of the run, one line each ("scene / technique: message").
    pub errors: Vec<String>,
    /// The rows whose technique panicked ("scene / technique: message"). A panic is a defect
    /// even where it is caught: the binary exits non-zero when this is not empty.
    pub panics: Vec<String>,
    /// Per scene: error against frame time, and which techniques are on the front
    /// (`crate::pareto`; the plot under `pareto/`).
    pub pareto: Vec<ParetoScene>,
    /// Every image file the run wrote, per ground truth and technique (the report shows these).
    pub images: Vec<WrittenImages>,
    #[serde(skip)]
    pub markdown: String,
}

/// The start of the error of a row whose technique panicked.
pub const PANICKED: &str = "panicked: ";

/// A one-line message of a caught panic (it starts with [`PANICKED`]).
pub(crate) fn panic_message(payload: Box<dyn std::any::Any + Send>) -> String {
    let text = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into());
    format!("{PANICKED}{}", text.lines().next().unwrap_or(""))
}

/// Share of pixels that must show light (a channel above [`LIT_RADIANCE`]) for a reference
/// to be scored against: below it the reference is (nearly) black, and every technique that
/// draws black too would score a perfect, meaningless, 0 error.
pub const MIN_LIT_SHARE: f64 = 0.01;
/// Linear radiance above which a reference pixel counts as lit (sRGB 8-bit value 3).
pub const LIT_RADIANCE: f32 = 1e-3;

/// `Some(reason)` when `image` is too dark to score against (see [`MIN_LIT_SHARE`]).
pub fn black_reference(image: &gpu::HdrImage) -> Option<String> {
    let lit = image
        .pixels
        .iter()
        .filter(|p| p[..3].iter().any(|&c| c > LIT_RADIANCE))
        .count();
    let share = lit as f64 / image.pixels.len().max(1) as f64;
    (share < MIN_LIT_SHARE).then(|| {
        format!(
            "invalid comparison: the reference is (nearly) black ({:.2}% of pixels above \
             {LIT_RADIANCE} radiance, {}% needed), so no error is scored; does the scene \
             have lights that reach what the camera sees?",
            share * 100.0,
            MIN_LIT_SHARE * 100.0
        )
    })
}

/// The reference at one error-frame time.
pub(crate) struct TimedReference {
    pub time: f32,
    pub reference: Reference,
}

/// The result of one technique on one scene, as the runners share it.
pub(crate) struct Outcome {
    pub row: ResultRow,
    pub run: Option<TechniqueRun>,
    /// FLIP maps of the error frames, in their order (empty without a reference).
    pub flips: Vec<truth::metrics::FlipMap>,
}

/// Runs one technique on an uploaded scene at the row's size, measures each error frame
/// against the reference at its time, and fills the row. Errors and panics end up in the row.
/// `references` holds the scene's references at `frames.error_times` (empty: none).
pub(crate) fn measure(
    env: &Env,
    technique: &mut dyn Technique,
    gpu_scene: &mut GpuScene,
    references: &[TimedReference],
    frames: Frames,
    row: ResultRow,
    on_frame: &mut dyn FnMut(&str, usize, usize),
) -> Outcome {
    let size = Size::new(row.width, row.height);
    // The `reference` technique is the ground truth itself: instead of rendering it again for
    // every warm-up and timed frame (seconds each on the CPU), its row reuses the (cached)
    // ground-truth images and reports the CPU time the first took as one frame.
    if technique.id() == "reference" && !references.is_empty() {
        let ms = references[0].reference.stats.seconds * 1e3;
        let run = TechniqueRun {
            error_frames: references
                .iter()
                .map(|r| ErrorFrame {
                    time: r.time,
                    image: r.reference.image.clone(),
                })
                .collect(),
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
        return score(technique, &gpu_scene.scene, references, row, run);
    }
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        run::run_technique(env.ctx, technique, gpu_scene, size, frames, on_frame)
    }));
    let run = match result {
        Ok(Ok(run)) => Ok(run),
        Ok(Err(e)) => Err(format!("{e:#}")),
        Err(p) => Err(panic_message(p)),
    };
    match run {
        Ok(run) => score(technique, &gpu_scene.scene, references, row, run),
        Err(message) => Outcome {
            row: row.with_error(message),
            run: None,
            flips: Vec::new(),
        },
    }
}

/// Fills the row with the run's times and, where references exist, each error frame's
/// figures against the reference at its time (through the technique's `ground_truth` hook).
fn score(
    technique: &dyn Technique,
    scene: &Scene,
    references: &[TimedReference],
    row: ResultRow,
    run: TechniqueRun,
) -> Outcome {
    let mut row = row.with_run(&run);
    if references.is_empty() {
        return Outcome {
            row,
            run: Some(run),
            flips: Vec::new(),
        };
    }
    if let Some(reason) = references
        .iter()
        .find_map(|r| black_reference(&r.reference.image))
    {
        return Outcome {
            row: row.with_error(reason),
            run: Some(run),
            flips: Vec::new(),
        };
    }
    let mut errors = Vec::new();
    let mut flips = Vec::new();
    for frame in &run.error_frames {
        let Some(r) = references.iter().find(|r| r.time == frame.time) else {
            return Outcome {
                row: row.with_error(format!("no reference at time {}", frame.time)),
                run: Some(run),
                flips,
            };
        };
        let view = scene::View {
            camera: scene.camera_at(frame.time),
            time: frame.time,
            width: row.width,
            height: row.height,
        };
        let reference = &r.reference;
        let truth = technique.ground_truth(scene, &view, &reference.image);
        let (m, map) = truth::metrics::compare(
            &frame.image,
            truth.as_ref().unwrap_or(&reference.image),
            Some(&reference.mask),
        );
        errors.push(ErrorAt::new(frame.time, &m));
        flips.push(map);
    }
    row = row.with_errors_along(errors);
    Outcome {
        row,
        run: Some(run),
        flips,
    }
}

/// The file stem of an error frame's images: `stem` at the first time, `stem.t<time>` after.
pub(crate) fn frame_stem(stem: &str, index: usize, time: f32) -> String {
    match index {
        0 => stem.to_string(),
        _ => format!("{stem}{}", time_suffix(time)),
    }
}

/// The files of one error frame of an image, relative to the output folder (what the report
/// shows: only what this run wrote).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ImageFrame {
    pub time: f32,
    pub png: String,
    /// The FLIP map (techniques with a reference only).
    pub flip: Option<String>,
    /// The HDR copy the report's exposure control reads ([`images::write_hdr_script`]).
    pub hdr: String,
}

/// The images a run wrote for one ground truth (`technique` None) or one technique's result.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct WrittenImages {
    pub scene: String,
    pub technique: Option<String>,
    /// The swept value (sweep only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub value: Option<String>,
    pub frames: Vec<ImageFrame>,
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

/// Writes a technique's images under `<out>/<rel_dir>`: `<stem>.png`, `.hdr.js`, `.exr` and
/// `.flip.png` of the first error frame, `<stem>.t<time>.png`, `.hdr.js` and `.flip.png` of the
/// later ones; returns them.
pub(crate) fn write_outcome_images(
    out: &Path,
    rel_dir: &str,
    stem: &str,
    outcome: &Outcome,
) -> Result<Vec<ImageFrame>> {
    let frames = outcome
        .run
        .as_ref()
        .map_or(&[][..], |r| &r.error_frames[..]);
    let mut written = Vec::new();
    for (i, frame) in frames.iter().enumerate() {
        let mut files = write_frame(out, rel_dir, stem, i, frame.time, &frame.image)?;
        if let Some(map) = outcome.flips.get(i) {
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

/// Writes the references' images under `<out>/<rel_dir>`: `<stem>.png`, `.hdr.js` and `.exr` at
/// the first time, `<stem>.t<time>.png` and `.hdr.js` after; returns them.
pub(crate) fn write_reference_images(
    out: &Path,
    rel_dir: &str,
    stem: &str,
    references: &[TimedReference],
) -> Result<Vec<ImageFrame>> {
    references
        .iter()
        .enumerate()
        .map(|(i, r)| write_frame(out, rel_dir, stem, i, r.time, &r.reference.image))
        .collect()
}

/// A loaded scene of a run: its spec, the model, the importer's notes.
pub(crate) struct LoadedScene {
    pub spec: String,
    pub scene: Scene,
    pub notes: Vec<String>,
}

/// Loads every scene spec first, so a bad one fails before any GPU work.
pub(crate) fn load_scenes(specs: &[String]) -> Result<Vec<LoadedScene>> {
    specs
        .iter()
        .map(|s| {
            crate::load_scene_noted(s).map(|(scene, notes)| LoadedScene {
                spec: s.clone(),
                scene,
                notes,
            })
        })
        .collect()
}

/// The reference of a scene's camera-path view at `time`, through the cache.
pub(crate) fn scene_reference(
    env: &Env,
    out: &Path,
    spec: &str,
    scene: &Scene,
    size: Size,
    time: f32,
) -> Result<(Reference, bool)> {
    let view = RefView {
        spec,
        scene,
        camera: scene.camera_at(time),
        time,
        size,
    };
    cache::reference(&out.join(".cache"), env.ground_truth, &view)
        .with_context(|| format!("reference at time {time}"))
}

/// The references at every error-frame time of `frames` on the scene's camera path, each with
/// whether it came from the cache.
pub(crate) fn path_references(
    env: &Env,
    out: &Path,
    spec: &str,
    scene: &Scene,
    size: Size,
    frames: Frames,
) -> Result<Vec<(TimedReference, bool)>> {
    frames
        .error_times_for(scene)
        .into_iter()
        .map(|time| {
            let (reference, cached) = scene_reference(env, out, spec, scene, size, time)?;
            Ok((TimedReference { time, reference }, cached))
        })
        .collect()
}

/// Runs the comparison (see the module documentation) and writes every file.
pub fn run(env: &Env, opts: &CompareOptions) -> Result<CompareReport> {
    let registered = (env.techniques)();
    let all_ids: Vec<String> = registered.iter().map(|t| t.id()).collect();
    let selected = match &opts.techniques {
        Some(wanted) => crate::select_techniques(&all_ids, Some(wanted))?,
        None if opts.all_variants => all_ids,
        None => registered
            .iter()
            .filter(|t| t.representative())
            .map(|t| t.id())
            .collect(),
    };
    let specs = if opts.scenes.is_empty() {
        crate::builtin_scene_names()
    } else {
        opts.scenes.clone()
    };
    let scenes = load_scenes(&specs)?;
    crate::limits::check_memory(env.ctx, opts.size, opts.frames)?;
    let _lock = crate::OutputLock::acquire(&opts.out)?;
    let dir_names = crate::scene_dir_names(&specs);

    let adapter = AdapterJson::of(env.ctx);
    let adapter_name = env.ctx.summary.name.clone();
    let mut report = CompareReport {
        adapter,
        size: opts.size.to_string(),
        frames: opts.frames.timed,
        warmup: opts.frames.warmup,
        error_frames: opts.frames.errors,
        rows: Vec::new(),
        skipped: Vec::new(),
        references: Vec::new(),
        image_dirs: specs
            .iter()
            .cloned()
            .zip(dir_names.iter().cloned())
            .collect(),
        scene_notes: Vec::new(),
        errors: Vec::new(),
        panics: Vec::new(),
        pareto: Vec::new(),
        images: Vec::new(),
        markdown: String::new(),
    };
    let progress = crate::Progress::new(env.progress);
    let say = |line: String| progress.say(&line);

    for (loaded, dir_name) in scenes.iter().zip(&dir_names) {
        let (spec, scene) = (&loaded.spec, &loaded.scene);
        let bar = progress.scene(spec, selected.len() as u64 + 1);
        let errors_before = report.errors.len();
        for note in &loaded.notes {
            say(format!("warning: {spec}: {note}"));
            report.scene_notes.push(format!("{spec}: {note}"));
        }
        let rel_dir = format!("images/{dir_name}");
        bar.set_message("reference");
        let references = match path_references(env, &opts.out, spec, scene, opts.size, opts.frames)
        {
            Ok(timed) => {
                for (r, cached) in &timed {
                    report.references.push(ReferenceInfo {
                        scene: spec.clone(),
                        time: r.time,
                        cached: *cached,
                        stats: Some(r.reference.stats.clone()),
                        masked_pixels: r.reference.mask.iter().filter(|&&m| m).count(),
                        error: None,
                    });
                }
                let timed: Vec<TimedReference> = timed.into_iter().map(|(r, _)| r).collect();
                let frames = write_reference_images(&opts.out, &rel_dir, "reference", &timed)?;
                report.images.push(WrittenImages {
                    scene: spec.clone(),
                    technique: None,
                    value: None,
                    frames,
                });
                timed
            }
            Err(e) => {
                let msg = format!("{spec} / reference: {e:#}");
                say(format!("error: {msg}"));
                report.errors.push(msg);
                report.references.push(ReferenceInfo {
                    scene: spec.clone(),
                    time: 0.0,
                    cached: false,
                    stats: None,
                    masked_pixels: 0,
                    error: Some(format!("{e:#}")),
                });
                Vec::new()
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
                say(format!("skipped: {spec} / {id}: {e}"));
                report.skipped.push(Skipped {
                    scene: spec.clone(),
                    technique: id,
                    reason: e.to_string(),
                });
                bar.inc(1);
                continue;
            }
            if gpu_scene.is_none() && upload_error.is_none() {
                bar.set_message("uploading");
                match backend::upload_scene(env.ctx, scene) {
                    Ok(s) => gpu_scene = Some(s),
                    Err(e) => {
                        let msg = format!("{spec} / upload: {e:#}");
                        say(format!("error: {msg}"));
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
            bar.set_message(id.clone());
            let row_bar = progress.technique(&id);
            let mut on_frame = |step: &str, done: usize, total: usize| {
                crate::Progress::step(&row_bar, step, done, total)
            };
            let outcome = measure(
                env,
                technique.as_mut(),
                gs,
                &references,
                opts.frames,
                row,
                &mut on_frame,
            );
            row_bar.finish_and_clear();
            // The `reference` technique's images are the ground truth's, already written.
            if id != "reference" {
                report.images.push(WrittenImages {
                    scene: spec.clone(),
                    technique: Some(id.clone()),
                    value: None,
                    frames: write_outcome_images(&opts.out, &rel_dir, &file_name(&id), &outcome)?,
                });
            }
            if let Some(err) = &outcome.row.error {
                let msg = format!("{spec} / {id}: {err}");
                say(format!("error: {msg}"));
                if err.starts_with(PANICKED) {
                    report.panics.push(msg.clone());
                }
                report.errors.push(msg);
            } else if let Some(n) = outcome.row.nan_pixels.filter(|&n| n > 0) {
                say(format!(
                    "warning: {spec} / {id}: {n} NaN or infinite pixels"
                ));
            }
            report.rows.push(outcome.row);
            bar.inc(1);
        }
        if let Some(first) = report.rows.iter().position(|r| &r.scene == spec) {
            let rows = &mut report.rows[first..];
            let (points, warning) =
                pareto::write_scene(&opts.out, spec, dir_name, rows, &adapter_name)?;
            if let Some(w) = warning {
                say(format!("warning: {w}"));
            }
            report.pareto.push(points);
        }
        let failed = report.errors.len() - errors_before;
        bar.finish_with_message(match failed {
            0 => "done".to_string(),
            n => format!("done, {n} failed"),
        });
    }

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
    let provenance = crate::html::Provenance::capture(env.ground_truth.key());
    crate::html::write_compare_page(&opts.out, &report, &provenance)?;
    Ok(report)
}

pub(crate) fn write_text(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}
