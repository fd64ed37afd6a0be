//! `harness`: runs techniques on scenes against the reference; see `harness --help` and
//! harness/README.md.

use anyhow::{Context as _, Result, bail};
use clap::{Args, Parser, Subcommand};
use harness::cache::Cached;
use harness::compare::CompareOptions;
use harness::engine::{DevicePolicy, ExecOptions};
use harness::model::RunReport;
use harness::plan::Shard;
use harness::sweep::SweepOptions;
use harness::{Env, Frames, Size, images};
use std::path::PathBuf;
use std::process::ExitCode;

/// `println!` for the program's output, except that a closed stdout (`harness list | head`)
/// ends the program quietly with status 0, as it does other Unix tools, instead of
/// `println!`'s panic ("failed printing to stdout: Broken pipe").
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if writeln!(std::io::stdout(), $($arg)*).is_err() {
            std::process::exit(0);
        }
    }};
}

/// `print!` with [`outln!`]'s handling of a closed stdout.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if write!(std::io::stdout(), $($arg)*).is_err() {
            std::process::exit(0);
        }
    }};
}

/// The examples and the environment that `harness --help` ends with.
const AFTER_HELP: &str = "\
Examples:
  harness list
  harness compare --out out
  harness compare --scenes my-scene.glb,cornell-sphere:light=spot --techniques impostors,raytracer --out out
  harness render --scene chess --technique refractor-maps/multi-bounce-2 --size 256x256 --out chess.png
  harness sweep --scene cornell-box --technique impostors/secant-4 --param iterations=1,2,4,8 --out sweep
  harness report out/results.json --techniques impostors --markdown impostors-evidence.md

Environment:
  WGPU_ADAPTER_NAME  use the adapter whose name contains this (case-insensitive), e.g. \"H100\" or \"llvmpipe\"
  WGPU_BACKEND       backends to look on: vulkan, metal, dx12, gl (comma separated; default the platform's primary ones)
  VK_ICD_FILENAMES   the Vulkan driver manifest to load (cargo xtask compare sets Mesa 25's lavapipe on a machine without a GPU)
  RUST_LOG           wgpu's log level on stderr (default warn; e.g. RUST_LOG=wgpu_core=info)";

#[derive(Parser)]
#[command(
    name = "harness",
    version,
    about = "Runs every technique on the same scenes against the same ground truth; writes tables, images and plots.",
    after_help = AFTER_HELP
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Args, Clone, Copy)]
struct FrameArgs {
    /// Timed frames along the scene's camera path (time = i * duration / N; the error frames
    /// are timed too).
    #[arg(long, default_value_t = Frames::default().timed, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=Frames::MAX_TIMED as i64))]
    frames: u32,
    /// Untimed warm-up frames before them.
    #[arg(long, default_value_t = Frames::default().warmup, value_name = "N",
          value_parser = clap::value_parser!(u32).range(0..=Frames::MAX_WARMUP as i64))]
    warmup: u32,
    /// Error frames: times spread evenly over the camera path, start and end included, at
    /// which the image is measured against a reference of its own (1: time 0 only).
    #[arg(long, default_value_t = Frames::default().errors, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=Frames::MAX_ERRORS as i64))]
    error_frames: u32,
    /// Seconds of timed frames per row: a technique whose first warm-up frame shows that the
    /// timed frames would take longer is timed on fewer (at least its error frames), after
    /// that one warm-up; 0: no limit. The row's `frames` says how many were timed.
    #[arg(long, default_value_t = Frames::DEFAULT_TIMED_BUDGET_S, value_name = "SECONDS")]
    timed_budget: f64,
}

impl FrameArgs {
    fn frames(self) -> Result<Frames> {
        if !(self.timed_budget >= 0.0 && self.timed_budget.is_finite()) {
            bail!(
                "--timed-budget must be a number of seconds, 0 or more (0: no limit), not {}",
                self.timed_budget
            );
        }
        Ok(Frames {
            timed: self.frames,
            warmup: self.warmup,
            errors: self.error_frames,
            timed_budget_s: self.timed_budget,
        })
    }
}

