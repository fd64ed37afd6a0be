//! A run as data: which rows (a scene, a technique with its parameters, a swept value), at which
//! size and frames, against which ground truth. `compare` and `sweep` build a plan and hand it
//! to [`crate::engine`], which executes it row by row; `--shard i/n` executes a slice of it and
//! `harness merge` joins the slices back.
//!
//! Everything that decides a row's figures is in the plan, so its [`Plan::key`] says whether
//! two runs measured the same thing: `--resume` keeps the rows of an earlier run only under the
//! same key and commit, and `merge` joins only shards of one plan.

use crate::report::Skipped;
use crate::{Frames, Size, file_name};
use anyhow::{Result, anyhow, bail};
use std::fmt;

/// A technique as a plan names it: `id`, or `id:name=value[:name=value...]` with parameters set
/// on a fresh instance.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TechniqueSpec {
    pub id: String,
    pub params: Vec<(String, f64)>,
}

impl TechniqueSpec {
    /// The technique `id` with its defaults.
    pub fn id(id: &str) -> Self {
        TechniqueSpec {
            id: id.to_string(),
            params: Vec::new(),
        }
    }

    /// Parses `id:name=value:name=value`.
    pub fn parse(spec: &str) -> Result<Self> {
        let mut parts = spec.split(':');
        let id = parts.next().unwrap_or_default().trim().to_string();
        let params = parts
            .map(|p| {
                let (name, value) = p.split_once('=').ok_or_else(|| {
                    anyhow!("technique parameter \"{p}\" in \"{spec}\" is not name=value")
                })?;
                let value: f64 = value.trim().parse().map_err(|_| {
                    anyhow!("technique parameter {name} in \"{spec}\": \"{value}\" is not a number")
                })?;
                Ok((name.trim().to_string(), value))
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(TechniqueSpec { id, params })
    }

    /// A fresh instance from `techniques` with the parameters set.
    pub fn instance(
        &self,
        techniques: &crate::TechniqueFactory,
    ) -> Result<Box<dyn scene::Technique>> {
        let mut technique = techniques()
            .into_iter()
            .find(|t| t.id() == self.id)
            .ok_or_else(|| {
                let ids: Vec<String> = techniques().iter().map(|t| t.id()).collect();
                match crate::select_techniques(&ids, Some(std::slice::from_ref(&self.id))) {
                    Err(e) => e,
                    // A family where one variant is needed.
                    Ok(variants) => anyhow!(
                        "\"{}\" is a family; name one of its variants: {}",
                        self.id,
                        variants.join(", ")
                    ),
                }
            })?;
        for (name, value) in &self.params {
            technique
                .set_param(name, *value)
                .map_err(|e| anyhow!(e).context(format!("technique {self}")))?;
        }
        Ok(technique)
    }
}

impl fmt::Display for TechniqueSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.id)?;
        for (name, value) in &self.params {
            write!(f, ":{name}={value}")?;
        }
        Ok(())
    }
}

/// A scene of a plan and where its images go.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PlannedScene {
    /// The spec it is loaded from (built-in spec or path).
    pub spec: String,
    /// The folder of its images, relative to the output folder (`images/cornell-sphere`).
    pub image_dir: String,
    /// The file stem of its references' images in that folder (`reference`).
    pub reference_stem: String,
    /// The swept value this scene is made with (a sweep over a scene parameter).
    pub value: Option<String>,
}

/// One row of a plan: a technique on a scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PlannedRow {
    /// The scene's spec (one of the plan's scenes).
    pub scene: String,
    pub technique: TechniqueSpec,
    /// The row's `technique` column: the spec (a sweep's: as given, without the swept value).
    pub label: String,
    /// The swept parameter and its value (sweep only).
    pub swept: Option<(String, String)>,
    /// The file stem of the row's images in the scene's image folder.
    pub image_stem: String,
}

impl PlannedRow {
    /// What identifies the row within its plan (and in a results file): scene, technique and
    /// swept value.
    pub fn key(&self) -> String {
        let value = self.swept.as_ref().map(|(_, v)| v.as_str()).unwrap_or("");
        format!("{} | {} | {value}", self.scene, self.label)
    }
}

/// Which command made a plan (and how its output is named).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PlanKind {
    /// `results.{csv,json,md}`, one image folder per scene.
    Compare,
    /// `sweep.{csv,json,md}`: one technique over the values of one parameter.
    Sweep(SweepInfo),
}

impl PlanKind {
    /// The stem of the run's table files: `results` or `sweep`.
    pub fn table_stem(&self) -> &'static str {
        match self {
            PlanKind::Compare => "results",
            PlanKind::Sweep(_) => "sweep",
        }
    }
}

