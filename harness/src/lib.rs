//! The harness: runs every technique on the same scenes, against the same ground truth, with
//! the same metrics and timers, and writes tables, images and plots.
//!
//! The binary (`harness list | compare | sweep | bench | merge | render | pareto |
//! export-scene`) is a thin layer over this library, which workspace tests reuse. A run is a
//! [`plan::Plan`] (rows: scene, technique spec, swept value; size, frames, ground truth) that
//! [`engine::execute`] carries out row by row, filling one report model
//! ([`model::RunReport`]) that every writer reads:
//!
//! - [`compare`], [`sweep`]: build a plan and execute it; [`bench`]: the interleaved timing
//!   of a few techniques on the engine's pieces; [`merge`]: shards of one plan joined.
//! - [`measure`]: one technique on one uploaded scene (prepare, warm-up, the camera path's
//!   frames, every one timed, the error frames read back); [`score`]: its error figures.
//! - [`output`]: the folder written as the run goes (tables after every row, everything after
//!   every scene); [`report`] (CSV, markdown), [`html`] (`index.html`), [`pareto`], [`plot`].
//! - [`registry`]: fresh instances of every technique variant; [`Env`]: what a run needs (GPU
//!   context, technique factory, ground truth, progress bars); [`cache`]: the on-disk
//!   reference cache; [`images`]: PNG/EXR writing and reading; [`backend`]: the adapters onto
//!   scene- and truth-crate APIs (reference renderer, glTF export, GPU upload).
//!
//! ```no_run
//! # fn main() -> anyhow::Result<()> {
//! use harness::compare::CompareOptions;
//! use harness::engine::ExecOptions;
//!
//! let ctx = gpu::Context::new()?;
//! let reference = harness::CpuReference::default();
//! let env = harness::Env::standard(&ctx, &reference); // registry() + CPU reference
//! let opts = CompareOptions {
//!     scenes: vec!["cornell-sphere".into()],
//!     techniques: Some(vec!["impostors/false-position-4".into(), "raytracer".into()]),
//!     all_variants: false,
//!     size: harness::Size::new(64, 64),
//!     frames: harness::Frames {
//!         timed: 4,
//!         warmup: 1,
//!         errors: 3,
//!         timed_budget_s: 0.0,
//!     },
//! };
//! let report = harness::compare::run(&env, &opts, &ExecOptions::new("out"))?;
//! for row in &report.rows {
//!     println!("{} {:?} {:?}", row.technique, row.flip_mean_masked, row.frame_ms_median);
//! }
//! # Ok(())
//! # }
//! ```

pub mod backend;
pub mod bench;
pub mod cache;
pub mod compare;
pub mod engine;
pub mod html;
pub mod images;
pub mod json_float;
pub mod limits;
pub mod measure;
pub mod merge;
pub mod model;
pub mod output;
pub mod pareto;
pub mod plan;
pub mod plot;
mod progress;
pub mod provenance;
pub mod rays;
pub mod render;
pub mod report;
pub mod score;
pub mod sweep;

pub use progress::Progress;

/// The README's code (its library example) compiled as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

use anyhow::{Context as _, Result, bail};
use gpu::HdrImage;
use scene::{Camera, Scene, Technique};
use std::str::FromStr;

/// Every family of techniques: the ground truth as a technique (`reference`), the
/// foundation's baselines, then one line per technique crate (and the crate in
/// harness/Cargo.toml). [`registry`] and [`image_checks`] read this list.
pub fn families() -> Vec<scene::Family> {
    vec![
        truth::FAMILY,
        scene::foundation::FAMILY,
        impostors::FAMILY,
        refractor_maps::FAMILY,
        height_maps::FAMILY,
        screen_photons::FAMILY,
        image_space_refraction::FAMILY,
        raytracer::FAMILY,
        volumes::FAMILY,
        interior_mapping::FAMILY,
    ]
}

/// Every registered technique variant, fresh, family by family.
pub fn registry() -> Vec<Box<dyn Technique>> {
    families().iter().flat_map(|f| (f.techniques)()).collect()
}

/// Every image check the families declare (`scene::ImageCheck`), run by the tests crate
/// against the reference.
pub fn image_checks() -> Vec<scene::ImageCheck> {
    families().iter().flat_map(|f| (f.image_checks)()).collect()
}

