//! Renders the volume variants on a scene, measures their frame times and their error
//! against the ground truth (the reference's participating media composited over the raster
//! pass, `truth::composite::with_reference_media`), and writes PNGs: the table of the thesis's figure 6.23 without
//! the harness.
//!
//! ```text
//! cargo run --release -p rtapprox-volumes --example volumes -- [--scene smoke] [--size 256]
//!     [--frames 20] [--rounds 1] [--out DIR] [--inside] [--density D] [--row Y] [--param name=value]
//!     [id-substring ...]
//! ```
//!
//! `--inside` puts the eye inside the scene's large volume; `--density` overrides the large
//! volumes' density (extinction per metre at the centre); `--row` prints the
//! luminance of one image row of the test and the truth.
//!
//! Times are the harness's: the GPU timer's `frame` span (GPU timestamps where the adapter
//! has them, else wall clock around submit + wait, labelled), median and 95th percentile over
//! `--frames` frames after 3 warm-up frames, in the best of `--rounds` rounds over all
//! variants (on a shared machine, load bursts then hit single rounds); "RMSE cut" is the RMSE over the pixels where the
//! scene cuts a volume (its first surface lies inside a sphere: where slices staircase); `volumes` and `scene-depth` are the spans of the
//! volume pass and of the depth pre-pass inside the frame.

#[path = "../tests/common/mod.rs"]
mod common;