/// What a sweep sweeps.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SweepInfo {
    /// The scene as given (before a scene parameter's value is set).
    pub scene: String,
    /// The technique spec as given (with the parameters fixed for the whole sweep).
    pub technique: String,
    pub param: String,
    pub owner: ParamOwner,
}

/// Whose parameter a sweep sweeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ParamOwner {
    Technique,
    Scene,
}

/// A whole run: its rows in order (grouped by scene), with what decides their figures.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plan {
    pub kind: PlanKind,
    pub size: Size,
    pub frames: Frames,
    /// The ground truth's key (renderer and options).
    pub ground_truth: String,
    /// The scenes, in the order they run.
    pub scenes: Vec<PlannedScene>,
    pub rows: Vec<PlannedRow>,
    /// (scene, technique) pairs the plan leaves out, with the reason.
    pub skipped: Vec<Skipped>,
}

impl Plan {
    /// A plan of `kind` with no scenes or rows yet: the builders (`compare::plan`,
    /// `sweep::plan`) add them.
    pub fn empty(kind: PlanKind, size: Size, frames: Frames, ground_truth: String) -> Self {
        Plan {
            kind,
            size,
            frames,
            ground_truth,
            scenes: Vec::new(),
            rows: Vec::new(),
            skipped: Vec::new(),
        }
    }

    /// The stem of the run's table files: `results` or `sweep`.
    pub fn table_stem(&self) -> &'static str {
        self.kind.table_stem()
    }

    /// A hash of everything that decides the run's figures (kind, size, frames, ground truth,
    /// scenes and rows in order, the harness version): equal keys measured the same thing.
    pub fn key(&self) -> String {
        let text = serde_json::to_string(self).unwrap_or_default();
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in text.bytes().chain(env!("CARGO_PKG_VERSION").bytes()) {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        format!("{h:016x}")
    }

    /// The index of the first row of scene `spec`, or for a scene without rows that of the
    /// next scene's first row (the number of rows past the last).
    fn scene_start(&self, spec: &str) -> usize {
        let from = self.scenes.iter().position(|s| s.spec == spec).unwrap_or(0);
        self.scenes[from..]
            .iter()
            .find_map(|s| self.rows.iter().position(|r| r.scene == s.spec))
            .unwrap_or(self.rows.len())
    }

    /// The scene of `spec`.
    pub fn scene(&self, spec: &str) -> Option<&PlannedScene> {
        self.scenes.iter().find(|s| s.spec == spec)
    }

    /// The rows of shard `shard`: a contiguous slice of the rows (so a scene's references are
    /// rendered by one or two shards, not by all), its scenes, and the skipped pairs of those
    /// scenes. The shards of a plan hold every row exactly once.
    pub fn shard(&self, shard: Shard) -> Plan {
        let n = self.rows.len();
        let (i, count) = (shard.index as usize - 1, shard.count as usize);
        let rows: Vec<PlannedRow> = self.rows[i * n / count..(i + 1) * n / count].to_vec();
        let range = i * n / count..(i + 1) * n / count;
        let owns_scene = |spec: &str| -> bool {
            // A scene belongs to the shard where its rows start (a scene without rows: where
            // the next scene's start), so that the shards' scenes, in shard order, are the
            // plan's in its order; past the last row, to the last shard.
            let at = self.scene_start(spec);
            range.contains(&at) || (at == n && i + 1 == count)
        };
        let scenes = self
            .scenes
            .iter()
            .filter(|s| rows.iter().any(|r| r.scene == s.spec) || owns_scene(&s.spec))
            .cloned()
            .collect();
        let skipped = self
            .skipped
            .iter()
            .filter(|s| owns_scene(&s.scene))
            .cloned()
            .collect();
        Plan {
            rows,
            scenes,
            skipped,
            ..self.clone()
        }
    }
}

/// One of `count` slices of a plan, `index` from 1: `--shard 2/4`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("\"{s}\" is not a shard; expected I/N with 1 <= I <= N, e.g. 2/4");
        let (i, n) = s.trim().split_once('/').ok_or_else(bad)?;
        let (index, count): (u32, u32) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if index == 0 || index > count || count > Shard::MAX_COUNT {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    /// Most shards a plan splits into.
    pub const MAX_COUNT: u32 = 100_000;
}

/// The image folders of a run's scenes, unique within the run (see [`crate::scene_dir_names`]).
pub fn compare_image_dirs(specs: &[String]) -> Vec<String> {
    crate::scene_dir_names(specs)
        .into_iter()
        .map(|d| format!("images/{d}"))
        .collect()
}

