//! The impostors tests' names for the workspace's `testkit`: renders at a time with the
//! scene's default camera, PNGs under `target/impostors-tests/`.
#![allow(dead_code, unused_imports)]

use gpu::HdrImage;
use scene::Technique;
use std::path::PathBuf;
use testkit::Shot;

pub use testkit::{context as ctx, gpu_lock, submit};

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
    let shots: Vec<Shot> = times
        .iter()
        .map(|&t| Shot::default_camera(scene, t, size))
        .collect();
    testkit::render_shots(technique, scene, &shots)
}

pub fn out_dir() -> PathBuf {
    testkit::out_dir("impostors-tests")
}

/// Writes `image` as an sRGB PNG under [`out_dir`].
pub fn save_png(image: &HdrImage, name: &str) -> PathBuf {
    let path = out_dir().join(name);
    testkit::save_png(image, &path);
    path
}

pub fn technique(id: &str) -> Box<dyn Technique> {
    testkit::technique(impostors::techniques(), id)
}

/// Writes images side by side, each scaled up `scale` times (nearest), as one PNG.
pub fn save_strip(images: &[&HdrImage], name: &str, scale: u32) -> PathBuf {
    save_png(&testkit::strip(images, scale), name)
}
