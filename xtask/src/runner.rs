//! Running the test build's test executables, each test timed, and the slowest listed at the
//! end: what `cargo test` does (every executable in its package's folder, the tests of one
//! executable in parallel threads), plus the times it does not print, and executables run side
//! by side ([`run_all`]): one test executable keeps about 1.3 of the 2 cores busy (a single
//! long test draws through lavapipe's one command thread), so running them one after another
//! left a third of the machine idle.
//!
//! Per-test times come from libtest's JSON events (`--format json --report-time`), which stable
//! libtest gives when `RUSTC_BOOTSTRAP=1` is in the *test's* environment (only there: the build
//! never sees it, so no artifact changes). An executable that refuses the options (a harness
//! other than libtest) runs again without them, its time then counted as one.

use std::collections::HashMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::Instant;

/// A test executable of the build: which package and target, where it runs.
#[derive(Clone, Debug)]
pub struct TestExecutable {
    /// `<package>/<target>` (`rtapprox-harness/end_to_end`).
    pub name: String,
    pub path: String,
    /// The package's folder: cargo runs a package's tests there.
    pub dir: PathBuf,
}

/// One test's outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct TestTime {
    /// `<executable> <test>`.
    pub name: String,
    pub seconds: f64,
    pub passed: bool,
}

/// What running every executable gave.
#[derive(Debug, Default)]
pub struct Summary {
    pub tests: Vec<TestTime>,
    /// Per executable: its name and wall-clock seconds.
    pub executables: Vec<(String, f64)>,
    pub passed: usize,
    pub failed: Vec<String>,
    pub ignored: usize,
}

/// The string value of `"key":"..."` in one JSON line, unescaped (libtest's events).
pub fn json_string(line: &str, key: &str) -> Option<String> {
    let value = value_of(line, key)?.strip_prefix('"')?;
    let mut out = String::new();
    let mut chars = value.chars();
    while let Some(c) = chars.next() {
        match c {
            '"' => return Some(out),
            '\\' => match chars.next()? {
                'n' => out.push('\n'),
                't' => out.push('\t'),
                'r' => out.push('\r'),
                'u' => {
                    let hex: String = chars.by_ref().take(4).collect();
                    out.push(
                        u32::from_str_radix(&hex, 16)
                            .ok()
                            .and_then(char::from_u32)
                            .unwrap_or('?'),
                    );
                }
                other => out.push(other),
            },
            c => out.push(c),
        }
    }
    None
}

/// The number value of `"key":1.25` in one JSON line.
pub fn json_number(line: &str, key: &str) -> Option<f64> {
    let rest = value_of(line, key)?;
    let end = rest.find([',', '}']).unwrap_or(rest.len());
    rest[..end].trim().parse().ok()
}

/// The text after `"key":` and any spaces (libtest writes `"key": value`).
fn value_of<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    let start = line.find(&format!("\"{key}\":"))? + key.len() + 3;
    Some(line[start..].trim_start())
}

/// Reads one executable's JSON events: the tests' times and outcomes, a failure's output
/// printed as it comes.
fn read_events(executable: &str, stdout: impl BufRead, summary: &mut Summary) {
    for line in stdout.lines().map_while(Result::ok) {
        if !line.starts_with('{') {
            println!("{line}");
            continue;
        }
        let (Some(kind), Some(event)) = (json_string(&line, "type"), json_string(&line, "event"))
        else {
            continue;
        };
        // "started", and "timeout": libtest's note that a test runs for over a minute.
        if kind != "test" || !["ok", "failed", "ignored"].contains(&event.as_str()) {
            continue;
        }
        let name = json_string(&line, "name").unwrap_or_default();
        let seconds = json_number(&line, "exec_time").unwrap_or(0.0);
        match event.as_str() {
            "ok" => summary.passed += 1,
            "ignored" => {
                summary.ignored += 1;
                continue;
            }
            _ => {
                let output = json_string(&line, "stdout").unwrap_or_default();
                eprintln!("---- {executable} {name} ({event}) ----\n{output}");
                summary.failed.push(format!("{executable} {name}"));
            }
        }
        summary.tests.push(TestTime {
            name: format!("{executable} {name}"),
            seconds,
            passed: event == "ok",
        });
    }
}

