//! GPU time of one frame of `refractor-maps/multi-bounce-4` and `refractor-maps/separated` on
//! `cornell-sphere` at 64 x 64, and the CPU twin of the board grid's nearest-piece search on
//! the chess pieces (wall clock). The scene is uploaded and the technique prepared once, then each
//! iteration is one `scene::runner::render_frame`, measured by the "frame" span of GPU
//! timestamp queries where the device has them, the timer's wall clock otherwise
//! (`testkit::gpu_time`). `cargo bench -p rtapprox-refractor-maps --bench frame`.

use glam::{Vec2, Vec3};
use scene::multi_object::grid::{ALL_CELLS, BoardGrid, EMPTY, nearest_piece};
use testkit::gpu_time::{FrameClock, bench_frame};

fn main() {
    let clock = FrameClock::new(testkit::context());
    let mut c = clock.criterion();
    for id in ["refractor-maps/multi-bounce-4", "refractor-maps/separated"] {
        let technique = testkit::technique(refractor_maps::techniques(), id);
        bench_frame(&mut c, &clock, technique, "cornell-sphere", 64);
    }
    // The grid of chess: 33 footprints; rays across the board at piece height.
    let scene = scene::load("chess").unwrap();
    let kinds = scene::Kinds::of(&scene);
    let (_, footprints) = scene::multi_object::pieces::pieces_at(&scene, &kinds, 0.0);
    let grid = BoardGrid::build(&footprints).unwrap();
    let centres: Vec<Vec2> = footprints
        .iter()
        .map(|(lo, hi)| 0.5 * (*lo + *hi))
        .collect();
    c.final_summary();
    // The CPU twin is timed by the wall clock (the frame clock above measures GPU spans).
    let mut c = criterion::Criterion::default().configure_from_args();
    c.bench_function("grid/nearest_piece/chess", |b| {
        let mut k = 0u32;
        b.iter(|| {
            k = k.wrapping_add(1);
            let h = |i: u32| gpu::prelude::hash_to_unit(3 * k + i) * 2.0 - 1.0;
            let o = Vec3::new(h(0) * 0.9, 0.1, 0.9);
            let d = Vec3::new(h(1), -0.05, -1.0).normalize();
            // A stand-in hit: the piece's footprint circle, radius 0.06 m.
            nearest_piece(&grid, o, d, EMPTY, ALL_CELLS, |p| {
                let c = centres[p as usize];
                let oc = Vec2::new(o.x, o.z) - c;
                let dd = Vec2::new(d.x, d.z);
                let b = oc.dot(dd) / dd.length_squared();
                let disc = b * b - (oc.length_squared() - 0.0036) / dd.length_squared();
                (disc >= 0.0 && -b - disc.sqrt() > 0.0).then(|| -b - disc.sqrt())
            })
        })
    });
    c.final_summary();
}