/// A technique factory: returns fresh instances of every variant it knows.
pub type TechniqueFactory = dyn Fn() -> Vec<Box<dyn Technique>>;

/// The ground truth for one view, as the reference renderer returns it.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    pub image: HdrImage,
    /// Per pixel: index of the object the camera ray hits first, -1 for background.
    pub object_ids: Vec<i32>,
    /// Per pixel: whether the pixel shows a special object (the masked FLIP mean uses it).
    pub mask: Vec<bool>,
    pub stats: ReferenceStats,
}

/// What the reference renderer reports about its work (written to `results.json`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReferenceStats {
    pub camera_rays: u64,
    pub shadow_rays: u64,
    pub photon_rays: u64,
    pub photons_stored: u64,
    pub seconds: f64,
    pub rays_per_second: f64,
}

/// Where the ground truth comes from: the CPU reference renderer ([`CpuReference`]), or in
/// tests anything else.
pub trait GroundTruth {
    /// Identifies the renderer and its options; part of the cache key, so changing options
    /// never reuses a stale image.
    fn key(&self) -> String;
    fn render(
        &self,
        scene: &Scene,
        camera: &Camera,
        time: f32,
        width: u32,
        height: u32,
    ) -> Result<Reference>;
}

/// The CPU reference renderer (`truth::reference`) with its options.
#[derive(Clone, Debug, Default)]
pub struct CpuReference {
    /// Everything but the photon count, which `photons` sets.
    pub options: truth::reference::ReferenceOptions,
    /// Caustic photons of a render: `None` (the default) the image-scaled density the GPU
    /// tracer uses too (61 per pixel, at least 100 000:
    /// `truth::reference::ReferenceOptions::for_image`), so a 128 x 128 reference has the
    /// per-pixel noise of a 256 x 256 one at a quarter of the cost; `Some(n)` exactly `n`
    /// (`--ref-photons`).
    pub photons: Option<u64>,
}

impl CpuReference {
    /// The reference with `options`, their photon count as given.
    pub fn fixed(options: truth::reference::ReferenceOptions) -> Self {
        CpuReference {
            photons: Some(options.photons),
            options,
        }
    }

    /// The options of a `width` x `height` render.
    pub fn options_for(&self, width: u32, height: u32) -> truth::reference::ReferenceOptions {
        let photons = self.photons.unwrap_or_else(|| {
            truth::reference::ReferenceOptions::for_image(width, height).photons
        });
        truth::reference::ReferenceOptions {
            photons,
            ..self.options.clone()
        }
    }
}

impl GroundTruth for CpuReference {
    fn key(&self) -> String {
        let photons = match self.photons {
            Some(n) => format!("{n} photons"),
            None => "photons per image".to_string(),
        };
        format!(
            "cpu-reference {} {photons}",
            backend::reference_options_key(&self.options)
        )
    }
    fn render(
        &self,
        scene: &Scene,
        camera: &Camera,
        time: f32,
        w: u32,
        h: u32,
    ) -> Result<Reference> {
        backend::render_reference(scene, camera, time, w, h, &self.options_for(w, h))
    }
}

/// What every runner needs.
pub struct Env<'a> {
    pub ctx: &'a gpu::Context,
    pub techniques: &'a TechniqueFactory,
    pub ground_truth: &'a dyn GroundTruth,
    /// Draw progress bars (they hide themselves when stderr is not a terminal).
    pub progress: bool,
}

impl<'a> Env<'a> {
    /// The standard environment: [`registry`] and the given CPU reference.
    pub fn standard(ctx: &'a gpu::Context, reference: &'a CpuReference) -> Self {
        Env {
            ctx,
            techniques: &registry,
            ground_truth: reference,
            progress: true,
        }
    }
}

/// An image size `WxH` (also accepts `W` for a square).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Size {
    pub width: u32,
    pub height: u32,
}

impl Size {
    pub const fn new(width: u32, height: u32) -> Self {
        Size { width, height }
    }
}

