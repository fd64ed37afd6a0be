//! `harness sweep`: one technique on one scene over the values of one parameter. The
//! technique may be given with other parameters fixed for the whole sweep, as `bench` takes
//! it: `--technique id:name=value:name=value`.
//!
//! The parameter is looked up first among the technique's declared parameters
//! (`Technique::params`, set with `set_param` on a fresh instance per value), then among the
//! built-in scene's declared parameters (the scene spec is rebuilt with `NAME=value`, so the
//! reference is rendered, and cached, per value). Every value is checked before any GPU work.
//!
//! Writes `sweep.csv` (the compare columns plus `param` and `value`), `sweep.json`, `sweep.md`,
//! `sweep.png` (see [`crate::plot`]) and `images/<technique>__<param>=<value>.{png,exr,flip.png}`
//! (with `images/reference__<param>=<value>.{png,exr}` for a scene parameter, or
//! `images/reference.{png,exr}` for a technique parameter), each at the first error frame; the
//! later error frames along the camera path add `.t<time>.png` and `.t<time>.flip.png` (see
//! [`crate::time_suffix`]); beside every PNG its HDR copy `.hdr.js` for the report,
//! `index.html` (see [`crate::html`]). Error figures are measured along the path as in
//! `compare`.

use crate::compare::{self, Outcome, write_text};
use crate::plot::{self, PlotPoint, PlotText};
use crate::report::{self, AdapterJson, ResultRow};
use crate::{Env, Frames, Size, backend, file_name};
use anyhow::{Context as _, Result, anyhow, bail};
use scene::Technique;
use std::collections::BTreeMap;
use std::path::PathBuf;

#[derive(Clone, Debug)]
pub struct SweepOptions {
    pub out: PathBuf,
    pub scene: String,
    pub technique: String,
    pub param: String,
    pub values: Vec<String>,
    pub size: Size,
    pub frames: Frames,
}

/// Whose parameter is swept.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ParamOwner {
    Technique,
    Scene,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct SweepReport {
    pub adapter: AdapterJson,
    pub scene: String,
    pub technique: String,
    pub param: String,
    pub owner: ParamOwner,
    pub size: String,
    pub frames: u32,
    pub warmup: u32,
    pub rows: Vec<ResultRow>,
    pub errors: Vec<String>,
    /// The values whose technique panicked (a defect: the binary exits non-zero).
    pub panics: Vec<String>,
    /// Whether `sweep.png` has text (false when no font could be loaded).
    pub plot_has_text: bool,
    /// Every image file the sweep wrote: the reference(s) (`technique` None; `value` set for a
    /// scene parameter) and each value's.
    pub images: Vec<compare::WrittenImages>,
    #[serde(skip)]
    pub markdown: String,
}

/// Parses `NAME=v1,v2,...`.
pub fn parse_param_arg(arg: &str) -> Result<(String, Vec<String>)> {
    let (name, values) = arg
        .split_once('=')
        .ok_or_else(|| anyhow!("--param \"{arg}\" is not NAME=v1,v2,..."))?;
    let values: Vec<String> = values
        .split(',')
        .map(str::trim)
        .filter(|v| !v.is_empty())
        .map(String::from)
        .collect();
    if name.trim().is_empty() || values.is_empty() {
        bail!("--param \"{arg}\" is not NAME=v1,v2,...");
    }
    Ok((name.trim().to_string(), values))
}

/// A fresh instance of technique `id` with the `fixed` parameters of the sweep's technique
/// spec set.
fn instance(env: &Env, id: &str, fixed: &[(String, f64)]) -> Result<Box<dyn Technique>> {
    let mut technique = (env.techniques)()
        .into_iter()
        .find(|t| t.id() == id)
        .ok_or_else(|| anyhow!("technique {id} vanished"))?;
    for (name, value) in fixed {
        technique
            .set_param(name, *value)
            .with_context(|| format!("technique {id}: {name}={value}"))?;
    }
    Ok(technique)
}

/// The built-in scene spec with `name=value` set.
fn scene_spec_with(spec: &str, name: &str, value: &str) -> Result<String> {
    let (scene_name, mut params) = scene::builtin::parse_spec(spec)?;
    params.insert(name.to_string(), value.to_string());
    let kv: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    Ok(format!("{scene_name}:{}", kv.join(",")))
}

