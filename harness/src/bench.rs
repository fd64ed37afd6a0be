//! `harness bench`: the cost of two or more techniques (or one technique with different
//! parameters) as ratios measured in one interleaved run, with the spread that says whether
//! the difference is bigger than the machine's noise.
//!
//! Timings on a shared or software adapter drift: lavapipe renders on the same CPU cores as
//! everything else, so a figure from one run and a figure from another do not compare. Here
//! every technique is prepared once on the same uploaded scene, warmed up, and then measured in
//! `rounds` rounds; in each round every technique renders `frames` frames of the same view (the
//! camera path's view at `time`), the order rotating from round to round so that neither
//! position nor drift favours one. Per round, each technique's median of the chosen span is
//! divided by the baseline's (the first technique's) median in the same round: the result is
//! the median of those per-round ratios and their range over the rounds. Whether the run can
//! tell a difference from its noise is a two-sided sign test over the rounds: the rounds in
//! which the technique was faster than the baseline against those in which it was slower.
//! With p < 0.05 the verdict is "faster"/"slower" (for 12 rounds: at least 10 of 12 on one
//! side); otherwise "not distinguishable". The sign test needs no assumption about how the
//! noise is distributed, and one disturbed round (a build starting on the machine) cannot
//! decide it.
//!
//! All techniques stay alive together for the run: keep the list short on lavapipe, whose
//! shader cache is bounded (`impostors/README.md`, "The lavapipe timing outlier").
//!
//! Writes `bench.json` and `bench.md` under `--out` when given.

use crate::measure::{Sample, render_frame, update_scene};
use crate::output::write_text;
use crate::plan::TechniqueSpec;
use crate::{Env, Frames, Size, backend};
use anyhow::{Context as _, Result, anyhow, bail};
use gpu::{GpuTimer, Target};
use scene::{GpuScene, Technique, View};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;

/// What to time.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    pub scene: String,
    /// Technique specs, the first the baseline: `id` or `id:name=value[:name=value...]`.
    pub techniques: Vec<String>,
    /// The span compared: `frame` (the whole frame) or a span a technique records (`lookup`).
    pub span: String,
    pub size: Size,
    /// Scene time of the measured view (the camera path's camera at that time).
    pub time: f32,
    pub rounds: u32,
    /// Frames per technique per round.
    pub frames: u32,
    /// Untimed frames per technique before the first round.
    pub warmup: u32,
    pub out: Option<PathBuf>,
}

/// One technique's timings.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchRow {
    pub technique: String,
    /// Median of the span over every timed frame (ms).
    pub median_ms: f64,
    /// Median of the span in each round (ms).
    pub round_medians_ms: Vec<f64>,
    /// Median, smallest and largest per-round ratio to the baseline.
    pub ratio_median: f64,
    pub ratio_min: f64,
    pub ratio_max: f64,
    /// Rounds in which the technique was faster (ratio < 1) and slower (ratio > 1).
    pub rounds_faster: u32,
    pub rounds_slower: u32,
    /// Two-sided sign-test p-value of those counts.
    pub sign_test_p: f64,
    /// "baseline", "faster", "slower" (sign test p < 0.05) or "not distinguishable".
    pub verdict: String,
    /// Median of every other span the technique recorded (ms).
    pub spans_ms: BTreeMap<String, f64>,
}

/// A bench run (also written to `bench.json`).
#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchReport {
    pub adapter: crate::report::AdapterJson,
    pub scene: String,
    pub span: String,
    pub size: String,
    pub time: f32,
    pub rounds: u32,
    pub frames: u32,
    pub rows: Vec<BenchRow>,
    /// The command line, commit, date and driver that made the run.
    pub provenance: crate::provenance::Provenance,
    #[serde(skip)]
    pub markdown: String,
}

/// `id:name=value:name=value` as the id and its parameters.
pub fn parse_technique_spec(spec: &str) -> Result<(String, Vec<(String, f64)>)> {
    let spec = TechniqueSpec::parse(spec)?;
    Ok((spec.id, spec.params))
}

fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// The span's time in one sample: its GPU span when recorded, else the frame's time.
fn span_ms(sample: &Sample, span: &str, technique: &dyn Technique, timer: &GpuTimer) -> f64 {
    if span == "frame" {
        return sample.time("frame", technique.timing(), timer.kind());
    }
    sample
        .spans()
        .iter()
        .find(|(label, _)| label == span)
        .map_or(f64::NAN, |(_, ms)| *ms)
}

/// Significance level of the sign test.
const SIGN_TEST_ALPHA: f64 = 0.05;

/// Two-sided sign test: the probability, with no difference, of a split at least as uneven as
/// `a` against `b` (ties left out).
fn sign_test_p(a: u32, b: u32) -> f64 {
    let n = a + b;
    if n == 0 {
        return 1.0;
    }
    // P(X <= min(a, b)) for X ~ Binomial(n, 1/2), doubled.
    let mut term = 0.5f64.powi(n as i32); // C(n, 0) / 2^n
    let mut tail = 0.0;
    for i in 0..=a.min(b) {
        tail += term;
        term *= (n - i) as f64 / (i + 1) as f64;
    }
    (2.0 * tail).min(1.0)
}

/// The verdict of per-round ratios to the baseline.
fn verdict(faster: u32, slower: u32) -> &'static str {
    match sign_test_p(faster, slower) < SIGN_TEST_ALPHA {
        true if faster > slower => "faster",
        true => "slower",
        false => "not distinguishable",
    }
}

/// The bench's plan: the techniques as fresh instances with their parameters, each checked
/// against the scene and the adapter.
fn instances(
    env: &Env,
    opts: &BenchOptions,
    scene: &scene::Scene,
) -> Result<Vec<Box<dyn Technique>>> {
    if opts.techniques.len() < 2 {
        bail!("bench needs at least two techniques (the first is the baseline)");
    }
    if opts.rounds < 2 || opts.frames == 0 {
        bail!("bench needs at least 2 rounds of at least 1 frame to state a spread");
    }
    let techniques = opts
        .techniques
        .iter()
        .map(|spec| TechniqueSpec::parse(spec)?.instance(env.techniques))
        .collect::<Result<Vec<_>>>()?;
    for (t, spec) in techniques.iter().zip(&opts.techniques) {
        if !t.supports(scene) {
            bail!("technique {spec} does not support scene {}", opts.scene);
        }
        scene::orthographic_refusal(t.as_ref(), scene)?;
        env.ctx
            .require(t.required_features())
            .with_context(|| format!("technique {spec}"))?;
    }
    if techniques
        .iter()
        .any(|t| t.timing() != techniques[0].timing())
    {
        bail!("bench cannot compare a CPU technique's clock with GPU timestamps: time them apart");
    }
    Ok(techniques)
}

/// The shared scene, target, timer and view every technique of a bench renders with.
struct Stage {
    scene: GpuScene,
    target: Target,
    timer: GpuTimer,
    view: View,
}

impl Stage {
    fn frame(&mut self, env: &Env, technique: &mut dyn Technique) -> Result<Sample> {
        render_frame(
            env.ctx,
            &mut self.timer,
            technique,
            &mut self.scene,
            &self.view,
            &self.target,
        )
    }
}

/// Prepares and warms up every technique on the stage.
fn prepare_all(
    env: &Env,
    opts: &BenchOptions,
    stage: &mut Stage,
    techniques: &mut [Box<dyn Technique>],
) -> Result<()> {
    for (t, spec) in techniques.iter_mut().zip(&opts.techniques) {
        update_scene(env.ctx, &mut stage.timer, &mut stage.scene, opts.time)?;
        crate::measure::prepare(env.ctx, &mut stage.timer, t.as_mut(), &stage.scene)
            .with_context(|| format!("{spec}: prepare"))?;
        for _ in 0..opts.warmup {
            stage
                .frame(env, t.as_mut())
                .with_context(|| format!("{spec}: warm-up"))?;
        }
    }
    Ok(())
}

