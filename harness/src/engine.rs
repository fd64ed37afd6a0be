//! The measuring engine: executes a [`Plan`] row by row and keeps the results as they come.
//!
//! Per scene of the plan, in order: the importer's notes; the references at every error time
//! (through the cache, [`crate::cache`]), written as images; then each row:
//!
//! 1. a fresh instance of the technique with the row's parameters and its `prepare`, on the
//!    run's device and the scene uploaded once (or a fresh device and upload per row: see
//!    [`DevicePolicy`]);
//! 2. the frames ([`crate::measure`]): warm-up, then the camera path, every frame timed and the
//!    error frames read back;
//! 3. the error figures against the references ([`crate::score`]);
//! 4. the row's images, then the CSV and JSON tables rewritten with the row in them.
//!
//! After the scene's last row its speed-ups against the exact tracer and its Pareto view are
//! set ([`crate::pareto`]) and every file is rewritten, the markdown table and `index.html`
//! included. A technique that fails (an error, a GPU validation error, a panic) gets a row with
//! the error, and the run goes on. Each row also records where its wall-clock time went
//! ([`crate::report::RowWall`]).
//!
//! `--resume` ([`ExecOptions::resume`]) keeps the rows an earlier run of the same plan on the
//! same commit left in the folder, and runs only the others; `--shard i/n` runs one slice of
//! the plan ([`Plan::shard`]) into a folder of its own, which `harness merge` joins.

use crate::cache::{self, RefView};
use crate::measure::{self, ErrorFrame, TechniqueRun};
use crate::model::{ReferenceInfo, RunReport, SceneWall, WrittenImages};
use crate::output::{self, Output};
use crate::plan::{Plan, PlannedRow, PlannedScene, Shard};
use crate::provenance::Provenance;
use crate::report::{AdapterJson, ResultRow, RowWall};
use crate::score::{self, TimedReference};
use crate::{Env, Progress, backend};
use anyhow::{Context as _, Result, anyhow, bail};
use scene::{Contained, GpuScene, Scene, Technique};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

/// Which device a row renders on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DevicePolicy {
    /// Every row on the run's device, the scene uploaded once per scene: what an application
    /// does. The default.
    #[default]
    Shared,
    /// A new device on the adapter for every row, the scene uploaded to it: each row finds the
    /// driver as the first did, whatever ran before it (`--device per-row`). It costs about
    /// 0.05 s a row (13 s of the default compare) and changed no figure and no timing beyond
    /// the run-to-run spread on Mesa 25's lavapipe (see the harness README, "Cost").
    PerRow,
}

/// How to execute a plan.
#[derive(Clone, Debug)]
pub struct ExecOptions {
    pub out: PathBuf,
    /// Execute this slice of the plan only (`--shard i/n`).
    pub shard: Option<Shard>,
    /// Keep the rows an earlier run of the same plan and commit left in `out` (`--resume`).
    pub resume: bool,
    pub device: DevicePolicy,
}

impl ExecOptions {
    /// The whole plan into `out`, nothing resumed, on the run's device.
    pub fn new(out: impl Into<PathBuf>) -> Self {
        ExecOptions {
            out: out.into(),
            shard: None,
            resume: false,
            device: DevicePolicy::default(),
        }
    }
}

/// The share of a frame its named spans must account for before a contained variant is timed
/// from them (see `measure::TechniqueRun::spans_cover`).
const SPANS_COVER: std::ops::RangeInclusive<f64> = 0.8..=1.25;

/// The start of the error of a row whose technique panicked.
pub const PANICKED: &str = "panicked: ";

/// A one-line message of a caught panic (it starts with [`PANICKED`]).
fn panic_message(payload: Box<dyn std::any::Any + Send>) -> String {
    let text = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into());
    format!("{PANICKED}{}", text.lines().next().unwrap_or(""))
}

/// A loaded scene of a run: its spec, the model, the importer's notes.
pub struct LoadedScene {
    pub spec: String,
    pub scene: Scene,
    pub notes: Vec<String>,
}