/// Runs `test` with `args`; false when it failed.
pub fn run_executable(
    test: &TestExecutable,
    args: &[String],
    env: &[(&str, &str)],
    summary: &mut Summary,
) -> bool {
    let start = Instant::now();
    let (passed, failed) = (summary.passed, summary.failed.len());
    let mut cmd = Command::new(&test.path);
    cmd.current_dir(&test.dir).envs(env.iter().copied());
    let timed = cmd
        .args([
            "-Z",
            "unstable-options",
            "--format",
            "json",
            "--report-time",
        ])
        .args(args)
        .env("RUSTC_BOOTSTRAP", "1")
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn();
    let ok = match timed {
        Ok(mut child) => {
            if let Some(stdout) = child.stdout.take() {
                read_events(&test.name, BufReader::new(stdout), summary);
            }
            child.wait().is_ok_and(|s| s.success())
        }
        Err(e) => {
            eprintln!("error: cannot run {}: {e}", test.path);
            false
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    summary.executables.push((test.name.clone(), seconds));
    if !ok && !summary.failed.iter().any(|f| f.starts_with(&test.name)) {
        summary
            .failed
            .push(format!("{} (the executable failed)", test.name));
    }
    eprintln!(
        "xtask: {}: {} passed, {} failed, {seconds:.1} s",
        test.name,
        summary.passed - passed,
        summary.failed.len() - failed
    );
    ok
}

/// Runs every executable of `tests`, `jobs` at a time, the longest first by `previous` (their
/// wall-clock seconds in an earlier run; an executable it does not know counts as long, so a
/// first run starts with cargo's order): longest-first keeps the last one to finish from
/// starting last. Returns whether all passed, and what they gave.
pub fn run_all(
    tests: Vec<TestExecutable>,
    args: &[String],
    env: &[(&str, &str)],
    jobs: usize,
    previous: &HashMap<String, f64>,
) -> (bool, Summary) {
    let mut queue = run_order(tests, previous);
    queue.reverse(); // popped from the back
    let queue = Mutex::new(queue);
    let results = Mutex::new((true, Summary::default()));
    std::thread::scope(|scope| {
        for _ in 0..jobs.max(1) {
            scope.spawn(|| {
                loop {
                    let Some(test) = queue.lock().unwrap_or_else(|e| e.into_inner()).pop() else {
                        break;
                    };
                    let mut own = Summary::default();
                    let ok = run_executable(&test, args, env, &mut own);
                    let mut all = results.lock().unwrap_or_else(|e| e.into_inner());
                    all.0 &= ok;
                    all.1.absorb(own);
                }
            });
        }
    });
    results.into_inner().unwrap_or_else(|e| e.into_inner())
}

/// The order [`run_all`] starts `tests` in: those `previous` does not know first, in the
/// order given (cargo's), then the known ones, longest first.
fn run_order(
    mut tests: Vec<TestExecutable>,
    previous: &HashMap<String, f64>,
) -> Vec<TestExecutable> {
    // A stable sort on the time, unknown as infinite, longest first.
    tests.sort_by(|a, b| {
        let time = |t: &TestExecutable| previous.get(&t.name).copied().unwrap_or(f64::INFINITY);
        time(b).total_cmp(&time(a))
    });
    tests
}

impl Summary {
    fn absorb(&mut self, other: Summary) {
        self.tests.extend(other.tests);
        self.executables.extend(other.executables);
        self.passed += other.passed;
        self.failed.extend(other.failed);
        self.ignored += other.ignored;
    }

    /// The executables' wall-clock seconds as `seconds<TAB>name` lines: what [`read_times`]
    /// reads back for the next run's order.
    pub fn times_text(&self) -> String {
        self.executables
            .iter()
            .map(|(name, seconds)| format!("{seconds:.2}\t{name}\n"))
            .collect()
    }
}

/// The executables' times a previous run wrote with [`Summary::times_text`] (empty when there
/// is none or it cannot be read).
pub fn read_times(path: &Path) -> HashMap<String, f64> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    text.lines()
        .filter_map(|line| {
            let (seconds, name) = line.split_once('\t')?;
            Some((name.to_string(), seconds.parse().ok()?))
        })
        .collect()
}

/// The slowest tests and executables as a table, and the totals.
pub fn report(summary: &Summary, slowest: usize) -> String {
    let mut tests = summary.tests.clone();
    tests.sort_by(|a, b| b.seconds.total_cmp(&a.seconds));
    let mut executables = summary.executables.clone();
    executables.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut out = format!("xtask: the {slowest} slowest tests (seconds):\n");
    for t in tests.iter().take(slowest) {
        out.push_str(&format!("  {:8.2}  {}\n", t.seconds, t.name));
    }
    out.push_str(&format!(
        "xtask: the {slowest} slowest test executables (seconds, wall clock):\n"
    ));
    for (name, seconds) in executables.iter().take(slowest) {
        out.push_str(&format!("  {seconds:8.2}  {name}\n"));
    }
    let total: f64 = summary.executables.iter().map(|e| e.1).sum();
    out.push_str(&format!(
        "xtask: {} passed, {} failed, {} ignored, in {} executables, {:.1} s of executables' \
         wall-clock time together\n",
        summary.passed,
        summary.failed.len(),
        summary.ignored,
        summary.executables.len(),
        total
    ));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_are_read() {
        let events = concat!(
            r#"{ "type": "suite", "event": "started", "test_count": 3 }"#,
            "\n",
            r#"{ "type": "test", "event": "started", "name": "a::b" }"#,
            "\n",
            r#"{ "type": "test", "name": "a::b", "event": "ok", "exec_time": 1.5 }"#,
            "\n",
            r#"{ "type": "test", "name": "c", "event": "failed", "exec_time": 0.25, "stdout": "line \"one\"\nline two\u0021" }"#,
            "\n",
            r#"{ "type": "test", "name": "d", "event": "ignored" }"#,
            "\n"
        );
        let mut summary = Summary::default();
        read_events("x/y", events.as_bytes(), &mut summary);
        assert_eq!(summary.passed, 1);
        assert_eq!(summary.ignored, 1);
        assert_eq!(summary.failed, vec!["x/y c".to_string()]);
        assert_eq!(
            summary.tests,
            vec![
                TestTime {
                    name: "x/y a::b".into(),
                    seconds: 1.5,
                    passed: true
                },
                TestTime {
                    name: "x/y c".into(),
                    seconds: 0.25,
                    passed: false
                }
            ]
        );
        let failed = r#"{ "stdout": "line \"one\"\nline two\u0021" }"#;
        assert_eq!(
            json_string(failed, "stdout").as_deref(),
            Some("line \"one\"\nline two!")
        );
        assert_eq!(
            json_number(r#"{"exec_time":0.125}"#, "exec_time"),
            Some(0.125)
        );
    }

    #[test]
    fn the_report_lists_the_slowest_first() {
        let summary = Summary {
            tests: vec![
                TestTime {
                    name: "fast".into(),
                    seconds: 0.1,
                    passed: true,
                },
                TestTime {
                    name: "slow".into(),
                    seconds: 9.0,
                    passed: true,
                },
            ],
            executables: vec![("e".into(), 9.5)],
            passed: 2,
            ..Default::default()
        };
        let text = report(&summary, 1);
        assert!(
            text.contains("9.00  slow") && !text.contains("fast"),
            "{text}"
        );
        assert!(text.contains("2 passed, 0 failed, 0 ignored, in 1 executables, 9.5 s"));
    }

    #[test]
    fn times_are_read_back() {
        let summary = Summary {
            executables: vec![("a/b".into(), 12.5), ("c/d".into(), 0.25)],
            ..Default::default()
        };
        let dir = std::env::temp_dir().join(format!("xtask-times-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("times.tsv");
        std::fs::write(&path, summary.times_text()).unwrap();
        let times = read_times(&path);
        assert_eq!(times.get("a/b"), Some(&12.5));
        assert_eq!(times.get("c/d"), Some(&0.25));
        assert!(read_times(&dir.join("none")).is_empty());
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn unknown_executables_start_first_then_the_longest() {
        let named = |name: &str| TestExecutable {
            name: name.into(),
            path: String::new(),
            dir: PathBuf::new(),
        };
        let tests = ["short", "new-1", "long", "new-2", "middle"]
            .map(named)
            .to_vec();
        let previous = HashMap::from([
            ("short".to_string(), 1.0),
            ("long".to_string(), 90.0),
            ("middle".to_string(), 10.0),
        ]);
        let order: Vec<String> = run_order(tests, &previous)
            .into_iter()
            .map(|t| t.name)
            .collect();
        assert_eq!(order, ["new-1", "new-2", "long", "middle", "short"]);
    }

    /// Every executable runs once, side by side, and a failing one fails the whole.
    #[test]
    fn all_executables_run_and_a_failure_counts() {
        use std::os::unix::fs::PermissionsExt;
        let dir = std::env::temp_dir().join(format!("xtask-run-all-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // A script ignores the libtest options it is given.
        let script = |name: &str, status: u8| {
            let path = dir.join(name);
            std::fs::write(&path, format!("#!/bin/sh\nexit {status}\n")).unwrap();
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
            TestExecutable {
                name: format!("pkg/{name}"),
                path: path.to_string_lossy().into_owned(),
                dir: dir.clone(),
            }
        };
        let tests = vec![script("ok", 0), script("fails", 1), script("also-ok", 0)];
        let previous = HashMap::from([("pkg/ok".to_string(), 1.0)]);
        let (ok, summary) = run_all(tests, &[], &[], 2, &previous);
        assert!(!ok);
        let mut ran: Vec<&str> = summary.executables.iter().map(|e| e.0.as_str()).collect();
        ran.sort();
        assert_eq!(ran, ["pkg/also-ok", "pkg/fails", "pkg/ok"]);
        assert_eq!(summary.failed, ["pkg/fails (the executable failed)"]);
        std::fs::remove_dir_all(dir).unwrap();
    }
}