/// Per technique, per round, the span's time of each frame; per technique every other span.
type Samples = (Vec<Vec<Vec<f64>>>, Vec<BTreeMap<String, Vec<f64>>>);

/// The rounds: in each, every technique renders `frames` frames, the order rotating.
fn measure_rounds(
    env: &Env,
    opts: &BenchOptions,
    stage: &mut Stage,
    techniques: &mut [Box<dyn Technique>],
) -> Result<Samples> {
    let n = techniques.len();
    let mut samples: Vec<Vec<Vec<f64>>> = vec![vec![Vec::new(); opts.rounds as usize]; n];
    let mut extra: Vec<BTreeMap<String, Vec<f64>>> = vec![BTreeMap::new(); n];
    for round in 0..opts.rounds as usize {
        for k in 0..n {
            let i = (k + round) % n; // rotate the order
            let t = techniques[i].as_mut();
            for _ in 0..opts.frames {
                let sample = stage
                    .frame(env, t)
                    .with_context(|| format!("{}: frame", opts.techniques[i]))?;
                samples[i][round].push(span_ms(&sample, &opts.span, t, &stage.timer));
                for (label, ms) in sample.extra() {
                    extra[i].entry(label.clone()).or_default().push(*ms);
                }
            }
        }
    }
    for (rounds, spec) in samples.iter().zip(&opts.techniques) {
        if rounds.iter().flatten().all(|v| v.is_nan()) {
            bail!("technique {spec} recorded no span \"{}\"", opts.span);
        }
    }
    Ok((samples, extra))
}

/// The rows: each technique's per-round ratios to the baseline and the sign test's verdict.
fn bench_rows(opts: &BenchOptions, (samples, extra): &Samples) -> Vec<BenchRow> {
    let round_medians: Vec<Vec<f64>> = samples
        .iter()
        .map(|rounds| rounds.iter().map(|s| median(s)).collect())
        .collect();
    (0..samples.len())
        .map(|i| {
            let ratios: Vec<f64> = round_medians[i]
                .iter()
                .zip(&round_medians[0])
                .map(|(a, b)| a / b)
                .collect();
            let (min, max) = ratios
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &r| {
                    (lo.min(r), hi.max(r))
                });
            let faster = ratios.iter().filter(|&&r| r < 1.0).count() as u32;
            let slower = ratios.iter().filter(|&&r| r > 1.0).count() as u32;
            let all: Vec<f64> = samples[i].iter().flatten().copied().collect();
            BenchRow {
                technique: opts.techniques[i].clone(),
                median_ms: median(&all),
                round_medians_ms: round_medians[i].clone(),
                ratio_median: median(&ratios),
                ratio_min: min,
                ratio_max: max,
                rounds_faster: faster,
                rounds_slower: slower,
                sign_test_p: sign_test_p(faster, slower),
                verdict: match i {
                    0 => "baseline",
                    _ => verdict(faster, slower),
                }
                .to_string(),
                spans_ms: extra[i]
                    .iter()
                    .map(|(l, v)| (format!("{l}_ms"), median(v)))
                    .collect(),
            }
        })
        .collect()
}

