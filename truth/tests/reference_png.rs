//! Not a check but a tool: renders `cornell-sphere` with the reference at 128x128 and
//! 256x256, prints the ray throughput, and writes PNGs (linear -> sRGB, clamped:
//! `testkit::save_png`) to look at.
//!
//! ```text
//! cargo test -p rtapprox-truth --test reference_png -- --ignored --nocapture
//! REFERENCE_PNG_DIR=/tmp/out REFERENCE_PHOTONS=8000000 cargo test -p rtapprox-truth --test reference_png -- --ignored --nocapture
//! ```

use std::path::PathBuf;
use truth::reference::{ReferenceOptions, render};

#[test]
#[ignore = "writes PNGs and prints timings; run by hand"]
fn cornell_sphere_png_and_throughput() {
    let dir = std::env::var("REFERENCE_PNG_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("reference_png"));
    std::fs::create_dir_all(&dir).unwrap();
    let photons = std::env::var("REFERENCE_PHOTONS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(ReferenceOptions::default().photons);
    let spec = std::env::var("REFERENCE_SCENE").unwrap_or_else(|_| "cornell-sphere".into());
    let scene = scene::load(&spec).unwrap();
    for size in [128u32, 256] {
        for (label, p) in [("direct", 0u64), ("full", photons)] {
            let opts = ReferenceOptions {
                photons: p,
                ..Default::default()
            };
            let r = render(&scene, &scene.camera, 0.0, size, size, &opts);
            let s = r.stats;
            println!(
                "{spec} {size}x{size} {label:6} photons={p:>9}: {:.3} s, {:.2} Mrays/s \
                 (camera {}, shadow {}, photon {}), photons stored {}, threads {}",
                s.seconds,
                s.rays_per_second / 1e6,
                s.camera_rays,
                s.shadow_rays,
                s.photon_rays,
                s.photons_stored,
                rayon::current_num_threads()
            );
            assert_eq!(r.image.non_finite_count(), 0);
            let name = format!("{}-{size}-{label}.png", spec.replace([':', '=', ','], "_"));
            testkit::save_png(&r.image, &dir.join(name));
        }
    }
    println!("PNGs in {}", dir.display());
}

#[test]
#[ignore = "prints single-thread BVH throughput; run by hand"]
fn bvh_throughput_single_thread() {
    let scene = scene::load("cornell-sphere").unwrap();
    let bvh = scene::bvh::SceneBvh::build(&scene, 0.0);
    let cam = scene.camera;
    let n = 512u32;
    let t = std::time::Instant::now();
    let mut hits = 0u64;
    for y in 0..n {
        for x in 0..n {
            let d = cam.ray_dir(x as f32 + 0.5, y as f32 + 0.5, n, n);
            hits += bvh.closest_hit(cam.eye, d, f32::INFINITY).is_some() as u64;
        }
    }
    let s = t.elapsed().as_secs_f64();
    println!(
        "coherent closest-hit: {:.2} Mrays/s ({hits} hits)",
        (n * n) as f64 / s / 1e6
    );
    let mut state = 1u32;
    let mut rnd = || {
        state = gpu::prelude::pcg_hash(state);
        state as f32 / u32::MAX as f32
    };
    let rays: Vec<(glam::Vec3, glam::Vec3)> = (0..(n * n))
        .map(|_| {
            let o = glam::Vec3::new(rnd() * 1.8 - 0.9, rnd() * 1.8 + 0.1, rnd() * 1.8 - 0.9);
            let d = glam::Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
            (o, d)
        })
        .collect();
    let t = std::time::Instant::now();
    for (o, d) in &rays {
        hits += bvh.closest_hit(*o, *d, f32::INFINITY).is_some() as u64;
    }
    let s = t.elapsed().as_secs_f64();
    println!(
        "incoherent closest-hit: {:.2} Mrays/s ({hits})",
        (n * n) as f64 / s / 1e6
    );
    // From inside the glass sphere (the photons' and refracted rays' hard case: a chord
    // through a closed mesh crosses many fat bounding boxes of surface patches).
    let sphere = scene.objects.iter().find(|o| o.name == "sphere").unwrap();
    let c = sphere.center_at(0.0);
    let t = std::time::Instant::now();
    for (_, d) in &rays {
        hits += bvh.closest_hit(c + *d * 0.1, *d, f32::INFINITY).is_some() as u64;
    }
    let s = t.elapsed().as_secs_f64();
    println!(
        "inside-sphere closest-hit: {:.2} Mrays/s ({hits})",
        (n * n) as f64 / s / 1e6
    );
}

#[test]
#[ignore = "prints light-pass throughput; run by hand"]
fn light_pass_throughput() {
    use truth::reference::{PhotonSetup, light_trace};
    let scene = scene::load("cornell-sphere").unwrap();
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let opts = ReferenceOptions {
            photons: 500_000,
            ..Default::default()
        };
        let t = std::time::Instant::now();
        let lt = pool.install(|| {
            light_trace(
                &scene,
                &scene.camera,
                0.0,
                256,
                256,
                &opts,
                &PhotonSetup::caustics(&scene),
            )
        });
        let s = t.elapsed().as_secs_f64();
        println!(
            "{threads} threads: {} rays in {s:.3} s = {:.2} Mrays/s",
            lt.rays,
            lt.rays as f64 / s / 1e6
        );
    }
}
