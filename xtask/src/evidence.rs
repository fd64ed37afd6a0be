//! `cargo xtask evidence CRATE [NAME...]`: a crate's measurements, regenerated from runs.
//!
//! A technique crate's README states findings; the figures behind them live in generated
//! files under `CRATE/docs/measured/`, one per run, never edited by hand. The runs are listed
//! in `CRATE/docs/measured/runs.txt`, one per line: a name, then the command
//!
//! ```text
//! # comment
//! against-distance-maps  harness compare --scenes chess --techniques height-maps --size 256x256
//! search-rates           cargo test -p rtapprox-height-maps --test search_properties -- --nocapture
//! ```
//!
//! - `harness ...` runs the test build's `harness` binary (the one `cargo xtask compare` runs,
//!   on the same driver) with `--out target/evidence/CRATE/NAME`; the references are shared by
//!   every run through one cache (`target/evidence/.cache`). The run's own markdown
//!   (`results.md` of compare, `sweep.md` of sweep, `bench.md` of bench: each says the
//!   command line, commit, date and adapter that made it) becomes `NAME.md`, and a sweep's
//!   plot `NAME.svg`.
//! - `cargo test ...` runs with the same driver; its standard output (the tables the test
//!   prints with `--nocapture`) becomes `NAME.md` under the command, commit and date.
//!
//! Every file starts with the line that regenerates it, and ends with its wall-clock time.
//! With NAMEs, only those runs; without, all of them in order. The files are written when the
//! last run has finished (or one has failed: then those of the runs before it), so that every
//! run finds the checkout as it was committed and says so (`git commit` without `-dirty`).
//! Run it on a committed checkout, and commit a crate's files before running another crate's
//! runs: a run that finds tracked files changed says `-dirty` (xtask warns before it starts).

use std::path::Path;
use std::process::{Command, ExitCode};
use std::time::Instant;

use crate::runs::{GENERATED_PREFIX, RUNS, Run, RunKind, parse_runs};

/// `cargo xtask evidence CRATE [NAME...]`.
pub(crate) fn evidence(rest: &[String]) -> ExitCode {
    let Some((krate, names)) = rest.split_first() else {
        eprintln!("usage: cargo xtask evidence CRATE [NAME...]   (runs CRATE/{RUNS})");
        return ExitCode::from(2);
    };
    let root = crate::workspace_root();
    let manifest = root.join(krate).join(RUNS);
    let runs = match std::fs::read_to_string(&manifest) {
        Ok(text) => parse_runs(&text),
        Err(e) => Err(format!("cannot read it: {e}")),
    };
    let runs = match runs {
        Ok(runs) => runs,
        Err(why) => {
            eprintln!("error: {}: {why}", manifest.display());
            return ExitCode::FAILURE;
        }
    };
    if let Some(unknown) = names.iter().find(|n| !runs.iter().any(|r| &r.name == *n)) {
        let known: Vec<&str> = runs.iter().map(|r| r.name.as_str()).collect();
        eprintln!(
            "error: {} has no run \"{unknown}\"; its runs are {}",
            manifest.display(),
            known.join(", ")
        );
        return ExitCode::FAILURE;
    }
    let harness = match crate::test_build().map(|a| crate::harness_of(&a)) {
        Ok(Some(h)) => h,
        Ok(None) => {
            eprintln!("error: the test build made no harness binary");
            return ExitCode::FAILURE;
        }
        Err(code) => return code,
    };
    if commit(&root).ends_with("-dirty") {
        eprintln!(
            "xtask: warning: tracked files have changed since the last commit; every file these \
             runs write will say -dirty (commit first for files that name their commit)"
        );
    }
    let docs = manifest
        .parent()
        .expect("the manifest is in a folder")
        .to_path_buf();
    // The driver once for every run (finding it may fetch it, and warns when it cannot).
    let driver = driver_env();
    let env: Vec<(&str, &std::ffi::OsStr)> =
        driver.iter().map(|(k, v)| (*k, v.as_os_str())).collect();
    let mut done = Vec::new();
    let mut failed = None;
    for run in runs
        .iter()
        .filter(|r| names.is_empty() || names.contains(&r.name))
    {
        match regenerate(&root, krate, &harness, run, &env) {
            Ok(output) => done.push(output),
            Err(why) => {
                failed = Some(format!("run {}: {why}", run.name));
                break;
            }
        }
    }
    let written = done.iter().try_for_each(|output| output.write(&docs));
    match (failed, written) {
        (None, Ok(())) => ExitCode::SUCCESS,
        (Some(why), _) | (None, Err(why)) => {
            eprintln!("error: {why}");
            ExitCode::FAILURE
        }
    }
}