/// Options of the CPU reference renderer (part of the reference cache key).
#[derive(Args, Clone, Copy, Default)]
struct RefArgs {
    /// Reference: specular interactions followed per path [default: the renderer's, 8].
    #[arg(long, value_name = "N",
          value_parser = clap::value_parser!(u32).range(0..=harness::limits::MAX_REF_DEPTH as i64))]
    ref_depth: Option<u32>,
    /// Reference: caustic photons in total; 0 disables caustics [default: the image-scaled
    /// density, 61 per pixel and at least 100 000, as the GPU tracer's].
    #[arg(long, value_name = "N",
          value_parser = clap::value_parser!(u64).range(0..=harness::limits::MAX_REF_PHOTONS))]
    ref_photons: Option<u64>,
    /// Reference: eye samples per pixel [default: 1, the pixel centre].
    #[arg(long, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=harness::limits::MAX_REF_SPP as i64))]
    ref_spp: Option<u32>,
}

impl RefArgs {
    fn reference(self) -> harness::CpuReference {
        let mut options = truth::reference::ReferenceOptions::default();
        if let Some(d) = self.ref_depth {
            options.max_depth = d;
        }
        if let Some(s) = self.ref_spp {
            options.samples_per_pixel = s.max(1);
        }
        harness::CpuReference {
            options,
            photons: self.ref_photons,
        }
    }
}

/// Where a compare or sweep writes, and how it runs.
#[derive(Args, Clone)]
struct RunArgs {
    /// The output folder: tables, images, index.html, the reference cache (.cache/).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Run one slice of the rows only, I of N (from 1): a complete output folder of its own,
    /// which `harness merge` joins with the other N-1 (a job array's tasks, a CI matrix).
    #[arg(long, value_name = "I/N")]
    shard: Option<Shard>,
    /// Keep the rows an interrupted run of the same arguments on the same commit left in
    /// --out, and run only the rest.
    #[arg(long)]
    resume: bool,
    /// `shared`: every row on the run's device, as an application would; `per-row`: a fresh
    /// device for every row (each row finds the driver as the first did).
    #[arg(long, default_value = "shared", value_name = "POLICY", value_parser = ["per-row", "shared"])]
    device: String,
}

