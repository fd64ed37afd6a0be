//! The scaffold every technique crate's standalone example stands on, in the manner of the
//! wgpu examples' `framework.rs`: an example says what is its own (the technique and its
//! parameters, the built-in scene, how the camera moves, what to print) by implementing
//! [`Example`]; this crate does what every renderer does the same way, each step in a
//! function a reader can lift into their own code:
//!
//! 1. [`parse_args`]: `[scene.gltf|scene.glb] [out.png]`, in any order;
//! 2. [`create_context`]: the user's own wgpu device (plain wgpu, with the features the
//!    technique cannot run without, and GPU timestamps where the adapter has them), wrapped
//!    for the workspace's crates by `gpu::Context::from_parts`;
//! 3. [`load_scene`]: a glTF file (validated) or the example's built-in scene; [`run`] then
//!    asks the technique whether it supports it;
//! 4. [`create_target`]: colour and depth textures the user owns, wrapped as a `gpu::Target`;
//! 5. upload once (`scene::GpuScene`), prepare once, render [`Example::FRAMES`] frames along
//!    [`Example::view`], read the last one back;
//! 6. [`write_png`]: sRGB of the clamped linear radiance, 8 bits per channel.
//!
//! [`run`] does all six; an example's `main` is `example_framework::main::<MyExample>()`.

pub mod scenes;

use glam::Vec3;
use gpu::{Context, HdrImage, Target};
use scene::runner::{prepare, render_frame, update_scene};
use scene::{Camera, GpuScene, Scene, Technique, View};
use std::error::Error;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// What an example's functions return: any error, printed as one sentence by [`main`].
pub type Result<T> = std::result::Result<T, Box<dyn Error>>;

/// What one standalone example is made of; the rest is [`run`]'s.
pub trait Example {
    /// The example's name as Cargo knows it (`cargo run --example NAME`); its PNG goes to
    /// `target/examples/NAME.png` unless the command line names another.
    const NAME: &'static str;
    /// Width and height of the frames, in pixels.
    const SIZE: u32 = 128;
    /// How many frames are rendered; the last one is written.
    const FRAMES: u32 = 4;
    /// What a scene must hold for the technique, said when a glTF file lacks it
    /// ("a volume (`scene::Volume`)").
    const NEEDS: &'static str;
    /// Timer spans printed after each frame's total (`"caustics"`, `"splat"`); a span the
    /// technique did not record prints as 0.
    const SPANS: &'static [&'static str] = &[];

    /// The technique, with the parameters the example sets by name.
    fn technique() -> Result<Box<dyn Technique>>;

    /// The scene rendered when no glTF file is given, with the camera it starts from.
    fn built_in_scene() -> Result<Scene>;

    /// The camera and scene time of frame `frame` of [`Self::FRAMES`]: by default along the
    /// scene's own camera path ([`along_path`]).
    fn view(scene: &Scene, frame: u32) -> (Camera, f32) {
        along_path(scene, frame, Self::FRAMES)
    }
}

