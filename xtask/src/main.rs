//! `cargo xtask test` and `cargo xtask compare` (the alias is in `.cargo/config.toml`).
//!
//! Both first make sure the machine can build and run the workspace:
//!
//! - a Vulkan driver: an ICD manifest (`*.json` in `/usr/share/vulkan/icd.d`,
//!   `/etc/vulkan/icd.d` or `/usr/local/share/vulkan/icd.d`) and the loader `libvulkan.so.1`
//!   (`ldconfig -p`); Debian packages `mesa-vulkan-drivers libvulkan1` (lavapipe);
//! - what the native build steps need: a C++ compiler (`nv-flip` builds FLIP from C++);
//!   package `g++` (the plots are SVG text: no font or font library is needed);
//! - for `test` only: headless Chromium (Debian package `chromium`), which opens the HTML
//!   report in `harness/tests/report_browser.rs`; the tests run with
//!   `HARNESS_BROWSER_TEST=require`, so that test fails rather than skips without it.
//!
//! When something required is missing and we run as root on a system with `apt-get`, it runs
//! `apt-get update` and `apt-get install -y ...` (DEBIAN_FRONTEND=noninteractive). Otherwise it
//! prints the exact command to run and exits with status 1.
//!
//! Then, with `NODEVICE_SELECT=1` (silences Mesa's device-select layer), it runs
//!
//! - `test`: `cargo fmt --all --check` (the style of `rustfmt.toml`), then
//!   `cargo test --workspace [ARGS...]` (every member: unit, integration and doc tests; `-p
//!   NAME` in ARGS replaces `--workspace`). A full run builds the test targets (timed), runs
//!   every test executable with each test timed and lists the slowest (`runner`), on the
//!   driver `compare` uses (on a machine without a GPU, Mesa 25's lavapipe from
//!   bookworm-backports, fetched into `target/mesa-backports` without installing it: faster
//!   than Debian 12's Mesa 22.3 and without its memory growth; the system's where
//!   it cannot be fetched, or where `VK_ICD_FILENAMES` is set); checks that the build
//!   `compare` uses is exactly this one (`cargo test --workspace --no-run` reports every
//!   artifact fresh) and fails naming what would be compiled otherwise. The tests that must
//!   not skip on Mesa 25 ([`ON_MESA_25`]: hardware ray queries, the 50-frame memory test,
//!   every declared image check) run
//!   with their `require` variables set: in the suite when it ran on Mesa 25, otherwise again
//!   there after it (skipped, saying why, where it cannot be fetched);
//! - `ray-query`: that last step alone;
//! - `compare`: the same test build (`cargo test --workspace --no-run`: nothing to compile
//!   after `cargo xtask test`), then the `harness` binary it contains: `harness compare --out
//!   out [ARGS...]` (`--out DIR` in ARGS replaces `--out out`), run in the folder `cargo
//!   xtask` was run from, so paths in ARGS (`--scenes my.glb`, `--out`) are the user's; the
//!   default `out/` is the workspace root's wherever that is. `cargo run -p rtapprox-harness` would
//!   unify features over the harness's dependencies alone and recompile the wgpu stack (3-6
//!   min on the 2-core machine). The dev profile optimizes the dependencies and the `truth`
//!   and `scene` crates at opt-level 3 (the CPU reference and its BVH, FLIP, wgpu), so it runs
//!   as fast as a release build for this job (see the README for the measurements).
//!   `cargo xtask compare --release` builds and runs a release harness instead.
//! - `evidence CRATE [NAME...]`: the same test build's `harness` (and `cargo test` for test
//!   runs) over the runs of `CRATE/docs/measured/runs.txt`, each written to
//!   `CRATE/docs/measured/NAME.md` ([`evidence`]).
//!
//! Every command is printed before it runs; the exit status is the child's.

mod evidence;
mod runner;
mod runs;

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

const ICD_DIRS: &[&str] = &[
    "/usr/share/vulkan/icd.d",
    "/etc/vulkan/icd.d",
    "/usr/local/share/vulkan/icd.d",
];