impl RunArgs {
    fn exec(&self) -> ExecOptions {
        ExecOptions {
            out: self.out.clone(),
            shard: self.shard,
            resume: self.resume,
            device: match self.device.as_str() {
                "shared" => DevicePolicy::Shared,
                _ => DevicePolicy::PerRow,
            },
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// Built-in scenes and technique variants.
    #[command(after_help = "Example: harness list --params")]
    List {
        /// Also show every technique parameter (default, range, help) and scene parameter.
        #[arg(long)]
        params: bool,
    },
    /// Every supported (scene, technique) pair against the reference: results.{csv,json,md}
    /// and images under --out.
    #[command(
        after_help = "Example: harness compare --scenes chess,my-scene.glb --techniques refractor-maps,raytracer/caustics --size 256x256 --out out"
    )]
    Compare(CompareArgs),
    /// One technique on one scene over the values of one parameter: sweep.{csv,json,md,png}.
    #[command(
        after_help = "Example: harness sweep --scene cornell-box --technique impostors/secant-4 --param iterations=1,2,4,8 --out sweep"
    )]
    Sweep(SweepArgs),
    /// Cost of two or more techniques as ratios to the first, measured in one interleaved run
    /// with the spread over rounds: bench.{json,md} under --out when given.
    #[command(
        after_help = "Example: harness bench --scene chess --technique raster --technique refractor-maps/single-bounce --technique raytracer/whitted --out bench"
    )]
    Bench(BenchArgs),
    /// Renders one image of the camera path's view at time 0 (.png or .exr by extension).
    /// `--technique reference` gives the ground truth, through the reference cache.
    #[command(
        after_help = "Example: harness render --scene pool:light=sun --technique reference --size 256x256 --out pool.exr"
    )]
    Render(RenderArgs),
    /// Joins the output folders of the shards of one compare or sweep (`--shard 1/N` ...
    /// `--shard N/N`) into one, as the unsharded run writes it.
    #[command(after_help = "Example: harness merge shard-1 shard-2 shard-3 --out out")]
    Merge {
        /// The shards' output folders.
        #[arg(required = true, value_name = "DIR")]
        shards: Vec<PathBuf>,
        /// The folder the joined run is written to, as the unsharded run writes its --out.
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
    },
    /// Redraws the Pareto view (error against frame time, `pareto/<scene>.svg`, and
    /// `pareto.json`) from the results.json of earlier compare runs, one or more (scenes of
    /// several runs side by side; a scene in two files: the later file's rows)
    #[command(
        after_help = "Example: harness pareto out/results.json gpu-run/results.json --out pareto"
    )]
    Pareto {
        /// results.json files written by compare.
        #[arg(required = true, value_name = "RESULTS.json")]
        results: Vec<PathBuf>,
        /// The folder `pareto/<scene>.svg` and `pareto.json` are written to.
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
    },
    /// Writes the rows of chosen techniques from an earlier run's results.json (or a sweep's
    /// sweep.json) as markdown, with what made the run: a crate's evidence table, regenerated
    /// instead of copied.
    #[command(
        after_help = "Example: harness report out-all/results.json --techniques impostors,raster --markdown evidence.md"
    )]
    Report {
        /// The results.json of a compare, or the sweep.json of a sweep.
        #[arg(value_name = "RESULTS.json")]
        results: PathBuf,
        /// Technique ids (with or without parameters) or families (every variant), comma
        /// separated.
        #[arg(long, value_name = "X,Y", value_delimiter = ',', required = true)]
        techniques: Vec<String>,
        /// The markdown file to write.
        #[arg(long, value_name = "FILE.md")]
        markdown: PathBuf,
    },
    /// The ground truth's speed on this machine: rays per second of the reference's BVH
    /// (coherent and incoherent, closest-hit and any-hit) and one reference render split into
    /// its phases and parts, on a stated number of threads (CPU only; no adapter)
    #[command(
        after_help = "Example: harness rays --scenes refraction-bunny,my-scene.glb --threads 2 --markdown rays.md"
    )]
    Rays(RaysArgs),
    /// Writes a scene (built-in spec or glTF) as binary glTF.
    #[command(
        after_help = "Example: harness export-scene cornell-box:light=spot --out cornell-box.glb"
    )]
    ExportScene {
        /// Scene spec, e.g. cornell-sphere:material=mirror.
        scene: String,
        /// The binary glTF file to write.
        #[arg(long, value_name = "FILE.glb")]
        out: PathBuf,
    },
}

#[derive(Args)]
struct CompareArgs {
    #[command(flatten)]
    run: RunArgs,
    /// Scene specs or .gltf/.glb paths, comma separated (default: every built-in scene).
    #[arg(long, value_name = "A,B")]
    scenes: Option<String>,
    /// Technique ids, families or specs with parameters (`id:name=value`), comma separated
    /// (default: every family's representative variants; see --all-variants).
    #[arg(long, value_name = "X,Y", value_delimiter = ',')]
    techniques: Option<Vec<String>>,
    /// Every variant of every family (the default runs each family's representative
    /// variants; the exhaustive rest, every iteration or slice count, is for sweeps).
    #[arg(long)]
    all_variants: bool,
    #[command(flatten)]
    measure: MeasureArgs,
    /// Exit with status 3 if any technique failed or produced NaN/infinite pixels.
    #[arg(long)]
    strict: bool,
}

#[derive(Args)]
struct SweepArgs {
    /// The scene: a built-in spec (`cornell-box:material=gold`) or a .gltf/.glb path.
    #[arg(long, value_name = "SCENE")]
    scene: String,
    /// The technique's id, with other parameters fixed for the whole sweep if wanted:
    /// `id:name=value:name=value`.
    #[arg(long, value_name = "ID")]
    technique: String,
    /// A technique or scene parameter and its values.
    #[arg(long, value_name = "NAME=V1,V2,...")]
    param: String,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    measure: MeasureArgs,
}

