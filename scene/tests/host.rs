//! The uploaded scene as a technique's host (`gpu::DrawScene`): a cube map drawn through the
//! trait is, bit for bit, the one `GpuScene::raster_cube` draws, so every technique that now
//! asks its host for its maps (impostors, image-space refraction) renders what it rendered
//! before the trait existed.

use gpu::cube::CubeTarget;
use gpu::{Objects, read_texture_bytes};
use scene::{BACKGROUND_DISTANCE, Frame, GpuScene, ObjectFilter};

#[test]
fn a_cube_drawn_through_the_trait_is_the_raster_cube() {
    let _lock = testkit::gpu_lock();
    let ctx = testkit::context();
    let scene = scene::load("cornell-sphere").unwrap();
    let specular = scene.specular_objects()[0];
    let centre = scene.objects[specular].center_at(0.0);
    let mut uploaded = GpuScene::new(ctx, &scene).unwrap();
    let format = wgpu::TextureFormat::Rgba16Float;
    let [by_raster, by_trait] = ["raster_cube", "draw_scene_cube"]
        .map(|label| CubeTarget::new(ctx, 32, format, label).unwrap());
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    Frame::untimed(ctx, &mut encoder, |frame| {
        uploaded.set_time(frame, 0.0);
        let others = ObjectFilter::Except(vec![specular]);
        uploaded.raster_cube(frame, &by_raster, centre, &others, false);
        let depth_range = (0.01, 2.0 * BACKGROUND_DISTANCE);
        let others = Objects::AllBut(&[specular]);
        gpu::host::draw_scene_cube(frame, &uploaded, &by_trait, centre, depth_range, others);
    });
    ctx.queue.submit([encoder.finish()]);
    for face in 0..6 {
        let raster = read_texture_bytes(ctx, &by_raster.color, face, 8).unwrap();
        let host = read_texture_bytes(ctx, &by_trait.color, face, 8).unwrap();
        assert!(raster.iter().any(|&b| b != 0), "face {face} holds the room");
        assert_eq!(raster, host, "face {face}");
    }
}

/// A renderer's own formats keep its alpha; the harness's targets take every channel (the
/// distance in alpha).
#[test]
fn a_renderers_alpha_is_kept() {
    let own = gpu::TargetFormats::new(
        wgpu::TextureFormat::Rgba8UnormSrgb,
        wgpu::TextureFormat::Depth24Plus,
    );
    let writes = |formats: gpu::TargetFormats| formats.color_target().unwrap().write_mask;
    assert_eq!(writes(own), wgpu::ColorWrites::COLOR);
    assert_eq!(writes(gpu::TargetFormats::HDR), wgpu::ColorWrites::ALL);
}
