//! Running one technique on one uploaded scene: prepare, the error frame, warm-up and timed
//! frames, each in its own command encoder bracketed by the timer.
//!
//! The per-step recording is `scene::runner`'s (shared with `testkit`, so tests render what the
//! harness measures): per frame it creates an encoder, calls `timer.begin(enc, "frame")`,
//! `technique.render(...)`, `timer.end(enc, "frame")` and `timer.submit_and_collect(ctx, enc)`.
//! The frame time is the "frame" span when the timer has GPU timestamps ("gpu-timestamp"), the
//! "wall" span (CPU clock around submit + wait) when it has not ("wall"), and the wall-clock
//! time of the `render` call for a technique whose [`Timing`] is `Cpu` ("cpu"). Prepare is
//! timed the same way under the label "prepare". Any other span label a technique records is
//! reported apart (median per frame, as `<label>_ms`).
//!
//! Before each frame, and before prepare, the shared scene is moved to the frame's time in a
//! submission of its own (objects' transforms and shadow maps: the same work for every
//! technique), so it is not part of any technique's time.
//!
//! Order: prepare (scene at time 0); `warmup` untimed frames on the camera path at time 0 (only
//! the first when it shows the timed frames would overrun [`Frames::timed_budget_s`]: the row is
//! then timed on fewer frames, [`Frames::timed_within_budget`]); then the camera path in time
//! order: the `timed` frames at `time = i * duration / timed` and,
//! among them, the error frames at [`Frames::error_times_for`] (start, middle and end of the
//! path by default), each read back and not timed. Every frame uses the path's camera at its
//! time with the scene moved to that time. Because the error frames sit in the same sequence
//! as the timed frames, a technique that keeps state from frame to frame (maps made at
//! prepare, amortized regeneration) reaches each error time through the frames an application
//! would have rendered before it, not by a jump. A GPU validation error in any frame is the
//! technique's error.

use crate::{Frames, Size};
use anyhow::{Result, anyhow};
use gpu::{Context, GpuTimer, HdrImage, Target, TimeStats, TimerKind};
use scene::runner::{self, Recorded};
use scene::{GpuScene, Technique, Timing, View};
use std::collections::BTreeMap;

/// What a frame of a run is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    /// Read back and measured against the reference at its time; not timed.
    Error,
    /// Timed.
    Timed,
}

/// One error frame: the image of the camera path's view at `time`, read back.
#[derive(Clone, Debug)]
pub struct ErrorFrame {
    pub time: f32,
    pub image: HdrImage,
}

/// What a run measured.
#[derive(Clone, Debug)]
pub struct TechniqueRun {
    /// The error frames in time order; the first is at time 0.
    pub error_frames: Vec<ErrorFrame>,
    /// "gpu-timestamp", "wall" or "cpu".
    pub timer: String,
    pub frame: TimeStats,
    pub prepare_ms: f64,
    /// Wall clock of prepare including submission and wait.
    pub prepare_wall_ms: f64,
    /// Extra named spans: `<label>_ms` (median per timed frame) and `prepare.<label>_ms`.
    pub spans_ms: BTreeMap<String, f64>,
}

impl TechniqueRun {
    /// The error frame at time 0 (the camera path's view there).
    pub fn image(&self) -> &HdrImage {
        &self.error_frames[0].image
    }
}

/// Spans a timer can return that are not a technique's own.
const HARNESS_LABELS: &[&str] = &["frame", "prepare", "wall", "scene_update"];

/// One recorded step (`scene::runner::Recorded`) read the harness's way.
pub(crate) struct Sample(Recorded);

impl Sample {
    /// The figure for `label` under this timer kind (see the module documentation).
    pub(crate) fn time(&self, label: &str, timing: Timing, kind: TimerKind) -> f64 {
        let r = &self.0;
        match (timing, kind) {
            (Timing::Cpu, _) => r.call_ms,
            (Timing::Gpu, TimerKind::GpuTimestamp) => r.span(label).unwrap_or(r.total_ms),
            (Timing::Gpu, TimerKind::Wall) => r.span("wall").unwrap_or(r.total_ms),
        }
    }

    pub(crate) fn spans(&self) -> &[(String, f64)] {
        &self.0.spans
    }

    pub(crate) fn extra(&self) -> impl Iterator<Item = &(String, f64)> {
        self.0
            .spans
            .iter()
            .filter(|(l, _)| !HARNESS_LABELS.contains(&l.as_str()))
    }
}

/// Moves the shared scene to `time` in a submission of its own.
pub(crate) fn update_scene(
    ctx: &Context,
    timer: &mut GpuTimer,
    scene: &mut GpuScene,
    time: f32,
) -> Result<()> {
    runner::update_scene(ctx, timer, scene, time)
        .map_err(|e| anyhow!(e).context("moving the scene to the frame's time"))
}