use gpu::{GpuTimer, HdrImage, Target, TimeStats};
use scene::foundation::RasterTechnique;
use scene::{Camera, Frame, GpuScene, Technique, View};
use std::collections::BTreeMap;
use std::path::Path;
use volumes::VolumeSet;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut spec = "smoke".to_string();
    let mut size = 256u32;
    let mut frames = 20usize;
    let mut rounds = 1usize;
    let mut out: Option<String> = None;
    let mut inside = false;
    let mut row: Option<u32> = None;
    let mut density: Option<f32> = None;
    let mut params: Vec<(String, f64)> = Vec::new();
    let mut filters: Vec<String> = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--scene" => spec = args.next().ok_or("--scene needs a value")?,
            "--size" => size = args.next().ok_or("--size needs a value")?.parse()?,
            "--frames" => frames = args.next().ok_or("--frames needs a value")?.parse()?,
            "--rounds" => rounds = args.next().ok_or("--rounds needs a value")?.parse()?,
            "--out" => out = Some(args.next().ok_or("--out needs a value")?),
            "--inside" => inside = true,
            "--density" => density = Some(args.next().ok_or("--density needs a value")?.parse()?),
            "--row" => row = Some(args.next().ok_or("--row needs a value")?.parse()?),
            "--param" => {
                let p = args.next().ok_or("--param needs name=value")?;
                let (k, v) = p.split_once('=').ok_or("--param needs name=value")?;
                params.push((k.to_string(), v.parse()?));
            }
            other => filters.push(other.to_string()),
        }
    }
    if let Some(dir) = &out {
        std::fs::create_dir_all(dir)?;
    }

    let ctx = testkit::context();
    let mut scene = scene::load(&spec)?;
    if let Some(d) = density {
        scene
            .volumes
            .iter_mut()
            .filter(|v| !v.particle)
            .for_each(|v| v.density = d);
    }
    let mut camera = scene.camera;
    if inside {
        let v = scene
            .volumes
            .iter()
            .find(|v| !v.particle)
            .ok_or("the scene has no large volume")?;
        camera = Camera {
            eye: v.center + glam::Vec3::new(0.2, 0.1, 0.3) * v.radius,
            ..camera
        };
    }
    let view = View {
        camera,
        time: 0.0,
        width: size,
        height: size,
    };
    let mut gpu_scene = GpuScene::new(ctx, &scene)?;
    let target = Target::new(ctx, size, size)?;
    let mut timer = GpuTimer::new(ctx, 64);
    println!(
        "adapter: {}; timer: {}; scene {spec}, {size}x{size}, {frames} frames, best of {rounds} rounds",
        ctx.summary,
        timer.kind().label()
    );

    // The scene without volumes, and the exact distances, for the ground truth.
    let base = render_once(
        ctx,
        &mut timer,
        &mut gpu_scene,
        &mut RasterTechnique,
        &view,
        &target,
    )?;
    let distances = truth::composite::primary_distances(&scene, &camera, view.time, size, size);
    // The reference's media over the raster pass: every variant's truth.
    let truth =
        truth::composite::with_reference_media(&scene, &camera, view.time, &base, &distances);

    println!(
        "| id | thesis test | frame ms (median) | p95 | volumes ms | scene-depth ms | RMSE | RMSE cut | FLIP | FLIP masked | non-finite |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    let mut runs: Vec<Run> = Vec::new();
    for mut technique in volumes::techniques() {
        let id = technique.id();
        if !filters.is_empty() && !filters.iter().any(|f| id.contains(f.as_str())) {
            continue;
        }
        if !technique.supports(&scene) {
            println!("| {id} | unsupported on {spec} |");
            continue;
        }
        for (k, v) in &params {
            if technique.params().iter().any(|p| p.name == k) {
                technique.set_param(k, *v)?;
            }
        }
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut frame = Frame {
                gpu: ctx,
                encoder: &mut encoder,
                timer: &mut timer,
            };
            gpu_scene.set_time(&mut frame, view.time);
            technique.prepare(&mut frame, &gpu_scene)?;
        }
        timer.submit_and_collect(ctx, encoder)?;
        runs.push(Run {
            technique,
            best: BTreeMap::new(),
        });
    }
    // Rounds over all variants, so that a burst of load on a shared machine hits one round of
    // a variant rather than all its frames; each span reports its best round's median.
    for _ in 0..rounds {
        for run in runs.iter_mut() {
            let mut spans: BTreeMap<String, Vec<f64>> = BTreeMap::new();
            for i in 0..frames + 3 {
                let mut encoder = ctx.device.create_command_encoder(&Default::default());
                timer.begin(&mut encoder, "frame");
                {
                    let mut frame = Frame {
                        gpu: ctx,
                        encoder: &mut encoder,
                        timer: &mut timer,
                    };
                    run.technique
                        .render(&mut frame, &gpu_scene, &view, &target)?;
                }
                timer.end(&mut encoder, "frame");
                let measured = timer.submit_and_collect(ctx, encoder)?;
                if i >= 3 {
                    for (label, ms) in measured {
                        spans.entry(label).or_default().push(ms);
                    }
                }
            }
            for (label, samples) in spans {
                let stats = TimeStats::from_samples(&samples);
                let best = run.best.entry(label).or_insert(stats);
                if stats.median_ms < best.median_ms {
                    *best = stats;
                }
            }
        }
    }
    for run in runs.iter_mut() {
        let id = run.technique.id();
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut frame = Frame {
                gpu: ctx,
                encoder: &mut encoder,
                timer: &mut timer,
            };
            run.technique
                .render(&mut frame, &gpu_scene, &view, &target)?;
        }
        timer.submit_and_collect(ctx, encoder)?;
        let image = target.read(ctx)?;
        let spec_truth = common::spec_for(&id).expect("every id has a variant model");
        let mask = common::volume_mask(
            &scene,
            &camera,
            view.time,
            size,
            size,
            &distances,
            VolumeSet::All,
        );
        let (m, _) = truth::metrics::compare(&image, &truth, Some(&mask));
        let cut = cut_mask(&scene, &camera, view.time, size, &distances, spec_truth.set);
        let rmse_cut = rmse_over(&image, &truth, &cut);
        let frame_label = if timer.kind() == gpu::TimerKind::Wall {
            "wall"
        } else {
            "frame"
        };
        let f = run.best.get(frame_label).copied().unwrap_or_default();
        let fmt = |label: &str| {
            run.best
                .get(label)
                .map_or("-".to_string(), |s| format!("{:.3}", s.median_ms))
        };
        let test = volumes::technique::all_variants()
            .into_iter()
            .find(|v| v.id() == id)
            .and_then(|v| v.thesis_test())
            .map_or("-".to_string(), |t| t.to_string());
        println!(
            "| {id} | {test} | {:.3} | {:.3} | {} | {} | {:.5} | {:.5} | {:.4} | {:.4} | {} |",
            f.median_ms,
            f.p95_ms,
            fmt("volumes"),
            fmt("scene-depth"),
            m.rmse,
            rmse_cut,
            m.flip_mean,
            m.flip_mean_masked,
            m.nan_pixels
        );
        if let Some(y) = row {
            let lum = |img: &HdrImage, x: u32| {
                let p = img.get(x, y);
                format!(
                    "{:.3}",
                    gpu::prelude::luminance(glam::Vec3::new(p[0], p[1], p[2]))
                )
            };
            let xs = (0..size).step_by((size as usize / 32).max(1));
            println!(
                "  row {y} test : {}",
                xs.clone()
                    .map(|x| lum(&image, x))
                    .collect::<Vec<_>>()
                    .join(" ")
            );
            println!(
                "  row {y} truth: {}",
                xs.map(|x| lum(&truth, x)).collect::<Vec<_>>().join(" ")
            );
        }
        if let Some(dir) = &out {
            let dir = Path::new(dir);
            let name = id.replace('/', "_");
            testkit::save_png(&image, &dir.join(format!("{name}.png")));
            testkit::save_png(&truth, &dir.join(format!("{name}.truth.png")));
            let mut diff = image.clone();
            for (d, t) in diff.pixels.iter_mut().zip(&truth.pixels) {
                for c in 0..3 {
                    d[c] = 4.0 * (d[c] - t[c]).abs();
                }
            }
            testkit::save_png(&diff, &dir.join(format!("{name}.diff4.png")));
        }
    }
    Ok(())
}

