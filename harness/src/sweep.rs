//! `harness sweep`: one technique on one scene over the values of one parameter, as a plan the
//! engine executes ([`crate::engine`]). The technique may be given with other parameters fixed
//! for the whole sweep, as `bench` takes it: `--technique id:name=value:name=value`.
//!
//! The parameter is looked up first among the technique's declared parameters
//! (`Technique::params`, set with `set_param` on a fresh instance per value), then among the
//! built-in scene's declared parameters (the scene spec is rebuilt with `NAME=value`, so the
//! reference is rendered, and cached, per value). Every value is checked before any GPU work.
//!
//! Writes `sweep.csv` (the compare columns plus `param` and `value`), `sweep.json`, `sweep.md`,
//! `sweep.svg` (the report's figures, [`crate::plot`]) and `images/<technique>__<param>=<value>.{png,exr,flip.png}`
//! (with `images/reference__<param>=<value>.{png,exr}` for a scene parameter, or
//! `images/reference.{png,exr}` for a technique parameter), each at the first error frame; the
//! later error frames along the camera path add `.t<time>.png` and `.t<time>.flip.png` (see
//! [`crate::time_suffix`]); beside every PNG its HDR copy `.hdr.js` for the report,
//! `index.html` (see [`crate::html`]). Error figures are measured along the path as in
//! `compare`.

use crate::engine::{self, ExecOptions};
use crate::model::RunReport;
use crate::plan::{ParamOwner, Plan, PlanKind, PlannedRow, PlannedScene, SweepInfo, TechniqueSpec};
use crate::{Env, Frames, Size, file_name};
use anyhow::{Context as _, Result, anyhow, bail};

#[derive(Clone, Debug)]
pub struct SweepOptions {
    pub scene: String,
    pub technique: String,
    pub param: String,
    pub values: Vec<String>,
    pub size: Size,
    pub frames: Frames,
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

/// The built-in scene spec with `name=value` set.
fn scene_spec_with(spec: &str, name: &str, value: &str) -> Result<String> {
    let (scene_name, mut params) = scene::builtin::parse_spec(spec)?;
    params.insert(name.to_string(), value.to_string());
    let kv: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    Ok(format!("{scene_name}:{}", kv.join(",")))
}

/// The declared parameters of a built-in scene spec (none for a file).
fn scene_params(spec: &str) -> Result<Vec<&'static str>> {
    if crate::is_scene_path(spec) {
        return Ok(Vec::new());
    }
    let (name, _) = scene::builtin::parse_spec(spec)?;
    Ok(scene::builtin::builtin_scenes()
        .into_iter()
        .find(|s| s.name == name)
        .map(|s| s.params.iter().map(|p| p.name).collect())
        .unwrap_or_default())
}

/// Whose parameter `param` is: the technique's first, then the scene's; an error naming both
/// lists when neither has it.
fn owner(technique: &dyn scene::Technique, scene: &str, param: &str) -> Result<ParamOwner> {
    let of_technique: Vec<&str> = technique.params().iter().map(|p| p.name).collect();
    if of_technique.contains(&param) {
        return Ok(ParamOwner::Technique);
    }
    let of_scene = scene_params(scene)?;
    if of_scene.contains(&param) {
        return Ok(ParamOwner::Scene);
    }
    let list = |names: &[&str]| match names.is_empty() {
        true => "none".to_string(),
        false => names.join(", "),
    };
    bail!(
        "neither technique {} (parameters: {}) nor scene {scene} (parameters: {}) has a parameter \"{param}\"",
        technique.id(),
        list(&of_technique),
        list(&of_scene)
    )
}

/// The technique of the sweep: its spec as given, resolved to one registered id.
fn technique_spec(env: &Env, given: &str) -> Result<TechniqueSpec> {
    let spec = TechniqueSpec::parse(given)?;
    let all_ids: Vec<String> = (env.techniques)().iter().map(|t| t.id()).collect();
    let ids = crate::select_techniques(&all_ids, Some(std::slice::from_ref(&spec.id)))?;
    let [id] = ids.as_slice() else {
        bail!(
            "\"{given}\" names several techniques ({}); give one id",
            ids.join(", ")
        );
    };
    Ok(TechniqueSpec {
        id: id.clone(),
        ..spec
    })
}

/// The plan of a sweep: one row per value, every value checked first (technique values parse
/// and are in range, scene values make a valid scene).
pub fn plan(env: &Env, opts: &SweepOptions) -> Result<Plan> {
    let fixed = technique_spec(env, &opts.technique)?;
    crate::load_scene_noted(&opts.scene)?;
    let probe = fixed.instance(env.techniques)?;
    let owner = owner(probe.as_ref(), &opts.scene, &opts.param)?;
    env.ctx
        .require(probe.required_features())
        .with_context(|| format!("technique {}", fixed.id))?;
    let info = SweepInfo {
        scene: opts.scene.clone(),
        technique: opts.technique.clone(),
        param: opts.param.clone(),
        owner,
    };
    let mut plan = Plan::empty(
        PlanKind::Sweep(info),
        opts.size,
        opts.frames,
        env.ground_truth.key(),
    );
    if owner == ParamOwner::Technique {
        plan.scenes
            .push(sweep_scene(opts.scene.clone(), "reference".into(), None));
    }
    for value in &opts.values {
        let suffix = format!("{}={value}", opts.param);
        let (scene, technique) = match owner {
            ParamOwner::Technique => (
                opts.scene.clone(),
                with_value(env, &fixed, &opts.param, value)?,
            ),
            ParamOwner::Scene => {
                let spec = scene_spec_with(&opts.scene, &opts.param, value)?;
                crate::load_scene(&spec)?;
                let stem = format!("reference__{}", file_name(&suffix));
                plan.scenes
                    .push(sweep_scene(spec.clone(), stem, Some(value.clone())));
                (spec, fixed.clone())
            }
        };
        plan.rows.push(PlannedRow {
            scene,
            label: opts.technique.clone(),
            image_stem: format!("{}__{}", file_name(&fixed.id), file_name(&suffix)),
            technique,
            swept: Some((opts.param.clone(), value.clone())),
        });
    }
    crate::plan::check_unique(&plan.rows)?;
    Ok(plan)
}

fn sweep_scene(spec: String, reference_stem: String, value: Option<String>) -> PlannedScene {
    PlannedScene {
        spec,
        image_dir: "images".into(),
        reference_stem,
        value,
    }
}

/// The fixed technique spec with the swept parameter at `value`, checked on an instance.
fn with_value(env: &Env, fixed: &TechniqueSpec, param: &str, value: &str) -> Result<TechniqueSpec> {
    let v: f64 = value
        .parse()
        .map_err(|_| anyhow!("{param}={value} is not a number"))?;
    let mut spec = fixed.clone();
    spec.params.retain(|(name, _)| name != param);
    spec.params.push((param.to_string(), v));
    spec.instance(env.techniques)?;
    Ok(spec)
}

/// Runs the sweep (see the module documentation) and writes every file.
pub fn run(env: &Env, opts: &SweepOptions, exec: &ExecOptions) -> Result<RunReport> {
    let plan = plan(env, opts)?;
    engine::execute(env, &plan, exec)
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