impl std::fmt::Display for Size {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

impl FromStr for Size {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("\"{s}\" is not a size; expected WxH, e.g. 256x256");
        let (w, h) = match s.trim().split_once(['x', 'X']) {
            Some((w, h)) => (w, h),
            None => (s.trim(), s.trim()),
        };
        let w: u32 = w.trim().parse().map_err(|_| bad())?;
        let h: u32 = h.trim().parse().map_err(|_| bad())?;
        if w == 0 || h == 0 {
            return Err(format!("size {s} has a zero side"));
        }
        Ok(Size {
            width: w,
            height: h,
        })
    }
}

/// Frame counts of a timed run.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Frames {
    /// Timed frames along the scene's camera path (time = i * duration / N).
    pub timed: u32,
    /// Untimed frames first (at time 0).
    pub warmup: u32,
    /// Error frames: read back and measured against the reference at this many times spread
    /// evenly over the camera path, start and end included (see [`Frames::error_times`]).
    pub errors: u32,
    /// Seconds of timed frames a row may take (0: no limit): a technique whose first warm-up
    /// frame shows that `timed` frames would take longer is timed on fewer, evenly spread along
    /// the path (at least [`Frames::MIN_TIMED`]), after that one warm-up frame
    /// ([`Frames::timed_within_budget`]). The row's `frames` says how many were timed.
    pub timed_budget_s: f64,
}

impl Default for Frames {
    /// What `compare` and `sweep` measure unless told otherwise: 8 timed frames along the path
    /// after one warm-up frame (which compiles the shaders and makes the maps), within a
    /// quarter of a second of timed frames per row, and error frames at the start, middle and
    /// end of the path.
    fn default() -> Self {
        Frames {
            timed: 8,
            warmup: 1,
            errors: 3,
            timed_budget_s: Frames::DEFAULT_TIMED_BUDGET_S,
        }
    }
}

impl Frames {
    /// Most error frames a run may ask for (each needs a CPU reference).
    pub const MAX_ERRORS: u32 = 64;
    /// Most timed frames a run may ask for.
    pub const MAX_TIMED: u32 = 10_000;
    /// Most warm-up frames a run may ask for.
    pub const MAX_WARMUP: u32 = 1_000;
    /// The default [`Frames::timed_budget_s`]: a quarter of a second of timed frames per row.
    /// A row whose frame takes more than 31 ms is timed on fewer than 8 frames; one taking more
    /// than 83 ms on its error frames alone (every frame is timed: see `measure`). On the
    /// 2-core software rasterizer that keeps the main job in minutes; `--timed-budget 0` times
    /// every row on `--frames` frames, and `harness bench` compares a few techniques' times in
    /// interleaved rounds.
    pub const DEFAULT_TIMED_BUDGET_S: f64 = 0.25;
    /// Fewest timed frames a budget leaves (a median and a spread need a few).
    pub const MIN_TIMED: u32 = 3;

    /// Timed frames for a technique whose warm-up frame took `frame_ms` (wall clock): `timed`
    /// when they fit [`Frames::timed_budget_s`] (or there is no budget), else as many as fit,
    /// at least [`Frames::MIN_TIMED`] (never more than `timed`).
    pub fn timed_within_budget(&self, frame_ms: f64) -> u32 {
        if !(self.timed_budget_s > 0.0) || !(frame_ms > 0.0) {
            return self.timed;
        }
        let fit = (self.timed_budget_s * 1e3 / frame_ms).floor();
        if fit >= self.timed as f64 {
            self.timed
        } else {
            (fit as u32).max(Self::MIN_TIMED).min(self.timed)
        }
    }

    /// The times of the error frames on a camera path of `duration` seconds: `errors` times
    /// from 0 to `duration` evenly spaced (3: start, middle, end), duplicates removed, so a
    /// scene without motion (duration 0) or `errors` <= 1 measures time 0 only.
    pub fn error_times(&self, duration: f32) -> Vec<f32> {
        let n = self.errors.clamp(1, Self::MAX_ERRORS);
        let duration = if duration.is_finite() {
            duration.max(0.0)
        } else {
            0.0
        };
        let mut times: Vec<f32> = (0..n)
            .map(|i| match n {
                1 => 0.0,
                _ => duration * i as f32 / (n - 1) as f32,
            })
            .collect();
        times.dedup();
        times
    }
}

