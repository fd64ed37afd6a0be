//! GPU timers on timestamp queries, with an honest wall-clock fallback.
//!
//! Spans are written on the command encoder (`write_timestamp`) or as a pass's
//! `timestamp_writes`; never inside a pass (Mesa 22 returns meaningless values there).

use std::time::Instant;

/// Where a time came from; the harness prints it beside every figure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimerKind {
    GpuTimestamp,
    /// CPU wall clock around submit + wait: includes driver overhead; labelled as such.
    Wall,
}

impl TimerKind {
    pub fn label(self) -> &'static str {
        match self {
            TimerKind::GpuTimestamp => "gpu-timestamp",
            TimerKind::Wall => "wall",
        }
    }
}

/// Median and 95th percentile of a set of samples (milliseconds).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TimeStats {
    pub median_ms: f64,
    pub p95_ms: f64,
    pub samples: usize,
}

impl TimeStats {
    pub fn from_samples(samples: &[f64]) -> Self {
        if samples.is_empty() {
            return Self::default();
        }
        let mut sorted = samples.to_vec();
        sorted.sort_by(f64::total_cmp);
        let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
        Self {
            median_ms: at(0.5),
            p95_ms: at(0.95),
            samples: sorted.len(),
        }
    }
}

/// One named interval recorded in the current submission.
struct Span {
    label: String,
    first_query: u32,
}

/// Records named GPU intervals for one submission at a time.
pub struct GpuTimer {
    queries: Option<Queries>,
    spans: Vec<Span>,
    used: u32,
    wall_start: Option<Instant>,
}

struct Queries {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    /// Where the resolved timestamps are copied to be read: one buffer for the timer's life,
    /// not one per submission (a row renders hundreds of frames).
    staging: wgpu::Buffer,
    capacity: u32,
    period_ns: f64,
    encoder_timestamps: bool,
}

impl GpuTimer {
    /// A timer able to record `max_spans` intervals per submission.
    pub fn new(ctx: &crate::Context, max_spans: u32) -> Self {
        let queries = ctx.has_timestamps().then(|| {
            let capacity = max_spans * 2;
            Queries {
                set: ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count: capacity,
                }),
                resolve: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamp resolve"),
                    size: capacity as u64 * 8,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
                staging: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamp read-back"),
                    size: capacity as u64 * 8,
                    usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                    mapped_at_creation: false,
                }),
                capacity,
                period_ns: ctx.queue.get_timestamp_period() as f64,
                encoder_timestamps: ctx
                    .features()
                    .contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS),
            }
        });
        Self {
            queries,
            spans: Vec::new(),
            used: 0,
            wall_start: None,
        }
    }

    /// A timer that measures nothing: no query set, no read-back, every span and pass
    /// recorded without timestamps. What a renderer passes to a technique when it does not
    /// time it (the timer is optional: [`crate::Frame`] records the same passes with it).
    pub const fn off() -> Self {
        Self {
            queries: None,
            spans: Vec::new(),
            used: 0,
            wall_start: None,
        }
    }

    /// Whether encoder-level spans are GPU timestamps on this device.
    pub fn kind(&self) -> TimerKind {
        match &self.queries {
            Some(q) if q.encoder_timestamps => TimerKind::GpuTimestamp,
            _ => TimerKind::Wall,
        }
    }

    fn reserve(&mut self, label: &str) -> Option<(u32, &wgpu::QuerySet)> {
        let q = self.queries.as_ref()?;
        if self.used + 2 > q.capacity {
            return None;
        }
        let first = self.used;
        self.used += 2;
        self.spans.push(Span {
            label: label.to_string(),
            first_query: first,
        });
        Some((first, &q.set))
    }

    /// Starts an encoder-level span; pair with [`GpuTimer::end`].
    pub fn begin(&mut self, encoder: &mut wgpu::CommandEncoder, label: &str) {
        if self.kind() != TimerKind::GpuTimestamp {
            self.wall_start.get_or_insert_with(Instant::now);
            return;
        }
        if let Some((first, set)) = self.reserve(label) {
            encoder.write_timestamp(set, first);
        }
    }

    /// Ends the most recent encoder-level span with this label.
    pub fn end(&mut self, encoder: &mut wgpu::CommandEncoder, label: &str) {
        let Some(q) = &self.queries else { return };
        if !q.encoder_timestamps {
            return;
        }
        if let Some(span) = self.spans.iter().rev().find(|s| s.label == label) {
            encoder.write_timestamp(&q.set, span.first_query + 1);
        }
    }

    /// Timestamp writes bracketing one render pass (None without timestamp support).
    pub fn render_pass(&mut self, label: &str) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let (first, set) = self.reserve(label)?;
        Some(wgpu::RenderPassTimestampWrites {
            query_set: set,
            beginning_of_pass_write_index: Some(first),
            end_of_pass_write_index: Some(first + 1),
        })
    }

    /// Timestamp writes bracketing one compute pass (None without timestamp support).
    pub fn compute_pass(&mut self, label: &str) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let (first, set) = self.reserve(label)?;
        Some(wgpu::ComputePassTimestampWrites {
            query_set: set,
            beginning_of_pass_write_index: Some(first),
            end_of_pass_write_index: Some(first + 1),
        })
    }

    /// Submits `encoder` (resolving the queries into it first), waits, and returns the
    /// milliseconds of every span recorded since the last call, by label (spans with the same
    /// label are summed). Without timestamps, returns one "wall" span per begun label measured
    /// on the CPU around submit + wait.
    pub fn submit_and_collect(
        &mut self,
        ctx: &crate::Context,
        mut encoder: wgpu::CommandEncoder,
    ) -> Result<Vec<(String, f64)>, crate::GpuError> {
        let staging = self.queries.as_ref().filter(|_| self.used > 0).map(|q| {
            encoder.resolve_query_set(&q.set, 0..self.used, &q.resolve, 0);
            encoder.copy_buffer_to_buffer(&q.resolve, 0, &q.staging, 0, self.used as u64 * 8);
            &q.staging
        });
        let wall_start = self.wall_start.take().unwrap_or_else(Instant::now);
        ctx.queue.submit([encoder.finish()]);
        ctx.wait();
        let wall_ms = wall_start.elapsed().as_secs_f64() * 1e3;

        let mut out: Vec<(String, f64)> = Vec::new();
        let mut add = |label: &str, ms: f64| match out.iter_mut().find(|(l, _)| l == label) {
            Some((_, total)) => *total += ms,
            None => out.push((label.to_string(), ms)),
        };
        if let (Some(staging), Some(q)) = (staging, &self.queries) {
            let bytes = crate::target::map_buffer(ctx, staging)?;
            let ticks: &[u64] = bytemuck::cast_slice(&bytes);
            for span in &self.spans {
                let (a, b) = (
                    ticks[span.first_query as usize],
                    ticks[span.first_query as usize + 1],
                );
                add(&span.label, b.saturating_sub(a) as f64 * q.period_ns * 1e-6);
            }
        }
        if self.kind() == TimerKind::Wall {
            add("wall", wall_ms);
        }
        self.spans.clear();
        self.used = 0;
        Ok(out)
    }
}
