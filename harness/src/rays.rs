//! `harness rays`: how fast the ground truth is on this machine. The reference's BVH throughput
//! on five ray sets ([`truth::throughput`]: coherent and incoherent, closest-hit and any-hit,
//! and the light pass's own photon paths)
//! and one reference render of the scene's view split into its phases and parts
//! ([`truth::reference::render_profiled`]), on a stated number of threads: the figures a
//! comparison with another renderer (Mitsuba 3's ray casts on the same exported scene) needs.
//! Everything is seen by the scene's own camera at time 0.

use crate::provenance::Provenance;
use crate::{CpuReference, Size};
use anyhow::{Context as _, Result};
use std::fmt::Write as _;
use truth::reference::{ReferenceImage, RenderParts};
use truth::throughput::{Query, Throughput};

/// What `harness rays` measures.
#[derive(Clone, Debug)]
pub struct RaysOptions {
    /// Built-in scene specs or .gltf/.glb paths (none: every built-in scene).
    pub scenes: Vec<String>,
    /// The image: one camera ray per pixel, and the size of the reference render.
    pub size: Size,
    /// Threads of the pool everything runs in (`None`: one per logical core).
    pub threads: Option<usize>,
    /// Rounds each ray set is cast (the table gives the median and the spread).
    pub rounds: u32,
    /// The reference render's options (`--ref-*`).
    pub reference: CpuReference,
}

/// The measurements of one `harness rays`.
pub struct RaysReport {
    pub scene: String,
    pub triangles: usize,
    pub threads: usize,
    pub throughput: Vec<Throughput>,
    /// Caustic photons of the reference render.
    pub photons: u64,
    /// The render without the parts' clocks (its total and phases are the honest times).
    pub plain: ReferenceImage,
    /// The same render with them, and the parts.
    pub profiled: (ReferenceImage, RenderParts),
    pub provenance: Provenance,
}

/// Runs the measurements of every scene in turn on a pool of `options.threads` threads
/// (every scene loaded first, so a bad one fails before any is measured).
pub fn measure(options: &RaysOptions) -> Result<Vec<RaysReport>> {
    let specs = match options.scenes.is_empty() {
        true => crate::builtin_scene_names(),
        false => options.scenes.clone(),
    };
    let scenes = specs
        .iter()
        .map(|spec| Ok((spec, crate::load_scene(spec)?)))
        .collect::<Result<Vec<_>>>()?;
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(threads) = options.threads {
        pool = pool.num_threads(threads);
    }
    let pool = pool.build().context("cannot start the thread pool")?;
    scenes
        .into_iter()
        .map(|(spec, scene)| measure_scene(options, spec, &scene, &pool))
        .collect()
}

fn measure_scene(
    options: &RaysOptions,
    spec: &str,
    scene: &scene::Scene,
    pool: &rayon::ThreadPool,
) -> Result<RaysReport> {
    let (w, h) = (options.size.width, options.size.height);
    // The scene's own camera, the one `harness export-scene` writes: another renderer given the
    // exported file casts the same camera rays.
    let camera = scene.camera;
    let reference = options.reference.options_for(w, h);
    pool.install(|| {
        let bvh = scene::bvh::SceneBvh::build(scene, 0.0);
        let sets = truth::throughput::ray_sets(scene, &bvh, &camera, (w, h), (0x5eed, &reference));
        let throughput = sets
            .iter()
            .map(|set| truth::throughput::measure(&bvh, set, options.rounds))
            .collect();
        let plain = truth::reference::render(scene, &camera, 0.0, w, h, &reference);
        let profiled = truth::reference::render_profiled(scene, &camera, 0.0, w, h, &reference);
        Ok(RaysReport {
            scene: spec.to_string(),
            triangles: bvh.triangle_count(),
            threads: rayon::current_num_threads(),
            throughput,
            photons: reference.photons,
            plain,
            profiled,
            provenance: Provenance::capture(format!("{reference:?}")),
        })
    })
}

