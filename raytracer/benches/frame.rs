//! GPU time of one frame of `raytracer/whitted` and `raytracer/caustics` on `cornell-sphere`
//! and `chess` at 64 x 64 (the "frame" span of GPU timestamp queries where the device has
//! them, the timer's wall clock otherwise: `testkit::gpu_time`), and the CPU twin of the
//! traversal (`FlatBvh::closest_hit`) against the reference's BVH (`SceneBvh`) on the camera
//! rays of `chess`. `cargo bench -p rtapprox-raytracer --bench frame`.

use criterion::BenchmarkId;
use raytracer::bvh::FlatBvh;
use scene::bvh::SceneBvh;
use std::hint::black_box;
use testkit::gpu_time::{FrameClock, bench_frame};

fn main() {
    let clock = FrameClock::new(testkit::context());
    let mut c = clock.criterion();
    for scene in ["cornell-sphere", "chess"] {
        for id in ["raytracer/whitted", "raytracer/caustics"] {
            let technique = testkit::technique(raytracer::techniques(), id);
            bench_frame(&mut c, &clock, technique, scene, 64);
        }
    }
    c.final_summary();

    // The twin runs on the CPU: wall-clock criterion, not the GPU clock of the frames.
    let chess = scene::load("chess").expect("the built-in chess scene");
    let flat = FlatBvh::build(&chess, 0.0).expect("chess's BVH fits the stack");
    let reference = SceneBvh::build(&chess, 0.0);
    let camera = chess.camera_at(0.0);
    let rays: Vec<_> = (0..64 * 64)
        .map(|i| camera.ray_dir((i % 64) as f32 + 0.5, (i / 64) as f32 + 0.5, 64, 64))
        .collect();
    let mut c = criterion::Criterion::default().configure_from_args();
    let mut group = c.benchmark_group("traversal");
    group.bench_function(
        BenchmarkId::new("FlatBvh::closest_hit (twin)", rays.len()),
        |b| {
            b.iter(|| {
                for d in &rays {
                    black_box(flat.closest_hit(camera.eye, *d, f32::INFINITY));
                }
            })
        },
    );
    group.bench_function(
        BenchmarkId::new("SceneBvh::closest_hit (reference)", rays.len()),
        |b| {
            b.iter(|| {
                for d in &rays {
                    black_box(reference.closest_hit(camera.eye, *d, f32::INFINITY));
                }
            })
        },
    );
    group.finish();
    c.final_summary();
}
