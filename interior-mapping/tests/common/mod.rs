//! Shared helpers of the image tests: one GPU context per test binary, a small close view of
//! building 0 of the `city` scene, and rendering a technique into an `HdrImage`.
#![allow(dead_code)]

use glam::Vec3;
use scene::{Camera, Frame, GpuScene, Scene, Technique, View};
use std::sync::OnceLock;

pub fn ctx() -> &'static gpu::Context {
    static CTX: OnceLock<gpu::Context> = OnceLock::new();
    CTX.get_or_init(|| {
        gpu::Context::new().unwrap_or_else(|e| panic!("image tests need a GPU adapter: {e}"))
    })
}

/// A camera on the street, 7 m from building 0's +x facade, seeing that face and the +z face
/// with the corner between them (the building has real interiors in the default `city`).
pub fn close_camera() -> Camera {
    Camera {
        eye: Vec3::new(17.0, 8.0, 16.0),
        target: Vec3::new(10.0, 9.5, 4.0),
        up: Vec3::Y,
        fov_y_deg: 50.0,
    }
}

pub fn view(size: u32, time: f32) -> View {
    View {
        camera: close_camera(),
        time,
        width: size,
        height: size,
    }
}

/// Renders one frame of `technique` (prepared on the spot) and reads it back.
pub fn render(scene: &Scene, technique: &mut dyn Technique, view: &View) -> gpu::HdrImage {
    let ctx = ctx();
    let mut gpu_scene = GpuScene::new(ctx, scene).expect("upload");
    let target = gpu::Target::new(ctx, view.width, view.height).expect("target");
    let mut timer = gpu::GpuTimer::new(ctx, 64);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let mut frame = Frame {
        gpu: ctx,
        encoder: &mut encoder,
        timer: &mut timer,
    };
    gpu_scene.set_time(&mut frame, view.time);
    technique.prepare(&mut frame, &gpu_scene).expect("prepare");
    technique
        .render(&mut frame, &gpu_scene, view, &target)
        .expect("render");
    ctx.queue.submit([encoder.finish()]);
    target.read(ctx).expect("read back")
}

pub fn reference(scene: &Scene, view: &View) -> truth::reference::ReferenceImage {
    let opts = truth::reference::ReferenceOptions {
        photons: 0,
        ..Default::default()
    };
    truth::reference::render(
        scene,
        &view.camera,
        view.time,
        view.width,
        view.height,
        &opts,
    )
}

pub fn technique(id: &str) -> Box<dyn Technique> {
    interior_mapping::techniques()
        .into_iter()
        .find(|t| t.id() == id)
        .unwrap_or_else(|| panic!("no technique {id}"))
}

/// Writes a PNG (sRGB of the clamped value) when INTERIOR_TEST_PNG names a folder.
pub fn dump(name: &str, image: &gpu::HdrImage) {
    let Ok(dir) = std::env::var("INTERIOR_TEST_PNG") else {
        return;
    };
    let gpu::HdrImage { width, height, .. } = *image;
    let bytes = truth::metrics::to_srgb8(image);
    let path = std::path::Path::new(&dir).join(format!("{}.png", name.replace('/', "_")));
    let channels = bytes.len() / (width * height) as usize;
    let color = if channels == 4 {
        image::ExtendedColorType::Rgba8
    } else {
        image::ExtendedColorType::Rgb8
    };
    image::save_buffer(path, &bytes, width, height, color).expect("png");
}
