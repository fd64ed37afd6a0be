//! GPU time of one frame of `impostors/false-position-4` on `cornell-box` at 64 x 64: the scene
//! uploaded and the technique prepared once, then each iteration is one
//! `scene::runner::render_frame`, measured by the "frame" span of GPU timestamp queries where the
//! device has them, the timer's wall clock otherwise (`testkit::gpu_time`; the benchmark id says
//! which: `frame/gpu-timestamp/...` or `frame/wall/...`). `cargo bench -p rtapprox-impostors --bench frame`.

use testkit::gpu_time::{FrameClock, bench_frame};

fn main() {
    let clock = FrameClock::new(testkit::context());
    let mut c = clock.criterion();
    let technique = testkit::technique(impostors::techniques(), "impostors/false-position-4");
    bench_frame(&mut c, &clock, technique, "cornell-box", 64);
    c.final_summary();
}