/// What one run leaves for its crate's `docs/measured/`: `NAME.md` and a sweep's plot.
struct Output {
    name: String,
    markdown: String,
    plot: Option<std::path::PathBuf>,
}

impl Output {
    /// Writes `NAME.md` (and `NAME.svg`) into `docs`.
    fn write(&self, docs: &Path) -> Result<(), String> {
        if let Some(plot) = &self.plot {
            let to = docs.join(format!("{}.svg", self.name));
            std::fs::copy(plot, &to)
                .map_err(|e| format!("cannot copy {} to {}: {e}", plot.display(), to.display()))?;
        }
        let path = docs.join(format!("{}.md", self.name));
        std::fs::write(&path, &self.markdown)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        eprintln!("xtask: wrote {}", path.display());
        Ok(())
    }
}

/// The Vulkan driver the runs load: the one `cargo xtask compare` chooses, or none (the
/// caller's environment or the system's).
fn driver_env() -> Vec<(&'static str, std::ffi::OsString)> {
    crate::compare_driver()
        .map(|icd| ("VK_ICD_FILENAMES", icd.into_os_string()))
        .into_iter()
        .collect()
}

/// The driver files a run loads, as the harness's provenance names them.
fn drivers_named(env: &[(&str, &std::ffi::OsStr)]) -> String {
    env.first()
        .map(|(_, v)| v.to_string_lossy().into_owned())
        .or_else(|| {
            ["VK_DRIVER_FILES", "VK_ICD_FILENAMES"]
                .iter()
                .find_map(|k| std::env::var(k).ok().filter(|v| !v.is_empty()))
        })
        .unwrap_or_else(|| "system".into())
}

/// Runs `run`: its markdown and plot, not yet written.
fn regenerate(
    root: &Path,
    krate: &str,
    harness: &str,
    run: &Run,
    env: &[(&str, &std::ffi::OsStr)],
) -> Result<Output, String> {
    let started = Instant::now();
    let (body, plot) = match run.kind {
        RunKind::Harness => {
            let out = root.join("target/evidence").join(krate).join(&run.name);
            prepare_out(root, &out)?;
            let mut cmd = vec![harness.to_string()];
            cmd.extend(run.args.iter().cloned());
            cmd.extend(["--out".to_string(), out.to_string_lossy().into_owned()]);
            if crate::run_in(root, &cmd, env) != ExitCode::SUCCESS {
                return Err("the harness failed (above)".into());
            }
            let plot = Some(out.join("sweep.svg")).filter(|p| p.is_file());
            let page = run.harness_page().expect("a harness run");
            (harness_markdown(&out, page)?, plot)
        }
        RunKind::CargoTest => (test_markdown(root, run, env)?, None),
    };
    let seconds = started.elapsed().as_secs();
    let markdown = format!(
        "{GENERATED_PREFIX}{krate} {}` from {RUNS}; edits are lost when it runs again. \
         -->\n\n{body}\n_Wall clock of the run: {} min {} s._\n",
        run.name,
        seconds / 60,
        seconds % 60
    );
    Ok(Output {
        name: run.name.clone(),
        markdown,
        plot,
    })
}