/// The file stem of a technique's images in a compare's scene folder.
pub fn compare_image_stem(technique: &TechniqueSpec) -> String {
    file_name(&technique.to_string())
}

/// Fails when `rows` name one row twice (the tables could not tell them apart).
pub fn check_unique(rows: &[PlannedRow]) -> Result<()> {
    let mut keys: Vec<String> = rows.iter().map(PlannedRow::key).collect();
    keys.sort();
    if let Some(w) = keys.windows(2).find(|w| w[0] == w[1]) {
        bail!("the run names one row twice: {}", w[0]);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(rows_per_scene: &[usize]) -> Plan {
        let mut scenes = Vec::new();
        let mut rows = Vec::new();
        let mut skipped = Vec::new();
        for (s, &n) in rows_per_scene.iter().enumerate() {
            let spec = format!("scene-{s}");
            scenes.push(PlannedScene {
                spec: spec.clone(),
                image_dir: format!("images/{spec}"),
                reference_stem: "reference".into(),
                value: None,
            });
            skipped.push(Skipped {
                scene: spec.clone(),
                technique: "x".into(),
                reason: "no".into(),
            });
            for r in 0..n {
                rows.push(PlannedRow {
                    scene: spec.clone(),
                    technique: TechniqueSpec::id(&format!("t/{r}")),
                    label: format!("t/{r}"),
                    swept: None,
                    image_stem: format!("t__{r}"),
                });
            }
        }
        Plan {
            kind: PlanKind::Compare,
            size: Size::new(8, 8),
            frames: Frames::default(),
            ground_truth: "test".into(),
            scenes,
            rows,
            skipped,
        }
    }

    #[test]
    fn shards_hold_every_row_once_and_the_scenes_they_need() {
        let plan = plan(&[5, 0, 3, 4]);
        for count in 1..=13 {
            let shards: Vec<Plan> = (1..=count)
                .map(|index| plan.shard(Shard { index, count }))
                .collect();
            let rows: Vec<PlannedRow> = shards.iter().flat_map(|s| s.rows.clone()).collect();
            assert_eq!(rows, plan.rows, "{count} shards");
            let skipped: Vec<Skipped> = shards.iter().flat_map(|s| s.skipped.clone()).collect();
            assert_eq!(
                skipped, plan.skipped,
                "{count} shards: each skip once, in order"
            );
            for s in &shards {
                for r in &s.rows {
                    assert!(s.scene(&r.scene).is_some(), "a shard has its rows' scenes");
                }
                if count > 1 {
                    assert_ne!(s.key(), plan.key(), "a shard is not the plan");
                }
            }
        }
    }

    #[test]
    fn a_shard_is_i_of_n() {
        assert_eq!("2/4".parse::<Shard>(), Ok(Shard { index: 2, count: 4 }));
        assert_eq!(" 1 / 1 ".parse::<Shard>(), Ok(Shard { index: 1, count: 1 }));
        for bad in ["0/4", "5/4", "4", "a/b", "1/0", "-1/4", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
        assert_eq!(Shard { index: 3, count: 8 }.to_string(), "3/8");
    }

    #[test]
    fn technique_specs_parse_and_print() {
        let spec = TechniqueSpec::parse("volumes/billboard:depth_prepass=1:x=0.5").unwrap();
        assert_eq!(spec.id, "volumes/billboard");
        assert_eq!(
            spec.params,
            vec![("depth_prepass".into(), 1.0), ("x".into(), 0.5)]
        );
        assert_eq!(spec.to_string(), "volumes/billboard:depth_prepass=1:x=0.5");
        assert_eq!(
            TechniqueSpec::parse("raster").unwrap(),
            TechniqueSpec::id("raster")
        );
        assert!(TechniqueSpec::parse("a:b").is_err());
        assert!(TechniqueSpec::parse("a:b=x").is_err());
    }

    #[test]
    fn the_key_follows_what_decides_the_figures() {
        let a = plan(&[2, 1]);
        assert_eq!(a.key(), plan(&[2, 1]).key());
        let mut b = a.clone();
        b.frames.errors = 5;
        assert_ne!(a.key(), b.key());
        let mut c = a.clone();
        c.rows.swap(0, 1);
        assert_ne!(a.key(), c.key());
        assert!(check_unique(&a.rows).is_ok());
        let mut twice = a.rows.clone();
        twice.push(a.rows[0].clone());
        assert!(check_unique(&twice).is_err());
    }
}
