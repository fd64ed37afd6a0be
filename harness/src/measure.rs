//! Measuring one technique on one uploaded scene: prepare, warm-up, then the camera path, whose
//! frames are both timed samples and, at the error times, the images measured against the
//! reference.
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
//! Order: prepare (scene at time 0); `warmup` untimed frames at time 0 (only the first when it
//! shows the timed frames would overrun [`Frames::timed_budget_s`]: the row is then timed on
//! fewer frames, [`Frames::timed_within_budget`]; when that leaves it its error frames alone,
//! the warm-up frame is the first of them, timed and read back, so a slow row renders each
//! error frame once and nothing more); then the camera path in time order, each
//! frame at the path's camera and the scene moved to its time: the `timed` frames at
//! `time = i * duration / timed` and the error frames at [`Frames::error_times_for`] (start,
//! middle and end of the path by default). A time that is both is one frame. An error frame is
//! read back after its submission, in a submission of its own, so its timestamps are those of
//! any other frame and it is a timed sample too: every frame on the path is timed. A technique
//! that converges over frames of an unchanged view ([`Technique::frames_to_converge`], the exact
//! tracer's progressive caustics) renders that many frames at an error frame's view, each one
//! timed, and its image is read after the last; it is timed on those frames alone, without a
//! warm-up frame (which, at the first error frame's view, would add to its image: its shaders
//! are compiled in the first of them, which shows in its p95, not its median). Because the error frames sit in the same
//! sequence as the timed frames, a technique that keeps state from frame to frame (maps made at
//! prepare, amortized regeneration) reaches each error time through the frames an application
//! would have rendered before it, not by a jump. A GPU validation error in any frame is the
//! technique's error.

use crate::Frames;
use anyhow::{Result, anyhow};
use gpu::{Context, GpuTimer, HdrImage, Target, TimeStats, TimerKind};
use scene::runner::{self, Recorded};
use scene::{Contained, GpuScene, Technique, Timing, View};
use std::collections::BTreeMap;

/// One error frame: the image of the camera path's view at `time`, read back.
#[derive(Clone, Debug)]
pub struct ErrorFrame {
    pub time: f32,
    pub image: HdrImage,
}

/// A contained variant (`Technique::contains`) as its container's run measured it.
#[derive(Clone, Debug)]
pub struct ContainedRun {
    pub id: String,
    /// Its images at the container's error frames.
    pub error_frames: Vec<ErrorFrame>,
    /// The sum of its spans in each timed frame of the container.
    pub frame: TimeStats,
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
    /// The contained variants asked for, measured from this run's frames.
    pub contained: Vec<ContainedRun>,
    /// The median share of a frame's time its named spans account for: about 1 where the
    /// timer's spans are trustworthy (GPUs, Mesa 25's lavapipe), far below where they are not
    /// (Mesa 22.3's lavapipe gives compute passes no time), and then a contained variant
    /// cannot be timed from them.
    pub spans_cover: f64,
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
pub(crate) struct Sample(pub(crate) Recorded);

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

/// A frame on the camera path: its time, and whether its image is read back as an error
/// frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PathFrame {
    pub time: f32,
    pub error: bool,
}

/// The frames of the camera path in time order: `timed` frames at `i * duration / timed`, of
/// which those at an error time are that error frame, and the error times no timed frame hit.
/// At one time, the error frame comes first (a still scene's error frame is its first frame).
pub(crate) fn path_frames(duration: f32, timed: u32, error_times: &[f32]) -> Vec<PathFrame> {
    let mut pending: Vec<f32> = error_times.to_vec();
    let mut frames: Vec<PathFrame> = Vec::new();
    for i in 0..timed {
        let time = i as f32 * duration / timed as f32;
        let error = match pending.iter().position(|&e| e == time) {
            Some(k) => {
                pending.remove(k);
                true
            }
            None => false,
        };
        frames.push(PathFrame { time, error });
    }
    frames.extend(
        pending
            .into_iter()
            .map(|time| PathFrame { time, error: true }),
    );
    frames.sort_by(|a, b| a.time.total_cmp(&b.time).then(b.error.cmp(&a.error)));
    frames
}

/// The steps of one row, for a progress display: `(step, done, total)`.
pub type OnStep<'a> = dyn FnMut(&str, usize, usize) + 'a;

/// The frames of a row, as the module documentation orders them.
struct Schedule {
    duration: f32,
    error_times: Vec<f32>,
    /// Frames an error frame takes ([`Technique::frames_to_converge`]).
    converge: usize,
    warmup: usize,
}