/// The reports as markdown: what made them, then three tables with a row per scene (or per
/// scene and ray set): the rates and the render's phases, each ray set's spread, the render's
/// phases and parts.
pub fn markdown(reports: &[RaysReport]) -> String {
    let Some(first) = reports.first() else {
        return String::new();
    };
    let p = &first.provenance;
    let mut md = format!(
        "# The reference's speed\n\nWritten by `{}` at commit {} on {}: {} thread{} of {}.\n\n",
        p.command_line,
        p.git_commit,
        p.date_utc,
        first.threads,
        if first.threads == 1 { "" } else { "s" },
        cpu_name()
    );
    md.push_str(
        "| scene | triangles | coherent closest | incoherent closest | coherent any | \
         incoherent any | photon paths | reference s | eye pass s | light pass s |\n",
    );
    md.push_str("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
    for r in reports {
        let rates: Vec<String> = r
            .throughput
            .iter()
            .map(|t| match t.rays {
                0 => "".to_string(),
                _ => format!("{:.2}", t.median()),
            })
            .collect();
        let stats = &r.plain.stats;
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.3} | {:.3} | {:.3} |",
            r.scene,
            r.triangles,
            rates.join(" | "),
            stats.seconds,
            stats.phases.eye_seconds,
            stats.phases.light_seconds
        );
    }
    md.push_str(
        "\nRates in millions of rays per second (the median of the rounds); times in seconds of \
         one reference render of the view.\n\n## Ray sets\n\n",
    );
    md.push_str("| scene | ray set | query | rays | hits | Mrays/s (median) | min - max |\n");
    md.push_str("| --- | --- | --- | --- | --- | --- | --- |\n");
    for r in reports {
        md.push_str(&r.ray_set_rows());
    }
    md.push_str(&split_table(reports));
    md
}

/// The reference renders' phases and parts, a row per scene: the plain render's phases, then
/// the profiled render's own phases with the parts inside them.
fn split_table(reports: &[RaysReport]) -> String {
    let mut md = String::from(
        "\n## The reference render, by phase and part\n\n\
         | scene | size | photons asked | camera rays | shadow rays | photon rays | whole s | \
         BVH s | eye pass s | light pass s | profiled: whole s | eye pass s | direct light s | \
         media s | light pass s | connections s | beams s |\n",
    );
    md.push_str(&"| --- ".repeat(17));
    md.push_str("|\n");
    for r in reports {
        let (stats, phases) = (&r.plain.stats, &r.plain.stats.phases);
        let (profiled, parts) = (&r.profiled.0.stats, &r.profiled.1);
        let seconds = [
            stats.seconds,
            phases.bvh_seconds,
            phases.eye_seconds,
            phases.light_seconds,
            profiled.seconds,
            profiled.phases.eye_seconds,
            parts.direct_light_seconds,
            parts.eye_media_seconds,
            profiled.phases.light_seconds,
            parts.connection_seconds,
            parts.beam_seconds,
        ];
        let seconds: Vec<String> = seconds.iter().map(|s| format!("{s:.3}")).collect();
        let _ = writeln!(
            md,
            "| {} | {}x{} | {} | {} | {} | {} | {} |",
            r.scene,
            r.plain.image.width,
            r.plain.image.height,
            r.photons,
            stats.camera_rays,
            stats.shadow_rays,
            stats.photon_rays,
            seconds.join(" | ")
        );
    }
    md.push_str(
        "\nThe phases (whole, BVH, eye pass, light pass) are wall-clock seconds of a render; \
         photons are asked of every scene, and traced only where a specular object casts \
         caustics. A second, profiled render of the same view times the parts on every thread, \
         as the thread-seconds spent in each divided by the threads, beside its own phases: \
         direct light with its shadow rays and the media (the volumes, the medium's \
         transmittance and in-scattering) inside its eye pass, the connections of landed \
         photons to the eye and the photon beams inside its light pass. The two renders' \
         wholes differ by the timers' cost and by the machine's run-to-run noise.\n",
    );
    md
}

impl RaysReport {
    /// This scene's rows of the ray-set table.
    fn ray_set_rows(&self) -> String {
        let mut md = String::new();
        for t in self.throughput.iter().filter(|t| t.rays > 0) {
            let rates = t.mrays_per_second();
            let (low, high) = (rates[0], rates[rates.len() - 1]);
            let query = match t.query {
                Query::Closest => "closest",
                Query::Any => "any",
            };
            let _ = writeln!(
                md,
                "| {} | {} | {query} | {} | {} | {:.2} | {low:.2} - {high:.2} |",
                self.scene,
                t.name,
                t.rays,
                t.hits,
                t.median()
            );
        }
        md
    }
}

/// The CPU's model name (Linux's /proc/cpuinfo), or "an unnamed CPU".
fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|info| {
            info.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|name| name.trim().to_string())
        })
        .unwrap_or_else(|| "an unnamed CPU".into())
}