impl Frames {
    /// [`Frames::error_times`] on the scene's camera path: what the run renders and what the
    /// references are rendered for (one function, so their times are equal bit for bit).
    pub fn error_times_for(&self, scene: &scene::Scene) -> Vec<f32> {
        self.error_times(scene.camera_path.duration())
    }
}

/// The file-name suffix of the images of an error frame after the first: `.t1`, `.t0.5`,
/// `.t0.6666667` (the shortest text that reads back as the same `f32`, so distinct times
/// never share a file).
pub fn time_suffix(time: f32) -> String {
    format!(".t{time}")
}

/// A technique id or scene spec as a file name: `/` becomes `__`, and every character other
/// than ASCII letters, digits, `-`, `_`, `.` and `=` becomes `_`
/// (`impostors/false-position` -> `impostors__false-position`,
/// `cornell-sphere:material=mirror` -> `cornell-sphere_material=mirror`).
pub fn file_name(id: &str) -> String {
    let mut out = String::with_capacity(id.len() + 4);
    for c in id.chars() {
        match c {
            '/' => out.push_str("__"),
            c if c.is_ascii_alphanumeric() || "-_.=".contains(c) => out.push(c),
            _ => out.push('_'),
        }
    }
    if out.is_empty() || out.starts_with('.') {
        out.insert(0, '_');
    }
    out
}

/// Whether a scene spec names a file rather than a built-in scene.
pub fn is_scene_path(spec: &str) -> bool {
    scene::is_file_spec(spec)
}

/// The folder name of a scene's images: the file name for a glTF path, the spec otherwise.
pub fn scene_dir_name(spec: &str) -> String {
    if is_scene_path(spec) {
        let name = std::path::Path::new(spec)
            .file_name()
            .map(|n| n.to_string_lossy().into_owned());
        return file_name(&name.unwrap_or_else(|| spec.to_string()));
    }
    file_name(spec)
}

/// The image folder names of a run's scenes, unique within the run: [`scene_dir_name`] of
/// each, and where two specs would share a folder (`x/scene.glb` and `y/scene.glb`), the
/// whole spec made a file name (`x__scene.glb`), then `-2`, `-3`, ... if still equal.
pub fn scene_dir_names(specs: &[String]) -> Vec<String> {
    let base: Vec<String> = specs.iter().map(|s| scene_dir_name(s)).collect();
    let mut names: Vec<String> = specs
        .iter()
        .zip(&base)
        .map(
            |(spec, name)| match base.iter().filter(|b| *b == name).count() {
                1 => name.clone(),
                _ => file_name(spec.trim_start_matches("./")),
            },
        )
        .collect();
    for i in 0..names.len() {
        let mut k = 2;
        while names[..i].contains(&names[i]) {
            names[i] = format!("{}-{k}", names[i].trim_end_matches(&format!("-{}", k - 1)));
            k += 1;
        }
    }
    names
}

/// The lock a run holds on its output folder (`<out>/.lock`) while it writes there: a second
/// run into the same folder fails at once with one sentence instead of mixing its rows and
/// images with the first's. The operating system releases it when the process ends, however
/// it ends.
pub struct OutputLock {
    _file: std::fs::File,
}

impl OutputLock {
    /// Creates `out` and takes its lock, or fails when another run holds it.
    pub fn acquire(out: &std::path::Path) -> Result<Self> {
        std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
        let path = out.join(".lock");
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .with_context(|| format!("cannot create the lock file {}", path.display()))?;
        match file.try_lock() {
            Ok(()) => Ok(OutputLock { _file: file }),
            Err(std::fs::TryLockError::WouldBlock) => bail!(
                "another harness run is writing to {} (it holds {}); wait for it to finish or \
                 choose another --out",
                out.display(),
                path.display()
            ),
            Err(std::fs::TryLockError::Error(e)) => {
                Err(anyhow::anyhow!(e).context(format!("cannot lock {}", path.display())))
            }
        }
    }
}

/// Splits a `--scenes` list on commas, keeping `key=value` pieces with the spec before them:
/// `city:buildings=64,rooms_per_building=8,cornell-sphere` is two scenes.
pub fn split_scene_list(list: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for piece in list.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let continues = piece.contains('=') && !piece.contains(':') && !is_scene_path(piece);
        match out.last_mut() {
            Some(last) if continues && last.contains(':') => {
                last.push(',');
                last.push_str(piece);
            }
            _ => out.push(piece.to_string()),
        }
    }
    out
}

