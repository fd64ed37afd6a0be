//! GPU time of one frame of `image-space-refraction/hu-qin`, `nearby-corrected` and `caustics`
//! on `hu-qin` at 64 x 64, measured by the "frame" span of GPU timestamp queries where the
//! device has them, the timer's wall clock otherwise (`testkit::gpu_time`), and the CPU twins:
//! the two-interface search (`search::hu_qin_exit`, both strategies, and `wyman_exit`) over an
//! analytic sphere's buffers, and the caustic filter. `cargo bench -p rtapprox-image-space-refraction
//! --bench frame`.

use criterion::BenchmarkId;
use glam::{Vec2, Vec3, Vec3Swizzles};
use image_space_refraction::caustics;
use image_space_refraction::search::{
    self, Buffers, Eye, FrontBack, Iteration, Side, Strategy, hu_qin_exit, wyman_exit,
};
use std::hint::black_box;
use testkit::gpu_time::{FrameClock, bench_frame};

fn main() {
    let clock = FrameClock::new(testkit::context());
    let mut c = clock.criterion();
    for id in [
        "image-space-refraction/hu-qin",
        "image-space-refraction/nearby-corrected",
        "image-space-refraction/caustics",
    ] {
        let technique = testkit::technique(image_space_refraction::techniques(), id);
        bench_frame(&mut c, &clock, technique, "hu-qin", 64);
    }

    // The twins: entries on a grid of a glass sphere's disc, index 1.5.
    let camera = scene::Camera {
        eye: Vec3::new(0.0, 0.0, 4.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 40.0,
        orthographic: None,
    };
    let eye = Eye::of_camera(&camera, 128, 128);
    let buffers = FrontBack::sphere(&eye, Vec3::ZERO, 1.0);
    let entries: Vec<(Vec3, Vec3, Vec3, Vec3)> = (0..128 * 128)
        .step_by(37)
        .filter_map(|i| {
            let pixel = Vec2::new((i % 128) as f32 + 0.5, (i / 128) as f32 + 0.5);
            let front = buffers.texel(Side::Front, pixel)?;
            let p1 = eye.unproject(pixel, front.depth);
            let v = (p1 - eye.position).normalize();
            let t1 = gpu::prelude::refract_dir(v, front.normal, 1.0 / 1.5).truncate();
            Some((p1, v, front.normal, t1))
        })
        .collect();
    let it = Iteration {
        tolerance: 1e-3,
        max_iterations: 8,
        initial_step: 0.1,
    };
    c.final_summary();
    // The twins run on the CPU: wall-clock criterion, not the GPU clock of the frames.
    let mut c = criterion::Criterion::default().configure_from_args();
    let mut group = c.benchmark_group("twin");
    for (name, strategy) in [
        ("hu_qin_exit angle test", Strategy::AngleTest),
        ("hu_qin_exit back first", Strategy::BackFirst),
    ] {
        group.bench_function(BenchmarkId::new(name, entries.len()), |b| {
            b.iter(|| {
                for (p1, v, _, t1) in &entries {
                    black_box(hu_qin_exit(&buffers, &eye, *p1, *v, *t1, strategy, &it));
                }
            })
        });
    }
    group.bench_function(BenchmarkId::new("wyman_exit", entries.len()), |b| {
        b.iter(|| {
            for (p1, v, n1, t1) in &entries {
                black_box(wyman_exit(&buffers, &eye, *p1, *v, *n1, *t1, 1.0));
            }
        })
    });
    group.bench_function(BenchmarkId::new("silhouette_search", entries.len()), |b| {
        b.iter(|| {
            for (p1, _, _, t1) in &entries {
                let dir = search::projected_direction(&eye, *p1, *t1);
                black_box(search::silhouette_search(
                    &buffers,
                    &eye,
                    eye.project(*p1).xy(),
                    dir,
                    1.0,
                ));
            }
        })
    });
    let counts: Vec<[f32; 3]> = (0..128 * 128)
        .map(|i| {
            if i % 7 == 0 {
                [1.0, 2.0, 3.0]
            } else {
                [0.0; 3]
            }
        })
        .collect();
    for k in [1u32, 2, 3] {
        group.bench_function(BenchmarkId::new("caustic filter 128^2 k", k), |b| {
            b.iter(|| black_box(caustics::filter(&counts, 128, k, 1.0)))
        });
    }
    group.finish();
    c.final_summary();
}
