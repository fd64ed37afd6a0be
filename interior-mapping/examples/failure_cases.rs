//! Renders the known failure cases from close cameras the harness's default view does not
//! reach: the seam at a box building's corner and the window/furniture distortion on the
//! cylinder and sphere buildings. Writes PNGs (sRGB of the clamped value) into a folder.
//!
//! `cargo run -p interior-mapping --example failure_cases -- interior-mapping/docs`

use glam::Vec3;
use scene::{Camera, Frame, GpuScene, View};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).unwrap_or_else(|| ".".into());
    let size = 192;
    let ctx = gpu::Context::new()?;
    let scene = scene::load("city")?;
    // Building 0 is a box at the origin (20 x 40 x 20 m), building 1 the cylinder at x = 32,
    // building 2 the sphere (radius 10) centred at (64, 10, 0).
    let views = [
        (
            "box-corner",
            Vec3::new(16.0, 9.0, 16.0),
            Vec3::new(10.0, 8.0, 10.0),
        ),
        (
            "cylinder",
            Vec3::new(50.0, 9.0, 14.0),
            Vec3::new(32.0, 9.0, 0.0),
        ),
        (
            "sphere",
            Vec3::new(82.0, 12.0, 14.0),
            Vec3::new(64.0, 10.0, 0.0),
        ),
    ];
    for (name, eye, target) in views {
        let camera = Camera {
            eye,
            target,
            up: Vec3::Y,
            fov_y_deg: 60.0,
        };
        for id in ["interior-mapping/textured", "interior-mapping/furniture"] {
            let mut technique = interior_mapping::techniques()
                .into_iter()
                .find(|t| t.id() == id)
                .ok_or("technique missing")?;
            let mut gpu_scene = GpuScene::new(&ctx, &scene)?;
            let target_image = gpu::Target::new(&ctx, size, size)?;
            let mut timer = gpu::GpuTimer::new(&ctx, 64);
            let view = View {
                camera,
                time: 0.0,
                width: size,
                height: size,
            };
            let mut encoder = ctx.device.create_command_encoder(&Default::default());
            {
                let mut frame = Frame {
                    gpu: &ctx,
                    encoder: &mut encoder,
                    timer: &mut timer,
                };
                gpu_scene.set_time(&mut frame, 0.0);
                technique.prepare(&mut frame, &gpu_scene)?;
                technique.render(&mut frame, &gpu_scene, &view, &target_image)?;
            }
            timer.submit_and_collect(&ctx, encoder)?;
            let image = target_image.read(&ctx)?;
            let bytes = truth::metrics::to_srgb8(&image);
            let channels = bytes.len() / (size * size) as usize;
            let color = if channels == 4 {
                image::ExtendedColorType::Rgba8
            } else {
                image::ExtendedColorType::Rgb8
            };
            let path = format!(
                "{out}/failure-{name}-{}.png",
                id.replace("interior-mapping/", "")
            );
            image::save_buffer(&path, &bytes, size, size, color)?;
            println!("wrote {path}");
        }
    }
    Ok(())
}