/// An empty output folder whose reference cache is the one every evidence run shares.
fn prepare_out(root: &Path, out: &Path) -> Result<(), String> {
    let cache = root.join("target/evidence/.cache");
    let _ = std::fs::remove_dir_all(out);
    std::fs::create_dir_all(out)
        .and_then(|()| std::fs::create_dir_all(&cache))
        .and_then(|()| std::os::unix::fs::symlink(&cache, out.join(".cache")))
        .map_err(|e| format!("cannot prepare {}: {e}", out.display()))
}

/// The run's own markdown (compare's `results.md`, sweep's `sweep.md`, bench's `bench.md`).
fn harness_markdown(out: &Path, page: &str) -> Result<String, String> {
    let path = out.join(page);
    std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))
}

/// A test's standard output under the command, commit and date that made it.
fn test_markdown(
    root: &Path,
    run: &Run,
    env: &[(&str, &std::ffi::OsStr)],
) -> Result<String, String> {
    let mut cmd = vec![crate::cargo()];
    cmd.extend(run.args.iter().cloned());
    let output = crate::command_in(root, &cmd, env)
        .stderr(std::process::Stdio::inherit())
        .output()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if !output.status.success() {
        return Err(format!("`cargo {}` failed", run.args.join(" ")));
    }
    let drivers = drivers_named(env);
    Ok(format!(
        "# Test output\n\n- command line: cargo {}\n- git commit: {}\n- date (UTC): {}\n- Vulkan \
         drivers: {drivers}\n\n```text\n{}```\n",
        run.args.join(" "),
        commit(root),
        shell_line(root, "date", &["-u", "+%Y-%m-%dT%H:%M:%SZ"]),
        String::from_utf8_lossy(&output.stdout)
    ))
}

/// The checkout's commit, `-dirty` when a tracked file has changed (as the harness says it).
fn commit(root: &Path) -> String {
    let head = shell_line(root, "git", &["rev-parse", "HEAD"]);
    let changed = Command::new("git")
        .args(["status", "--porcelain", "--untracked-files=no"])
        .current_dir(root)
        .output()
        .is_ok_and(|o| !o.stdout.is_empty());
    if changed {
        format!("{head}-dirty")
    } else {
        head
    }
}

/// The first line a command prints, or "unknown".
fn shell_line(dir: &Path, program: &str, args: &[&str]) -> String {
    Command::new(program)
        .args(args)
        .current_dir(dir)
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .and_then(|s| s.lines().next().map(String::from))
        .unwrap_or_else(|| "unknown".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_are_named_commands() {
        let runs = parse_runs(
            "# a comment\n\n\
             steps  harness sweep --scene chess --technique height-maps/single --param steps=1,2\n\
             rates  cargo test -p x --test y -- --nocapture\n",
        )
        .unwrap();
        assert_eq!(runs.len(), 2);
        assert_eq!(runs[0].name, "steps");
        assert_eq!(runs[0].kind, RunKind::Harness);
        assert_eq!(runs[0].args[0], "sweep");
        assert_eq!(runs[1].kind, RunKind::CargoTest);
        assert_eq!(runs[1].args.last().unwrap(), "--nocapture");
    }

    #[test]
    fn bad_lines_are_refused_with_their_number() {
        let cases = [
            ("lonely\n", "line 1: a run is a name and a command"),
            ("a harness render --scene x\n", "line 1: the command is"),
            ("a/b harness compare\n", "line 1: a name is"),
            (
                "a harness compare\n\na harness bench\n",
                "line 3: the name is taken",
            ),
            ("a harness compare --out x\n", "line 1: xtask chooses --out"),
            ("a harness sweep --out=x\n", "line 1: xtask chooses --out"),
        ];
        for (text, why) in cases {
            let err = parse_runs(text).unwrap_err();
            assert!(err.starts_with(why), "{text:?}: {err}");
        }
    }
}
