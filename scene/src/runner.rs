//! Running a technique frame by frame: the one piece of code that the harness (`compare`,
//! `sweep`, `bench`), the tests (`testkit`) and the crates' examples share, so a test renders
//! exactly what the harness measures.
//!
//! Each step is one submission of its own encoder, bracketed by the timer under a label:
//! "scene_update" moves the shared scene to the frame's time (objects' transforms, shadow
//! maps: the same work for every technique, so it is not part of any technique's time),
//! "prepare" is [`Technique::prepare`], "frame" is [`Technique::render`]. A GPU validation
//! error raised by a step is that step's error.

use crate::{Frame, GpuScene, Technique, TechniqueError, TechniqueResult, View};
use gpu::{Context, GpuTimer, Target};
use std::time::Instant;

/// What one recorded submission measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Recorded {
    /// Timer spans (label, milliseconds): the step's own label and any a technique bracketed.
    pub spans: Vec<(String, f64)>,
    /// Wall clock of the technique's call alone (what a CPU technique costs).
    pub call_ms: f64,
    /// Wall clock of the call plus submission and wait.
    pub total_ms: f64,
}

impl Recorded {
    /// The span `label`, if the timer measured it.
    pub fn span(&self, label: &str) -> Option<f64> {
        self.spans.iter().find(|(l, _)| l == label).map(|(_, v)| *v)
    }
}

/// Records one submission: a fresh encoder, `timer.begin(label)`, `f`, `timer.end(label)`,
/// submit and collect the spans.
pub fn record(
    ctx: &Context,
    timer: &mut GpuTimer,
    label: &str,
    f: impl FnOnce(&mut Frame) -> TechniqueResult<()>,
) -> TechniqueResult<Recorded> {
    let result = ctx.validated(|| -> TechniqueResult<Recorded> {
        let mut encoder = ctx
            .device
            .create_command_encoder(&gpu::wgpu::CommandEncoderDescriptor { label: Some(label) });
        timer.begin(&mut encoder, label);
        let start = Instant::now();
        {
            let mut frame = Frame {
                gpu: ctx,
                encoder: &mut encoder,
                timer: &mut *timer,
            };
            f(&mut frame)?;
        }
        let call_ms = start.elapsed().as_secs_f64() * 1e3;
        timer.end(&mut encoder, label);
        let spans = timer.submit_and_collect(ctx, encoder)?;
        Ok(Recorded {
            spans,
            call_ms,
            total_ms: start.elapsed().as_secs_f64() * 1e3,
        })
    });
    match result {
        Ok(inner) => inner,
        Err(validation) => Err(TechniqueError::Gpu(validation)),
    }
}

/// Moves the shared scene to `time` in a submission of its own ("scene_update").
pub fn update_scene(
    ctx: &Context,
    timer: &mut GpuTimer,
    scene: &mut GpuScene,
    time: f32,
) -> TechniqueResult<()> {
    record(ctx, timer, "scene_update", |frame| {
        scene.set_time(frame, time);
        Ok(())
    })
    .map(|_| ())
}

/// The technique's `prepare`, recorded under the label "prepare".
pub fn prepare(
    ctx: &Context,
    timer: &mut GpuTimer,
    technique: &mut dyn Technique,
    scene: &GpuScene,
) -> TechniqueResult<Recorded> {
    record(ctx, timer, "prepare", |frame| {
        technique.prepare(frame, scene)
    })
}

/// Moves the scene to the view's time, then renders one frame of `technique` into `target`
/// under the label "frame".
pub fn render_frame(
    ctx: &Context,
    timer: &mut GpuTimer,
    technique: &mut dyn Technique,
    scene: &mut GpuScene,
    view: &View,
    target: &Target,
) -> TechniqueResult<Recorded> {
    update_scene(ctx, timer, scene, view.time)?;
    let scene = &*scene;
    record(ctx, timer, "frame", |frame| {
        technique.render(frame, scene, view, target)
    })
}
