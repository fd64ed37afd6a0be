//! The report model: everything a run produced, in one value that every writer reads (the CSV,
//! JSON and markdown tables, the HTML page, the Pareto and sweep plots) and that the engine
//! fills row by row. Its JSON form is the run's `results.json` (`sweep.json` for a sweep),
//! which reads back without loss: `--resume` continues from it and `harness merge` joins the
//! shards' into one.

use crate::pareto::ParetoScene;
use crate::plan::{Plan, PlanKind, Shard, SweepInfo};
use crate::provenance::Provenance;
use crate::report::{AdapterJson, ResultRow, Skipped};
use crate::{Frames, ReferenceStats};
use std::collections::BTreeMap;

/// How a scene's reference at one error-frame time went.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReferenceInfo {
    pub scene: String,
    pub time: f32,
    pub cached: bool,
    /// Why the cache could not serve it (`cache::miss_reason`); none when it did.
    #[serde(default)]
    pub miss: Option<String>,
    pub stats: Option<ReferenceStats>,
    pub masked_pixels: usize,
    pub error: Option<String>,
}

/// The files of one error frame of an image, relative to the output folder (what the report
/// shows: only what this run wrote).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ImageFrame {
    pub time: f32,
    pub png: String,
    /// The FLIP map (techniques with a reference only).
    pub flip: Option<String>,
    /// The HDR copy the report's exposure control reads
    /// ([`crate::images::write_hdr_script`]).
    pub hdr: String,
}

/// The images a run wrote for one ground truth (`technique` None) or one technique's result.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WrittenImages {
    pub scene: String,
    pub technique: Option<String>,
    /// The swept value (sweep only).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub value: Option<String>,
    pub frames: Vec<ImageFrame>,
}

/// Where a scene's own wall-clock time went (its references and the upload).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SceneWall {
    pub scene: String,
    /// The references at every error time: rendered, or read from the cache, and written.
    #[serde(with = "crate::json_float::num")]
    pub reference_s: f64,
    /// After its rows: the Pareto view and every file written again.
    #[serde(default, with = "crate::json_float::num")]
    pub close_s: f64,
}

/// Everything a run produced (its JSON is `results.json` or `sweep.json`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunReport {
    /// `compare` or `sweep` (with what it sweeps).
    pub kind: PlanKind,
    /// [`Plan::key`] of the whole plan (not of the shard): what `--resume` and `merge` check.
    pub plan_key: String,
    /// The slice of the plan this run measured; `None`: all of it.
    pub shard: Option<Shard>,
    pub adapter: AdapterJson,
    pub provenance: Provenance,
    pub size: String,
    /// Timed frames asked for per row (fewer where the timed budget cut them: see each row).
    pub frames: u32,
    pub warmup: u32,
    /// Error frames asked for per row (fewer on a scene whose path is shorter: see each
    /// row's `error_times`).
    pub error_frames: u32,
    pub timed_budget_s: f64,
    pub rows: Vec<ResultRow>,
    pub skipped: Vec<Skipped>,
    pub references: Vec<ReferenceInfo>,
    /// Per scene spec: the folder under `images/` its images are in (unique within the run;
    /// empty for a sweep's scenes, whose images are in `images/` itself).
    pub image_dirs: BTreeMap<String, String>,
    /// What the glTF importer supplied or repaired, per scene ("scene: note"): default
    /// lighting for a file without lights, replaced normals.
    pub scene_notes: Vec<String>,
    /// Every error of the run, one line each ("scene / technique: message").
    pub errors: Vec<String>,
    /// The rows whose technique panicked ("scene / technique: message"). A panic is a defect
    /// even where it is caught: the binary exits non-zero when this is not empty.
    pub panics: Vec<String>,
    /// Per scene: error against frame time, and which techniques are on the front
    /// (`crate::pareto`; the plot under `pareto/`).
    pub pareto: Vec<ParetoScene>,
    /// Every image file the run wrote, per ground truth and technique (the report shows these).
    pub images: Vec<WrittenImages>,
    /// Per scene: the wall-clock seconds of its references.
    pub scene_walls: Vec<SceneWall>,
}

impl RunReport {
    /// An empty report of `plan` (the whole plan's key; `shard` the slice it runs).
    pub fn new(
        plan: &Plan,
        plan_key: String,
        shard: Option<Shard>,
        adapter: AdapterJson,
        provenance: Provenance,
    ) -> Self {
        RunReport {
            kind: plan.kind.clone(),
            plan_key,
            shard,
            adapter,
            provenance,
            size: plan.size.to_string(),
            frames: plan.frames.timed,
            warmup: plan.frames.warmup,
            error_frames: plan.frames.errors,
            timed_budget_s: plan.frames.timed_budget_s,
            rows: Vec::new(),
            skipped: plan.skipped.clone(),
            references: Vec::new(),
            image_dirs: plan
                .scenes
                .iter()
                .map(|s| {
                    let dir = s.image_dir.trim_start_matches("images");
                    (s.spec.clone(), dir.trim_start_matches('/').to_string())
                })
                .collect(),
            scene_notes: Vec::new(),
            errors: Vec::new(),
            panics: Vec::new(),
            pareto: Vec::new(),
            images: Vec::new(),
            scene_walls: Vec::new(),
        }
    }

    /// What the sweep sweeps (`None` for a compare).
    pub fn sweep(&self) -> Option<&SweepInfo> {
        match &self.kind {
            PlanKind::Sweep(info) => Some(info),
            PlanKind::Compare => None,
        }
    }

    /// The frames the run asked for.
    pub fn frames(&self) -> Frames {
        Frames {
            timed: self.frames,
            warmup: self.warmup,
            errors: self.error_frames,
            timed_budget_s: self.timed_budget_s,
        }
    }

    /// Reads a report written by an earlier run.
    pub fn read(path: &std::path::Path) -> anyhow::Result<Self> {
        use anyhow::Context as _;
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        serde_json::from_str(&text).with_context(|| {
            format!(
                "{} is not the results of this version of the harness",
                path.display()
            )
        })
    }
}
