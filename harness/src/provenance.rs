//! What produced a run's output, so that it can be reproduced: the command line, the commit,
//! the date, the ground truth's options, the harness version and the Vulkan driver files.

use crate::report::AdapterJson;

/// What produced a page, so it can be reproduced.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Provenance {
    /// The program's arguments, shell-quoted where needed.
    pub command_line: String,
    /// `git rev-parse HEAD` of the working directory (`-dirty` when tracked files changed), or
    /// why there is none.
    pub git_commit: String,
    /// When the page was written, UTC, ISO 8601.
    pub date_utc: String,
    /// The ground truth and its options (the reference cache's key).
    pub reference: String,
    pub harness_version: String,
    /// The Vulkan driver manifests the run was told to load (`VK_DRIVER_FILES` or
    /// `VK_ICD_FILENAMES`, as `cargo xtask` sets them for the newer lavapipe it fetches), or
    /// "system" for the system's drivers.
    pub vulkan_drivers: String,
}

impl Provenance {
    /// The page's "how this page was made" list: these fields with the run's adapter, image
    /// size and frames.
    pub(crate) fn rows(
        &self,
        adapter: &AdapterJson,
        size: &str,
        frames: String,
    ) -> Vec<(&'static str, String)> {
        vec![
            ("command line", self.command_line.clone()),
            ("git commit", self.git_commit.clone()),
            ("date (UTC)", self.date_utc.clone()),
            ("adapter", adapter_line(adapter)),
            ("timer", adapter.timer_kind.clone()),
            ("image size", size.to_string()),
            ("frames", frames),
            ("reference", self.reference.clone()),
            ("Vulkan drivers", self.vulkan_drivers.clone()),
            ("harness", self.harness_version.clone()),
        ]
        .into_iter()
        // A run without a ground truth (a bench) has no reference to name.
        .filter(|(what, value)| !(*what == "reference" && value.is_empty()))
        .collect()
    }

    /// [`Provenance::rows`] as the markdown list a page starts with.
    pub(crate) fn markdown(&self, adapter: &AdapterJson, size: &str, frames: String) -> String {
        self.rows(adapter, size, frames)
            .into_iter()
            .map(|(what, value)| format!("- {what}: {value}\n"))
            .collect()
    }

    /// This process's command line, the working directory's commit and the time now.
    pub fn capture(reference: String) -> Self {
        Provenance {
            command_line: std::env::args_os()
                .map(|a| quote(&a.to_string_lossy()))
                .collect::<Vec<_>>()
                .join(" "),
            git_commit: git_commit(),
            date_utc: utc_now(),
            reference,
            harness_version: env!("CARGO_PKG_VERSION").to_string(),
            vulkan_drivers: ["VK_DRIVER_FILES", "VK_ICD_FILENAMES"]
                .iter()
                .find_map(|k| std::env::var(k).ok().filter(|v| !v.is_empty()))
                .unwrap_or_else(|| "system".into()),
        }
    }
}

/// A word as a POSIX shell would need it.
pub fn quote(word: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c);
    if !word.is_empty() && word.chars().all(plain) {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', r"'\''"))
    }
}

fn git_commit() -> String {
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match git(&["rev-parse", "HEAD"]) {
        Some(commit) => match git(&["status", "--porcelain", "--untracked-files=no"]) {
            Some(changes) if !changes.is_empty() => format!("{commit}-dirty"),
            _ => commit,
        },
        None => "unknown (not run inside a git checkout)".into(),
    }
}

/// The time now, UTC, as `YYYY-MM-DDTHH:MM:SSZ`.
fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    utc(secs)
}

/// Seconds since 1970 as a UTC date and time (Howard Hinnant's days-to-civil).
fn utc(secs: u64) -> String {
    let (days, rest) = ((secs / 86_400) as i64, secs % 86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rest / 3600,
        rest / 60 % 60,
        rest % 60
    )
}

fn adapter_line(a: &AdapterJson) -> String {
    format!(
        "{} ({}, {}, driver {}{})",
        a.name,
        a.backend,
        a.device_type,
        a.driver,
        if a.is_software { ", software" } else { "" }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_are_utc_civil_dates() {
        assert_eq!(utc(0), "1970-01-01T00:00:00Z");
        assert_eq!(utc(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(utc(1_795_723_445), "2026-11-26T20:04:05Z");
    }

    #[test]
    fn command_lines_are_quoted_for_a_shell() {
        assert_eq!(quote("--scenes"), "--scenes");
        assert_eq!(
            quote("cornell-box:material=gold"),
            "cornell-box:material=gold"
        );
        assert_eq!(quote("a b"), "'a b'");
        assert_eq!(quote("it's"), r"'it'\''s'");
        assert_eq!(quote(""), "''");
    }
}
