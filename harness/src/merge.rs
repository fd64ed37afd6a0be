//! `harness merge`: the output folders of the shards of one plan (`compare --shard i/n`, run as
//! the tasks of a Slurm job array or a CI matrix) joined into one folder, the same as the
//! unsharded run would have written: the rows in plan order, every shard's images, the
//! speed-ups and Pareto views computed again over each scene's whole set of rows, then every
//! table, plot and `index.html` written by the same writers.
//!
//! The shards must be of one plan (the same [`crate::plan::Plan::key`]: scenes, techniques,
//! size, frames, reference options), of one commit and one adapter (timings from different
//! GPUs do not compare), and together complete: 1/n to n/n, each once.

use crate::model::RunReport;
use crate::output::Output;
use anyhow::{Context as _, Result, bail};
use std::path::{Path, PathBuf};

/// The report of a shard's folder (`results.json`, or `sweep.json` for a sweep).
fn read_shard(dir: &Path) -> Result<RunReport> {
    let path = ["results.json", "sweep.json"]
        .iter()
        .map(|f| dir.join(f))
        .find(|p| p.is_file());
    let Some(path) = path else {
        bail!(
            "{} holds no results.json or sweep.json: is it the --out folder of a shard?",
            dir.display()
        );
    };
    RunReport::read(&path)
}

/// The shards in order, checked to be the complete set of one plan's shards.
fn read_shards(dirs: &[PathBuf]) -> Result<Vec<(PathBuf, RunReport)>> {
    let mut shards: Vec<(PathBuf, RunReport)> = dirs
        .iter()
        .map(|d| read_shard(d).map(|r| (d.clone(), r)))
        .collect::<Result<_>>()?;
    let Some((first_dir, first)) = shards.first() else {
        bail!("merge needs the folders of a plan's shards");
    };
    let (key, commit, adapter) = (
        first.plan_key.clone(),
        first.provenance.git_commit.clone(),
        first.adapter.name.clone(),
    );
    let Some(count) = first.shard.map(|s| s.count) else {
        bail!(
            "{} is not a shard (its run had no --shard); nothing to merge",
            first_dir.display()
        );
    };
    for (dir, r) in &shards {
        let why = if r.plan_key != key {
            "is a shard of another plan (other scenes, techniques, size, frames or reference options)"
        } else if r.provenance.git_commit != commit {
            "was made by another commit"
        } else if r.adapter.name != adapter {
            "was measured on another adapter (its timings would not compare)"
        } else if r.shard.is_none_or(|s| s.count != count) {
            "is not one of the same number of shards"
        } else {
            continue;
        };
        bail!(
            "{} {why} than {}; merge only the shards of one run",
            dir.display(),
            first_dir.display()
        );
    }
    shards.sort_by_key(|(_, r)| r.shard.map(|s| s.index));
    let indices: Vec<u32> = shards
        .iter()
        .filter_map(|(_, r)| r.shard.map(|s| s.index))
        .collect();
    if indices != (1..=count).collect::<Vec<u32>>() {
        bail!("the shards given are {indices:?} of {count}; merge needs each of 1..={count} once");
    }
    Ok(shards)
}

/// Copies `from` into `to`, folders included, files that exist already replaced.
fn copy_tree(from: &Path, to: &Path) -> Result<()> {
    if !from.is_dir() {
        return Ok(());
    }
    std::fs::create_dir_all(to).with_context(|| format!("cannot create {}", to.display()))?;
    for entry in
        std::fs::read_dir(from).with_context(|| format!("cannot read {}", from.display()))?
    {
        let entry = entry?;
        let target = to.join(entry.file_name());
        if entry.file_type()?.is_dir() {
            copy_tree(&entry.path(), &target)?;
        } else {
            std::fs::copy(entry.path(), &target)
                .with_context(|| format!("cannot copy {}", entry.path().display()))?;
        }
    }
    Ok(())
}

/// Joins `shards` into `out` (see the module documentation) and returns the merged report.
pub fn merge(shards: &[PathBuf], out: &Path) -> Result<RunReport> {
    let shards = read_shards(shards)?;
    let _lock = crate::OutputLock::acquire(out)?;
    let mut merged: Option<RunReport> = None;
    for (dir, shard) in shards {
        for folder in ["images", ".cache"] {
            copy_tree(&dir.join(folder), &out.join(folder))?;
        }
        match merged.as_mut() {
            None => merged = Some(shard),
            Some(m) => append(m, shard),
        }
    }
    let mut report = merged.expect("at least one shard");
    report.shard = None;
    report.pareto.clear();
    report.provenance.command_line =
        crate::provenance::Provenance::capture(String::new()).command_line;
    let output = Output::new(out, report.kind.table_stem());
    if report.sweep().is_none() {
        pareto_again(&mut report, out)?;
    }
    output.write_sweep_plot(&report)?;
    output.write_all(&report)?;
    Ok(report)
}

/// A later shard's report after the earlier ones'. A scene split between two shards has its
/// references (and their images) in both: kept once.
fn append(m: &mut RunReport, s: RunReport) {
    m.rows.extend(s.rows);
    m.skipped.extend(s.skipped);
    for r in s.references {
        if !m
            .references
            .iter()
            .any(|x| x.scene == r.scene && x.time == r.time)
        {
            m.references.push(r);
        }
    }
    for w in s.images {
        if !m.images.contains(&w) {
            m.images.push(w);
        }
    }
    for w in s.scene_walls {
        if !m.scene_walls.iter().any(|x| x.scene == w.scene) {
            m.scene_walls.push(w);
        }
    }
    m.image_dirs.extend(s.image_dirs);
    for n in s.scene_notes {
        if !m.scene_notes.contains(&n) {
            m.scene_notes.push(n);
        }
    }
    m.errors.extend(s.errors);
    m.panics.extend(s.panics);
}

/// Every scene's speed-ups and Pareto view over all its rows, as the unsharded run sets them.
fn pareto_again(report: &mut RunReport, out: &Path) -> Result<()> {
    let mut scenes: Vec<String> = report.rows.iter().map(|r| r.scene.clone()).collect();
    scenes.dedup();
    let adapter = report.adapter.name.clone();
    for spec in scenes {
        let first = report
            .rows
            .iter()
            .position(|r| r.scene == spec)
            .unwrap_or(0);
        let end = first
            + report.rows[first..]
                .iter()
                .take_while(|r| r.scene == spec)
                .count();
        let dir_name = report.image_dirs.get(&spec).cloned().unwrap_or_default();
        let (points, warning) = crate::output::write_pareto_scene(
            out,
            &spec,
            &dir_name,
            &mut report.rows[first..end],
            &adapter,
        )?;
        if let Some(w) = warning {
            eprintln!("warning: {w}");
        }
        report.pareto.push(points);
    }
    Ok(())
}
