//! `harness compare`: every supported (scene, technique) pair against the reference, as a plan
//! the engine executes ([`crate::engine`]).
//!
//! Writes, under the output folder:
//!
//! - `results.csv`, `results.json`, `results.md` (see [`crate::report`]), the first two
//!   rewritten after every row, all three after every scene;
//! - `images/<scene>/<technique>.png` and `.exr` (the first error frame: the camera path's
//!   view at time 0), `images/<scene>/<technique>.flip.png` (FLIP error map, magma colour
//!   map), `images/<scene>/reference.png` and `.exr`; the later error frames along the camera
//!   path as `<technique>.t<time>.png`, `<technique>.t<time>.flip.png` and
//!   `reference.t<time>.png` (`.t1`, see [`crate::time_suffix`]); beside every PNG its HDR copy
//!   `.hdr.js` (see [`crate::images::write_hdr_script`]), all listed in the report's `images`;
//! - `pareto/<scene>.svg`, the Pareto view of each scene ([`crate::pareto`]);
//! - `index.html`, the report a person reads (see [`crate::html`]);
//! - `.cache/` with the references (see [`crate::cache`]).
//!
//! `<scene>` and `<technique>` are made file names by [`crate::file_name`] (`/` becomes `__`).
//! A technique whose `supports(scene)` is false is left out quietly; one whose required
//! features the adapter lacks is left out with the reason printed, and so is every technique
//! on a scene seen by an orthographic camera (`scene::orthographic_refusal`; one line per
//! scene); all are listed under `skipped` in `results.json`. A technique that fails (an error, a GPU validation error or a
//! panic) gets a row with the error and the run goes on. If the reference fails, the rows of
//! that scene have timings but no error figures, and the reason is in `results.json`.

use crate::engine::{self, ExecOptions};
use crate::model::RunReport;
use crate::plan::{self, Plan, PlanKind, PlannedRow, PlannedScene, TechniqueSpec};
use crate::report::Skipped;
use crate::{Env, Frames, Size};
use anyhow::Result;
use std::collections::BTreeMap;

/// What to compare.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    /// Scene specs (built-in or paths); every built-in scene when empty.
    pub scenes: Vec<String>,
    /// Technique ids, families (`impostors`) or specs with parameters
    /// (`raytracer/caustics:converge=4`); when `None`, every registered technique that is
    /// [`scene::Technique::representative`], or every one with `all_variants`.
    pub techniques: Option<Vec<String>>,
    /// Run every variant of every family, not just the representative ones (ignored when
    /// `techniques` names them).
    pub all_variants: bool,
    pub size: Size,
    pub frames: Frames,
}

/// The techniques a compare runs, in registry order.
fn selected(env: &Env, opts: &CompareOptions) -> Result<Vec<TechniqueSpec>> {
    let registered = (env.techniques)();
    let all_ids: Vec<String> = registered.iter().map(|t| t.id()).collect();
    match &opts.techniques {
        Some(wanted) => crate::select_technique_specs(&all_ids, wanted),
        None => Ok(registered
            .iter()
            .filter(|t| opts.all_variants || t.representative())
            .map(|t| TechniqueSpec::id(&t.id()))
            .collect()),
    }
}

/// The plan of a compare: per scene, every selected technique that supports it and whose
/// features the adapter has (the others under `skipped`, with the reason).
pub fn plan(env: &Env, opts: &CompareOptions) -> Result<Plan> {
    let techniques = selected(env, opts)?;
    let specs = match opts.scenes.is_empty() {
        true => crate::builtin_scene_names(),
        false => opts.scenes.clone(),
    };
    let scenes = engine::load_scenes(&specs)?;
    let mut plan = Plan::empty(
        PlanKind::Compare,
        opts.size,
        opts.frames,
        env.ground_truth.key(),
    );
    for (loaded, image_dir) in scenes.iter().zip(plan::compare_image_dirs(&specs)) {
        plan.scenes.push(PlannedScene {
            spec: loaded.spec.clone(),
            image_dir,
            reference_stem: "reference".into(),
            value: None,
        });
        for spec in &techniques {
            let technique = spec.instance(env.techniques)?;
            let skip = |reason: String| Skipped {
                scene: loaded.spec.clone(),
                technique: spec.to_string(),
                reason,
            };
            if !technique.supports(&loaded.scene) {
                plan.skipped
                    .push(skip("does not support this scene".into()));
            } else if let Err(e) = scene::orthographic_refusal(technique.as_ref(), &loaded.scene) {
                plan.skipped.push(skip(e.to_string()));
            } else if let Err(e) = env.ctx.require(technique.required_features()) {
                plan.skipped.push(skip(e.to_string()));
            } else {
                plan.rows.push(PlannedRow {
                    scene: loaded.spec.clone(),
                    technique: spec.clone(),
                    label: spec.to_string(),
                    swept: None,
                    image_stem: plan::compare_image_stem(spec),
                });
            }
        }
    }
    plan::check_unique(&plan.rows)?;
    Ok(plan)
}

/// Runs the comparison (see the module documentation) and writes every file.
pub fn run(env: &Env, opts: &CompareOptions, exec: &ExecOptions) -> Result<RunReport> {
    let plan = plan(env, opts)?;
    // An orthographic camera leaves out every technique: one line per scene says so.
    let pinhole_only = |s: &&Skipped| s.reason.contains(scene::PINHOLE_ONLY);
    let mut pinhole_skips: BTreeMap<&str, usize> = BTreeMap::new();
    for s in plan.skipped.iter().filter(pinhole_only) {
        *pinhole_skips.entry(s.scene.as_str()).or_default() += 1;
    }
    for (scene, count) in pinhole_skips {
        eprintln!(
            "skipped: {scene}: {count} techniques, which need a pinhole camera (the scene's \
             camera is orthographic; the reference, the ray tracer and raster render it)"
        );
    }
    for s in plan
        .skipped
        .iter()
        .filter(|s| !s.reason.starts_with("does not") && !pinhole_only(s))
    {
        eprintln!("skipped: {} / {}: {}", s.scene, s.technique, s.reason);
    }
    engine::execute(env, &plan, exec)
}
