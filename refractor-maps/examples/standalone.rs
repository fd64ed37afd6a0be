//! Refractor distance maps in your own wgpu renderer: no harness, no test kit.
//!
//! What an engine programmer does with this crate, step by step: create the wgpu device
//! yourself (plain wgpu, with the features the technique needs), wrap it in a
//! `gpu::Context`, build a scene in code (a small room with a mirror and a glass sphere: two
//! kinds of refractor map, rays bouncing between them) or
//! load a glTF file, upload it once (`scene::GpuScene`), prepare the technique once, render a
//! few frames along a short camera move into colour and depth textures you created, read the
//! colour back and write it as a PNG (sRGB of the clamped linear radiance).
//!
//! ```text
//! cargo run -p refractor-maps --example refractor-maps-standalone [-- [scene.gltf|scene.glb] [out.png]]
//! ```
//!
//! Writes `target/examples/refractor-maps-standalone.png` unless given another path. A glTF file
//! must hold a mirror, metal or glass object; it brings its own camera (the one
//! `scene::gltf_io::import` reads), which the example moves the same way.

use glam::{Mat4, Vec2, Vec3};
use scene::builtin::textures::checker_texture;
use scene::mesh::{quad, uv_sphere};
use scene::runner::{prepare, render_frame, update_scene};
use scene::{Camera, CameraPath, GpuScene, Material, Object, PointLight, Roles, Scene, View};
use std::error::Error;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

const TECHNIQUE: &str = "refractor-maps/multi-bounce-4";
const SIZE: u32 = 128;
const FRAMES: u32 = 4;

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

    // The technique: every variant of the crate, picked by id.
    let mut technique = refractor_maps::techniques()
        .into_iter()
        .find(|t| t.id() == TECHNIQUE)
        .ok_or(format!("refractor-maps has no technique {TECHNIQUE}"))?;

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
    // Optional: GPU timestamps where the adapter has them (else frames are timed by the clock).
    let timestamps = adapter.features()
        & (wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("my device"),
        required_features: technique.required_features() | timestamps,
        ..Default::default()
    }))?;
    // Wrapped for the workspace's crates (adapter summary and shared samplers).
    let ctx = gpu::Context::from_parts(instance, adapter, device, queue)?;

    // Your scene and camera.
    let (scene, base_camera) = match &scene_file {
        Some(path) => {
            let scene = scene::gltf_io::import(path)?;
            scene.validate()?;
            let camera = scene.camera;
            (scene, camera)
        }
        None => mirror_and_glass_room(),
    };
    if !technique.supports(&scene) {
        return Err(
            format!("{TECHNIQUE} needs a mirror, metal or glass object in the scene").into(),
        );
    }

    // Your render target: two textures you own, wrapped. The colour is linear radiance
    // (`gpu::HDR_FORMAT`); `COPY_SRC` lets `Target::read` copy it back.
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

    // Upload once, prepare once, then render frames.
    let mut gpu_scene = GpuScene::new(&ctx, &scene)?;
    let mut timer = gpu::GpuTimer::new(&ctx, 64);
    println!("{TECHNIQUE} on {}, {SIZE}x{SIZE}", ctx.summary);
    update_scene(&ctx, &mut timer, &mut gpu_scene, 0.0)?;
    let prepared = prepare(&ctx, &mut timer, technique.as_mut(), &gpu_scene)?;
    // What `prepare` builds (pipelines, maps) is mostly CPU work: its wall-clock time.
    println!("prepare: {:.1} ms (wall clock)", prepared.total_ms);
    for i in 0..FRAMES {
        // A short sideways move of the camera, 0.1 s per frame.
        let s = i as f32 / (FRAMES - 1) as f32;
        let camera = Camera {
            eye: base_camera.eye + Vec3::new(0.4 * s - 0.2, 0.0, 0.0),
            ..base_camera
        };
        let view = View {
            camera,
            time: 0.1 * i as f32,
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
            "frame {}/{FRAMES}: t = {:.1} s, eye ({:.2}, {:.2}, {:.2}), {:.1} ms ({})",
            i + 1,
            view.time,
            camera.eye.x,
            camera.eye.y,
            camera.eye.z,
            frame.span("frame").unwrap_or(frame.total_ms),
            timer.kind().label(),
        );
    }

    // Read back the last frame and write it as a PNG.
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
    let mut out = PathBuf::from("target/examples/refractor-maps-standalone.png");
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