/// What a compare or a sweep measures with: the image size, the frames, the ground truth.
#[derive(Args)]
struct MeasureArgs {
    /// Image size.
    #[arg(long, default_value = "128x128", value_name = "WxH")]
    size: Size,
    #[command(flatten)]
    frames: FrameArgs,
    #[command(flatten)]
    reference: RefArgs,
}

#[derive(Args)]
struct BenchArgs {
    /// The scene: a built-in spec (`chess`) or a .gltf/.glb path.
    #[arg(long, value_name = "SCENE")]
    scene: String,
    /// A technique, `id` or `id:name=value[:name=value]`; repeat it, the first is the
    /// baseline.
    #[arg(long = "technique", value_name = "SPEC", required = true)]
    techniques: Vec<String>,
    /// The span compared: `frame`, or a span the techniques record (`lookup`, `slices`).
    #[arg(long, default_value = "frame", value_name = "LABEL")]
    span: String,
    /// Image size.
    #[arg(long, default_value = "256x256", value_name = "WxH")]
    size: Size,
    /// Scene time of the measured view.
    #[arg(long, default_value_t = 0.0, value_name = "T")]
    time: f32,
    /// Interleaved rounds (the spread is over rounds).
    #[arg(long, default_value_t = 8, value_name = "N",
          value_parser = clap::value_parser!(u32).range(2..=10_000))]
    rounds: u32,
    /// Frames per technique per round.
    #[arg(long, default_value_t = 8, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=10_000))]
    frames: u32,
    /// Untimed frames per technique before the first round.
    #[arg(long, default_value_t = 3, value_name = "N",
          value_parser = clap::value_parser!(u32).range(0..=10_000))]
    warmup: u32,
    /// A folder to write bench.json and bench.md to (default: the table on stdout only).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

#[derive(Args)]
struct RenderArgs {
    /// The scene: a built-in spec (`pool:light=sun`) or a .gltf/.glb path.
    #[arg(long, value_name = "SCENE")]
    scene: String,
    /// A technique id (`harness list`), or `reference` for the ground truth.
    #[arg(long, value_name = "ID")]
    technique: String,
    /// The image to write: .png (sRGB of the clamped radiance) or .exr (linear radiance).
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
    /// The image's width and height in pixels (compare's default is 128x128).
    #[arg(long, default_value = "256x256", value_name = "WxH")]
    size: Size,
    #[command(flatten)]
    reference: RefArgs,
    /// The reference cache `--technique reference` reads and fills. The default is the one
    /// `harness compare --out out` keeps (`cargo xtask compare`, run from the workspace root):
    /// a view it rendered at the same --size (its default is 128x128) is read back.
    #[arg(long, default_value = "out/.cache", value_name = "DIR")]
    cache: PathBuf,
    /// Render the reference without reading or filling a cache (after a change to the
    /// reference renderer, whose code is not part of the cache key).
    #[arg(long, conflicts_with = "cache")]
    no_cache: bool,
}

#[derive(Args)]
struct RaysArgs {
    /// Scene specs or .gltf/.glb paths, comma separated (default: every built-in scene).
    #[arg(long, value_name = "A,B")]
    scenes: Option<String>,
    /// One camera ray per pixel, and the reference render's size.
    #[arg(long, default_value = "256x256", value_name = "WxH")]
    size: Size,
    /// Threads [default: one per logical core].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Rounds each ray set is cast (the table gives the median and the spread).
    #[arg(long, default_value_t = 5, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=100))]
    rounds: u32,
    /// Also write the table to this markdown file.
    #[arg(long, value_name = "FILE.md")]
    markdown: Option<PathBuf>,
    #[command(flatten)]
    reference: RefArgs,
}

