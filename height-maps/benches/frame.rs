//! GPU time of one frame of `height-maps/double-refraction`, `height-maps/in-chess` and
//! `height-maps/separated` on `chess` at 64 x 64 (the scene uploaded and the technique
//! prepared once, then each iteration one `scene::runner::render_frame`, measured by the
//! "frame" span of GPU timestamp queries where the device has them, the timer's wall clock
//! otherwise: `testkit::gpu_time`), and the CPU twin of the search (`search_from_outside` and
//! `exit_from_inside` in a 256-texel map of an ellipsoid, the paper's binary search and the
//! linear bracket; wall clock). `cargo bench -p rtapprox-height-maps --bench frame`.

use glam::Vec3;
use height_maps::search::{Bounds, SampledField, Steps, exit_from_inside, search_from_outside};
use testkit::gpu_time::{FrameClock, bench_frame};

fn main() {
    let clock = FrameClock::new(testkit::context());
    let mut c = clock.criterion();
    for id in [
        "height-maps/double-refraction",
        "height-maps/in-chess",
        "height-maps/separated",
    ] {
        let technique = testkit::technique(height_maps::techniques(), id);
        bench_frame(&mut c, &clock, technique, "chess", 64);
    }
    c.final_summary();

    // The CPU twin is timed by the wall clock (the frame clock above measures GPU spans).
    let field = ellipsoid_map(256);
    let mut c = criterion::Criterion::default().configure_from_args();
    for (name, steps) in [
        ("paper-8", Steps::paper(8)),
        (
            "bracket-8-8",
            Steps {
                linear: 8,
                binary: 8,
            },
        ),
    ] {
        c.bench_function(&format!("search/from_outside/{name}"), |b| {
            let mut k = 0u32;
            b.iter(|| {
                k = k.wrapping_add(1);
                let (o, d) = ray_at_the_billboard(k);
                search_from_outside(&field, o, d, steps)
            })
        });
        c.bench_function(&format!("search/exit_from_inside/{name}"), |b| {
            let mut k = 0u32;
            b.iter(|| {
                k = k.wrapping_add(1);
                let (_, d) = ray_at_the_billboard(k);
                exit_from_inside(&field, Vec3::new(0.0, 0.1, 0.05), d, steps)
            })
        });
    }
    c.final_summary();
}

/// The ellipsoid of radius 0.6 and half-height 0.9 (the search's property tests' convex
/// solid) sampled into a `resolution`-square map.
fn ellipsoid_map(resolution: u32) -> SampledField {
    let bounds = Bounds {
        half_width: 0.61,
        v_min: -0.91,
        v_max: 0.91,
        height: 0.61,
    };
    SampledField::from_fn(bounds, resolution, resolution, |u, v| {
        let r2 = 0.36 * (1.0 - (v / 0.9) * (v / 0.9));
        let h2 = r2 - u * u;
        (h2 > 0.0).then(|| {
            let h = h2.sqrt();
            (h, Vec3::new(u, v * 0.36 / 0.81, h))
        })
    })
}

/// Ray `k` of a spread toward the billboard from in front of it (plane frame).
fn ray_at_the_billboard(k: u32) -> (Vec3, Vec3) {
    let h = |i: u32| gpu::prelude::hash_to_unit(3 * k + i) * 2.0 - 1.0;
    let o = Vec3::new(h(0) * 0.5, h(1) * 0.8, 2.0);
    let target = Vec3::new(h(2) * 0.6, h(0) * 0.9, 0.0);
    (o, (target - o).normalize())
}
