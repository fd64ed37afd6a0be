//! The exact GPU ray tracer as a pass of your own frame: your device, your `Rgba8UnormSrgb`
//! colour and `Depth24Plus` depth textures, your camera's matrices; no `GpuScene`, no harness
//! formats, no timer (`raytracer::pass::TracerPass`).
//!
//! What is this crate's own: the world handed over once as a `scene::Scene` (the tracer holds
//! its own BVH of it), and one call per frame, `TracerPass::draw`, which writes the exact image
//! and the first surfaces' depth into your targets. The scene here is the built-in `hu-qin`,
//! whose refractor deforms along the camera path (the BVH follows each frame's time), with
//! 200 000 caustic photons per frame.
//!
//! ```text
//! cargo run -p rtapprox-raytracer --example raytracer-pass [-- [scene.gltf|scene.glb] [out.png]]
//! ```
//!
//! Writes `target/examples/raytracer-pass.png` unless given another path.

use example_framework::Result;
use gpu::{Frame, TargetFormats, wgpu};
use raytracer::TracerSettings;
use raytracer::pass::{TracerPass, eye_view_of};
use std::path::PathBuf;

const SIZE: u32 = 96;
const FRAMES: u32 = 3;
/// Your renderer's formats.
const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;

/// Your colour or depth texture.
fn my_texture(ctx: &gpu::Context, label: &str, format: wgpu::TextureFormat) -> wgpu::Texture {
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: SIZE,
            height: SIZE,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// The whole example: returns the last frame's sRGB bytes (RGBA) after writing its PNG.
fn run(args: impl IntoIterator<Item = String>) -> Result<Vec<u8>> {
    let default_out = PathBuf::from("target/examples/raytracer-pass.png");
    let options = example_framework::parse_args(args, default_out)?;
    let ctx = example_framework::create_context(wgpu::Features::empty())?;
    let world = example_framework::load_scene(options.scene.as_deref(), || {
        Ok(scene::load("hu-qin:refractor=morph")?)
    })?;
    let color = my_texture(&ctx, "my colour", COLOR);
    let depth = my_texture(&ctx, "my depth", DEPTH);
    let (color_view, depth_view) = (
        color.create_view(&Default::default()),
        depth.create_view(&Default::default()),
    );

    let settings = TracerSettings {
        photons: Some(200_000),
        ..TracerSettings::default()
    };
    let mut pass = TracerPass::new(&ctx, world, TargetFormats::new(COLOR, DEPTH), settings)?;
    println!("raytracer pass on {}, {SIZE}x{SIZE}", ctx.summary);
    for frame in 0..FRAMES {
        // Your camera: here the scene's path, as view and projection matrices.
        let (camera, time) = example_framework::along_path(pass.world(), frame, FRAMES);
        let view = eye_view_of(&camera, SIZE, SIZE);
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        Frame::untimed(&ctx, &mut encoder, |frame| {
            pass.draw(frame, &view, time, &color_view, &depth_view)
        })?;
        ctx.queue.submit([encoder.finish()]);
        let rays = pass.ray_counts(&ctx)?;
        println!(
            "frame {frame} (t = {time:.2} s): {} camera, {} shadow and {} photon rays",
            rays.camera, rays.shadow, rays.photon
        );
    }
    let rgba = gpu::read_texture_bytes(&ctx, &color, 0, 4)?;
    if let Some(dir) = options.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    // The pass leaves your alpha as it was (`TargetFormats::new` keeps it): the PNG is rgb.
    let rgb: Vec<u8> = rgba.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    image::save_buffer(
        &options.out,
        &rgb,
        SIZE,
        SIZE,
        image::ExtendedColorType::Rgb8,
    )
    .map_err(|e| format!("cannot write {}: {e}", options.out.display()))?;
    println!("wrote {}", options.out.display());
    Ok(rgba)
}

fn main() -> std::process::ExitCode {
    example_framework::init_logger();
    match run(std::env::args().skip(1)) {
        Ok(_) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    /// `cargo test -p rtapprox-raytracer --example raytracer-pass`: the pass traces the deforming
    /// refractor into the renderer's 8-bit sRGB target: a lit room, and a caustic brighter than
    /// the format holds (saturated pixels, as `raytracer-standalone`'s brighter than 1).
    #[test]
    fn traces_the_morphing_refractor_into_srgb8() {
        let out = std::env::temp_dir().join("raytracer-pass-test.png");
        let rgba = super::run([out.display().to_string()]).expect("the example runs");
        let pixels = rgba.chunks(4);
        let lit = pixels
            .clone()
            .filter(|p| p[..3].iter().any(|&c| c > 40))
            .count();
        let saturated = pixels.filter(|p| p[..3].contains(&255)).count();
        assert!(
            lit > rgba.len() / 4 / 2,
            "only {lit} lit pixels of {}",
            rgba.len() / 4
        );
        assert!(saturated > 0, "no caustic brighter than the format holds");
    }
}
