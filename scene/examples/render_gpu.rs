//! Renders a scene with one of the foundation's GPU techniques and writes a PNG — the
//! smallest complete use of `GpuScene` + `Technique` outside the harness.
//!
//! `cargo run -p rtapprox-scene --example render_gpu -- cornell-sphere envmap/classic out.png 256`

use scene::foundation::{ClassicEnvMap, RasterTechnique};
use scene::{Frame, GpuScene, Technique, View};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let spec = args.get(1).map_or("cornell-sphere", String::as_str);
    let id = args.get(2).map_or("raster", String::as_str);
    let out = args.get(3).map_or("render.png", String::as_str);
    let size: u32 = args.get(4).map_or(Ok(256), |s| s.parse())?;

    let ctx = gpu::Context::new()?;
    let scene = scene::load(spec)?;
    let mut technique: Box<dyn Technique> = match id {
        "raster" => Box::new(RasterTechnique),
        "envmap/classic" => Box::new(ClassicEnvMap::default()),
        other => return Err(format!("unknown technique {other}").into()),
    };
    let mut gpu_scene = GpuScene::new(&ctx, &scene)?;
    let target = gpu::Target::new(&ctx, size, size)?;
    let mut timer = gpu::GpuTimer::new(&ctx, 64);
    let view = View {
        camera: scene.camera,
        time: 0.0,
        width: size,
        height: size,
    };

    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let mut frame = Frame {
        gpu: &ctx,
        encoder: &mut encoder,
        timer: &mut timer,
    };
    gpu_scene.set_time(&mut frame, 0.0);
    technique.prepare(&mut frame, &gpu_scene)?;
    technique.render(&mut frame, &gpu_scene, &view, &target)?;
    let spans = timer.submit_and_collect(&ctx, encoder)?;
    println!("{spans:?}");

    let image = target.read(&ctx)?;
    // sRGB of the clamped value, the workspace's PNG convention.
    testkit::save_png(&image, std::path::Path::new(out));
    Ok(())
}
