//! Helpers shared by the GPU tests: one device per test binary, rendering a technique on a
//! scene at a time, writing PNGs under `target/impostors-tests/`.
#![allow(dead_code)]

use std::path::PathBuf;
use std::sync::{Mutex, OnceLock};

use gpu::{Context, GpuTimer, HdrImage, Target};
use scene::{Frame, GpuScene, Technique, View};

pub fn ctx() -> &'static Context {
    static CTX: OnceLock<Context> = OnceLock::new();
    CTX.get_or_init(|| {
        Context::new().unwrap_or_else(|e| panic!("these tests need a GPU adapter: {e}"))
    })
}

/// Tests of one binary share the device; serialising their GPU work keeps lavapipe's threads
/// from being oversubscribed on small machines.
pub fn gpu_lock() -> std::sync::MutexGuard<'static, ()> {
    static LOCK: Mutex<()> = Mutex::new(());
    LOCK.lock().unwrap_or_else(|e| e.into_inner())
}

/// Records one submission through `f` with the scene moved to `time` first.
pub fn submit(
    ctx: &Context,
    gpu_scene: &mut GpuScene,
    time: f32,
    f: impl FnOnce(&mut Frame, &GpuScene),
) -> Vec<(String, f64)> {
    let mut timer = GpuTimer::new(ctx, 64);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    {
        let mut frame = Frame {
            gpu: ctx,
            encoder: &mut encoder,
            timer: &mut timer,
        };
        gpu_scene.set_time(&mut frame, time);
        f(&mut frame, gpu_scene);
    }
    timer.submit_and_collect(ctx, encoder).expect("submit")
}

/// Renders `technique` on `scene` (default camera) at `time`, `size` x `size` pixels.
pub fn render(
    technique: &mut dyn Technique,
    scene: &scene::Scene,
    time: f32,
    size: u32,
) -> HdrImage {
    render_frames(technique, scene, &[time], size)
}

/// Prepares at `times[0]`, renders one frame at each time in turn (default camera) and
/// returns the last image: a map made at an earlier time is reused if the technique's
/// `regen_threshold` allows it.
pub fn render_frames(
    technique: &mut dyn Technique,
    scene: &scene::Scene,
    times: &[f32],
    size: u32,
) -> HdrImage {
    let ctx = ctx();
    let mut gpu_scene = GpuScene::new(ctx, scene).expect("upload");
    let target = Target::new(ctx, size, size).expect("target");
    let result = ctx.validated(|| {
        submit(ctx, &mut gpu_scene, times[0], |frame, s| {
            technique.prepare(frame, s).expect("prepare")
        });
        for &time in times {
            let view = View {
                camera: scene.camera,
                time,
                width: size,
                height: size,
            };
            submit(ctx, &mut gpu_scene, time, |frame, s| {
                technique.render(frame, s, &view, &target).expect("render")
            });
        }
    });
    result.expect("GPU validation");
    target.read(ctx).expect("read back")
}

pub fn out_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/impostors-tests");
    std::fs::create_dir_all(&dir).expect("output dir");
    dir
}

/// Writes `image` as an sRGB PNG (the workspace's convention: clamp, sRGB, no tone mapping).
pub fn save_png(image: &HdrImage, name: &str) -> PathBuf {
    let bytes = truth::metrics::to_srgb8(image);
    let path = out_dir().join(name);
    image::save_buffer(
        &path,
        &bytes,
        image.width,
        image.height,
        image::ExtendedColorType::Rgb8,
    )
    .expect("png");
    path
}

pub fn technique(id: &str) -> Box<dyn Technique> {
    impostors::techniques()
        .into_iter()
        .find(|t| t.id() == id)
        .unwrap_or_else(|| panic!("no variant {id}"))
}

/// Writes images side by side, each scaled up `scale` times (nearest), as one PNG.
pub fn save_strip(images: &[&HdrImage], name: &str, scale: u32) -> PathBuf {
    let h = images.iter().map(|i| i.height).max().unwrap_or(0) * scale;
    let w: u32 = images.iter().map(|i| i.width * scale).sum();
    let mut strip = HdrImage::new(w, h);
    let mut x0 = 0;
    for img in images {
        for y in 0..img.height * scale {
            for x in 0..img.width * scale {
                strip.set(x0 + x, y, img.get(x / scale, y / scale));
            }
        }
        x0 += img.width * scale;
    }
    save_png(&strip, name)
}
