//! Interior mapping in your own wgpu renderer: no harness, no test kit.
//!
//! What an engine programmer does with this crate, step by step: create the wgpu device
//! yourself (plain wgpu, with the features the technique needs), wrap it in a
//! `gpu::Context`, build a scene in code (a street with two box buildings and a round tower,
//! each hull marked as a building with its room size) or load a glTF file, upload it once
//! (`scene::GpuScene`), prepare the technique once, render a few frames along a short camera
//! move into colour and depth textures you created, read the colour back and write it as a
//! PNG (sRGB of the clamped linear radiance).
//!
//! ```text
//! cargo run -p interior-mapping --example interior-mapping-standalone [-- [scene.gltf|scene.glb] [out.png]]
//! ```
//!
//! Writes `target/examples/interior-mapping-standalone.png` unless given another path. A
//! glTF file must hold building hulls with a room layout (`harness export-scene city` writes
//! them); it brings its own camera (the one `scene::gltf_io::import` reads), which the example
//! moves the same way.

use glam::{Mat4, Vec2, Vec3};
use scene::mesh::{cuboid, cylinder, quad};
use scene::runner::{prepare, render_frame, update_scene};
use scene::{
    Building, Camera, CameraPath, GpuScene, Material, Object, PointLight, Roles, Scene, View,
};
use std::error::Error;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

const TECHNIQUE: &str = "interior-mapping/textured";
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
    let mut technique = interior_mapping::techniques()
        .into_iter()
        .find(|t| t.id() == TECHNIQUE)
        .ok_or(format!("interior-mapping has no technique {TECHNIQUE}"))?;
    // Parameters by name (`technique.params()` lists them): a light in every room, radiance
    // = albedo x 0.5, so the rooms show even where the sun does not reach through a window.
    technique.set_param("interior_light", 0.5)?;

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
        None => street(),
    };
    if !technique.supports(&scene) {
        return Err(format!(
            "{TECHNIQUE} needs building hulls (role building, with a room layout) in the scene"
        )
        .into());
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
            eye: base_camera.eye + Vec3::new(6.0 * s - 3.0, 0.0, 0.0),
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
    let mut out = PathBuf::from("target/examples/interior-mapping-standalone.png");
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

/// A street: ground, two box buildings and a round tower. A hull is an ordinary object with
/// the `building` role and a `Building` (its room size); the technique draws the rooms
/// behind its windows, the window pattern coming from the room grid (one window per room and
/// face, `scene::builtin::city::is_window`). One far, sun-like light; the camera on the street.
fn street() -> (Scene, Camera) {
    let facade = Material::diffuse(0.7, 0.62, 0.5);
    let building = |name: &str, mesh, at: Vec3, room_size: Vec3| {
        let mut hull = Object::new(name, mesh, facade.clone(), Mat4::from_translation(at))
            .with_roles(Roles::BUILDING);
        hull.building = Some(Building { room_size });
        hull
    };
    let objects = vec![
        Object::new(
            "ground",
            // `quad`'s normal is u x v: +Y.
            quad(
                Vec3::new(-60.0, 0.0, 60.0),
                Vec3::X * 120.0,
                Vec3::NEG_Z * 120.0,
                Vec2::ONE,
            ),
            Material::diffuse(0.3, 0.3, 0.3),
            Mat4::IDENTITY,
        ),
        // Hulls in object space start at their bounding-box minimum: the room grid does too.
        building(
            "office",
            cuboid(Vec3::new(-8.0, 0.0, -8.0), Vec3::new(8.0, 24.0, 8.0)),
            Vec3::new(-11.0, 0.0, 0.0),
            Vec3::new(4.0, 3.0, 4.0),
        ),
        building(
            "flats",
            cuboid(Vec3::new(-7.0, 0.0, -7.0), Vec3::new(7.0, 18.0, 7.0)),
            Vec3::new(10.0, 0.0, 4.0),
            Vec3::new(3.5, 3.6, 3.5),
        ),
        building(
            "tower",
            cylinder(6.0, 36.0, 32),
            Vec3::new(2.0, 0.0, -24.0),
            Vec3::new(3.0, 3.0, 3.0),
        ),
    ];
    let camera = Camera {
        eye: Vec3::new(0.0, 4.0, 30.0),
        target: Vec3::new(0.0, 12.0, 0.0),
        up: Vec3::Y,
        fov_y_deg: 60.0,
    };
    let scene = Scene {
        name: "street".into(),
        objects,
        textures: vec![],
        lights: vec![PointLight {
            name: "sun-like light".into(),
            position: Vec3::new(250.0, 400.0, 300.0),
            intensity: Vec3::splat(4.0e5),
        }],
        camera,
        camera_path: CameraPath::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::new(0.35, 0.45, 0.6),
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
    /// `cargo test -p interior-mapping --example interior-mapping-standalone`: the example renders its built-in scene
    /// to a finite image that is not black.
    #[test]
    fn renders_the_built_in_scene() {
        let out = std::env::temp_dir().join("interior-mapping-standalone-test.png");
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
