//! Helpers shared by the workspace tests: one GPU context per test binary and a one-call
//! "render this technique on this scene" that mirrors what the harness does.

use scene::{Frame, GpuScene, Scene, Technique, View};
use std::sync::OnceLock;

/// The shared context (lavapipe on CI); a missing adapter fails with its one-line reason.
pub fn context() -> &'static gpu::Context {
    static CTX: OnceLock<gpu::Context> = OnceLock::new();
    CTX.get_or_init(|| gpu::Context::new().unwrap_or_else(|e| panic!("{e}")))
}

/// Renders `technique` on `scene` at its default view (time 0) and reads the image back.
pub fn render(technique: &mut dyn Technique, scene: &Scene, size: u32) -> gpu::HdrImage {
    let ctx = context();
    let mut gpu_scene = GpuScene::new(ctx, scene).expect("scene uploads");
    let target = gpu::Target::new(ctx, size, size).expect("target");
    let mut timer = gpu::GpuTimer::new(ctx, 64);
    let view = View {
        camera: scene.camera,
        time: 0.0,
        width: size,
        height: size,
    };
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    {
        let mut frame = Frame {
            gpu: ctx,
            encoder: &mut encoder,
            timer: &mut timer,
        };
        gpu_scene.set_time(&mut frame, 0.0);
        technique.prepare(&mut frame, &gpu_scene).expect("prepare");
        technique
            .render(&mut frame, &gpu_scene, &view, &target)
            .expect("render");
    }
    timer.submit_and_collect(ctx, encoder).expect("submit");
    target.read(ctx).expect("read back")
}

/// The ground truth at the default view, with caustics off unless asked (they only add light
/// under specular objects, and cost most of the reference's time).
pub fn reference(scene: &Scene, size: u32, photons: u64) -> truth::reference::ReferenceImage {
    let options = truth::reference::ReferenceOptions {
        photons,
        ..Default::default()
    };
    truth::reference::render(scene, &scene.camera, 0.0, size, size, &options)
}
