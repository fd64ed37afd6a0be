//! `cargo xtask test` and `cargo xtask compare` (the alias is in `.cargo/config.toml`).
//!
//! Both first make sure the machine can build and run the workspace:
//!
//! - a Vulkan driver: an ICD manifest (`*.json` in `/usr/share/vulkan/icd.d`,
//!   `/etc/vulkan/icd.d` or `/usr/local/share/vulkan/icd.d`) and the loader `libvulkan.so.1`
//!   (`ldconfig -p`); Debian packages `mesa-vulkan-drivers libvulkan1` (lavapipe);
//! - what the native build steps need: a C++ compiler (`nv-flip` builds FLIP from C++) and
//!   fontconfig's development files through pkg-config (the plots' font lookup); packages
//!   `g++ pkg-config libfontconfig1-dev`;
//! - optionally a font for the text in `sweep.png` (`fonts-dejavu-core`; without one the plot
//!   is drawn without text).
//!
//! When something required is missing and we run as root on a system with `apt-get`, it runs
//! `apt-get update` and `apt-get install -y ...` (DEBIAN_FRONTEND=noninteractive). Otherwise it
//! prints the exact command to run and exits with status 1.
//!
//! Then, with `NODEVICE_SELECT=1` (silences Mesa's device-select layer), it runs
//!
//! - `test`: `cargo fmt --all --check` (the style of `rustfmt.toml`), then
//!   `cargo test --workspace [ARGS...]` (every member: unit, integration and doc
//!   tests; `-p NAME` in ARGS replaces `--workspace`);
//! - `compare`: `cargo run -p harness -- compare --out out [ARGS...]` (`--out DIR` in ARGS
//!   replaces `--out out`). It uses the dev profile on purpose: the workspace's dev profile
//!   optimizes the dependencies and the `truth` and `scene` crates at opt-level 3 (the CPU
//!   reference and its BVH, FLIP, wgpu), so it runs as fast as a release build for this job
//!   while reusing the build `cargo xtask test` made, instead of a separate release build of
//!   several minutes (see the README for the measurements). `cargo xtask compare --release` asks for a release build.
//!
//! Every command is printed before it runs; the exit status is the child's.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

const ICD_DIRS: &[&str] = &[
    "/usr/share/vulkan/icd.d",
    "/etc/vulkan/icd.d",
    "/usr/local/share/vulkan/icd.d",
];

fn usage() -> ExitCode {
    eprintln!(
        "usage: cargo xtask <test|compare> [ARGS...]\n\
         \x20 test      cargo test --workspace [ARGS...]\n\
         \x20 compare   cargo run -p harness -- compare --out out [ARGS...]   (--release for a release build)"
    );
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let Some(job) = args.next() else {
        return usage();
    };
    let rest: Vec<String> = args.collect();
    let command = match job.as_str() {
        "test" => test_command(&rest),
        "compare" => compare_command(&rest),
        "-h" | "--help" | "help" => {
            usage();
            return ExitCode::SUCCESS;
        }
        other => {
            eprintln!("error: unknown job \"{other}\"");
            return usage();
        }
    };
    if let Err(code) = ensure_prerequisites() {
        return code;
    }
    if job == "test" {
        let status = check_format();
        if status != ExitCode::SUCCESS {
            return status;
        }
    }
    run(&command)
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

/// `cargo run [--release] -p harness -- compare --out out ARGS`.
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
    cmd.extend(["-p", "harness", "--", "compare"].map(String::from));
    if !has_flag(&pass, &["--out"]) {
        cmd.extend(["--out", "out"].map(String::from));
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
    print_command(cmd);
    let status = Command::new(&cmd[0])
        .args(&cmd[1..])
        .current_dir(workspace_root())
        .env("NODEVICE_SELECT", "1")
        .status();
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

fn missing_prerequisites() -> Vec<Missing> {
    let mut missing = Vec::new();
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
    if !succeeds("pkg-config", &["--exists", "fontconfig"]) {
        missing.push(Missing {
            what: "fontconfig development files via pkg-config (plot fonts)",
            packages: &["pkg-config", "libfontconfig1-dev"],
            required: true,
        });
    }
    let fonts = output("fc-list", &[]).is_some_and(|o| o.status.success() && !o.stdout.is_empty());
    if !fonts {
        missing.push(Missing {
            what: "a font (text in sweep.png)",
            packages: &["fonts-dejavu-core"],
            required: false,
        });
    }
    missing
}

/// Installs what is missing when it can, or says how. Err carries the exit code.
fn ensure_prerequisites() -> Result<(), ExitCode> {
    let missing = missing_prerequisites();
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
        let still: Vec<Missing> = missing_prerequisites()
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
            test_command(&strings(&["-p", "harness"]))[1..],
            strings(&["test", "-p", "harness"])
        );
        assert_eq!(
            test_command(&strings(&["--", "-p"]))[1..],
            strings(&["test", "--workspace", "--", "-p"])
        );
    }

    #[test]
    fn compare_command_defaults_and_overrides() {
        assert_eq!(
            compare_command(&[])[1..],
            strings(&["run", "-p", "harness", "--", "compare", "--out", "out"])
        );
        assert_eq!(
            compare_command(&strings(&["--release", "--out=x", "--size", "64x64"]))[1..],
            strings(&[
                "run",
                "--release",
                "-p",
                "harness",
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