/// The built-in scene specs (default parameters), in declaration order.
pub fn builtin_scene_names() -> Vec<String> {
    scene::builtin::builtin_scenes()
        .iter()
        .map(|s| s.name.to_string())
        .collect()
}

/// Loads a scene spec (built-in or .gltf/.glb path) with a one-line error.
pub fn load_scene(spec: &str) -> Result<Scene> {
    load_scene_noted(spec).map(|(scene, _)| scene)
}

/// [`load_scene`] with the importer's notes (default lighting added, normals repaired): what
/// `compare` prints as warnings and records in `results.json`.
pub fn load_scene_noted(spec: &str) -> Result<(Scene, Vec<String>)> {
    // A file's errors name the file already (`cannot load glTF x.glb: ...`); a built-in
    // spec's parameter errors do not, so they get the spec in front.
    if scene::is_file_spec(spec) {
        return Ok(scene::load_noted(spec)?);
    }
    let loaded = scene::load_noted(spec).with_context(|| format!("scene \"{spec}\""))?;
    Ok(loaded)
}

/// Resolves `--techniques` entries to technique specs: an id or a family as
/// [`select_techniques`] takes them, or a spec with parameters (`raytracer/caustics:converge=2`,
/// which names one technique and the values set on it).
pub fn select_technique_specs(
    all_ids: &[String],
    wanted: &[String],
) -> Result<Vec<plan::TechniqueSpec>> {
    let mut out: Vec<plan::TechniqueSpec> = Vec::new();
    for name in wanted {
        let specs = match name.contains(':') {
            true => {
                let spec = plan::TechniqueSpec::parse(name)?;
                select_techniques(all_ids, Some(std::slice::from_ref(&spec.id)))?;
                if !all_ids.contains(&spec.id) {
                    bail!(
                        "\"{name}\": parameters are set on one technique, not on the family {}",
                        spec.id
                    );
                }
                vec![spec]
            }
            false => select_techniques(all_ids, Some(std::slice::from_ref(name)))?
                .iter()
                .map(|id| plan::TechniqueSpec::id(id))
                .collect(),
        };
        for spec in specs {
            if !out.contains(&spec) {
                out.push(spec);
            }
        }
    }
    Ok(out)
}

/// The family of a technique id: what comes before the `/` (`envmap/classic` -> `envmap`).
pub fn technique_family(id: &str) -> &str {
    id.split('/').next().unwrap_or(id)
}

/// What an unknown technique name was probably meant to be: the ids (and families) closest to
/// it by edit distance, at most five, or `harness list` when none is close.
fn suggestion(name: &str, all_ids: &[String]) -> String {
    if all_ids.is_empty() {
        return " (no technique is registered)".into();
    }
    let mut families: Vec<&str> = all_ids.iter().map(|id| technique_family(id)).collect();
    families.dedup();
    let candidates = families
        .into_iter()
        .chain(all_ids.iter().map(String::as_str));
    let mut scored: Vec<(usize, &str)> = candidates
        .map(|c| (edit_distance(name, c), c))
        .filter(|&(d, c)| d <= (c.len().max(name.len()) / 3).max(2))
        .collect();
    scored.sort();
    scored.dedup();
    let close: Vec<&str> = scored.iter().take(5).map(|&(_, c)| c).collect();
    let all = all_ids.len();
    match close.as_slice() {
        [] => format!("; `harness list` shows all {all} technique ids"),
        [one] => format!("; did you mean {one}? (`harness list` shows all {all})"),
        many => format!(
            "; did you mean one of {}? (`harness list` shows all {all})",
            many.join(", ")
        ),
    }
}

/// Levenshtein distance between two strings, in characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let substitute = diagonal + usize::from(ca != cb);
            diagonal = row[j + 1];
            row[j + 1] = substitute.min(row[j] + 1).min(row[j + 1] + 1);
        }
    }
    row[b.len()]
}