/// The example's `main`: runs it on the process's arguments; an error is one line on stderr
/// and a non-zero exit.
pub fn main<E: Example>() -> ExitCode {
    init_logger();
    match run::<E>(std::env::args().skip(1)) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The binary edge's logger: wgpu's own warnings reach standard error (`RUST_LOG` changes the
/// level). A library never installs one; an application installs its own.
pub fn init_logger() {
    let env = env_logger::Env::default().default_filter_or("warn");
    let _ = env_logger::Builder::from_env(env).try_init();
}

/// The whole example: returns the last frame (linear radiance) after writing its PNG.
pub fn run<E: Example>(args: impl IntoIterator<Item = String>) -> Result<HdrImage> {
    let default_out = PathBuf::from(format!("target/examples/{}.png", E::NAME));
    let options = parse_args(args, default_out)?;
    let mut technique = E::technique()?;
    let ctx = create_context(technique.required_features())?;
    let scene = load_scene(options.scene.as_deref(), E::built_in_scene)?;
    if !technique.supports(&scene) {
        return Err(format!("{} needs {} in the scene", technique.id(), E::NEEDS).into());
    }
    let target = create_target(&ctx, E::SIZE, E::SIZE)?;

    // Upload once, prepare once, then render frames.
    let mut gpu_scene = GpuScene::new(&ctx, &scene)?;
    let mut timer = gpu::GpuTimer::new(&ctx, 64);
    println!(
        "{} on {}, {}x{}",
        technique.id(),
        ctx.summary,
        E::SIZE,
        E::SIZE
    );
    update_scene(&ctx, &mut timer, &mut gpu_scene, 0.0)?;
    let prepared = prepare(&ctx, &mut timer, technique.as_mut(), &gpu_scene)?;
    // What `prepare` builds (pipelines, maps) is mostly CPU work: its wall-clock time.
    println!("prepare: {:.1} ms (wall clock)", prepared.total_ms);
    for i in 0..E::FRAMES {
        let (camera, time) = E::view(&scene, i);
        let view = View {
            camera,
            time,
            width: E::SIZE,
            height: E::SIZE,
        };
        let frame = render_frame(
            &ctx,
            &mut timer,
            technique.as_mut(),
            &mut gpu_scene,
            &view,
            &target,
        )?;
        let mut line = format!(
            "frame {}/{}: t = {time:.1} s, eye ({:.2}, {:.2}, {:.2}), {:.1} ms ({})",
            i + 1,
            E::FRAMES,
            camera.eye.x,
            camera.eye.y,
            camera.eye.z,
            frame.span("frame").unwrap_or(frame.total_ms),
            timer.kind().label(),
        );
        for span in E::SPANS {
            line += &format!(", {span} {:.1} ms", frame.span(span).unwrap_or(0.0));
        }
        println!("{line}");
    }

    // Read back the last frame and write it as a PNG.
    let image = target.read(&ctx)?;
    write_png(&image, &options.out)?;
    println!("wrote {}", options.out.display());
    Ok(image)
}

/// The variant `id` among a crate's `techniques()`; an error names the id when the crate has
/// no such variant.
pub fn pick(techniques: Vec<Box<dyn Technique>>, id: &str) -> Result<Box<dyn Technique>> {
    let found = techniques.into_iter().find(|t| t.id() == id);
    Ok(found.ok_or(format!("no technique {id}"))?)
}

/// The command line of every example.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// A glTF scene to render instead of the built-in one.
    pub scene: Option<PathBuf>,
    /// Where the last frame's PNG goes.
    pub out: PathBuf,
}

/// `[scene.gltf|scene.glb] [out.png]`, in any order; anything else is an error that says
/// what is expected.
pub fn parse_args(args: impl IntoIterator<Item = String>, default_out: PathBuf) -> Result<Options> {
    let mut options = Options {
        scene: None,
        out: default_out,
    };
    for arg in args {
        let lower = arg.to_lowercase();
        if lower.ends_with(".gltf") || lower.ends_with(".glb") {
            options.scene = Some(PathBuf::from(arg));
        } else if lower.ends_with(".png") {
            options.out = PathBuf::from(arg);
        } else {
            return Err(format!(
                "unexpected argument \"{arg}\": give a .gltf/.glb scene and/or a .png output path"
            )
            .into());
        }
    }
    Ok(options)
}

/// Your device: plain wgpu, with `features` (what the technique cannot run without) and GPU
/// timestamps where the adapter has them (else frames are timed by the clock), wrapped for
/// the workspace's crates (adapter summary and shared samplers).
pub fn create_context(features: wgpu::Features) -> Result<Context> {
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
        required_features: features | timestamps,
        ..Default::default()
    }))?;
    Ok(Context::from_parts(instance, adapter, device, queue)?)
}

/// Your scene: the glTF file at `path` (it brings its own camera, the one
/// `scene::gltf_io::import` reads), or `built_in` when there is none.
pub fn load_scene(path: Option<&Path>, built_in: impl FnOnce() -> Result<Scene>) -> Result<Scene> {
    match path {
        Some(path) => {
            let scene = scene::gltf_io::import(path)?;
            scene.validate()?;
            Ok(scene)
        }
        None => built_in(),
    }
}

