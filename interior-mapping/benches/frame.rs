//! GPU time of one frame of `interior-mapping/textured` on `city` at 64 x 64: the scene uploaded
//! and the technique prepared once, then each iteration is one `scene::runner::render_frame`,
//! measured by the "frame" span of GPU timestamp queries where the device has them, the timer's
//! wall clock otherwise (`testkit::gpu_time`; the benchmark id says which:
//! `frame/gpu-timestamp/...` or `frame/wall/...`). `cargo bench -p rtapprox-interior-mapping --bench frame`.

use testkit::gpu_time::{FrameClock, bench_frame};

fn main() {
    let clock = FrameClock::new(testkit::context());
    let mut c = clock.criterion();
    let technique = testkit::technique(interior_mapping::techniques(), "interior-mapping/textured");
    bench_frame(&mut c, &clock, technique, "city", 64);
    c.final_summary();
}