/// Runs `technique` on `scene` (see the module documentation). `on_frame` is told each step:
/// what it is, how many steps are done and how many there are (prepare, warm-up frames, error
/// and timed frames; the total shrinks when the timed budget cuts frames).
pub fn run_technique(
    ctx: &Context,
    technique: &mut dyn Technique,
    scene: &mut GpuScene,
    size: Size,
    frames: Frames,
    on_frame: &mut dyn FnMut(&str, usize, usize),
) -> Result<TechniqueRun> {
    let target = Target::new(ctx, size.width, size.height)?;
    let mut timer = GpuTimer::new(ctx, 64);
    let kind = timer.kind();
    let timing = technique.timing();
    let duration = scene.scene.camera_path.duration().max(0.0);
    let error_times = frames.error_times_for(&scene.scene);
    let (camera_path, still) = (scene.scene.camera_path.clone(), scene.scene.camera);
    let path_camera = |t: f32| camera_path.sample(t).unwrap_or(still);
    let view = |camera, time| View {
        camera,
        time,
        width: size.width,
        height: size.height,
    };
    let mut total = 1 + frames.warmup as usize + error_times.len() + frames.timed as usize;
    on_frame("prepare", 0, total);
    update_scene(ctx, &mut timer, scene, 0.0)?;
    let prep = prepare(ctx, &mut timer, technique, scene)?;
    let mut spans_ms = BTreeMap::new();
    for (label, ms) in prep.extra() {
        *spans_ms.entry(format!("prepare.{label}_ms")).or_insert(0.0) += ms;
    }

    // Warm-up; the first frame also tells how many timed frames fit the budget (a slow
    // technique then needs no further warm-up: its shaders are compiled and its maps made).
    let mut timed = frames.timed;
    for w in 0..frames.warmup {
        on_frame("warm-up", 1 + w as usize, total);
        let warm = view(path_camera(0.0), 0.0);
        let sample = render_frame(ctx, &mut timer, technique, scene, &warm, &target)?;
        if w == 0 {
            timed = frames.timed_within_budget(sample.0.total_ms);
            if timed < frames.timed {
                total = 2 + error_times.len() + timed as usize;
                break;
            }
        }
    }

    // The error frames take their place among the timed frames in time order (an error frame
    // before a timed frame of the same time), so a technique reaches each error time through
    // the frames an application would have rendered before it.
    let mut path: Vec<(View, Step)> = error_times
        .iter()
        .map(|&t| (view(path_camera(t), t), Step::Error))
        .collect();
    for i in 0..timed {
        let t = i as f32 * duration / timed as f32;
        path.push((view(path_camera(t), t), Step::Timed));
    }
    path.sort_by(|a, b| a.0.time.total_cmp(&b.0.time));
    let steps = path;

    let mut error_frames = Vec::new();
    let mut times = Vec::new();
    let mut extra: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    let mut timed_done = 0;
    for (done, (v, step)) in (total - steps.len()..).zip(&steps) {
        let label = match step {
            Step::Error => format!("error frame at time {}", v.time),
            Step::Timed => format!("frame {}/{timed}", timed_done + 1),
        };
        on_frame(&label, done, total);
        let sample = render_frame(ctx, &mut timer, technique, scene, v, &target)?;
        match step {
            Step::Error => error_frames.push(ErrorFrame {
                time: v.time,
                image: target.read(ctx)?,
            }),
            Step::Timed => {
                timed_done += 1;
                times.push(sample.time("frame", timing, kind));
                for (label, ms) in sample.extra() {
                    extra.entry(format!("{label}_ms")).or_default().push(*ms);
                }
            }
        }
    }
    for (label, samples) in extra {
        spans_ms.insert(label, TimeStats::from_samples(&samples).median_ms);
    }
    Ok(TechniqueRun {
        error_frames,
        timer: match timing {
            Timing::Cpu => "cpu".to_string(),
            Timing::Gpu => kind.label().to_string(),
        },
        frame: TimeStats::from_samples(&times),
        prepare_ms: prep.time("prepare", timing, kind),
        prepare_wall_ms: prep.0.total_ms,
        spans_ms,
    })
}

/// The technique's `prepare`, timed under the label "prepare".
pub(crate) fn prepare(
    ctx: &Context,
    timer: &mut GpuTimer,
    technique: &mut dyn Technique,
    scene: &GpuScene,
) -> Result<Sample> {
    runner::prepare(ctx, timer, technique, scene)
        .map(Sample)
        .map_err(|e| anyhow!(e).context("prepare"))
}

/// Moves the scene to the view's time and renders one timed frame.
pub(crate) fn render_frame(
    ctx: &Context,
    timer: &mut GpuTimer,
    technique: &mut dyn Technique,
    scene: &mut GpuScene,
    view: &View,
    target: &Target,
) -> Result<Sample> {
    runner::render_frame(ctx, timer, technique, scene, view, target)
        .map(Sample)
        .map_err(|e| anyhow!(e).context(format!("frame at time {}", view.time)))
}