/// Loads every scene spec first, so a bad one fails before any GPU work.
pub fn load_scenes(specs: &[String]) -> Result<Vec<LoadedScene>> {
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

/// Executes `plan` (see the module documentation) and returns what it wrote.
pub fn execute(env: &Env, plan: &Plan, opts: &ExecOptions) -> Result<RunReport> {
    let slice = match opts.shard {
        Some(shard) => plan.shard(shard),
        None => plan.clone(),
    };
    let specs: Vec<String> = slice.scenes.iter().map(|s| s.spec.clone()).collect();
    let scenes = load_scenes(&specs)?;
    crate::limits::check_memory(env.ctx, plan.size, plan.frames)?;
    let _lock = crate::OutputLock::acquire(&opts.out)?;
    let output = Output::new(&opts.out, plan.table_stem());
    let provenance = Provenance::capture(env.ground_truth.key());
    let adapter = AdapterJson::of(env.ctx);
    let mut report = RunReport::new(&slice, plan.key(), opts.shard, adapter, provenance);
    let mut earlier = match opts.resume {
        true => Earlier::read(&output, &report)?,
        false => Earlier::default(),
    };
    let progress = Progress::new(env.progress);
    let run = Run {
        env,
        plan: &slice,
        out: &output,
        progress: &progress,
        device: opts.device,
    };
    for loaded in &scenes {
        run.scene(loaded, &mut report, &mut earlier)?;
    }
    output.write_sweep_plot(&report)?;
    output.write_all(&report)?;
    Ok(report)
}

/// What an earlier run of the same plan left in the folder (`--resume`).
#[derive(Default)]
struct Earlier {
    rows: BTreeMap<String, (ResultRow, Option<WrittenImages>)>,
    scenes: BTreeMap<String, (Vec<ReferenceInfo>, Option<WrittenImages>, SceneWall)>,
}

impl Earlier {
    /// The finished rows of the folder's results, which must be of the same plan (and shard)
    /// and the same commit; an empty folder resumes nothing.
    fn read(output: &Output, now: &RunReport) -> Result<Self> {
        let path = output.table("json");
        if !path.is_file() {
            return Ok(Earlier::default());
        }
        let old = RunReport::read(&path)?;
        if old.plan_key != now.plan_key || old.shard != now.shard {
            bail!(
                "--resume: {} holds the results of another run (other scenes, techniques, size, \
                 frames or reference options); resume with the same arguments, or choose another --out",
                path.display()
            );
        }
        let (was, is) = (&old.provenance.git_commit, &now.provenance.git_commit);
        if was != is {
            bail!(
                "--resume: {} was written by commit {was}, this is {is}; its rows would not be \
                 this code's figures (run without --resume to start again)",
                path.display()
            );
        }
        let mut earlier = Earlier::default();
        for row in old.rows {
            let images = old.images.iter().find(|w| row_images(w, &row)).cloned();
            earlier.rows.insert(result_key(&row), (row, images));
        }
        for spec in old.image_dirs.keys() {
            let refs: Vec<ReferenceInfo> = old
                .references
                .iter()
                .filter(|r| &r.scene == spec)
                .cloned()
                .collect();
            let images = old
                .images
                .iter()
                .find(|w| &w.scene == spec && w.technique.is_none())
                .cloned();
            let wall = old.scene_walls.iter().find(|w| &w.scene == spec).cloned();
            if !refs.is_empty() {
                earlier
                    .scenes
                    .insert(spec.clone(), (refs, images, wall.unwrap_or_default()));
            }
        }
        Ok(earlier)
    }
}

/// The key of a result row (what [`PlannedRow::key`] says of its planned row).
fn result_key(row: &ResultRow) -> String {
    format!(
        "{} | {} | {}",
        row.scene,
        row.technique,
        row.value.as_deref().unwrap_or("")
    )
}

/// Whether `images` are the images of `row`.
fn row_images(images: &WrittenImages, row: &ResultRow) -> bool {
    images.scene == row.scene
        && images.technique.as_deref() == Some(&row.technique)
        && images.value == row.value
}

/// What a plan's execution shares between its scenes.
struct Run<'a> {
    env: &'a Env<'a>,
    plan: &'a Plan,
    out: &'a Output,
    progress: &'a Progress,
    device: DevicePolicy,
}

