//! A criterion measurement of frame time as the GPU timer reports it: the "frame" span of
//! [`scene::runner::render_frame`] from timestamp queries where the device has encoder-level
//! timestamps ([`TimerKind::GpuTimestamp`]), and the timer's wall-clock fallback elsewhere
//! (CPU wall clock of the "frame" submission: recording, submit and wait, [`TimerKind::Wall`]).
//!
//! The technique crates' `benches/frame.rs` are [`bench_frame`] of one variant:
//!
//! ```no_run
//! use testkit::gpu_time::{FrameClock, bench_frame};
//! let clock = FrameClock::new(testkit::context());
//! let mut c = clock.criterion();
//! let technique = testkit::technique(scene::foundation::techniques(), "raster");
//! bench_frame(&mut c, &clock, technique, "cornell-box", 64);
//! c.final_summary();
//! ```
//!
//! Criterion calls [`Measurement::start`] before a batch of iterations and
//! [`Measurement::end`] after it; each iteration adds its frame's time to the clock with
//! [`FrameClock::record`], so a sample is the sum of the batch's frame times, not the wall
//! clock of the loop (which also holds the "scene_update" submission and the CPU recording).
//! Criterion still sizes batches from the wall clock of its warm-up, so `--measurement-time`
//! bounds the wall time of a run, as usual.

use criterion::measurement::{Measurement, ValueFormatter};
use criterion::{BenchmarkId, Criterion, Throughput};
use gpu::{Context, GpuTimer, Target, TimerKind};
use scene::runner::{self, Recorded};
use scene::{GpuScene, Technique};
use std::sync::{Arc, Mutex};

/// The measurement: nanoseconds of frame time from the source [`FrameClock::kind`] names.
/// Clones share one running total.
#[derive(Clone, Debug)]
pub struct FrameClock {
    kind: TimerKind,
    total_ns: Arc<Mutex<f64>>,
}

impl FrameClock {
    /// The clock of `ctx`'s timer: GPU timestamps where the device has them inside encoders,
    /// wall clock otherwise (what `GpuTimer::kind` says).
    pub fn new(ctx: &Context) -> Self {
        Self::with_kind(GpuTimer::new(ctx, 1).kind())
    }

    /// A clock that reads `kind`'s figure from every recorded frame.
    pub fn with_kind(kind: TimerKind) -> Self {
        Self {
            kind,
            total_ns: Arc::new(Mutex::new(0.0)),
        }
    }

    /// Where the figures come from.
    pub fn kind(&self) -> TimerKind {
        self.kind
    }

    /// The benchmark id `<gpu-timestamp|wall>/<parameter>`: every figure says what measured it.
    pub fn id(&self, parameter: &str) -> BenchmarkId {
        BenchmarkId::new(self.kind.label(), parameter)
    }

    /// Milliseconds of one recorded frame: its "frame" span for GPU timestamps; for the wall
    /// fallback the timer's "wall" span (the frame submission's recording, submit and wait),
    /// or the call's total wall clock when the timer has none.
    pub fn frame_ms(&self, recorded: &Recorded) -> f64 {
        match self.kind {
            TimerKind::GpuTimestamp => recorded
                .span("frame")
                .expect("a GPU-timestamp timer measures the \"frame\" span"),
            TimerKind::Wall => recorded.span("wall").unwrap_or(recorded.total_ms),
        }
    }

    /// Adds one frame's time to the running total and returns it (milliseconds).
    pub fn record(&self, recorded: &Recorded) -> f64 {
        let ms = self.frame_ms(recorded);
        *self.total_ns.lock().unwrap_or_else(|e| e.into_inner()) += ms * 1e6;
        ms
    }