fn usage() -> ExitCode {
    eprintln!(
        "usage: cargo xtask <test|compare|ray-query|evidence> [ARGS...]\n\
         \x20 test      cargo test --workspace [ARGS...], every test on Mesa 25's lavapipe where there is no GPU\n\
         \x20 compare   harness compare --out out [ARGS...] on the test build   (--release for a release build)\n\
         \x20 ray-query the tests that must run on Mesa 25's lavapipe (ray queries, flat memory, every image check), alone\n\
         \x20 evidence  CRATE [NAME...]: the runs of CRATE/docs/measured/runs.txt, each into CRATE/docs/measured/NAME.md"
    );
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let Some(job) = args.next() else {
        return usage();
    };
    let rest: Vec<String> = args.collect();
    let release = rest.iter().any(|a| a == "--release");
    let command = match job.as_str() {
        "test" => test_command(&rest),
        "compare" if release => compare_command(&rest),
        "compare" | "ray-query" | "evidence" => Vec::new(),
        "-h" | "--help" | "help" => {
            usage();
            return ExitCode::SUCCESS;
        }
        other => {
            eprintln!("error: unknown job \"{other}\"");
            return usage();
        }
    };
    if let Err(code) = ensure_prerequisites(&job) {
        return code;
    }
    match job.as_str() {
        "test" => {
            let status = check_format();
            if status != ExitCode::SUCCESS {
                return status;
            }
            if !runs_everything(&rest) {
                return run(&command);
            }
            timed_tests(&rest)
        }
        "compare" if !release => compare_with_test_build(&rest),
        "evidence" => evidence::evidence(&rest),
        "ray-query" => match test_build() {
            Ok(artifacts) => tests_on_backported_lavapipe(&artifacts),
            Err(code) => code,
        },
        // `compare --release`: cargo finds the workspace from the user's folder too.
        _ => match compare_driver() {
            Some(icd) => run_in(
                &user_dir(),
                &command,
                &[("VK_ICD_FILENAMES", icd.as_os_str())],
            ),
            None => run_in(&user_dir(), &command, &[]),
        },
    }
}

/// `CARGO_INCREMENTAL` for every cargo command xtask runs, whatever the caller's shell says:
/// the flag is part of every crate's fingerprint, so a `test` run with one setting and a
/// `compare` with the other would recompile every crate of the workspace (it did, in a fresh
/// clone, for a `compare` run after `.ci/run`'s `test`). Off, because the workspace is
/// built once per run and incremental artifacts only add gigabytes to CI's disk.
const ONE_BUILD_INCREMENTAL: &str = "0";

/// The build `cargo xtask test` makes and `cargo xtask compare` reuses: every test target of
/// the workspace, which includes the `harness` binary built with the workspace's unified
/// features (`cargo run -p rtapprox-harness` would unify features over harness's dependencies only
/// and recompile the wgpu stack).
fn test_build_command() -> Vec<String> {
    [
        cargo().as_str(),
        "test",
        "--workspace",
        "--no-run",
        "--message-format=json-render-diagnostics",
    ]
    .map(String::from)
    .to_vec()
}

/// The artifacts of a `--message-format=json` build: (package, target name, kinds, fresh,
/// executable).
struct Artifact {
    package: String,
    name: String,
    bin: bool,
    test_profile: bool,
    fresh: bool,
    executable: Option<String>,
    /// The folder of the package's Cargo.toml (where cargo runs its tests).
    dir: PathBuf,
}

/// Pulls the few fields we need out of cargo's JSON messages (one object per line) without a
/// JSON dependency: `"key":value` of the first occurrence after a marker.
fn json_field<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    let start = line.find(&format!("\"{key}\":"))? + key.len() + 3;
    let rest = &line[start..];
    if let Some(stripped) = rest.strip_prefix('"') {
        stripped.find('"').map(|end| &stripped[..end])
    } else {
        let end = rest.find([',', '}']).unwrap_or(rest.len());
        Some(&rest[..end])
    }
}

fn parse_artifacts(stdout: &str) -> Vec<Artifact> {
    stdout
        .lines()
        .filter(|l| l.contains("\"reason\":\"compiler-artifact\""))
        .map(|l| {
            let target = &l[l.find("\"target\":").unwrap_or(0)..];
            let profile = &l[l.find("\"profile\":").unwrap_or(0)..];
            Artifact {
                package: json_field(l, "package_id").unwrap_or("?").to_string(),
                name: json_field(target, "name").unwrap_or("?").to_string(),
                bin: json_field(target, "kind").is_some_and(|k| k.starts_with("[\"bin\"")),
                test_profile: json_field(profile, "test") == Some("true"),
                fresh: json_field(l, "fresh") == Some("true"),
                executable: json_field(l, "executable")
                    .filter(|e| *e != "null")
                    .map(String::from),
                dir: json_field(l, "manifest_path")
                    .map(|m| {
                        Path::new(m)
                            .parent()
                            .unwrap_or(Path::new("."))
                            .to_path_buf()
                    })
                    .unwrap_or_else(workspace_root),
            }
        })
        .collect()
}

/// Runs the test build and returns its artifacts (cargo's diagnostics go to stderr).
fn test_build() -> Result<Vec<Artifact>, ExitCode> {
    let cmd = test_build_command();
    print_command(&cmd);
    let output = Command::new(&cmd[0])
        .args(&cmd[1..])
        .current_dir(workspace_root())
        .env("CARGO_INCREMENTAL", ONE_BUILD_INCREMENTAL)
        .stderr(std::process::Stdio::inherit())
        .output()
        .map_err(|e| {
            eprintln!("error: cannot run {}: {e}", cmd[0]);
            ExitCode::FAILURE
        })?;
    if !output.status.success() {
        return Err(ExitCode::FAILURE);
    }
    Ok(parse_artifacts(&String::from_utf8_lossy(&output.stdout)))
}