impl Run<'_> {
    fn say(&self, line: String) {
        self.progress.say(&line);
    }

    /// One scene: its references, then its rows (see the module documentation).
    fn scene(
        &self,
        loaded: &LoadedScene,
        report: &mut RunReport,
        earlier: &mut Earlier,
    ) -> Result<()> {
        let planned = self
            .plan
            .scene(&loaded.spec)
            .ok_or_else(|| anyhow!("scene {} is not in the plan", loaded.spec))?;
        let rows: Vec<&PlannedRow> = self
            .plan
            .rows
            .iter()
            .filter(|r| r.scene == loaded.spec)
            .collect();
        let bar = self.progress.scene(&loaded.spec, rows.len() as u64 + 1);
        let errors_before = report.errors.len();
        for note in &loaded.notes {
            self.say(format!("warning: {}: {note}", loaded.spec));
            report.scene_notes.push(format!("{}: {note}", loaded.spec));
        }
        bar.set_message("reference");
        let all_done = rows.iter().all(|r| earlier.rows.contains_key(&r.key()));
        let references = match earlier.scenes.remove(&loaded.spec) {
            Some((infos, images, wall)) if all_done => {
                report.references.extend(infos);
                report.images.extend(images);
                report.scene_walls.push(wall);
                Vec::new()
            }
            _ => self.references(loaded, planned, report)?,
        };
        bar.inc(1);
        let first_row = report.rows.len();
        let mut turns = Turns::new(self, &rows, &loaded.scene, earlier);
        let mut shared: Option<GpuScene> = None;
        for (i, row) in rows.iter().enumerate() {
            match earlier.rows.remove(&row.key()) {
                Some((result, images)) => {
                    report.rows.push(result);
                    report.images.extend(images);
                }
                None => {
                    bar.set_message(row.label.clone());
                    let on = ((planned, loaded), references.as_slice(), &mut shared);
                    let measured = turns.take(self, i, on);
                    self.record(measured, report)?;
                }
            }
            bar.inc(1);
        }
        let closing = Instant::now();
        self.pareto(loaded, report, first_row)?;
        self.out.write_all(report)?;
        if let Some(wall) = report
            .scene_walls
            .iter_mut()
            .find(|w| w.scene == loaded.spec)
        {
            wall.close_s = closing.elapsed().as_secs_f64();
        }
        let failed = report.errors.len() - errors_before;
        bar.finish_with_message(match failed {
            0 => "done".to_string(),
            n => format!("done, {n} failed"),
        });
        Ok(())
    }

    /// A row's result into the report, its errors told, the tables rewritten.
    fn record(&self, measured: Measured, report: &mut RunReport) -> Result<()> {
        let Measured { mut row, images } = measured;
        let spec = match &row.value {
            Some(v) => format!("{} / {} {}={v}", row.scene, row.technique, {
                row.param.as_deref().unwrap_or("")
            }),
            None => format!("{} / {}", row.scene, row.technique),
        };
        if let Some(err) = &row.error {
            let msg = format!("{spec}: {err}");
            self.say(format!("error: {msg}"));
            if err.starts_with(PANICKED) {
                report.panics.push(msg.clone());
            }
            report.errors.push(msg);
        } else if let Some(n) = row.nan_pixels.filter(|&n| n > 0) {
            self.say(format!("warning: {spec}: {n} NaN or infinite pixels"));
        }
        let start = Instant::now();
        report.images.extend(images);
        report.rows.push(row.clone());
        self.out.write_rows(report)?;
        row.wall.write_s += start.elapsed().as_secs_f64();
        if let Some(last) = report.rows.last_mut() {
            *last = row;
        }
        Ok(())
    }

    /// The scene's rows' speed-ups against the exact tracer and its Pareto view.
    fn pareto(&self, loaded: &LoadedScene, report: &mut RunReport, first_row: usize) -> Result<()> {
        if report.rows.len() == first_row || report.sweep().is_some() {
            return Ok(());
        }
        let dir_name = report
            .image_dirs
            .get(&loaded.spec)
            .cloned()
            .unwrap_or_default();
        let rows = &mut report.rows[first_row..];
        let adapter = report.adapter.name.clone();
        let (points, warning) = crate::output::write_pareto_scene(
            &self.out.dir,
            &loaded.spec,
            &dir_name,
            rows,
            &adapter,
        )?;
        if let Some(w) = warning {
            self.say(format!("warning: {w}"));
        }
        report.pareto.push(points);
        Ok(())
    }

    /// Records each reference of the scene in the report, with why the cache could not serve
    /// it.
    fn note_references(
        &self,
        loaded: &LoadedScene,
        timed: &[(TimedReference, cache::Cached)],
        report: &mut RunReport,
    ) {
        for (r, cached) in timed {
            let miss = match cached {
                cache::Cached::Hit => None,
                cache::Cached::Miss(reason) => Some(reason.clone()),
            };
            report.references.push(ReferenceInfo {
                scene: loaded.spec.clone(),
                time: r.time,
                cached: miss.is_none(),
                miss,
                stats: Some(r.reference.stats.clone()),
                masked_pixels: r.reference.mask.iter().filter(|&&m| m).count(),
                error: None,
            });
        }
    }

    /// The references at every error time of the scene, through the cache, their images
    /// written; none (and the error in the report) when the reference fails.
    fn references(
        &self,
        loaded: &LoadedScene,
        planned: &PlannedScene,
        report: &mut RunReport,
    ) -> Result<Vec<TimedReference>> {
        let start = Instant::now();
        let say = |line: String| self.say(line);
        let rendered = path_references(self.env, self.out, loaded, self.plan, &say);
        let references = match rendered {
            Ok(timed) => {
                self.note_references(loaded, &timed, report);
                let timed: Vec<TimedReference> = timed.into_iter().map(|(r, _)| r).collect();
                let images: Vec<(f32, &gpu::HdrImage)> =
                    timed.iter().map(|r| (r.time, &r.reference.image)).collect();
                let frames = output::write_reference_images(
                    &self.out.dir,
                    &planned.image_dir,
                    &planned.reference_stem,
                    &images,
                )?;
                report.images.push(WrittenImages {
                    scene: loaded.spec.clone(),
                    technique: None,
                    value: planned.value.clone(),
                    frames,
                });
                timed
            }
            Err(e) => {
                let msg = format!("{} / reference: {e:#}", loaded.spec);
                self.say(format!("error: {msg}"));
                report.errors.push(msg);
                report.references.push(ReferenceInfo {
                    scene: loaded.spec.clone(),
                    time: 0.0,
                    cached: false,
                    miss: None,
                    stats: None,
                    masked_pixels: 0,
                    error: Some(format!("{e:#}")),
                });
                Vec::new()
            }
        };
        report.scene_walls.push(SceneWall {
            scene: loaded.spec.clone(),
            reference_s: start.elapsed().as_secs_f64(),
            close_s: 0.0,
        });
        Ok(references)
    }

    /// One row, measured and scored, its images written (see the module documentation); with
    /// its run when it measured `contained` variants too.
    fn row(
        &self,
        row: &PlannedRow,
        scene: (&PlannedScene, &LoadedScene),
        references: &[TimedReference],
        shared: &mut Option<GpuScene>,
        contained: &[Contained],
    ) -> (Measured, Option<TechniqueRun>) {
        let (_, loaded) = scene;
        let start = Instant::now();
        let result = self.new_row(row);
        let mut technique = match row.technique.instance(self.env.techniques) {
            Ok(t) => t,
            Err(e) => return (Measured::failed(result.with_error(format!("{e:#}"))), None),
        };
        if !technique.supports(&loaded.scene) {
            let message = "the technique does not support this scene";
            return (Measured::failed(result.with_error(message)), None);
        }
        let mut wall = RowWall::default();
        let run = match technique.id().as_str() {
            "reference" if !references.is_empty() => Ok(reference_run(references)),
            _ => {
                let on = (loaded, shared);
                self.run_on_device(technique.as_mut(), on, row, contained, &mut wall, start)
            }
        };
        match run {
            Ok(run) => {
                let technique = technique.as_ref();
                let measured =
                    self.finish_row(result, technique, &run, row, scene, references, wall);
                (measured, Some(run))
            }
            Err(message) => {
                let mut result = result.with_error(message);
                result.wall = wall;
                (Measured::failed(result), None)
            }
        }
    }

    /// A row of `row`'s identity, no figure yet.
    fn new_row(&self, row: &PlannedRow) -> ResultRow {
        let mut result = ResultRow::new(
            &row.scene,
            &row.label,
            self.plan.size,
            &self.env.ctx.summary.name,
        );
        if let Some((param, value)) = &row.swept {
            result.param = Some(param.clone());
            result.value = Some(value.clone());
        }
        result
    }

    /// A measured row's error figures and images.
    #[allow(clippy::too_many_arguments)]
    fn finish_row(
        &self,
        result: ResultRow,
        technique: &dyn Technique,
        run: &TechniqueRun,
        row: &PlannedRow,
        (planned, loaded): (&PlannedScene, &LoadedScene),
        references: &[TimedReference],
        mut wall: RowWall,
    ) -> Measured {
        let scene = &loaded.scene;
        let scoring = Instant::now();
        let (mut result, flips) = score::score(technique, scene, references, result, run);
        wall.metrics_s = scoring.elapsed().as_secs_f64();
        let writing = Instant::now();
        let images = match technique.id().as_str() {
            // The `reference` technique's images are the ground truth's, already written.
            "reference" => Ok(None),
            _ => output::write_row_images(
                &self.out.dir,
                &planned.image_dir,
                &row.image_stem,
                &run.error_frames,
                &flips,
            )
            .map(Some),
        };
        wall.write_s = writing.elapsed().as_secs_f64();
        result.wall = wall;
        match images {
            Ok(frames) => Measured {
                images: frames.map(|frames| WrittenImages {
                    scene: row.scene.clone(),
                    technique: Some(row.label.clone()),
                    value: row.swept.as_ref().map(|(_, v)| v.clone()),
                    frames,
                }),
                row: result,
            },
            Err(e) => Measured::failed(result.with_error(format!("writing its images: {e:#}"))),
        }
    }

    /// The row of variant `row`, contained in `container`'s run (see `Technique::contains`):
    /// its images and times from that run; `None` where the run's spans do not account for its
    /// frames (an adapter whose timer cannot time passes apart), and the row runs itself.
    fn contained_row(
        &self,
        row: &PlannedRow,
        scene: (&PlannedScene, &LoadedScene),
        references: &[TimedReference],
        (container, run): (&PlannedRow, &TechniqueRun),
    ) -> Option<Measured> {
        let id = &row.technique.id;
        let contained = run.contained.iter().find(|c| &c.id == id)?;
        if !(SPANS_COVER.contains(&run.spans_cover) && contained.frame.samples > 0) {
            return None;
        }
        let technique = row.technique.instance(self.env.techniques).ok()?;
        let own = TechniqueRun {
            error_frames: contained.error_frames.clone(),
            timer: run.timer.clone(),
            frame: contained.frame,
            prepare_ms: 0.0,
            prepare_wall_ms: 0.0,
            spans_ms: Default::default(),
            contained: Vec::new(),
            spans_cover: f64::NAN,
        };
        let mut result = self.new_row(row);
        result.measured_with = Some(container.label.clone());
        let wall = RowWall::default();
        Some(self.finish_row(
            result,
            technique.as_ref(),
            &own,
            row,
            scene,
            references,
            wall,
        ))
    }

    /// Renders the row's frames on its device (see [`DevicePolicy`]); an error, a GPU
    /// validation error or a panic is the row's error message.
    fn run_on_device(
        &self,
        technique: &mut dyn Technique,
        (loaded, shared): (&LoadedScene, &mut Option<GpuScene>),
        row: &PlannedRow,
        contained: &[Contained],
        wall: &mut RowWall,
        start: Instant,
    ) -> Result<TechniqueRun, String> {
        let fresh;
        let (ctx, mut own_scene) = match self.device {
            DevicePolicy::PerRow => {
                fresh = self.env.ctx.fresh_device().map_err(|e| format!("{e:#}"))?;
                (&fresh, None)
            }
            DevicePolicy::Shared => (self.env.ctx, None),
        };
        let gpu_scene = match (self.device, shared.as_mut()) {
            (DevicePolicy::Shared, Some(s)) => s,
            (policy, _) => {
                let uploaded = backend::upload_scene(ctx, &loaded.scene)
                    .map_err(|e| format!("scene upload failed: {e:#}"))?;
                match policy {
                    DevicePolicy::Shared => shared.insert(uploaded),
                    DevicePolicy::PerRow => own_scene.insert(uploaded),
                }
            }
        };
        let bar = self.progress.technique(&row.label);
        let mut on_step =
            |step: &str, done: usize, total: usize| Progress::step(&bar, step, done, total);
        let setup_s = start.elapsed().as_secs_f64();
        let frames_start = Instant::now();
        let (size, frames) = (self.plan.size, self.plan.frames);
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let scene = gpu_scene;
            measure::run_containing(ctx, technique, scene, size, frames, contained, &mut on_step)
        }));
        bar.finish_and_clear();
        let elapsed = frames_start.elapsed().as_secs_f64();
        wall.prepare_s = setup_s;
        wall.frames_s = elapsed;
        let run = match result {
            Ok(Ok(run)) => run,
            Ok(Err(e)) => return Err(format!("{e:#}")),
            Err(p) => return Err(panic_message(p)),
        };
        let prepare_s = run.prepare_wall_ms / 1e3;
        wall.prepare_s += prepare_s;
        wall.frames_s = (elapsed - prepare_s).max(0.0);
        Ok(run)
    }
}

