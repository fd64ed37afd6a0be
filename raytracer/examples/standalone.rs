//! The exact GPU ray tracer in your own wgpu renderer: no harness, no test kit.
//!
//! What an engine programmer does with this crate, step by step: create the wgpu device
//! yourself (plain wgpu), wrap it in a `gpu::Context`, take a scene from `scene`'s API (the
//! built-in `hu-qin` with its deforming refractor, or a glTF file), upload it once
//! (`scene::GpuScene`), prepare the tracer once, render frames along the scene's camera path
//! (the refractor deforms: the BVH is rebuilt for each frame's time) into colour and depth
//! textures you created, read the colour back and write it as a PNG (sRGB of the clamped
//! linear radiance). Each frame prints its passes' GPU times and the rays it cast.
//!
//! ```text
//! cargo run -p raytracer --example raytracer-standalone [-- [scene.gltf|scene.glb] [out.png]]
//! ```
//!
//! Writes `target/examples/raytracer-standalone.png` unless given another path.

use scene::runner::{prepare, render_frame, update_scene};
use scene::{GpuScene, View};
use std::error::Error;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

const TECHNIQUE: &str = "raytracer/caustics";
const SIZE: u32 = 96;
const FRAMES: u32 = 3;

fn main() -> ExitCode {
    match run(std::env::args().skip(1)) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The whole example; returns the last frame (linear radiance) after writing its PNG.
fn run(args: impl IntoIterator<Item = String>) -> Result<gpu::HdrImage, Box<dyn Error>> {
    let (scene_file, out) = parse_args(args)?;

    // The technique: the tracer with caustics, with fewer photons than the reference's
    // density (the caustic is then grainier, and the frame cheaper).
    let mut technique: Box<dyn scene::Technique> =
        Box::new(raytracer::RayTracer::new(raytracer::Variant::Caustics));
    technique.set_param("photons", 200_000.0)?;

    // Your device: plain wgpu, with the features the technique cannot run without.
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::PRIMARY,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        ..Default::default()
    }))
    .map_err(|e| {
        format!(
            "no Vulkan, Metal or DX12 adapter ({e}); on Debian/Ubuntu the software driver \
             is `sudo apt-get install mesa-vulkan-drivers`"
        )
    })?;
    let timestamps = adapter.features()
        & (wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("my device"),
        required_features: technique.required_features() | timestamps,
        ..Default::default()
    }))?;
    let ctx = gpu::Context::from_parts(instance, adapter, device, queue)?;

    // Your scene: a glTF file, or the built-in hu-qin scene with its morphing refractor.
    let scene = match &scene_file {
        Some(path) => {
            let scene = scene::gltf_io::import(path)?;
            scene.validate()?;
            scene
        }
        None => scene::load("hu-qin:refractor=morph")?,
    };
    // Your render target: two textures you own, wrapped.
    let texture = |label, format, usage| {
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
            usage,
            view_formats: &[],
        })
    };
    let color = texture(
        "my colour",
        gpu::HDR_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let depth = texture(
        "my depth",
        gpu::DEPTH_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let target = gpu::Target::from_textures(color, depth)?;

    // Upload once, prepare once, then render frames along the camera path.
    let mut gpu_scene = GpuScene::new(&ctx, &scene)?;
    let mut timer = gpu::GpuTimer::new(&ctx, 64);
    println!("{TECHNIQUE} on {}, {SIZE}x{SIZE}", ctx.summary);
    update_scene(&ctx, &mut timer, &mut gpu_scene, 0.0)?;
    prepare(&ctx, &mut timer, technique.as_mut(), &gpu_scene)?;
    let duration = scene.camera_path.duration();
    for i in 0..FRAMES {
        let time = duration * i as f32 / (FRAMES - 1) as f32;
        let view = View {
            camera: scene.camera_at(time),
            time,
            width: SIZE,
            height: SIZE,
        };
        let frame = render_frame(
            &ctx,
            &mut timer,
            technique.as_mut(),
            &mut gpu_scene,
            &view,
            &target,
        )?;
        println!(
            "frame {}/{FRAMES}: t = {time:.1} s, {:.1} ms ({}): eye {:.1} ms, photons {:.1} ms",
            i + 1,
            frame.span("frame").unwrap_or(frame.total_ms),
            timer.kind().label(),
            frame.span("eye").unwrap_or(0.0),
            frame.span("photons").unwrap_or(0.0),
        );
    }
    let image = target.read(&ctx)?;
    write_png(&image, &out)?;
    println!("wrote {}", out.display());
    Ok(image)
}

/// `[scene.gltf|scene.glb] [out.png]`, in any order.
fn parse_args(
    args: impl IntoIterator<Item = String>,
) -> Result<(Option<PathBuf>, PathBuf), Box<dyn Error>> {
    let mut scene_file = None;
    let mut out = PathBuf::from("target/examples/raytracer-standalone.png");
    for arg in args {
        let lower = arg.to_lowercase();
        if lower.ends_with(".gltf") || lower.ends_with(".glb") {
            scene_file = Some(PathBuf::from(arg));
        } else if lower.ends_with(".png") {
            out = PathBuf::from(arg);
        } else {
            return Err(format!(
                "unexpected argument \"{arg}\": give a .gltf/.glb scene and/or a .png output path"
            )
            .into());
        }
    }
    Ok((scene_file, out))
}

/// PNG of the image: sRGB of the clamped linear value, 8 bits per channel.
fn write_png(image: &gpu::HdrImage, path: &Path) -> Result<(), Box<dyn Error>> {
    let srgb = |c: f32| {
        let c = c.clamp(0.0, 1.0);
        let s = if c <= 0.003_130_8 {
            12.92 * c
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round() as u8
    };
    let bytes: Vec<u8> = image
        .pixels
        .iter()
        .flat_map(|p| [srgb(p[0]), srgb(p[1]), srgb(p[2])])
        .collect();
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create the folder {}: {e}", dir.display()))?;
    }
    image::save_buffer(
        path,
        &bytes,
        image.width,
        image.height,
        image::ExtendedColorType::Rgb8,
    )
    .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    /// `cargo test -p raytracer --example raytracer-standalone`: the example traces the
    /// deforming refractor to a finite image whose caustic lights the floor.
    #[test]
    fn traces_the_morphing_refractor_with_a_caustic() {
        let out = std::env::temp_dir().join("raytracer-standalone-test.png");
        let image = super::run([out.display().to_string()]).expect("the example runs");
        assert_eq!(image.non_finite_count(), 0, "NaN or infinite pixels");
        let brightest = image
            .pixels
            .iter()
            .map(|p| (p[0] + p[1] + p[2]) / 3.0)
            .fold(0.0f32, f32::max);
        assert!(
            brightest > 1.0,
            "no caustic brighter than the lit floor ({brightest})"
        );
    }
}