/// Whether `cargo xtask test ARGS` runs every test of the workspace (ARGS only after `--`, for
/// the test executables): then the timed runner runs them; otherwise `cargo test ARGS`.
fn runs_everything(rest: &[String]) -> bool {
    rest.first().is_none_or(|a| a == "--")
}

/// The full test run: the test build, every test executable with each test timed (see
/// `runner`), the doc tests, the check that `compare` reuses this build, the tests that run on
/// Mesa 25's lavapipe, and the slowest tests listed.
fn timed_tests(rest: &[String]) -> ExitCode {
    let build_start = std::time::Instant::now();
    let artifacts = match test_build() {
        Ok(a) => a,
        Err(code) => return code,
    };
    eprintln!(
        "xtask: the test build took {:.0} s",
        build_start.elapsed().as_secs_f64()
    );
    let args: Vec<String> = rest.iter().skip(1).cloned().collect();
    let driver = compare_driver().map(|icd| icd.to_string_lossy().into_owned());
    let mut env: Vec<(&str, &str)> = TEST_ENV.to_vec();
    if let Some(icd) = &driver {
        eprintln!("xtask: the tests run on the driver compare uses: VK_ICD_FILENAMES={icd}");
        env.push(("VK_ICD_FILENAMES", icd));
        // Mesa 25's lavapipe: the tests that must not skip there are told so in this run.
        env.extend(
            ON_MESA_25
                .iter()
                .map(|(_, _, _, require)| (*require, "require")),
        );
    }
    let jobs = test_jobs();
    let times = workspace_root().join(TEST_TIMES);
    eprintln!("xtask: {jobs} test executables at a time (XTASK_TEST_JOBS; 1 runs them one by one)");
    let start = std::time::Instant::now();
    let (mut ok, mut summary) = runner::run_all(
        test_executables(&artifacts),
        &args,
        &env,
        jobs,
        &runner::read_times(&times),
    );
    eprintln!(
        "xtask: the test executables took {:.0} s",
        start.elapsed().as_secs_f64()
    );
    // Only a whole run's times order the next run (a filtered run's are those of its filter).
    if args.is_empty()
        && let Err(e) = std::fs::write(&times, summary.times_text())
    {
        eprintln!(
            "xtask: cannot keep the executables' times in {}: {e}",
            times.display()
        );
    }
    let doc = [cargo(), "test".into(), "--workspace".into(), "--doc".into()];
    let start = std::time::Instant::now();
    let doc_env: Vec<(&str, &std::ffi::OsStr)> = driver
        .iter()
        .map(|icd| ("VK_ICD_FILENAMES", std::ffi::OsStr::new(icd.as_str())))
        .collect();
    ok &= run_with(&doc, &doc_env) == ExitCode::SUCCESS;
    summary.executables.push((
        "doc tests (cargo test --doc)".into(),
        start.elapsed().as_secs_f64(),
    ));
    eprint!("{}", runner::report(&summary, 15));
    if !ok {
        eprintln!("error: failed: {}", summary.failed.join("; "));
        return ExitCode::FAILURE;
    }
    let artifacts = match test_build() {
        Ok(a) => a,
        Err(code) => return code,
    };
    let status = check_compare_build_is_fresh(&artifacts);
    if status != ExitCode::SUCCESS || driver.is_some() {
        // On Mesa 25's lavapipe the suite has run the ON_MESA_25 tests with `require` already.
        return status;
    }
    tests_on_backported_lavapipe(&artifacts)
}

/// Where the test run keeps each executable's wall-clock time, for the next run's longest-first
/// order.
const TEST_TIMES: &str = "target/xtask-test-times.tsv";

/// How many test executables run at a time: `XTASK_TEST_JOBS`, else the machine's cores.
fn test_jobs() -> usize {
    std::env::var("XTASK_TEST_JOBS")
        .ok()
        .and_then(|v| v.parse().ok())
        .or_else(|| std::thread::available_parallelism().ok().map(|n| n.get()))
        .unwrap_or(1)
        .max(1)
}

/// What every test runs with: the device-select layer quiet, and the HTML report's browser
/// test failing rather than skipping without Chromium (the `test` job installed it).
const TEST_ENV: [(&str, &str); 2] = [
    ("NODEVICE_SELECT", "1"),
    ("HARNESS_BROWSER_TEST", "require"),
];