impl Schedule {
    /// The schedule of `technique` on `scene` with `frames`, and the frames it keeps: a
    /// progressive technique is timed on its error frames' frames (`converge` each) and warms
    /// up in the first of them (a warm-up frame of the first error frame's view would add to
    /// that view's image).
    fn of(technique: &dyn Technique, scene: &scene::Scene, frames: Frames) -> (Self, Frames) {
        let converge = technique.frames_to_converge().max(1) as usize;
        let frames = match converge > 1 {
            true => Frames {
                timed: 0,
                warmup: 0,
                ..frames
            },
            false => frames,
        };
        let schedule = Schedule {
            duration: scene.camera_path.duration().max(0.0),
            error_times: frames.error_times_for(scene),
            converge,
            warmup: frames.warmup as usize,
        };
        (schedule, frames)
    }

    /// The path's frames with `timed` timed frames; a row timed on no more frames than it has
    /// error frames is timed on its error frames alone.
    fn path(&self, timed: u32) -> Vec<PathFrame> {
        let timed = match self.error_frames_only(timed) {
            true => 0,
            false => timed,
        };
        path_frames(self.duration, timed, &self.error_times)
    }

    /// Whether a row with `timed` timed frames is timed on its error frames alone.
    fn error_frames_only(&self, timed: u32) -> bool {
        timed as usize <= self.error_times.len()
    }

    /// Whether the warm-up frame (time 0) can be the first error frame of a row timed on
    /// `timed` frames: the row is timed on its error frames alone, the first of them is at
    /// time 0, and it takes one frame.
    fn warm_up_is_first_error_frame(&self, timed: u32) -> bool {
        self.error_frames_only(timed)
            && self.converge == 1
            && self.error_times.first() == Some(&0.0)
    }

    /// Frames rendered along the path: each once, an error frame `converge` times.
    fn path_len(&self, timed: u32) -> usize {
        self.path(timed)
            .iter()
            .map(|f| if f.error { self.converge } else { 1 })
            .sum()
    }

    /// Every step: prepare, warm-up, the path.
    fn steps(&self, timed: u32, warmup: usize) -> usize {
        1 + warmup + self.path_len(timed)
    }
}

/// The timed samples of a row's frames.
#[derive(Default)]
struct Samples {
    frames: Vec<f64>,
    /// Per technique span: its time in every timed frame.
    spans: BTreeMap<String, Vec<f64>>,
    /// Per contained variant: the sum of its spans in every timed frame.
    contained: Vec<Vec<f64>>,
    /// Per timed frame: the share of it the technique's spans account for.
    cover: Vec<f64>,
}

impl Samples {
    fn add(&mut self, sample: &Sample, timing: Timing, kind: TimerKind, contained: &[Contained]) {
        let frame = sample.time("frame", timing, kind);
        self.frames.push(frame);
        let mut named = 0.0;
        for (label, ms) in sample.extra() {
            self.spans
                .entry(format!("{label}_ms"))
                .or_default()
                .push(*ms);
            named += ms;
        }
        self.cover.push(named / frame);
        self.contained.resize(contained.len(), Vec::new());
        for (c, times) in contained.iter().zip(&mut self.contained) {
            let sum = sample
                .extra()
                .filter(|(label, _)| c.spans.contains(&label.as_str()))
                .map(|(_, ms)| ms)
                .sum();
            times.push(sum);
        }
    }
}

/// Renders `technique` on `scene` (see the module documentation). `on_step` is told each step:
/// what it is, how many steps are done and how many there are (prepare, warm-up frames, the
/// path's frames; the total shrinks when the timed budget cuts frames).
pub fn run_technique(
    ctx: &Context,
    technique: &mut dyn Technique,
    scene: &mut GpuScene,
    size: crate::Size,
    frames: Frames,
    on_step: &mut OnStep,
) -> Result<TechniqueRun> {
    run_containing(ctx, technique, scene, size, frames, &[], on_step)
}