fn rays(args: RaysArgs) -> Result<ExitCode> {
    let options = harness::rays::RaysOptions {
        scenes: scene_list(args.scenes)?,
        size: args.size,
        threads: args.threads.map(|t| t as usize),
        rounds: args.rounds,
        reference: args.reference.reference(),
    };
    let markdown = harness::rays::markdown(&harness::rays::measure(&options)?);
    out!("{markdown}");
    if let Some(path) = args.markdown {
        std::fs::write(&path, &markdown)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The adapter line and a markdown table, as compare, sweep and bench print them.
fn print_table(ctx: &gpu::Context, timer_kind: &str, markdown: &str) {
    outln!("adapter: {} (timer: {timer_kind})", ctx.summary);
    outln!();
    out!("{markdown}");
}

/// Exit status of a compare or sweep in which a technique panicked (the harness caught it,
/// wrote every file, and still fails: a panic is a defect, never a result).
const PANIC_EXIT: u8 = 4;

/// An error as one line.
fn one_line(text: &str) -> String {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// wgpu's own warnings (validation, driver quirks) to standard error; `RUST_LOG` changes the
/// level (`RUST_LOG=wgpu_core=info`).
fn init_logger() {
    let env = env_logger::Env::default().default_filter_or("warn");
    let _ = env_logger::Builder::from_env(env).try_init();
}

fn main() -> ExitCode {
    init_logger();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion)
                || e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            {
                let _ = e.print();
                return ExitCode::from(e.exit_code() as u8);
            }
            // The message up to the first blank line, with clap's tips ("a similar argument
            // exists: '--size'"), on one line; its usage block is left to --help.
            let rendered = e.render().to_string();
            let head: String = rendered.split("\n\n").next().unwrap_or("").to_string();
            let line = one_line(&head);
            let line = line.strip_prefix("error: ").unwrap_or(&line);
            let tips: Vec<&str> = rendered
                .lines()
                .map(str::trim)
                .filter(|l| l.starts_with("tip:"))
                .collect();
            let tips: String = tips.iter().map(|t| format!("; {t}")).collect();
            eprintln!("error: {line}{tips} (see harness --help)");
            return ExitCode::from(2);
        }
    };
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", one_line(&format!("{e:#}")));
            ExitCode::FAILURE
        }
    }
}

fn context() -> Result<gpu::Context> {
    Ok(gpu::Context::new()?)
}

fn run(cli: Cli) -> Result<ExitCode> {
    match cli.command {
        Command::List { params } => list(params),
        Command::Compare(args) => compare(args),
        Command::Sweep(args) => sweep(args),
        Command::Bench(args) => bench(args),
        Command::Render(args) => render(&args),
        Command::Pareto { results, out } => pareto(&results, &out),
        Command::Merge { shards, out } => merge(&shards, &out),
        Command::Report {
            results,
            techniques,
            markdown,
        } => report(&results, &techniques, &markdown),
        Command::ExportScene { scene, out } => export_scene(&scene, &out),
        Command::Rays(args) => rays(args),
    }
}

/// `--scenes`: the specs it lists (none: every built-in scene).
fn scene_list(scenes: Option<String>) -> Result<Vec<String>> {
    let Some(list) = scenes else {
        return Ok(Vec::new());
    };
    let specs = harness::split_scene_list(&list);
    if specs.is_empty() {
        bail!("--scenes \"{list}\" names no scene; leave it out to run every built-in scene");
    }
    Ok(specs)
}

fn compare(args: CompareArgs) -> Result<ExitCode> {
    let scenes = scene_list(args.scenes)?;
    // Check names and scenes before creating the GPU context (seconds on a software adapter);
    // the plan checks them again.
    let all_ids: Vec<String> = harness::registry().iter().map(|t| t.id()).collect();
    if let Some(wanted) = &args.techniques {
        harness::select_technique_specs(&all_ids, wanted)?;
    }
    for spec in &scenes {
        harness::load_scene(spec)?;
    }
    let ctx = context()?;
    let reference = args.measure.reference.reference();
    let env = Env::standard(&ctx, &reference);
    let opts = CompareOptions {
        scenes,
        techniques: args.techniques,
        all_variants: args.all_variants,
        size: args.measure.size,
        frames: args.measure.frames.frames()?,
    };
    let report = harness::compare::run(&env, &opts, &args.run.exec())?;
    finish(&ctx, &report, &args.run.out, args.strict)
}

