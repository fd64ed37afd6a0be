//! GPU time of one frame of the photon marchers on `pool` at 64 x 64 (`screen-photons/lines`,
//! the paper's, and `screen-photons/dda`), measured by the "frame" span of GPU timestamp
//! queries where the device has them, the timer's wall clock otherwise (`testkit::gpu_time`),
//! and the CPU twin of the march (`march::march_lines` and `march::march_dda` over an exact
//! LDI of spheres). `cargo bench -p rtapprox-screen-photons --bench frame`.

use criterion::BenchmarkId;
use glam::Vec3;
use scene::Camera;
use screen_photons::march::{self, Eye, Ldi, RayState, Side, Sphere};
use std::hint::black_box;
use testkit::gpu_time::{FrameClock, bench_frame};

fn main() {
    let clock = FrameClock::new(testkit::context());
    let mut c = clock.criterion();
    for id in ["screen-photons/lines", "screen-photons/dda"] {
        let technique = testkit::technique(screen_photons::techniques(), id);
        bench_frame(&mut c, &clock, technique, "pool", 64);
    }

    // The twin: rays refracted into a glass sphere, marched to their exit.
    let cam = Camera {
        eye: Vec3::new(0.0, 0.5, 6.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 50.0,
        orthographic: None,
    };
    let eye = Eye {
        view_proj: cam.view_proj(128, 128),
        position: cam.eye,
        width: 128,
        height: 128,
    };
    let glass = Sphere {
        centre: Vec3::ZERO,
        radius: 1.5,
        object: 0,
        specular: true,
    };
    let ldi = Ldi::of_spheres(&eye, 4, &[glass]);
    let segments: Vec<_> = (0..128)
        .filter_map(|i| {
            let x = 40 + (i % 48);
            let y = 40 + (i / 3) % 48;
            let front = ldi.get(x, y, 0);
            (front.distance > 0.0).then(|| {
                let view = eye.pixel_ray(x, y);
                let p = eye.position + view * front.distance;
                let dir = gpu::prelude::refract_dir(view, front.normal, 1.0 / 1.5).truncate();
                march::clip(&eye, p, dir, (0.0, 12.0), 0.06)
            })?
        })
        .collect();
    let inside = RayState {
        side: Side::Inside,
        t_skip: 0.03,
    };
    let mut group = c.benchmark_group("twin");
    group.bench_function(BenchmarkId::new("march_lines", segments.len()), |b| {
        b.iter(|| {
            for s in &segments {
                black_box(march::march_lines(&ldi, &eye, s, 0.03, inside));
            }
        })
    });
    group.bench_function(BenchmarkId::new("march_dda", segments.len()), |b| {
        b.iter(|| {
            for s in &segments {
                black_box(march::march_dda(&ldi, &eye, s, 0.1, inside));
            }
        })
    });
    group.finish();
    c.final_summary();
}