/// Resolves `--techniques` names against the ids a factory offers: an exact id, or a family
/// (`impostors` or `impostors/`) for all its variants. An unknown name is an error that
/// suggests the closest ids. `None` selects every technique.
pub fn select_techniques(all_ids: &[String], wanted: Option<&[String]>) -> Result<Vec<String>> {
    let Some(wanted) = wanted else {
        return Ok(all_ids.to_vec());
    };
    let mut out: Vec<String> = Vec::new();
    for name in wanted {
        let family = name.trim_end_matches('/');
        let matches: Vec<&String> = all_ids
            .iter()
            .filter(|id| *id == name || technique_family(id) == family && !family.is_empty())
            .collect();
        if matches.is_empty() {
            bail!("unknown technique \"{name}\"{}", suggestion(name, all_ids));
        }
        for id in matches {
            if !out.contains(id) {
                out.push(id.clone());
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one list of families: ids unique, each variant named after its family (the
    /// foundation's baselines and the reference excepted), each image check naming a
    /// variant of the family that declares it.
    #[test]
    fn every_family_owns_its_variants_and_checks() {
        let mut ids = std::collections::BTreeSet::new();
        for family in families() {
            let own: Vec<String> = (family.techniques)().iter().map(|t| t.id()).collect();
            assert!(!own.is_empty(), "{} has no variant", family.name);
            for id in &own {
                assert!(ids.insert(id.clone()), "{id} registered twice");
                let named = id == family.name || id.starts_with(&format!("{}/", family.name));
                assert!(
                    named || family.name == "foundation",
                    "{id} is not named after its family {}",
                    family.name
                );
            }
            for check in (family.image_checks)() {
                assert!(
                    own.iter().any(|id| id == check.technique),
                    "{} declares a check of {}, not one of its variants",
                    family.name,
                    check.technique
                );
            }
        }
    }

    #[test]
    fn sizes_parse() {
        assert_eq!("256x128".parse::<Size>(), Ok(Size::new(256, 128)));
        assert_eq!("64".parse::<Size>(), Ok(Size::new(64, 64)));
        assert_eq!(" 32X16 ".parse::<Size>(), Ok(Size::new(32, 16)));
        assert!("abc".parse::<Size>().is_err());
        assert!("0x5".parse::<Size>().is_err());
        assert!("10x".parse::<Size>().is_err());
        assert!("-1x4".parse::<Size>().is_err());
        assert!("99999999999x4".parse::<Size>().is_err());
    }

    #[test]
    fn error_times_span_the_path() {
        let frames = |errors| Frames {
            errors,
            ..Frames::default()
        };
        assert_eq!(frames(3).error_times(2.0), vec![0.0, 1.0, 2.0]);
        assert_eq!(frames(5).error_times(2.0), vec![0.0, 0.5, 1.0, 1.5, 2.0]);
        assert_eq!(frames(1).error_times(2.0), vec![0.0]);
        assert_eq!(frames(0).error_times(2.0), vec![0.0]);
        assert_eq!(frames(3).error_times(0.0), vec![0.0]);
        assert_eq!(frames(3).error_times(f32::NAN), vec![0.0]);
        assert_eq!(
            frames(1000).error_times(1.0).len(),
            Frames::MAX_ERRORS as usize
        );
        assert_eq!(time_suffix(1.0), ".t1");
        assert_eq!(time_suffix(2.0 / 3.0), ".t0.6666667");
        assert_ne!(time_suffix(0.001), time_suffix(0.002));
    }

    #[test]
    fn slow_techniques_are_timed_on_fewer_frames_within_the_budget() {
        let f = Frames {
            timed: 16,
            timed_budget_s: 30.0,
            ..Frames::default()
        };
        assert_eq!(f.timed_within_budget(100.0), 16);
        assert_eq!(f.timed_within_budget(1875.0), 16); // exactly 30 s
        assert_eq!(f.timed_within_budget(3000.0), 10);
        assert_eq!(f.timed_within_budget(20_000.0), Frames::MIN_TIMED);
        let default = Frames::default(); // 8 frames within 0.25 s
        assert_eq!(default.timed_within_budget(31.25), 8);
        assert_eq!(default.timed_within_budget(50.0), 5);
        assert_eq!(default.timed_within_budget(900.0), Frames::MIN_TIMED);
        let unlimited = Frames {
            timed_budget_s: 0.0,
            ..f
        };
        assert_eq!(unlimited.timed_within_budget(20_000.0), 16);
        let two = Frames { timed: 2, ..f };
        assert_eq!(two.timed_within_budget(20_000.0), 2);
    }

    #[test]
    fn file_names_are_safe() {
        assert_eq!(
            file_name("impostors/false-position"),
            "impostors__false-position"
        );
        assert_eq!(
            file_name("cornell-sphere:material=mirror"),
            "cornell-sphere_material=mirror"
        );
        assert_eq!(file_name("a b/c"), "a_b__c");
        assert_eq!(file_name("../x"), "_..__x");
        assert_eq!(file_name(""), "_");
    }

    /// Every declared parameter of every variant is settable at both ends of its range and
    /// reads back what was set (a parameter listed but not settable, or set into another
    /// field, fails); its default lies in its range; an undeclared name is refused.
    #[test]
    fn every_declared_parameter_sets_and_reads_back() {
        let mut wrong = Vec::new();
        for mut technique in registry() {
            let id = technique.id();
            for param in technique.params() {
                let name = param.name;
                assert!(
                    param.min <= param.default && param.default <= param.max,
                    "{id}: {name}'s default {} outside [{}, {}]",
                    param.default,
                    param.min,
                    param.max
                );
                for value in [param.min, param.max, param.default] {
                    technique
                        .set_param(name, value)
                        .unwrap_or_else(|e| panic!("{id}: {name} = {value}: {e}"));
                    let read = technique.params().into_iter().find(|p| p.name == name);
                    if let Some(read) = read {
                        if (read.default - value).abs() > 1e-6 * value.abs().max(1.0) {
                            wrong.push(format!(
                                "{id}: set {name} = {value}, reads {}",
                                read.default
                            ));
                        }
                    }
                }
            }
            assert!(
                technique.set_param("no_such_parameter", 1.0).is_err(),
                "{id}"
            );
        }
        assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    }

    #[test]
    fn scene_folders_are_unique() {
        let specs: Vec<String> = ["x/scene.glb", "y/scene.glb", "cornell-sphere", "z/a.glb"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        assert_eq!(
            scene_dir_names(&specs),
            vec!["x__scene.glb", "y__scene.glb", "cornell-sphere", "a.glb"]
        );
        let same: Vec<String> = ["a.glb", "./a.glb", "a.glb"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let names = scene_dir_names(&same);
        assert_eq!(names, vec!["a.glb", "a.glb-2", "a.glb-3"]);
    }

    #[test]
    fn scene_lists_keep_parameters_together() {
        assert_eq!(
            split_scene_list("city:buildings=64,rooms_per_building=8,cornell-sphere"),
            vec!["city:buildings=64,rooms_per_building=8", "cornell-sphere"]
        );
        assert_eq!(split_scene_list("a, b,,c"), vec!["a", "b", "c"]);
        assert_eq!(
            split_scene_list("x.glb,cornell-box:material=gold"),
            vec!["x.glb", "cornell-box:material=gold"]
        );
    }

    #[test]
    fn technique_selection() {
        let ids: Vec<String> = ["reference", "impostors/classic", "impostors/false-position"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let pick = |w: &[&str]| {
            select_techniques(
                &ids,
                Some(&w.iter().map(|s| s.to_string()).collect::<Vec<_>>()),
            )
        };
        assert_eq!(
            pick(&["impostors"]).unwrap(),
            vec!["impostors/classic", "impostors/false-position"]
        );
        assert_eq!(
            pick(&["impostors/classic", "reference"]).unwrap(),
            vec!["impostors/classic", "reference"]
        );
        let err = pick(&["nope"]).unwrap_err().to_string();
        assert!(
            err.contains("unknown technique \"nope\"") && err.contains("harness list"),
            "{err}"
        );
        let err = pick(&["impostor/clasic"]).unwrap_err().to_string();
        assert!(
            err.ends_with("did you mean impostors/classic? (`harness list` shows all 3)"),
            "{err}"
        );
        let err = pick(&["impostor"]).unwrap_err().to_string();
        assert!(err.contains("did you mean impostors?"), "{err}");
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(select_techniques(&ids, None).unwrap().len(), 3);
    }
}