fn sweep(args: SweepArgs) -> Result<ExitCode> {
    let (param, values) = harness::sweep::parse_param_arg(&args.param)?;
    let all_ids: Vec<String> = harness::registry().iter().map(|t| t.id()).collect();
    let id = harness::plan::TechniqueSpec::parse(&args.technique)?.id;
    harness::select_techniques(&all_ids, Some(std::slice::from_ref(&id)))?;
    harness::load_scene(&args.scene)?;
    let ctx = context()?;
    let reference = args.measure.reference.reference();
    let env = Env::standard(&ctx, &reference);
    let opts = SweepOptions {
        scene: args.scene,
        technique: args.technique,
        param,
        values,
        size: args.measure.size,
        frames: args.measure.frames.frames()?,
    };
    let report = harness::sweep::run(&env, &opts, &args.run.exec())?;
    finish(&ctx, &report, &args.run.out, false)
}

fn bench(args: BenchArgs) -> Result<ExitCode> {
    if !(0.0..=harness::limits::MAX_TIME).contains(&args.time) {
        bail!(
            "--time {} is outside [0, {}] seconds",
            args.time,
            harness::limits::MAX_TIME
        );
    }
    harness::load_scene(&args.scene)?;
    let ctx = context()?;
    let reference = RefArgs::default().reference();
    let env = Env::standard(&ctx, &reference);
    let opts = harness::bench::BenchOptions {
        scene: args.scene,
        techniques: args.techniques,
        span: args.span,
        size: args.size,
        time: args.time,
        rounds: args.rounds,
        frames: args.frames,
        warmup: args.warmup,
        out: args.out.clone(),
    };
    let report = harness::bench::run(&env, &opts)?;
    print_table(&ctx, &report.adapter.timer_kind, &report.markdown);
    if let Some(out) = args.out {
        outln!();
        outln!("wrote {0}/bench.json and {0}/bench.md", out.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn merge(shards: &[PathBuf], out: &std::path::Path) -> Result<ExitCode> {
    let report = harness::merge::merge(shards, out)?;
    outln!(
        "merged {} shards: {} rows into {}",
        shards.len(),
        report.rows.len(),
        out.display()
    );
    wrote(&report, out);
    Ok(ExitCode::SUCCESS)
}

fn export_scene(scene: &str, out: &std::path::Path) -> Result<ExitCode> {
    if !out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"))
    {
        bail!("{} must end in .glb", out.display());
    }
    let model = harness::load_scene(scene)?;
    harness::backend::export_glb(&model, out)?;
    outln!("wrote {}", out.display());
    Ok(ExitCode::SUCCESS)
}

/// The files a compare or sweep wrote, one line each.
fn wrote(report: &RunReport, out: &std::path::Path) {
    let stem = report.kind.table_stem();
    outln!(
        "wrote {0}/{stem}.csv, {0}/{stem}.json, {0}/{stem}.md and {0}/images/",
        out.display()
    );
    outln!(
        "report: {}/index.html (open it in a browser)",
        out.display()
    );
}

/// A compare's or sweep's end: the table, the files, the errors, and the exit status (4 when a
/// technique panicked; 3 with `strict` when a row failed or had non-finite pixels).
fn finish(
    ctx: &gpu::Context,
    report: &RunReport,
    out: &std::path::Path,
    strict: bool,
) -> Result<ExitCode> {
    print_table(
        ctx,
        &report.adapter.timer_kind,
        &harness::output::markdown(report),
    );
    outln!();
    wrote(report, out);
    if !report.errors.is_empty() {
        eprintln!(
            "{} error(s), printed above and listed in {}.json",
            report.errors.len(),
            report.kind.table_stem()
        );
    }
    if !report.panics.is_empty() {
        eprintln!(
            "error: {} technique run(s) panicked (a defect, whatever --strict says): {}",
            report.panics.len(),
            report.panics.join("; ")
        );
        return Ok(ExitCode::from(PANIC_EXIT));
    }
    let nan = report.rows.iter().any(|r| r.nan_pixels.unwrap_or(0) > 0);
    if strict && (!report.errors.is_empty() || nan) {
        eprintln!("error: --strict: the run had errors or non-finite pixels");
        return Ok(ExitCode::from(3));
    }
    Ok(ExitCode::SUCCESS)
}

/// `harness report`: the rows of `techniques` in `results` as a markdown file.
fn report(
    results: &std::path::Path,
    techniques: &[String],
    markdown: &std::path::Path,
) -> Result<ExitCode> {
    let run = RunReport::read(results)?;
    let command = format!(
        "harness report {} --techniques {} --markdown {}",
        harness::provenance::quote(&results.display().to_string()),
        harness::provenance::quote(&techniques.join(",")),
        harness::provenance::quote(&markdown.display().to_string())
    );
    let file = results.display().to_string();
    let text = harness::output::selected_markdown(&run, techniques, &file, &command)?;
    harness::output::write_text(markdown, &text)?;
    outln!("wrote {}", markdown.display());
    Ok(ExitCode::SUCCESS)
}

/// `harness pareto`: the plots and points of every scene in `results`.
fn pareto(results: &[PathBuf], out: &std::path::Path) -> Result<ExitCode> {
    let mut scenes: Vec<(String, String, Vec<harness::report::ResultRow>)> = Vec::new();
    for path in results {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let (adapter, rows) = harness::pareto::rows_from_json(&text)
            .with_context(|| format!("{}", path.display()))?;
        let mut names: Vec<String> = rows.iter().map(|r| r.scene.clone()).collect();
        names.dedup();
        for name in names {
            let of_scene = rows.iter().filter(|r| r.scene == name).cloned().collect();
            scenes.retain(|(n, _, _)| *n != name);
            scenes.push((name, adapter.clone(), of_scene));
        }
    }
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let specs: Vec<String> = scenes.iter().map(|(n, _, _)| n.clone()).collect();
    let dirs = harness::scene_dir_names(&specs);
    let mut all = Vec::new();
    for ((name, adapter, mut rows), dir) in scenes.into_iter().zip(dirs) {
        let (points, warning) =
            harness::output::write_pareto_scene(out, &name, &dir, &mut rows, &adapter)?;
        if let Some(w) = warning {
            eprintln!("warning: {w}");
        }
        for p in points.points.iter().filter(|p| p.on_front) {
            outln!(
                "{name}: on the front: {} ({:.3} ms, {:.4})",
                p.technique,
                p.frame_ms,
                p.measured_error
            );
        }
        all.push(points);
    }
    let json = serde_json::to_string_pretty(&all).context("cannot encode the points")?;
    std::fs::write(out.join("pareto.json"), json)
        .with_context(|| format!("cannot write {}", out.join("pareto.json").display()))?;
    outln!(
        "wrote {} and {}",
        out.join("pareto").display(),
        out.join("pareto.json").display()
    );
    Ok(ExitCode::SUCCESS)
}

fn list(params: bool) -> Result<ExitCode> {
    outln!("Scenes (spec: name or name:key=value,...; or a path to a .gltf/.glb file):");
    for s in scene::builtin::builtin_scenes() {
        outln!("  {:<18} {}", s.name, s.description);
        if params {
            for p in &s.params {
                outln!(
                    "      {:<20} default {:<10} range {:<20} {}",
                    p.name,
                    p.default,
                    p.range_text(),
                    p.help
                );
            }
        } else if !s.params.is_empty() {
            let names: Vec<String> = s
                .params
                .iter()
                .map(|p| format!("{}={}", p.name, p.default))
                .collect();
            outln!("      params: {}", names.join(", "));
        }
    }
    outln!();
    let techniques = harness::registry();
    outln!(
        "Techniques ({}; * = in the default compare, the rest with --all-variants):",
        techniques.len()
    );
    if techniques.is_empty() {
        outln!("  (none registered)");
    }
    for t in &techniques {
        let mark = if t.representative() { '*' } else { ' ' };
        outln!("{mark} {:<32} {}", t.id(), t.description());
        if params {
            for p in t.params() {
                let kind = if p.integer { "integer" } else { "real" };
                outln!(
                    "      {:<20} default {:<8} range [{}, {}] {kind}  {}",
                    p.name,
                    p.default,
                    p.min,
                    p.max,
                    p.help
                );
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// `render`: one image of the camera path's view at time 0 (see `RenderArgs`).
fn render(args: &RenderArgs) -> Result<ExitCode> {
    let (spec, out, size) = (&args.scene, &args.out, args.size);
    let ext = out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_lowercase);
    if !matches!(ext.as_deref(), Some("png" | "exr")) {
        bail!(
            "cannot tell the image format of {}: use a .png or .exr name",
            out.display()
        );
    }
    // `reference` is the ground truth itself, rendered with the --ref-* options (the
    // registry's `reference` technique renders with the defaults; it is there for compare).
    let id = match args.technique.as_str() {
        "reference" => None,
        technique => Some(one_technique(technique)?),
    };
    let (scene, notes) = harness::load_scene_noted(spec)?;
    for note in notes {
        eprintln!("warning: {spec}: {note}");
    }
    let ctx = context()?;
    let one_image = Frames {
        timed: 0,
        warmup: 0,
        errors: 1,
        timed_budget_s: 0.0,
    };
    harness::limits::check_memory(&ctx, size, one_image)?;
    let image = match id {
        None => {
            let truth = args.reference.reference();
            let cache = (!args.no_cache).then_some(args.cache.as_path());
            let (image, how) = harness::render::reference_image(cache, &truth, spec, &scene, size)?;
            let dir = args.cache.display();
            match how {
                Some(Cached::Hit) => eprintln!("reference: read from the cache in {dir}"),
                Some(Cached::Miss(why)) => {
                    eprintln!("reference: rendered into the cache in {dir} ({why})")
                }
                None => {}
            }
            image
        }
        Some(id) => harness::render::technique_image(&ctx, &id, spec, &scene, size, one_image)?,
    };
    images::write_by_extension(out, &image)?;
    let bad = image.non_finite_count();
    if bad > 0 {
        eprintln!("warning: {bad} NaN or infinite pixels");
    }
    outln!("wrote {}", out.display());
    Ok(ExitCode::SUCCESS)
}

/// The one technique id `name` stands for.
fn one_technique(name: &str) -> Result<String> {
    let all_ids: Vec<String> = harness::registry().iter().map(|t| t.id()).collect();
    let ids = harness::select_techniques(&all_ids, Some(&[name.to_string()]))?;
    match ids.as_slice() {
        [id] => Ok(id.clone()),
        _ => bail!(
            "\"{name}\" names several techniques ({}); give one id",
            ids.join(", ")
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    /// Every example the help shows parses as the command line it claims to be.
    #[test]
    fn the_help_s_examples_parse() {
        let root = Cli::command();
        let mut texts = vec![AFTER_HELP.to_string()];
        for sub in root.get_subcommands() {
            if let Some(help) = sub.get_after_help() {
                texts.push(help.to_string());
            }
        }
        let examples: Vec<String> = texts
            .iter()
            .flat_map(|t| t.lines())
            .filter_map(|l| {
                l.trim()
                    .trim_start_matches("Example: ")
                    .strip_prefix("harness ")
            })
            .map(|l| format!("harness {l}"))
            .collect();
        assert!(examples.len() >= 12, "{examples:?}");
        for example in examples {
            let args = example.split_whitespace();
            if let Err(e) = Cli::try_parse_from(args) {
                panic!("{example}: {e}");
            }
        }
    }
}