    fn total(&self) -> f64 {
        *self.total_ns.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A criterion driver measuring with this clock, configured from the command line
    /// (`-- --warm-up-time 1 --sample-size 10`), as `criterion_main!` does.
    pub fn criterion(&self) -> Criterion<FrameClock> {
        Criterion::default()
            .with_measurement(self.clone())
            .configure_from_args()
    }
}

/// Benchmarks one frame of `technique` on the scene `spec` at `size` x `size` (the scene's
/// default camera, time 0): uploads the scene and prepares the technique once, then every
/// iteration is one [`runner::render_frame`] (its "scene_update" submission, then its
/// "frame" submission), measured by `clock`. The id is
/// `frame/<gpu-timestamp|wall>/<technique id>@<spec>-<size>x<size>`.
pub fn bench_frame(
    c: &mut Criterion<FrameClock>,
    clock: &FrameClock,
    mut technique: Box<dyn Technique>,
    spec: &str,
    size: u32,
) {
    let ctx = crate::context();
    let scene = scene::load(spec).unwrap_or_else(|e| panic!("scene {spec}: {e}"));
    assert!(
        technique.supports(&scene),
        "{} does not render {spec}",
        technique.id()
    );
    let id = format!("{}@{spec}-{size}x{size}", technique.id());
    let mut gpu_scene = GpuScene::new(ctx, &scene).expect("scene uploads");
    let target = Target::new(ctx, size, size).expect("target");
    let view = crate::Shot::default_camera(&scene, 0.0, size).view();
    let mut timer = GpuTimer::new(ctx, 64);
    runner::update_scene(ctx, &mut timer, &mut gpu_scene, view.time).expect("scene update");
    runner::prepare(ctx, &mut timer, technique.as_mut(), &gpu_scene).expect("prepare");
    let mut frame = || {
        runner::render_frame(
            ctx,
            &mut timer,
            technique.as_mut(),
            &mut gpu_scene,
            &view,
            &target,
        )
        .expect("render")
    };
    // One frame outside the measurement: pipelines and first-use allocations.
    clock.frame_ms(&frame());
    let mut group = c.benchmark_group("frame");
    group.bench_function(clock.id(&id), |b| b.iter(|| clock.record(&frame())));
    group.finish();
}

impl Measurement for FrameClock {
    /// The running total when the batch started (ns).
    type Intermediate = f64;
    /// Frame time of the batch (ns).
    type Value = f64;

    fn start(&self) -> f64 {
        self.total()
    }
    fn end(&self, start: f64) -> f64 {
        self.total() - start
    }
    fn add(&self, v1: &f64, v2: &f64) -> f64 {
        v1 + v2
    }
    fn zero(&self) -> f64 {
        0.0
    }
    fn to_f64(&self, value: &f64) -> f64 {
        *value
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        &NanosFormatter
    }
}

/// Formats nanoseconds as criterion's wall time does (ns, µs, ms, s), throughputs per second.
struct NanosFormatter;

impl ValueFormatter for NanosFormatter {
    fn scale_values(&self, typical_ns: f64, values: &mut [f64]) -> &'static str {
        let (factor, unit) = if typical_ns < 1e3 {
            (1.0, "ns")
        } else if typical_ns < 1e6 {
            (1e-3, "µs")
        } else if typical_ns < 1e9 {
            (1e-6, "ms")
        } else {
            (1e-9, "s")
        };
        for v in values {
            *v *= factor;
        }
        unit
    }

    fn scale_throughputs(
        &self,
        typical_ns: f64,
        throughput: &Throughput,
        values: &mut [f64],
    ) -> &'static str {
        let (count, per) = match *throughput {
            Throughput::Bytes(n) | Throughput::BytesDecimal(n) => (n as f64, "B/s"),
            Throughput::Bits(n) => (n as f64, "b/s"),
            Throughput::Elements(n) | Throughput::ElementsAndBytes { elements: n, .. } => {
                (n as f64, "elem/s")
            }
        };
        let typical = count * 1e9 / typical_ns;
        let (denominator, unit) = match (typical, per) {
            (t, "B/s") if t >= 1e9 => (1e9, "GB/s"),
            (t, "B/s") if t >= 1e6 => (1e6, "MB/s"),
            (t, "B/s") if t >= 1e3 => (1e3, "KB/s"),
            (_, "B/s") => (1.0, "B/s"),
            (t, "b/s") if t >= 1e9 => (1e9, "Gb/s"),
            (t, "b/s") if t >= 1e6 => (1e6, "Mb/s"),
            (t, "b/s") if t >= 1e3 => (1e3, "Kb/s"),
            (_, "b/s") => (1.0, "b/s"),
            (t, _) if t >= 1e9 => (1e9, "Gelem/s"),
            (t, _) if t >= 1e6 => (1e6, "Melem/s"),
            (t, _) if t >= 1e3 => (1e3, "Kelem/s"),
            _ => (1.0, "elem/s"),
        };
        for v in values {
            *v = count * 1e9 / *v / denominator;
        }
        unit
    }

    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn recorded(frame_ms: f64) -> Recorded {
        Recorded {
            spans: vec![("frame".into(), frame_ms), ("wall".into(), 2.0 * frame_ms)],
            call_ms: 0.1,
            total_ms: 3.0 * frame_ms,
        }
    }

    #[test]
    fn a_batch_measures_the_sum_of_its_frames() {
        let clock = FrameClock::with_kind(TimerKind::GpuTimestamp);
        let shared = clock.clone();
        let start = clock.start();
        for ms in [1.0, 2.0, 0.5] {
            shared.record(&recorded(ms));
        }
        assert!((clock.end(start) - 3.5e6).abs() < 1e-3);
        let wall = FrameClock::with_kind(TimerKind::Wall);
        assert_eq!(wall.frame_ms(&recorded(1.0)), 2.0);
    }
}