/// A package's name from its id: `path+file:///w/harness#0.1.0` (the folder's name) or
/// `path+file:///w/tests#workspace-tests@0.1.0`.
fn package_name(id: &str) -> &str {
    match id.rsplit_once('#') {
        Some((_, name_version)) if name_version.contains('@') => {
            name_version.split('@').next().unwrap_or(id)
        }
        Some((path, _)) => path.rsplit('/').next().unwrap_or(id),
        None => id,
    }
}

/// The test executables of the build, in cargo's order.
fn test_executables(artifacts: &[Artifact]) -> Vec<runner::TestExecutable> {
    artifacts
        .iter()
        .filter(|a| a.test_profile)
        .filter_map(|a| {
            let package = package_name(&a.package);
            Some(runner::TestExecutable {
                name: format!("{package}/{}", a.name),
                path: a.executable.clone()?,
                dir: a.dir.clone(),
            })
        })
        .collect()
}

/// `compare`: the test build (nothing to compile right after `cargo xtask test`), then the
/// `harness` binary it contains, `harness compare --out out ARGS`.
fn compare_with_test_build(rest: &[String]) -> ExitCode {
    let artifacts = match test_build() {
        Ok(a) => a,
        Err(code) => return code,
    };
    let compiled: Vec<&str> = artifacts
        .iter()
        .filter(|a| !a.fresh)
        .map(|a| a.name.as_str())
        .collect();
    eprintln!(
        "xtask: the test build compiled {} target(s){}",
        compiled.len(),
        if compiled.is_empty() {
            " (it was up to date)".to_string()
        } else {
            format!(": {}", compiled.join(", "))
        }
    );
    let Some(harness) = harness_of(&artifacts) else {
        eprintln!("error: the test build made no harness binary");
        return ExitCode::FAILURE;
    };
    let mut cmd = vec![harness, "compare".to_string()];
    if !has_flag(rest, &["--out"]) {
        cmd.extend(["--out".to_string(), default_out()]);
    }
    cmd.extend(rest.iter().cloned());
    match compare_driver() {
        Some(icd) => {
            eprintln!("+ VK_ICD_FILENAMES={}", icd.display());
            run_in(&user_dir(), &cmd, &[("VK_ICD_FILENAMES", icd.as_os_str())])
        }
        None => run_in(&user_dir(), &cmd, &[]),
    }
}

/// The `harness` binary of the test build.
fn harness_of(artifacts: &[Artifact]) -> Option<String> {
    artifacts
        .iter()
        .find(|a| a.name == "harness" && a.bin && !a.test_profile)
        .and_then(|a| a.executable.clone())
}

/// Where `compare` writes without `--out`: `out/` at the workspace's root, wherever it runs.
fn default_out() -> String {
    workspace_root().join("out").to_string_lossy().into_owned()
}

/// The folder the user ran `cargo xtask` from (cargo runs it there): `compare` runs the
/// harness in it, so `--scenes my.glb` and `--out` mean what they say there.
fn user_dir() -> PathBuf {
    std::env::current_dir().unwrap_or_else(|_| workspace_root())
}

/// The Vulkan driver `cargo xtask compare` runs the harness on: on a machine whose only
/// Vulkan device is the software rasterizer (no `/dev/dri/renderD*`, no `/dev/nvidia*`), Mesa
/// 25's lavapipe from bookworm-backports, which `cargo xtask test` fetched (fetched here if
/// not): it renders the main job faster than Debian 12's Mesa 22.3 and, unlike it, gives back
/// the memory of every frame (measured in harness/README.md, "Cost"). `None` (the
/// system's drivers) where there is a GPU, where `VK_ICD_FILENAMES` or `VK_DRIVER_FILES` is
/// set already, or where the backport cannot be had (said on stderr).
fn compare_driver() -> Option<PathBuf> {
    let chosen = ["VK_ICD_FILENAMES", "VK_DRIVER_FILES"]
        .iter()
        .any(|k| std::env::var_os(k).is_some_and(|v| !v.is_empty()));
    if chosen || has_gpu_device() {
        return None;
    }
    match backported_lavapipe() {
        Ok(icd) => Some(icd),
        Err(why) => {
            eprintln!(
                "xtask: comparing on the system's lavapipe (Mesa 25's could not be had: {why})"
            );
            None
        }
    }
}