/// A prepared variant and the best (lowest-median) round of each of its timer spans.
struct Run {
    technique: Box<dyn Technique>,
    best: BTreeMap<String, TimeStats>,
}

fn render_once(
    ctx: &gpu::Context,
    timer: &mut GpuTimer,
    gpu_scene: &mut GpuScene,
    technique: &mut dyn Technique,
    view: &View,
    target: &Target,
) -> Result<HdrImage, Box<dyn std::error::Error>> {
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    {
        let mut frame = Frame {
            gpu: ctx,
            encoder: &mut encoder,
            timer: &mut *timer,
        };
        gpu_scene.set_time(&mut frame, view.time);
        technique.prepare(&mut frame, gpu_scene)?;
        technique.render(&mut frame, gpu_scene, view, target)?;
    }
    timer.submit_and_collect(ctx, encoder)?;
    Ok(target.read(ctx)?)
}

/// Pixels where the scene cuts a volume: the ray's first surface lies inside a sphere.
fn cut_mask(
    scene: &scene::Scene,
    camera: &Camera,
    time: f32,
    size: u32,
    distances: &[f32],
    set: volumes::VolumeSet,
) -> Vec<bool> {
    let mut out = Vec::with_capacity(distances.len());
    for y in 0..size {
        for x in 0..size {
            let d = camera.ray_dir(x as f32 + 0.5, y as f32 + 0.5, size, size);
            let t = distances[(y * size + x) as usize];
            out.push(scene.volumes.iter().filter(|v| set.includes(v)).any(|v| {
                let s = gpu::prelude::ray_sphere(
                    camera.eye,
                    d,
                    v.center + v.motion.offset(time),
                    v.radius,
                );
                s.x <= s.y && t > s.x.max(0.0) && t < s.y
            }));
        }
    }
    out
}

/// RMSE over linear RGB of the pixels where `mask` is true.
fn rmse_over(a: &HdrImage, b: &HdrImage, mask: &[bool]) -> f64 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for ((p, q), &m) in a.pixels.iter().zip(&b.pixels).zip(mask) {
        if m {
            for c in 0..3 {
                sum += ((p[c] - q[c]) as f64).powi(2);
            }
            n += 3;
        }
    }
    if n == 0 {
        f64::NAN
    } else {
        (sum / n as f64).sqrt()
    }
}