/// Runs the benchmark (see the module documentation).
pub fn run(env: &Env, opts: &BenchOptions) -> Result<BenchReport> {
    let (scene, notes) = crate::load_scene_noted(&opts.scene)?;
    for note in &notes {
        eprintln!("warning: {}: {note}", opts.scene);
    }
    let mut techniques = instances(env, opts, &scene)?;
    let one_image = Frames {
        errors: 1,
        ..Frames::default()
    };
    crate::limits::check_memory(env.ctx, opts.size, one_image)?;
    let mut stage = Stage {
        scene: backend::upload_scene(env.ctx, &scene)?,
        target: Target::new(env.ctx, opts.size.width, opts.size.height)?,
        timer: GpuTimer::new(env.ctx, 64),
        view: View {
            camera: scene.camera_at(opts.time),
            time: opts.time,
            width: opts.size.width,
            height: opts.size.height,
        },
    };
    prepare_all(env, opts, &mut stage, &mut techniques)?;
    let samples = measure_rounds(env, opts, &mut stage, &mut techniques)?;
    let mut report = BenchReport {
        adapter: crate::report::AdapterJson::of(env.ctx),
        scene: opts.scene.clone(),
        span: opts.span.clone(),
        size: opts.size.to_string(),
        time: opts.time,
        rounds: opts.rounds,
        frames: opts.frames,
        rows: bench_rows(opts, &samples),
        provenance: crate::provenance::Provenance::capture(String::new()),
        markdown: String::new(),
    };
    report.markdown = to_markdown(&report);
    if let Some(out) = &opts.out {
        let _lock = crate::OutputLock::acquire(out)?;
        write_text(&out.join("bench.md"), &page_markdown(&report))?;
        let json = serde_json::to_string_pretty(&report)
            .map_err(|e| anyhow!("cannot encode the bench report: {e}"))?;
        write_text(&out.join("bench.json"), &json)?;
    }
    Ok(report)
}

/// `bench.md`: what made the run (the list `results.md` starts with), then the table, so
/// that a copy of the file says where its figures come from.
pub fn page_markdown(report: &BenchReport) -> String {
    let frames = format!(
        "{} rounds of {} frames per technique",
        report.rounds, report.frames
    );
    let list = report
        .provenance
        .markdown(&report.adapter, &report.size, frames);
    format!("# Bench\n\n{list}\n{}", report.markdown)
}

/// The markdown table: one row per technique, ratios to the first.
pub fn to_markdown(report: &BenchReport) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{} at {}, time {}, span `{}`: {} interleaved rounds of {} frames per technique",
        report.scene, report.size, report.time, report.span, report.rounds, report.frames
    );
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "| technique | median ms | ratio to the first (median of rounds) | range over rounds | rounds faster / slower | sign test p | verdict |"
    );
    let _ = writeln!(out, "| --- | --- | --- | --- | --- | --- | --- |");
    for (i, r) in report.rows.iter().enumerate() {
        let (rounds, p) = match i {
            0 => ("-".to_string(), "-".to_string()),
            _ => (
                format!("{} / {}", r.rounds_faster, r.rounds_slower),
                format!("{:.3}", r.sign_test_p),
            ),
        };
        let _ = writeln!(
            out,
            "| {} | {:.3} | {:.3} | {:.3}-{:.3} | {rounds} | {p} | {} |",
            r.technique, r.median_ms, r.ratio_median, r.ratio_min, r.ratio_max, r.verdict
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verdicts_follow_the_sign_test() {
        // 12 rounds: 10 of 12 on one side is p = 0.039, 9 of 12 is p = 0.146.
        assert!((sign_test_p(10, 2) - 0.0386).abs() < 1e-4);
        assert!((sign_test_p(9, 3) - 0.1460).abs() < 1e-4);
        assert_eq!(sign_test_p(6, 6), 1.0);
        assert_eq!(sign_test_p(0, 0), 1.0);
        assert!((sign_test_p(0, 5) - 0.0625).abs() < 1e-12);
        assert_eq!(verdict(10, 2), "faster");
        assert_eq!(verdict(1, 11), "slower");
        assert_eq!(verdict(9, 3), "not distinguishable");
        assert_eq!(
            verdict(0, 5),
            "not distinguishable",
            "5 rounds can never decide"
        );
        assert_eq!(median(&[3.0, 1.0, 2.0, f64::NAN]), 2.0);
        assert_eq!(median(&[1.0, 2.0]), 1.5);
    }
}
