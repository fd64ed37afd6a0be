//! `harness rays`: how fast the ground truth is on this machine. The reference's BVH throughput
//! on four ray sets ([`truth::throughput`]: coherent and incoherent, closest-hit and any-hit)
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
    /// Built-in scene specs or .gltf/.glb paths.
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
    let scenes = options
        .scenes
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
        let sets = truth::throughput::ray_sets(scene, &bvh, &camera, (w, h), 0x5eed);
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

/// The reports as markdown: what made them, a summary row per scene, then each scene's ray sets
/// and render split.
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
         incoherent any | reference s | eye pass s | light pass s |\n",
    );
    md.push_str("| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
    for r in reports {
        let rates: Vec<String> = r
            .throughput
            .iter()
            .map(|t| format!("{:.2}", t.median()))
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
    md.push_str("\nRates in millions of rays per second (the median of the rounds).\n");
    for r in reports {
        md.push('\n');
        md.push_str(&r.markdown());
    }
    md
}

impl RaysReport {
    /// One scene's section: the ray sets' rates, the render's split.
    pub fn markdown(&self) -> String {
        let mut md = format!("## {}\n\n{} triangles.\n\n", self.scene, self.triangles);
        md.push_str("| ray set | query | rays | hits | Mrays/s (median) | min - max |\n");
        md.push_str("| --- | --- | --- | --- | --- | --- |\n");
        for t in &self.throughput {
            let rates = t.mrays_per_second();
            let (low, high) = (rates[0], rates[rates.len() - 1]);
            let query = match t.query {
                Query::Closest => "closest",
                Query::Any => "any",
            };
            let _ = writeln!(
                md,
                "| {} | {query} | {} | {} | {:.2} | {low:.2} - {high:.2} |",
                t.name,
                t.rays,
                t.hits,
                t.median()
            );
        }
        md.push('\n');
        md.push_str(&self.split_markdown());
        md
    }

    /// The reference render's seconds by phase and part.
    fn split_markdown(&self) -> String {
        let plain = &self.plain.stats;
        let (profiled, parts) = (&self.profiled.0.stats, &self.profiled.1);
        let mut md = format!(
            "Reference render, {} x {}, {} photons: {} camera, {} shadow and {} photon rays.\n\n",
            self.plain.image.width,
            self.plain.image.height,
            self.photons,
            plain.camera_rays,
            plain.shadow_rays,
            plain.photon_rays
        );
        md.push_str("| part | seconds | share | profiled run |\n| --- | --- | --- | --- |\n");
        let row = |md: &mut String, name: &str, plain: Option<f64>, profiled: f64| {
            let total = self.plain.stats.seconds.max(1e-9);
            let (seconds, share) = match plain {
                Some(s) => (format!("{s:.3}"), format!("{:.0} %", 100.0 * s / total)),
                None => ("".into(), "".into()),
            };
            let _ = writeln!(md, "| {name} | {seconds} | {share} | {profiled:.3} |");
        };
        let (phases, profiled_phases) = (&plain.phases, &profiled.phases);
        row(
            &mut md,
            "whole render",
            Some(plain.seconds),
            profiled.seconds,
        );
        row(
            &mut md,
            "BVH build",
            Some(phases.bvh_seconds),
            profiled_phases.bvh_seconds,
        );
        row(
            &mut md,
            "eye pass",
            Some(phases.eye_seconds),
            profiled_phases.eye_seconds,
        );
        row(
            &mut md,
            "- direct light and its shadow rays",
            None,
            parts.direct_light_seconds,
        );
        row(&mut md, "- media", None, parts.eye_media_seconds);
        row(
            &mut md,
            "light pass (photons)",
            Some(phases.light_seconds),
            profiled_phases.light_seconds,
        );
        row(
            &mut md,
            "- connections to the eye",
            None,
            parts.connection_seconds,
        );
        row(&mut md, "- photon beams", None, parts.beam_seconds);
        md.push_str(
            "\nThe parts (rows starting with -) are timed only in a second, profiled render: \
             the thread-seconds spent in each, divided by the threads. Its column's whole \
             render against the first's is what timing them cost.\n",
        );
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