/// Runs the sweep (see the module documentation) and writes every file.
pub fn run(env: &Env, opts: &SweepOptions) -> Result<SweepReport> {
    let all_ids: Vec<String> = (env.techniques)().iter().map(|t| t.id()).collect();
    // `id:name=value:...` fixes other parameters of the technique for the whole sweep.
    let (technique_id, fixed) = crate::bench::parse_technique_spec(&opts.technique)?;
    let ids = crate::select_techniques(&all_ids, Some(std::slice::from_ref(&technique_id)))?;
    let [id] = ids.as_slice() else {
        bail!(
            "\"{}\" names several techniques ({}); give one id",
            opts.technique,
            ids.join(", ")
        );
    };
    let (base_scene, notes) = crate::load_scene_noted(&opts.scene)?;
    for note in &notes {
        eprintln!("warning: {}: {note}", opts.scene);
    }
    let probe = instance(env, id, &fixed)?;
    let owner = if probe.params().iter().any(|p| p.name == opts.param) {
        ParamOwner::Technique
    } else {
        let scene_params: Vec<&'static str> = if crate::is_scene_path(&opts.scene) {
            Vec::new()
        } else {
            let (name, _) = scene::builtin::parse_spec(&opts.scene)?;
            scene::builtin::builtin_scenes()
                .into_iter()
                .find(|s| s.name == name)
                .map(|s| s.params.iter().map(|p| p.name).collect())
                .unwrap_or_default()
        };
        if !scene_params.contains(&opts.param.as_str()) {
            let tp: Vec<&str> = probe.params().iter().map(|p| p.name).collect();
            bail!(
                "neither technique {id} (parameters: {}) nor scene {} (parameters: {}) has a parameter \"{}\"",
                if tp.is_empty() {
                    "none".into()
                } else {
                    tp.join(", ")
                },
                opts.scene,
                if scene_params.is_empty() {
                    "none".into()
                } else {
                    scene_params.join(", ")
                },
                opts.param
            );
        }
        ParamOwner::Scene
    };

    // Check every value before any GPU work: technique values parse and are in range, scene
    // values build a valid scene.
    let mut scenes = BTreeMap::new(); // value -> (spec, scene)
    for value in &opts.values {
        match owner {
            ParamOwner::Technique => {
                let v: f64 = value
                    .parse()
                    .map_err(|_| anyhow!("{}={value} is not a number", opts.param))?;
                instance(env, id, &fixed)?.set_param(&opts.param, v)?;
            }
            ParamOwner::Scene => {
                let spec = scene_spec_with(&opts.scene, &opts.param, value)?;
                let scene = crate::load_scene(&spec)?;
                scenes.insert(value.clone(), (spec, scene));
            }
        }
    }
    env.ctx
        .require(probe.required_features())
        .with_context(|| format!("technique {id}"))?;
    crate::limits::check_memory(env.ctx, opts.size, opts.frames)?;
    let _lock = crate::OutputLock::acquire(&opts.out)?;

    let adapter_name = env.ctx.summary.name.clone();
    let mut rows = Vec::new();
    let mut errors = Vec::new();
    let mut panics = Vec::new();
    let mut written = Vec::new();
    let progress = crate::Progress::new(env.progress);
    let bar = progress.scene(&opts.scene, opts.values.len() as u64);
    let say = |line: String| progress.say(&line);
    let mut shared: Option<(Vec<compare::TimedReference>, Option<scene::GpuScene>)> = None;
    for value in &opts.values {
        let (spec, scene) = match owner {
            ParamOwner::Scene => scenes
                .get(value)
                .map(|(s, sc)| (s.clone(), sc.clone()))
                .ok_or_else(|| anyhow!("scene for {}={value} was not built", opts.param))?,
            ParamOwner::Technique => (opts.scene.clone(), base_scene.clone()),
        };
        let suffix = format!("{}={value}", opts.param);
        let mut row = ResultRow::new(&spec, &opts.technique, opts.size, &adapter_name);
        row.param = Some(opts.param.clone());
        row.value = Some(value.clone());

        // Reference and upload: once for a technique parameter, per value for a scene one.
        if owner == ParamOwner::Scene || shared.is_none() {
            bar.set_message(format!("{suffix}: reference"));
            let references = match compare::path_references(
                env,
                &opts.out,
                &spec,
                &scene,
                opts.size,
                opts.frames,
            ) {
                Ok(timed) => {
                    let stem = match owner {
                        ParamOwner::Scene => format!("reference__{}", file_name(&suffix)),
                        ParamOwner::Technique => "reference".into(),
                    };
                    let timed: Vec<_> = timed.into_iter().map(|(r, _)| r).collect();
                    written.push(compare::WrittenImages {
                        scene: spec.clone(),
                        technique: None,
                        value: (owner == ParamOwner::Scene).then(|| value.clone()),
                        frames: compare::write_reference_images(
                            &opts.out, "images", &stem, &timed,
                        )?,
                    });
                    timed
                }
                Err(e) => {
                    let msg = format!("{spec} / reference: {e:#}");
                    say(format!("error: {msg}"));
                    errors.push(msg);
                    Vec::new()
                }
            };
            let gpu_scene = match backend::upload_scene(env.ctx, &scene) {
                Ok(s) => Some(s),
                Err(e) => {
                    let msg = format!("{spec} / upload: {e:#}");
                    say(format!("error: {msg}"));
                    errors.push(msg);
                    None
                }
            };
            shared = Some((references, gpu_scene));
        }
        let Some((references, gpu_scene)) = shared.as_mut() else {
            bail!("no scene prepared")
        };

        let mut technique = instance(env, id, &fixed)?;
        let outcome = if !technique.supports(&scene) {
            Outcome {
                row: row.with_error("the technique does not support this scene"),
                run: None,
                flips: Vec::new(),
            }
        } else if let Some(gs) = gpu_scene.as_mut() {
            if owner == ParamOwner::Technique {
                let v: f64 = value.parse().unwrap_or(f64::NAN);
                technique.set_param(&opts.param, v)?;
            }
            bar.set_message(suffix.clone());
            let row_bar = progress.technique(&suffix);
            let mut on_frame = |step: &str, done: usize, total: usize| {
                crate::Progress::step(&row_bar, step, done, total)
            };
            let outcome = compare::measure(
                env,
                technique.as_mut(),
                gs,
                references,
                opts.frames,
                row,
                &mut on_frame,
            );
            row_bar.finish_and_clear();
            outcome
        } else {
            Outcome {
                row: row.with_error("scene upload failed"),
                run: None,
                flips: Vec::new(),
            }
        };
        written.push(compare::WrittenImages {
            scene: spec.clone(),
            technique: Some(id.clone()),
            value: Some(value.clone()),
            frames: compare::write_outcome_images(
                &opts.out,
                "images",
                &format!("{}__{}", file_name(id), file_name(&suffix)),
                &outcome,
            )?,
        });
        if let Some(err) = &outcome.row.error {
            let msg = format!("{suffix}: {err}");
            say(format!("error: {msg}"));
            if err.starts_with(compare::PANICKED) {
                panics.push(msg.clone());
            }
            errors.push(msg);
        }
        rows.push(outcome.row);
        bar.inc(1);
    }
    bar.finish_with_message(match errors.len() {
        0 => "done".to_string(),
        n => format!("done, {n} failed"),
    });

    let points: Vec<PlotPoint> = rows
        .iter()
        .map(|r| PlotPoint {
            value: r.value.clone().unwrap_or_default(),
            flip_mean: r.flip_mean,
            rmse: r.rmse,
            frame_ms: r.frame_ms_median,
        })
        .collect();
    let title = format!("{} on {} over {}", opts.technique, opts.scene, opts.param);
    let text = plot::sweep_plot(&opts.out.join("sweep.png"), &title, &opts.param, &points)?;

    let report = SweepReport {
        adapter: AdapterJson::of(env.ctx),
        scene: opts.scene.clone(),
        technique: opts.technique.clone(),
        param: opts.param.clone(),
        owner,
        size: opts.size.to_string(),
        frames: opts.frames.timed,
        warmup: opts.frames.warmup,
        markdown: report::to_markdown(&rows, true),
        rows,
        errors,
        panics,
        plot_has_text: text == PlotText::Drawn,
        images: written,
    };
    write_text(
        &opts.out.join("sweep.csv"),
        &report::to_csv(&report.rows, true),
    )?;
    write_text(&opts.out.join("sweep.md"), &report.markdown)?;
    write_text(
        &opts.out.join("sweep.json"),
        &serde_json::to_string_pretty(&report)?,
    )?;
    let provenance = crate::html::Provenance::capture(env.ground_truth.key());
    crate::html::write_sweep_page(&opts.out, &report, &provenance)?;
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn param_arguments_parse() {
        assert_eq!(
            parse_param_arg("iterations=1,2, 4").unwrap(),
            (
                "iterations".into(),
                vec!["1".into(), "2".into(), "4".into()]
            )
        );
        assert!(parse_param_arg("iterations").is_err());
        assert!(parse_param_arg("iterations=").is_err());
        assert!(parse_param_arg("=1").is_err());
    }

    #[test]
    fn scene_specs_are_rebuilt_with_the_value() {
        assert_eq!(
            scene_spec_with("cornell-sphere", "material", "gold").unwrap(),
            "cornell-sphere:material=gold"
        );
        assert_eq!(
            scene_spec_with(
                "cornell-sphere:sphere_x=0.2,material=mirror",
                "material",
                "gold"
            )
            .unwrap(),
            "cornell-sphere:material=gold,sphere_x=0.2"
        );
    }
}