/// A scene's rows in turn, where one row's run measures another's (see
/// `Technique::contains`: the tracer's caustics contain its Whitted eye pass): the container
/// runs at the first of their turns, and the other row's result waits for its own turn.
struct Turns<'r> {
    rows: Vec<&'r PlannedRow>,
    /// Per container row: the rows it measures, with what of its frame they are.
    contains: BTreeMap<usize, Vec<(usize, Contained)>>,
    /// Per contained row: its container.
    container_of: BTreeMap<usize, usize>,
    /// Results measured before their turn.
    ready: BTreeMap<usize, Measured>,
}

/// Where a row runs: its scene (planned and loaded), its references, the shared GPU scene.
type RowSite<'a, 'b> = (
    (&'a PlannedScene, &'a LoadedScene),
    &'a [TimedReference],
    &'b mut Option<GpuScene>,
);

impl<'r> Turns<'r> {
    /// Which rows contain which, among the rows an earlier run did not leave done.
    fn new(run: &Run, rows: &[&'r PlannedRow], scene: &Scene, earlier: &Earlier) -> Self {
        let mut turns = Turns {
            rows: rows.to_vec(),
            contains: BTreeMap::new(),
            container_of: BTreeMap::new(),
            ready: BTreeMap::new(),
        };
        let todo = |r: &PlannedRow| !earlier.rows.contains_key(&r.key());
        for (i, row) in rows.iter().enumerate().filter(|(_, r)| todo(r)) {
            let Ok(technique) = row.technique.instance(run.env.techniques) else {
                continue;
            };
            if !technique.supports(scene) {
                continue;
            }
            for c in technique.contains() {
                let plain = crate::plan::TechniqueSpec::id(&c.id);
                let found = rows.iter().position(|r| r.technique == plain && todo(r));
                if let Some(j) = found.filter(|j| !turns.container_of.contains_key(j)) {
                    turns.container_of.insert(j, i);
                    turns.contains.entry(i).or_default().push((j, c));
                }
            }
        }
        turns
    }

    /// Row `i`'s result at its turn: measured ahead by its container, or now (its container
    /// first when that comes later, or the row itself).
    fn take(&mut self, run: &Run, i: usize, site: RowSite) -> Measured {
        if let Some(m) = self.ready.remove(&i) {
            return m;
        }
        let (scene, references, shared) = site;
        if let Some(&r) = self.container_of.get(&i).filter(|&&r| r > i) {
            self.measure(run, r, i, (scene, references, &mut *shared));
            if let Some(m) = self.ready.remove(&i) {
                return m;
            }
            // Its container could not time it (see `SPANS_COVER`): it runs itself.
            self.container_of.remove(&i);
        }
        self.measure(run, i, i, (scene, references, shared));
        self.ready
            .remove(&i)
            .unwrap_or_else(|| Measured::failed(ResultRow::default().with_error("not measured")))
    }

    /// Runs row `i` with the rows it contains from turn `now` on, keeping every result.
    fn measure(&mut self, run: &Run, i: usize, now: usize, site: RowSite) {
        let (scene, references, shared) = site;
        let contained: Vec<(usize, Contained)> = self
            .contains
            .get(&i)
            .into_iter()
            .flatten()
            .filter(|(j, _)| *j >= now && self.container_of.get(j) == Some(&i))
            .cloned()
            .collect();
        let variants: Vec<Contained> = contained.iter().map(|(_, c)| c.clone()).collect();
        let (measured, technique_run) = run.row(self.rows[i], scene, references, shared, &variants);
        self.ready.insert(i, measured);
        let Some(technique_run) = technique_run else {
            return;
        };
        for (j, _) in contained {
            let container = (self.rows[i], &technique_run);
            if let Some(m) = run.contained_row(self.rows[j], scene, references, container) {
                self.ready.insert(j, m);
            }
        }
    }
}

/// A row as measured, with the images it wrote.
struct Measured {
    row: ResultRow,
    images: Option<WrittenImages>,
}

impl Measured {
    fn failed(row: ResultRow) -> Self {
        Measured { row, images: None }
    }
}

/// The `reference` technique's run: the ground truth itself. Instead of rendering it again for
/// every frame (seconds each on the CPU), its row reuses the (cached) ground-truth images and
/// reports the CPU time the first took as one frame.
fn reference_run(references: &[TimedReference]) -> TechniqueRun {
    let ms = references[0].reference.stats.seconds * 1e3;
    TechniqueRun {
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
        contained: Vec::new(),
        spans_cover: f64::NAN,
    }
}

/// Says, before they are rendered, how many of a scene's references the cache cannot serve and
/// why (each distinct reason once).
fn say_misses(spec: &str, found: &[cache::Cached], say: &dyn Fn(String)) {
    let mut reasons: Vec<&str> = Vec::new();
    for cached in found {
        if let cache::Cached::Miss(reason) = cached
            && !reasons.contains(&reason.as_str())
        {
            reasons.push(reason);
        }
    }
    if !reasons.is_empty() {
        let misses = found.iter().filter(|c| **c != cache::Cached::Hit).count();
        say(format!(
            "{spec}: rendering {misses} of {} references ({})",
            found.len(),
            reasons.join("; ")
        ));
    }
}

/// The references at every error-frame time of the plan on the scene's camera path, each with
/// whether it came from the cache.
fn path_references(
    env: &Env,
    out: &Output,
    loaded: &LoadedScene,
    plan: &Plan,
    say: &dyn Fn(String),
) -> Result<Vec<(TimedReference, cache::Cached)>> {
    let cache_dir = out.dir.join(".cache");
    let views: Vec<RefView> = plan
        .frames
        .error_times_for(&loaded.scene)
        .into_iter()
        .map(|time| RefView {
            spec: &loaded.spec,
            scene: &loaded.scene,
            camera: loaded.scene.camera_at(time),
            time,
            size: plan.size,
        })
        .collect();
    // Every view's status before any is rendered: the reasons describe the cache as found.
    let found: Vec<cache::Cached> = views
        .iter()
        .map(|view| cache::status(&cache_dir, env.ground_truth, view))
        .collect();
    say_misses(&loaded.spec, &found, say);
    views
        .iter()
        .zip(found)
        .map(|(view, found)| {
            let time = view.time;
            let (reference, how) =
                cache::reference_as_found(&cache_dir, env.ground_truth, view, found)
                    .with_context(|| format!("reference at time {time}"))?;
            Ok((TimedReference { time, reference }, how))
        })
        .collect()
}