/// [`run_technique`], measuring the `contained` variants from its frames too (see
/// `Technique::contains`): their images at each error frame, their times from their spans.
pub fn run_containing(
    ctx: &Context,
    technique: &mut dyn Technique,
    scene: &mut GpuScene,
    size: crate::Size,
    frames: Frames,
    contained: &[Contained],
    on_step: &mut OnStep,
) -> Result<TechniqueRun> {
    scene::orthographic_refusal(technique, &scene.scene)?;
    let mut timer = GpuTimer::new(ctx, 64);
    let (kind, timing) = (timer.kind(), technique.timing());
    let target = Target::new(ctx, size.width, size.height)?;
    let (schedule, frames) = Schedule::of(technique, &scene.scene, frames);
    let mut recorder = Recorder::new(ctx, &mut timer, target, size, scene);
    on_step("prepare", 0, schedule.steps(frames.timed, schedule.warmup));
    update_scene(ctx, recorder.timer, scene, 0.0)?;
    let prep = prepare(ctx, recorder.timer, technique, scene)?;
    let mut spans_ms: BTreeMap<String, f64> = BTreeMap::new();
    for (label, ms) in prep.extra() {
        *spans_ms.entry(format!("prepare.{label}_ms")).or_insert(0.0) += ms;
    }
    let keep_first = contained.is_empty();
    let warmed_up = warm_up(
        &mut recorder,
        technique,
        scene,
        &schedule,
        frames,
        keep_first,
        on_step,
    )?;
    let clock = (timing, kind);
    let (samples, error_frames, contained_frames) = walk_path(
        &mut recorder,
        technique,
        scene,
        &schedule,
        warmed_up,
        (clock, contained),
        on_step,
    )?;
    for (label, values) in samples.spans {
        spans_ms.insert(label, TimeStats::from_samples(&values).median_ms);
    }
    Ok(TechniqueRun {
        contained: contained_runs(contained, contained_frames, &samples.contained),
        spans_cover: TimeStats::from_samples(&samples.cover).median_ms,
        error_frames,
        timer: match timing {
            Timing::Cpu => "cpu".to_string(),
            Timing::Gpu => kind.label().to_string(),
        },
        frame: TimeStats::from_samples(&samples.frames),
        prepare_ms: prep.time("prepare", timing, kind),
        prepare_wall_ms: prep.0.total_ms,
        spans_ms,
    })
}

/// The contained variants' runs: their images and the sums of their spans.
fn contained_runs(
    contained: &[Contained],
    frames: Vec<Vec<ErrorFrame>>,
    times: &[Vec<f64>],
) -> Vec<ContainedRun> {
    contained
        .iter()
        .zip(frames)
        .enumerate()
        .map(|(i, (c, error_frames))| ContainedRun {
            id: c.id.clone(),
            error_frames,
            frame: TimeStats::from_samples(times.get(i).map_or(&[][..], |t| t.as_slice())),
        })
        .collect()
}

/// What the warm-up leaves for the path.
struct WarmedUp {
    /// Timed frames the row keeps.
    timed: u32,
    /// Warm-up frames rendered.
    warmed: usize,
    /// For a row timed on its error frames alone, the warm-up frame as the first of them (its
    /// sample and image): the frame at time 0 rendered again would add nothing but time.
    first: Option<(Sample, ErrorFrame)>,
}

/// The warm-up frames at time 0; the first also tells how many timed frames fit the budget (a
/// slow technique then needs no further warm-up: its shaders are compiled and its maps made).
/// When the budget leaves the row its error frames alone, the first warm-up frame is the first
/// error frame (if `keep_first`): its image is read back and its time is a sample, so such a row
/// renders each error frame once and nothing else. Its first-frame costs then count among the
/// samples, where a median of three outvotes them; they show in p95.
fn warm_up(
    recorder: &mut Recorder,
    technique: &mut dyn Technique,
    scene: &mut GpuScene,
    schedule: &Schedule,
    frames: Frames,
    keep_first: bool,
    on_step: &mut OnStep,
) -> Result<WarmedUp> {
    let total = schedule.steps(frames.timed, schedule.warmup);
    for w in 0..schedule.warmup {
        on_step("warm-up", 1 + w, total);
        let sample = recorder.frame(technique, scene, 0.0)?;
        if w == 0 {
            let timed = frames.timed_within_budget(sample.0.total_ms);
            if timed < frames.timed {
                let first = match keep_first && schedule.warm_up_is_first_error_frame(timed) {
                    true => Some((sample, recorder.error_frame(0.0)?)),
                    false => None,
                };
                return Ok(WarmedUp {
                    timed,
                    warmed: 1,
                    first,
                });
            }
        }
    }
    Ok(WarmedUp {
        timed: frames.timed,
        warmed: schedule.warmup,
        first: None,
    })
}

