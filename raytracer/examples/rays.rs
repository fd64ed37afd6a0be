//! Rays per second of the GPU tracer and of the CPU reference on the same scene and size, in
//! one run, and the tracer's frame time as the image grows.
//!
//! ```text
//! cargo run --release -p rtapprox-raytracer --example rays -- [--scene cornell-sphere] [--sizes 256,512,1024] [--frames 5] [--cpu-size 256] [--max-caustics-size N]
//! ```
//!
//! For each size: the median GPU frame time of `raytracer/whitted` and `raytracer/caustics`
//! (timestamp queries, after a warm-up frame; wall-clock submit-to-idle beside it), the rays
//! the frame cast (counted on the GPU as the reference counts its own) and rays per second.
//! Then the CPU reference at `--cpu-size` (all cores, rayon): its rays and rays per second,
//! with caustics (its default photon density) and without. Prints a markdown table.
//! `--max-caustics-size N` leaves out the caustics rows above N x N (on a software
//! rasterizer a 1024 x 1024 frame of 64 million photons takes minutes).

use scene::runner::{prepare, render_frame};
use scene::{GpuScene, Technique, View};
use std::error::Error;

struct Options {
    scene: String,
    sizes: Vec<u32>,
    frames: usize,
    cpu_size: u32,
    max_caustics_size: u32,
}

fn parse() -> Result<Options, Box<dyn Error>> {
    let mut o = Options {
        scene: "cornell-sphere".into(),
        sizes: vec![256, 512, 1024],
        frames: 5,
        cpu_size: 256,
        max_caustics_size: u32::MAX,
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--scene" => o.scene = value()?,
            "--sizes" => {
                o.sizes = value()?
                    .split(',')
                    .map(|s| s.trim().parse())
                    .collect::<Result<_, _>>()?
            }
            "--frames" => o.frames = value()?.parse()?,
            "--cpu-size" => o.cpu_size = value()?.parse()?,
            "--max-caustics-size" => o.max_caustics_size = value()?.parse()?,
            _ => return Err(format!("unknown argument {a}").into()),
        }
    }
    if o.frames == 0 || o.sizes.is_empty() || o.sizes.contains(&0) || o.cpu_size == 0 {
        return Err("sizes, --frames and --cpu-size must be positive".into());
    }
    Ok(o)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<(), Box<dyn Error>> {
    let o = parse()?;
    let ctx = gpu::Context::new()?;
    let scene = scene::load(&o.scene)?;
    let mut gpu_scene = GpuScene::new(&ctx, &scene)?;
    let mut timer = gpu::GpuTimer::new(&ctx, 64);
    let camera = scene.camera_at(0.0);
    let start = std::time::Instant::now();
    let bvh = raytracer::bvh::FlatBvh::build(&scene, 0.0)
        .map_err(|e| format!("the BVH is {} levels deep", e.depth))?;
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    let reference_start = std::time::Instant::now();
    let _ = scene::bvh::SceneBvh::build(&scene, 0.0);
    let reference_ms = reference_start.elapsed().as_secs_f64() * 1e3;
    println!("{} on {}", o.scene, ctx.summary);
    println!(
        "adapter offers hardware ray queries (EXPERIMENTAL_RAY_QUERY): {}",
        ctx.adapter
            .features()
            .contains(gpu::wgpu::Features::EXPERIMENTAL_RAY_QUERY)
    );
    println!(
        "BVH: {} triangles, {} nodes, {} levels deep; built on the CPU in {build_ms:.1} ms \
         (the reference's CWBVH: {reference_ms:.1} ms)",
        bvh.triangles.len(),
        bvh.nodes.len(),
        bvh.depth
    );
    println!();
    println!(
        "| renderer | size | frame ms (median of {}) | wall ms | eye ms | photons ms | camera rays | shadow rays | photon rays | Mrays/s |",
        o.frames
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for &size in &o.sizes {
        let target = gpu::Target::new(&ctx, size, size)?;
        for variant in [raytracer::Variant::Whitted, raytracer::Variant::Caustics] {
            if variant == raytracer::Variant::Caustics && size > o.max_caustics_size {
                println!(
                    "| GPU raytracer/caustics | {size}² | not run (--max-caustics-size {}) | | | | | | | |",
                    o.max_caustics_size
                );
                continue;
            }
            let mut tracer = raytracer::RayTracer::new(variant);
            if variant == raytracer::Variant::Caustics {
                // The reference's whole light pass in each frame (the technique's default
                // frame traces a sixteenth of it), so the table compares like with like.
                let all = raytracer::tracer::photons_for_image(size, size);
                scene::Technique::set_param(&mut tracer, "photons", all as f64)?;
            }
            prepare(&ctx, &mut timer, &mut tracer, &gpu_scene)?;
            let view = View {
                camera,
                time: 0.0,
                width: size,
                height: size,
            };
            let mut frame_ms = Vec::new();
            let mut wall_ms = Vec::new();
            let (mut eye, mut photons) = (Vec::new(), Vec::new());
            for i in 0..=o.frames {
                let r = render_frame(
                    &ctx,
                    &mut timer,
                    &mut tracer,
                    &mut gpu_scene,
                    &view,
                    &target,
                )?;
                if i > 0 {
                    frame_ms.push(r.span("frame").unwrap_or(r.total_ms));
                    wall_ms.push(r.total_ms);
                    eye.push(r.span("eye").unwrap_or(0.0));
                    photons.push(r.span("photons").unwrap_or(0.0));
                }
            }
            let counts = tracer
                .tracer()
                .ok_or("the tracer was not prepared")?
                .ray_counts(&ctx)?;
            let ms = median(frame_ms);
            println!(
                "| GPU {} | {size}² | {ms:.2} | {:.2} | {:.2} | {:.2} | {} | {} | {} | {:.1} |",
                tracer.id(),
                median(wall_ms),
                median(eye),
                median(photons),
                counts.camera,
                counts.shadow,
                counts.photon,
                counts.total() as f64 / (ms * 1e-3) / 1e6
            );
        }
    }
    let size = o.cpu_size;
    for photons in [false, true] {
        let mut opts = truth::reference::ReferenceOptions::for_image(size, size);
        if !photons {
            opts.photons = 0;
        }
        let r = truth::reference::render(&scene, &camera, 0.0, size, size, &opts);
        let s = r.stats;
        println!(
            "| CPU reference{} ({} threads) | {size}² | {:.2} | {:.2} | - | - | {} | {} | {} | {:.1} |",
            if photons { " with caustics" } else { "" },
            rayon_threads(),
            s.seconds * 1e3,
            s.seconds * 1e3,
            s.camera_rays,
            s.shadow_rays,
            s.photon_rays,
            s.rays_per_second / 1e6
        );
    }
    Ok(())
}

fn rayon_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}