/// Whether the machine has a GPU's device node (a DRM render node or NVIDIA's).
fn has_gpu_device() -> bool {
    let names = |dir: &str| -> Vec<String> {
        std::fs::read_dir(dir)
            .map(|d| {
                d.flatten()
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default()
    };
    names("/dev/dri").iter().any(|n| n.starts_with("renderD"))
        || names("/dev").iter().any(|n| n.starts_with("nvidia"))
}

/// After the tests: the build `compare` uses must be exactly the one the tests made (every
/// artifact fresh), so that `cargo xtask compare` right after `cargo xtask test` compiles
/// nothing. Fails naming what would be compiled.
fn check_compare_build_is_fresh(artifacts: &[Artifact]) -> ExitCode {
    let stale: Vec<&str> = artifacts
        .iter()
        .filter(|a| !a.fresh)
        .map(|a| a.name.as_str())
        .collect();
    if stale.is_empty() {
        eprintln!(
            "xtask: cargo xtask compare reuses this build: all {} artifacts are fresh",
            artifacts.len()
        );
        ExitCode::SUCCESS
    } else {
        eprintln!(
            "error: cargo xtask compare would compile again after the tests: {}",
            stale.join(", ")
        );
        ExitCode::FAILURE
    }
}

/// Where [`backported_lavapipe`] keeps Mesa's backported lavapipe.
const BACKPORTS_DIR: &str = "target/mesa-backports";

/// A test that runs again on Mesa 25's lavapipe: (package, test target, test name, the
/// variable that makes it fail rather than skip where its adapter cannot run it).
const ON_MESA_25: [(&str, &str, &str, &str); 3] = [
    // Hardware ray queries, which Debian 12's Mesa (22.3) lacks and Mesa 25 has.
    (
        "raytracer",
        "images",
        "ray_queries_trace_what_the_bvh_traces_or_are_refused_with_the_reason",
        "RAYTRACER_EXPECT_RAY_QUERY",
    ),
    // Memory flat over 50 frames, which Mesa 22.3's lavapipe cannot keep (it holds on to
    // megabytes per descriptor set a draw binds: harness/README.md, "Cost").
    (
        "harness",
        "memory",
        "fifty_frames_keep_the_memory_flat",
        "HARNESS_MEMORY_TEST",
    ),
    // Every declared image check, caustic variants included (float32 blending, which some
    // adapters lack): none may be left out as not run.
    (
        "workspace-tests",
        "image_checks",
        "every_declared_image_check_holds_along_the_camera_path",
        "IMAGE_CHECKS_ALL",
    ),
];

/// The tests of [`ON_MESA_25`] on Mesa 25's lavapipe from bookworm-backports, fetched into
/// `target/mesa-backports` (`apt-get download`, unpacked with `dpkg -x`: nothing is installed,
/// the system's driver stays the one every other test ran on), through `VK_ICD_FILENAMES`, each
/// with its variable set to `require` so that it fails instead of passing through its
/// refusal branch. Where the driver cannot be fetched (no apt, no network), this says so and
/// is skipped.
fn tests_on_backported_lavapipe(artifacts: &[Artifact]) -> ExitCode {
    let icd = match backported_lavapipe() {
        Ok(icd) => icd,
        Err(why) => {
            eprintln!("xtask: skipped the tests on Mesa 25's lavapipe: {why}");
            return ExitCode::SUCCESS;
        }
    };
    let icd = icd.to_string_lossy().into_owned();
    let mut status = ExitCode::SUCCESS;
    for (package, target, test, require) in ON_MESA_25 {
        let Some(a) = artifacts
            .iter()
            .find(|a| a.package.contains(package) && a.name == target && a.test_profile)
        else {
            eprintln!("error: the test build made no {package} {target} test");
            return ExitCode::FAILURE;
        };
        let Some(executable) = &a.executable else {
            continue;
        };
        eprintln!("+ VK_ICD_FILENAMES={icd} {require}=require {executable} {test} --exact");
        let ok = Command::new(executable)
            .args([test, "--exact"])
            .current_dir(&a.dir)
            .env("NODEVICE_SELECT", "1")
            .env("VK_ICD_FILENAMES", &icd)
            .env(require, "require")
            .status()
            .is_ok_and(|s| s.success());
        if !ok {
            eprintln!("error: {package} {test} failed on Mesa 25's lavapipe");
            status = ExitCode::FAILURE;
        }
    }
    status
}

/// The ICD manifest of Mesa 25's lavapipe from bookworm-backports, fetched once into
/// [`BACKPORTS_DIR`]; Err says why it could not be.
fn backported_lavapipe() -> Result<PathBuf, String> {
    let dir = workspace_root().join(BACKPORTS_DIR);
    let icd = dir.join("lvp.json");
    let library = dir.join("root/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so");
    if icd.exists() && library.exists() {
        return Ok(icd);
    }
    if !succeeds("apt-get", &["--version"]) || !succeeds("dpkg", &["--version"]) {
        return Err("no apt-get and dpkg here".into());
    }
    let lists = dir.join("lists");
    std::fs::create_dir_all(lists.join("partial")).map_err(|e| e.to_string())?;
    let sources = dir.join("backports.list");
    std::fs::write(
        &sources,
        "deb http://deb.debian.org/debian bookworm-backports main\n",
    )
    .map_err(|e| e.to_string())?;
    let options = [
        format!("-oDir::Etc::SourceList={}", sources.display()),
        "-oDir::Etc::SourceParts=/dev/null".to_string(),
        format!("-oDir::State::Lists={}", lists.display()),
        "-oAPT::Sandbox::User=root".to_string(),
    ];
    let apt = |args: &[&str]| -> Result<(), String> {
        let mut cmd = Command::new("apt-get");
        cmd.args(&options).args(args).current_dir(&dir);
        let out = cmd.output().map_err(|e| e.to_string())?;
        if out.status.success() {
            Ok(())
        } else {
            Err(format!(
                "apt-get {} failed: {}",
                args.join(" "),
                String::from_utf8_lossy(&out.stderr).trim()
            ))
        }
    };
    apt(&["update"])?;
    apt(&["download", "mesa-vulkan-drivers"])?;
    let deb = std::fs::read_dir(&dir)
        .map_err(|e| e.to_string())?
        .flatten()
        .map(|e| e.path())
        .find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("mesa-vulkan-drivers_25"))
        })
        .ok_or("bookworm-backports offered no Mesa 25 mesa-vulkan-drivers")?;
    let root = dir.join("root");
    if !succeeds(
        "dpkg",
        &["-x", &deb.to_string_lossy(), &root.to_string_lossy()],
    ) || !library.exists()
    {
        return Err(format!("could not unpack {}", deb.display()));
    }
    std::fs::write(
        &icd,
        format!(
            "{{\"ICD\": {{\"api_version\": \"1.4.305\", \"library_path\": \"{}\"}}, \
             \"file_format_version\": \"1.0.0\"}}\n",
            library.display()
        ),
    )
    .map_err(|e| e.to_string())?;
    eprintln!(
        "xtask: Mesa 25's lavapipe from bookworm-backports is in {}",
        dir.display()
    );
    Ok(icd)
}