/// A 3 x 2.5 x 3 m room (checker floor, coloured walls, one light under the ceiling) with a
/// mirror sphere and a glass sphere, and the camera looking at them from near the front wall.
fn mirror_and_glass_room() -> (Scene, Camera) {
    let wall = |name: &str, origin: Vec3, u: Vec3, v: Vec3, material: Material| {
        // `quad`'s normal is u x v: every wall faces into the room.
        Object::new(
            name,
            quad(origin, u, v, Vec2::ONE),
            material,
            Mat4::IDENTITY,
        )
    };
    let (w, h) = (3.0, 2.5);
    let mut objects = vec![
        wall(
            "floor",
            Vec3::new(-1.5, 0.0, 1.5),
            Vec3::X * w,
            Vec3::NEG_Z * w,
            Material::Diffuse {
                albedo: Vec3::splat(0.8),
                texture: Some(0),
            },
        ),
        wall(
            "ceiling",
            Vec3::new(-1.5, h, -1.5),
            Vec3::X * w,
            Vec3::Z * w,
            Material::diffuse(0.8, 0.8, 0.8),
        ),
        wall(
            "back wall",
            Vec3::new(-1.5, 0.0, -1.5),
            Vec3::X * w,
            Vec3::Y * h,
            Material::diffuse(0.75, 0.7, 0.55),
        ),
        wall(
            "front wall",
            Vec3::new(1.5, 0.0, 1.5),
            Vec3::NEG_X * w,
            Vec3::Y * h,
            Material::diffuse(0.55, 0.55, 0.75),
        ),
        wall(
            "left wall",
            Vec3::new(-1.5, 0.0, 1.5),
            Vec3::NEG_Z * w,
            Vec3::Y * h,
            Material::diffuse(0.75, 0.15, 0.12),
        ),
        wall(
            "right wall",
            Vec3::new(1.5, 0.0, -1.5),
            Vec3::Z * w,
            Vec3::Y * h,
            Material::diffuse(0.15, 0.6, 0.2),
        ),
    ];
    // The specular objects carry the role the technique looks for.
    objects.push(
        Object::new(
            "mirror sphere",
            uv_sphere(0.45, 48, 96),
            Material::perfect_mirror(),
            Mat4::from_translation(Vec3::new(-0.6, 0.45, -0.4)),
        )
        .with_roles(Roles::REFLECTOR),
    );
    objects.push(
        Object::new(
            "glass sphere",
            uv_sphere(0.4, 48, 96),
            Material::glass(1.5),
            Mat4::from_translation(Vec3::new(0.6, 0.4, 0.1)),
        )
        .with_roles(Roles::REFRACTOR),
    );
    let camera = Camera {
        eye: Vec3::new(0.0, 1.3, 1.4),
        target: Vec3::new(0.0, 0.5, -0.4),
        up: Vec3::Y,
        fov_y_deg: 65.0,
    };
    let scene = Scene {
        name: "mirror and glass room".into(),
        objects,
        textures: vec![checker_texture(
            "floor",
            64,
            8,
            [220, 220, 220],
            [40, 40, 60],
        )],
        lights: vec![PointLight {
            name: "ceiling light".into(),
            position: Vec3::new(0.0, 2.3, 0.2),
            intensity: Vec3::splat(4.0),
        }],
        camera,
        camera_path: CameraPath::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::ZERO,
    };
    (scene, camera)
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
    /// `cargo test -p refractor-maps --example refractor-maps-standalone`: the example renders its built-in scene
    /// to a finite image that is not black.
    #[test]
    fn renders_the_built_in_scene() {
        let out = std::env::temp_dir().join("refractor-maps-standalone-test.png");
        let image = super::run([out.display().to_string()]).expect("the example runs");
        assert_eq!(image.non_finite_count(), 0, "NaN or infinite pixels");
        let mean = image
            .pixels
            .iter()
            .map(|p| (p[0] + p[1] + p[2]) / 3.0)
            .sum::<f32>()
            / image.pixels.len() as f32;
        assert!(
            mean > 0.02,
            "the image is almost black (mean radiance {mean})"
        );
    }
}