/// The camera path's frames (see [`Schedule::path`]): every one a timed sample, the error
/// frames read back after their last frame.
fn walk_path(
    recorder: &mut Recorder,
    technique: &mut dyn Technique,
    scene: &mut GpuScene,
    schedule: &Schedule,
    warmed_up: WarmedUp,
    ((timing, kind), contained): ((Timing, TimerKind), &[Contained]),
    on_step: &mut OnStep,
) -> Result<(Samples, Vec<ErrorFrame>, Vec<Vec<ErrorFrame>>)> {
    let WarmedUp {
        timed,
        warmed,
        first,
    } = warmed_up;
    let mut path = schedule.path(timed);
    let mut done = 1 + warmed;
    let total = done + schedule.path_len(timed) - usize::from(first.is_some());
    let mut samples = Samples::default();
    let mut error_frames = Vec::new();
    if let Some((sample, image)) = first {
        // The warm-up frame was the path's first frame, the error frame at time 0.
        debug_assert!(path[0].error && path[0].time == 0.0);
        path.remove(0);
        samples.add(&sample, timing, kind, contained);
        error_frames.push(image);
    }
    let mut contained_frames = vec![Vec::new(); contained.len()];
    for frame in &path {
        let repeats = if frame.error { schedule.converge } else { 1 };
        for k in 0..repeats {
            let label = match (frame.error, repeats) {
                (true, 1) => format!("error frame at time {}", frame.time),
                (true, _) => format!("error frame at time {} ({}/{repeats})", frame.time, k + 1),
                (false, _) => format!("frame at time {}", frame.time),
            };
            on_step(&label, done, total);
            let sample = recorder.frame(technique, scene, frame.time)?;
            samples.add(&sample, timing, kind, contained);
            done += 1;
        }
        if frame.error {
            error_frames.push(recorder.error_frame(frame.time)?);
            for (c, frames) in contained.iter().zip(&mut contained_frames) {
                frames.push(ErrorFrame {
                    time: frame.time,
                    image: recorder.contained(technique, &c.id)?,
                });
            }
        }
    }
    Ok((samples, error_frames, contained_frames))
}

fn target_image(ctx: &Context, target: &Target) -> Result<HdrImage> {
    target
        .read(ctx)
        .map_err(|e| anyhow!(e).context("reading the error frame back"))
}

/// What every frame of a row renders into, and with: the target, the timer and the path's
/// camera.
struct Recorder<'t> {
    ctx: &'t Context,
    timer: &'t mut GpuTimer,
    target: Target,
    size: crate::Size,
    camera_path: scene::CameraPath,
    still: scene::Camera,
}

impl<'t> Recorder<'t> {
    fn new(
        ctx: &'t Context,
        timer: &'t mut GpuTimer,
        target: Target,
        size: crate::Size,
        scene: &GpuScene,
    ) -> Self {
        Recorder {
            ctx,
            timer,
            target,
            size,
            camera_path: scene.scene.camera_path.clone(),
            still: scene.scene.camera,
        }
    }

    /// Contained variant `id`'s image of the frame just rendered, drawn in a submission of its
    /// own into a target of its own and read back.
    fn contained(&mut self, technique: &mut dyn Technique, id: &str) -> Result<HdrImage> {
        let target = Target::new(self.ctx, self.size.width, self.size.height)?;
        runner::record(self.ctx, self.timer, "contained", |frame| {
            technique.render_contained(frame, id, &target)
        })
        .map_err(|e| anyhow!(e).context(format!("the image of {id}")))?;
        target_image(self.ctx, &target)
    }

    /// The image of the frame just rendered, as the error frame at `time`.
    fn error_frame(&self, time: f32) -> Result<ErrorFrame> {
        Ok(ErrorFrame {
            time,
            image: target_image(self.ctx, &self.target)?,
        })
    }

    /// One frame of the path's view at `time`.
    fn frame(
        &mut self,
        technique: &mut dyn Technique,
        scene: &mut GpuScene,
        time: f32,
    ) -> Result<Sample> {
        let view = View {
            camera: self.camera_path.sample(time).unwrap_or(self.still),
            time,
            width: self.size.width,
            height: self.size.height,
        };
        render_frame(self.ctx, self.timer, technique, scene, &view, &self.target)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_frames_sit_among_the_timed_frames_once() {
        let times = |frames: &[PathFrame]| -> Vec<(f32, bool)> {
            frames.iter().map(|f| (f.time, f.error)).collect()
        };
        // 4 timed frames over 2 s (0, 0.5, 1, 1.5) and errors at 0, 1, 2: 0 and 1 are both.
        assert_eq!(
            times(&path_frames(2.0, 4, &[0.0, 1.0, 2.0])),
            [
                (0.0, true),
                (0.5, false),
                (1.0, true),
                (1.5, false),
                (2.0, true)
            ]
        );
        // A still scene: every frame at time 0, the first of them the error frame.
        assert_eq!(
            times(&path_frames(0.0, 3, &[0.0])),
            [(0.0, true), (0.0, false), (0.0, false)]
        );
        // Fewer timed frames than error times: every error time still has its frame.
        assert_eq!(
            times(&path_frames(2.0, 1, &[0.0, 1.0, 2.0])),
            [(0.0, true), (1.0, true), (2.0, true)]
        );
        // Timed frames that miss the error times keep their own places.
        assert_eq!(
            times(&path_frames(3.0, 3, &[0.0, 1.5, 3.0])),
            [
                (0.0, true),
                (1.0, false),
                (1.5, true),
                (2.0, false),
                (3.0, true)
            ]
        );
    }
}