/// `cargo fmt --all --check`: one style for the workspace (`rustfmt.toml`), checked before the
/// tests so that an unformatted change fails CI with the diff, not later in review.
fn check_format() -> ExitCode {
    if !succeeds(&cargo(), &["fmt", "--version"]) {
        eprintln!(
            "error: rustfmt is not installed; `cargo xtask test` checks the format first. \
             Install it with `rustup component add rustfmt`"
        );
        return ExitCode::FAILURE;
    }
    let status = run(&[cargo(), "fmt".into(), "--all".into(), "--check".into()]);
    if status != ExitCode::SUCCESS {
        eprintln!("error: the workspace is not rustfmt-clean; run `cargo fmt --all`");
    }
    status
}

/// The cargo that runs us (`cargo xtask` sets `CARGO`), else `cargo` from PATH.
fn cargo() -> String {
    std::env::var("CARGO").unwrap_or_else(|_| "cargo".into())
}

fn has_flag(args: &[String], names: &[&str]) -> bool {
    args.iter().any(|a| {
        names
            .iter()
            .any(|n| a == n || a.starts_with(&format!("{n}=")))
    })
}

/// `cargo test --workspace ARGS` (without `--workspace` when ARGS pick packages).
fn test_command(rest: &[String]) -> Vec<String> {
    let mut cmd = vec![cargo(), "test".to_string()];
    let before_separator = rest
        .iter()
        .position(|a| a == "--")
        .map_or(rest, |i| &rest[..i]);
    if !has_flag(
        before_separator,
        &["-p", "--package", "--workspace", "--all"],
    ) {
        cmd.push("--workspace".into());
    }
    cmd.extend(rest.iter().cloned());
    cmd
}

/// `cargo run --release -p rtapprox-harness -- compare --out out ARGS` (a release build of its own).
fn compare_command(rest: &[String]) -> Vec<String> {
    let mut cmd = vec![cargo(), "run".to_string()];
    let mut pass: Vec<String> = Vec::new();
    for a in rest {
        if a == "--release" {
            cmd.push("--release".into());
        } else {
            pass.push(a.clone());
        }
    }
    cmd.extend(["-p", "rtapprox-harness", "--", "compare"].map(String::from));
    if !has_flag(&pass, &["--out"]) {
        cmd.extend(["--out".to_string(), default_out()]);
    }
    cmd.extend(pass);
    cmd
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."))
}