/// Your render target: two textures you own, wrapped. The colour is linear radiance
/// (`gpu::HDR_FORMAT`); `COPY_SRC` lets `Target::read` copy it back.
pub fn create_target(ctx: &Context, width: u32, height: u32) -> Result<Target> {
    let texture = |label, format, usage| {
        ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width,
                height,
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
    Ok(Target::from_textures(color, depth)?)
}

/// Frame `frame` of `frames` spread evenly over the scene's camera path (the scene camera
/// at time 0 when it has none).
pub fn along_path(scene: &Scene, frame: u32, frames: u32) -> (Camera, f32) {
    let time = scene.camera_path.duration() * frame as f32 / (frames.max(2) - 1) as f32;
    (scene.camera_at(time), time)
}

/// Frame `frame` of `frames`: the scene camera moved sideways (along world x) over `width`
/// metres centred on where it stands, 0.1 s of scene time per frame (moving objects move).
pub fn sideways(scene: &Scene, frame: u32, frames: u32, width: f32) -> (Camera, f32) {
    let s = frame as f32 / (frames.max(2) - 1) as f32;
    let camera = Camera {
        eye: scene.camera.eye + Vec3::new(width * (s - 0.5), 0.0, 0.0),
        ..scene.camera
    };
    (camera, 0.1 * frame as f32)
}

/// Writes the image as a PNG: sRGB of the clamped linear value, 8 bits per channel, no tone
/// mapping (what the harness writes and FLIP compares); creates the folder if needed.
pub fn write_png(image: &HdrImage, path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create the folder {}: {e}", dir.display()))?;
    }
    image::save_buffer(
        path,
        &image.to_srgb8(),
        image.width,
        image.height,
        image::ExtendedColorType::Rgb8,
    )
    .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(())
}

/// The mean of the three channels over `pixels`: what an example's test asserts "not black"
/// or "lit" with.
pub fn mean_radiance(pixels: &[[f32; 4]]) -> f32 {
    let sum: f32 = pixels.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).sum();
    sum / pixels.len().max(1) as f32
}

/// The brightest pixel's mean of the three channels: a caustic shows as a value above the
/// directly lit floor's.
pub fn brightest(image: &HdrImage) -> f32 {
    image
        .pixels
        .iter()
        .map(|p| (p[0] + p[1] + p[2]) / 3.0)
        .fold(0.0, f32::max)
}

/// Runs example `E` into a temporary PNG (named after the example) and checks that the last
/// frame is finite: the first half of every example's test.
pub fn run_for_test<E: Example>() -> HdrImage {
    let out = std::env::temp_dir().join(format!("{}-test.png", E::NAME));
    let image = run::<E>([out.display().to_string()]).expect("the example runs");
    assert_eq!(image.non_finite_count(), 0, "NaN or infinite pixels");
    image
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_in_any_order_and_a_clear_error_otherwise() {
        let default = PathBuf::from("default.png");
        let args = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let o = parse_args(args(&["x.PNG", "s.glb"]), default.clone()).unwrap();
        assert_eq!(o.scene, Some(PathBuf::from("s.glb")));
        assert_eq!(o.out, PathBuf::from("x.PNG"));
        let o = parse_args(args(&[]), default.clone()).unwrap();
        assert_eq!((o.scene, o.out), (None, default.clone()));
        let e = parse_args(args(&["--fast"]), default).unwrap_err();
        assert!(e.to_string().contains("unexpected argument \"--fast\""));
    }

    #[test]
    fn sideways_moves_across_the_width_and_along_time() {
        let scene = scene::load("chess").expect("a built-in scene");
        let (first, t0) = sideways(&scene, 0, 4, 1.0);
        let (last, t3) = sideways(&scene, 3, 4, 1.0);
        assert!((last.eye.x - first.eye.x - 1.0).abs() < 1e-5);
        assert!((first.eye.x - (scene.camera.eye.x - 0.5)).abs() < 1e-5);
        assert_eq!(first.target, scene.camera.target);
        assert_eq!(t0, 0.0);
        assert!((t3 - 0.3).abs() < 1e-6);
    }
}
