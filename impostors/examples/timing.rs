//! GPU time of the impostor variants: the "lookup" pass (the specular objects' shading with
//! Hit()), the "regenerate" span (environment impostor, plus the split copy) and the
//! "caustics" span (caustic maps + splat), medians over frames, on whatever adapter
//! `gpu::Context` picks.
//!
//! `cargo run -p impostors --example timing -- [size] [frames] [scene] [rounds] [ids,...]`
//! (defaults 512, 20, `cornell-sphere:material=gold`, 3, all). Techniques are interleaved
//! round by round so a shared machine's load drifts affect all alike. The camera is moved to
//! 0.75 m from the sphere's centre so the sphere covers most of the image.

use scene::{Frame, GpuScene, Technique, View};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        v[v.len() / 2]
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let size: u32 = args.get(1).map_or(Ok(512), |s| s.parse())?;
    let frames: usize = args.get(2).map_or(Ok(20), |s| s.parse())?;
    let spec = args
        .get(3)
        .map_or("cornell-sphere:material=gold", String::as_str);
    let ctx = gpu::Context::new()?;
    println!("adapter: {} ({})", ctx.summary, ctx.summary.driver);
    let scene = scene::load(spec)?;
    let sphere = scene
        .objects
        .iter()
        .position(|o| o.name == "sphere")
        .ok_or("no sphere")?;
    let center = scene.objects[sphere].center_at(0.0);
    let mut camera = scene.camera;
    camera.target = center;
    camera.eye = center + (scene.camera.eye - center).normalize() * 0.75;
    let mut gpu_scene = GpuScene::new(&ctx, &scene)?;
    let target = gpu::Target::new(&ctx, size, size)?;
    let view = View {
        camera,
        time: 0.0,
        width: size,
        height: size,
    };
    let ids = [
        "impostors/classic",
        "impostors/initial-guess",
        "impostors/secant-1",
        "impostors/secant-2",
        "impostors/secant-4",
        "impostors/secant-8",
        "impostors/false-position-1",
        "impostors/false-position-2",
        "impostors/false-position-4",
        "impostors/false-position-8",
        "impostors/false-position-4-split",
        "impostors/double-refraction",
        "impostors/caustics",
    ];
    let rounds: usize = args.get(4).map_or(Ok(3), |s| s.parse())?;
    let only: Vec<&str> = args
        .get(5)
        .map(|s| s.split(',').collect())
        .unwrap_or_default();
    println!(
        "{spec}, {size}x{size}, {rounds} interleaved rounds of {frames} frames, impostor resolution 256"
    );
    let mut techniques: Vec<Box<dyn Technique>> = impostors::techniques()
        .into_iter()
        .filter(|t| ids.contains(&t.id().as_str()) && t.supports(&scene))
        .filter(|t| only.is_empty() || only.contains(&t.id().as_str()))
        .collect();
    let mut timer = gpu::GpuTimer::new(&ctx, 64);
    let mut run = |t: &mut dyn Technique,
                   prepare: bool|
     -> Result<Vec<(String, f64)>, Box<dyn std::error::Error>> {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut frame = Frame {
                gpu: &ctx,
                encoder: &mut encoder,
                timer: &mut timer,
            };
            gpu_scene.set_time(&mut frame, 0.0);
            if prepare {
                t.prepare(&mut frame, &gpu_scene)?;
            } else {
                frame.timer.begin(frame.encoder, "frame");
                t.render(&mut frame, &gpu_scene, &view, &target)?;
                frame.timer.end(frame.encoder, "frame");
            }
        }
        Ok(timer.submit_and_collect(&ctx, encoder)?)
    };
    let mut samples: Vec<[Vec<f64>; 4]> = techniques.iter().map(|_| Default::default()).collect();
    for t in techniques.iter_mut() {
        run(t.as_mut(), true)?;
        for _ in 0..2 {
            run(t.as_mut(), false)?; // warm-up
        }
    }
    for _ in 0..rounds {
        for (t, s) in techniques.iter_mut().zip(samples.iter_mut()) {
            for _ in 0..frames {
                for (label, ms) in run(t.as_mut(), false)? {
                    match label.as_str() {
                        "lookup" => s[0].push(ms),
                        "frame" | "wall" => s[1].push(ms),
                        "regenerate" => s[2].push(ms),
                        "caustics" => s[3].push(ms),
                        _ => {}
                    }
                }
            }
        }
    }
    println!(
        "{:<34} {:>10} {:>12} {:>14} {:>12}",
        "technique", "lookup ms", "frame ms", "regenerate ms", "caustics ms"
    );
    for (t, s) in techniques.iter().zip(samples) {
        let [lookup, frame, regen, caustics] = s;
        println!(
            "{:<34} {:>10.3} {:>12.3} {:>14.3} {:>12.3}",
            t.id(),
            median(lookup),
            median(frame),
            median(regen),
            median(caustics)
        );
    }
    Ok(())
}