fn shell_quote(s: &str) -> String {
    if !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@".contains(c))
    {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

fn print_command(cmd: &[String]) {
    // The program by its file name (`cargo`, not the toolchain's full path).
    let program = Path::new(&cmd[0])
        .file_name()
        .map_or(cmd[0].clone(), |n| n.to_string_lossy().into_owned());
    let shown: Vec<String> = std::iter::once(program)
        .chain(cmd[1..].iter().cloned())
        .map(|s| shell_quote(&s))
        .collect();
    eprintln!("+ {}", shown.join(" "));
}

fn run(cmd: &[String]) -> ExitCode {
    run_with(cmd, &[])
}

/// [`run`] with extra environment variables.
fn run_with(cmd: &[String], env: &[(&str, &std::ffi::OsStr)]) -> ExitCode {
    run_in(&workspace_root(), cmd, env)
}

/// [`run_with`] in folder `dir`.
fn run_in(dir: &Path, cmd: &[String], env: &[(&str, &std::ffi::OsStr)]) -> ExitCode {
    let status = command_in(dir, cmd, env).status();
    match status {
        Ok(s) => match s.code() {
            Some(0) => ExitCode::SUCCESS,
            Some(c) => ExitCode::from(c.clamp(1, 255) as u8),
            None => {
                eprintln!("error: {} was killed by a signal", cmd[0]);
                ExitCode::FAILURE
            }
        },
        Err(e) => {
            eprintln!("error: cannot run {}: {e}", cmd[0]);
            ExitCode::FAILURE
        }
    }
}

/// `cmd` in folder `dir` with `env` and the environment every job's commands share, printed.
fn command_in(dir: &Path, cmd: &[String], env: &[(&str, &std::ffi::OsStr)]) -> Command {
    print_command(cmd);
    let mut command = Command::new(&cmd[0]);
    command
        .args(&cmd[1..])
        .current_dir(dir)
        .envs(env.iter().copied())
        .env("CARGO_INCREMENTAL", ONE_BUILD_INCREMENTAL)
        .env("NODEVICE_SELECT", "1")
        // The HTML report's browser test fails, rather than skips, without Chromium: the
        // `test` job has installed it.
        .env("HARNESS_BROWSER_TEST", "require");
    command
}

/// Output of a command, or None when it cannot run.
fn output(program: &str, args: &[&str]) -> Option<std::process::Output> {
    Command::new(program).args(args).output().ok()
}

fn succeeds(program: &str, args: &[&str]) -> bool {
    output(program, args).is_some_and(|o| o.status.success())
}

fn has_vulkan_icd() -> bool {
    ICD_DIRS.iter().any(|dir| {
        std::fs::read_dir(dir).is_ok_and(|entries| {
            entries
                .flatten()
                .any(|e| e.path().extension().is_some_and(|x| x == "json"))
        })
    })
}

fn has_vulkan_loader() -> bool {
    let listed = ["/sbin/ldconfig", "ldconfig"]
        .iter()
        .find_map(|p| output(p, &["-p"]));
    match listed {
        Some(o) if o.status.success() => {
            String::from_utf8_lossy(&o.stdout).contains("libvulkan.so.1")
        }
        // No ldconfig: look in the usual library folders.
        _ => [
            "/usr/lib/x86_64-linux-gnu",
            "/usr/lib/aarch64-linux-gnu",
            "/usr/lib64",
            "/usr/lib",
            "/lib",
        ]
        .iter()
        .any(|d| Path::new(d).join("libvulkan.so.1").exists()),
    }
}

fn is_root() -> bool {
    output("id", &["-u"]).is_some_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// One missing thing and the packages that provide it.
struct Missing {
    what: &'static str,
    packages: &'static [&'static str],
    required: bool,
}

/// Whether a Chromium the report's browser test can start is here (or named by
/// `HARNESS_CHROMIUM`).
fn has_chromium() -> bool {
    std::env::var_os("HARNESS_CHROMIUM").is_some()
        || ["chromium", "chromium-browser", "google-chrome"]
            .iter()
            .any(|b| succeeds(b, &["--version"]))
}

/// What the job needs that is not here: `test` also needs headless Chromium.
fn missing_prerequisites(job: &str) -> Vec<Missing> {
    let mut missing = Vec::new();
    if job == "test" && !has_chromium() {
        missing.push(Missing {
            what: "headless Chromium (the HTML report's browser test)",
            packages: &["chromium"],
            required: true,
        });
    }
    if !has_vulkan_icd() || !has_vulkan_loader() {
        missing.push(Missing {
            what: "a Vulkan driver (ICD manifest and libvulkan.so.1)",
            packages: &["mesa-vulkan-drivers", "libvulkan1"],
            required: true,
        });
    }
    if !succeeds("c++", &["--version"]) && !succeeds("g++", &["--version"]) {
        missing.push(Missing {
            what: "a C++ compiler (nv-flip builds FLIP)",
            packages: &["g++"],
            required: true,
        });
    }
    missing
}

/// Installs what is missing when it can, or says how. Err carries the exit code.
fn ensure_prerequisites(job: &str) -> Result<(), ExitCode> {
    let missing = missing_prerequisites(job);
    if missing.is_empty() {
        return Ok(());
    }
    for m in &missing {
        let note = if m.required { "" } else { " (optional)" };
        eprintln!(
            "xtask: missing {}{note}: package {}",
            m.what,
            m.packages.join(" ")
        );
    }
    let packages: Vec<&str> = missing
        .iter()
        .flat_map(|m| m.packages.iter().copied())
        .collect();
    let required = missing.iter().any(|m| m.required);
    let has_apt = succeeds("apt-get", &["--version"]);
    if is_root() && has_apt {
        let update = ["apt-get", "update"].map(String::from).to_vec();
        let mut install = ["apt-get", "install", "-y", "--no-install-recommends"]
            .map(String::from)
            .to_vec();
        install.extend(packages.iter().map(|p| p.to_string()));
        for cmd in [update, install] {
            print_command(&cmd);
            let ok = Command::new(&cmd[0])
                .args(&cmd[1..])
                .env("DEBIAN_FRONTEND", "noninteractive")
                .status()
                .is_ok_and(|s| s.success());
            if !ok {
                eprintln!("error: `{}` failed", cmd.join(" "));
                return if required {
                    Err(ExitCode::FAILURE)
                } else {
                    Ok(())
                };
            }
        }
        let still: Vec<Missing> = missing_prerequisites(job)
            .into_iter()
            .filter(|m| m.required)
            .collect();
        if let Some(m) = still.first() {
            eprintln!(
                "error: still missing {} after installing {}",
                m.what,
                packages.join(" ")
            );
            return Err(ExitCode::FAILURE);
        }
        return Ok(());
    }
    let command = format!(
        "sudo apt-get update && sudo DEBIAN_FRONTEND=noninteractive apt-get install -y {}",
        packages.join(" ")
    );
    if !required {
        eprintln!("xtask: optional; to install: {command}");
        return Ok(());
    }
    if has_apt {
        eprintln!("error: not running as root; install them with:\n  {command}");
    } else {
        eprintln!(
            "error: no apt-get here; install the equivalents of these Debian packages ({}) with your \
             package manager; on Debian/Ubuntu: {command}",
            packages.join(" ")
        );
    }
    Err(ExitCode::FAILURE)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn test_command_passes_arguments_through() {
        assert_eq!(test_command(&[])[1..], strings(&["test", "--workspace"]));
        assert_eq!(
            test_command(&strings(&["-p", "rtapprox-harness"]))[1..],
            strings(&["test", "-p", "rtapprox-harness"])
        );
        assert_eq!(
            test_command(&strings(&["--", "-p"]))[1..],
            strings(&["test", "--workspace", "--", "-p"])
        );
    }

    #[test]
    fn artifacts_are_read_from_cargo_json() {
        let stdout = concat!(
            r#"{"reason":"compiler-artifact","package_id":"x","target":{"kind":["bin"],"crate_types":["bin"],"name":"harness","test":true},"profile":{"opt_level":"1","test":false},"features":[],"filenames":["/t/harness"],"executable":"/t/harness","fresh":true}"#,
            "\n",
            r#"{"reason":"compiler-artifact","package_id":"y","target":{"kind":["lib"],"crate_types":["lib"],"name":"scene","test":true},"profile":{"opt_level":"3","test":true},"features":[],"filenames":["/t/libscene.rlib"],"executable":null,"fresh":false}"#,
            "\n",
            r#"{"reason":"build-finished","success":true}"#
        );
        let a = parse_artifacts(stdout);
        assert_eq!(a.len(), 2);
        assert!(a[0].bin && !a[0].test_profile && a[0].fresh);
        assert_eq!(a[0].name, "harness");
        assert_eq!(a[0].executable.as_deref(), Some("/t/harness"));
        assert!(!a[1].bin && a[1].test_profile && !a[1].fresh);
        assert_eq!(a[1].executable, None);
    }

    #[test]
    fn compare_command_defaults_and_overrides() {
        assert_eq!(
            compare_command(&[])[1..],
            strings(&[
                "run",
                "-p",
                "rtapprox-harness",
                "--",
                "compare",
                "--out",
                &default_out()
            ])
        );
        assert!(default_out().ends_with("/out") && Path::new(&default_out()).is_absolute());
        assert_eq!(
            compare_command(&strings(&["--release", "--out=x", "--size", "64x64"]))[1..],
            strings(&[
                "run",
                "--release",
                "-p",
                "rtapprox-harness",
                "--",
                "compare",
                "--out=x",
                "--size",
                "64x64"
            ])
        );
    }

    #[test]
    fn quoting() {
        assert_eq!(shell_quote("--out"), "--out");
        assert_eq!(shell_quote("a b"), "'a b'");
        assert_eq!(shell_quote("it's"), "'it'\\''s'");
    }
}
