//! Checks of the repository's own files, not of the code: generated bulk must not be
//! committed, and documentation must not be written twice.
//!
//! Both look at the tracked files (`git ls-files`; every file but build and result folders
//! where there is no git). Both guard against a failure that happened (commit 5a43bf4): an edit meant to insert one
//! 704-character bullet into `impostors/README.md` inserted it before every character of the
//! file (the pattern of a string replace with an empty search string, `text.replace("", block)`),
//! growing a 38 kB README to 27 MB. A text file over 1 MB, or a README paragraph that occurs
//! twice, fails here with the file and the paragraph named.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Largest text file the repository may hold.
const MAX_TEXT_BYTES: u64 = 1 << 20;
/// Folders that hold build output, caches and results, never sources.
const SKIPPED_DIRS: &[&str] = &[".git", "target", "out", ".gl"];

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

/// Every file under `dir`, build and result folders left out.
fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        let Ok(kind) = entry.file_type() else {
            continue;
        };
        if kind.is_dir() && !SKIPPED_DIRS.contains(&name.to_string_lossy().as_ref()) {
            files_under(&path, out);
        } else if kind.is_file() {
            out.push(path);
        }
    }
}

/// The repository's tracked files (`git ls-files`), or, where git or the repository is not
/// there (a source archive), every file under the root but build and result folders.
fn repository_files(root: &Path) -> Vec<PathBuf> {
    let listed = std::process::Command::new("git")
        .args(["ls-files", "-z"])
        .current_dir(root)
        .output();
    match listed {
        Ok(out) if out.status.success() && !out.stdout.is_empty() => out
            .stdout
            .split(|&b| b == 0)
            .filter(|name| !name.is_empty())
            .map(|name| root.join(String::from_utf8_lossy(name).as_ref()))
            .filter(|path| path.is_file())
            .collect(),
        _ => {
            let mut files = Vec::new();
            files_under(root, &mut files);
            files
        }
    }
}

/// A file is text when its first 8 kB hold no NUL byte (PNG, EXR and GLB files all do).
fn is_text(path: &Path) -> bool {
    use std::io::Read;
    let mut head = [0u8; 8192];
    let Ok(mut file) = std::fs::File::open(path) else {
        return false;
    };
    let n = file.read(&mut head).unwrap_or(0);
    !head[..n].contains(&0)
}

/// Paragraphs (blocks between blank lines) of at least this many characters may occur once.
const MIN_REPEATED_PARAGRAPH_CHARS: usize = 80;
/// Lines of at least this many characters may occur twice (a figure quoted in a table and in
/// the text), not more.
const MIN_REPEATED_LINE_CHARS: usize = 60;

/// Text written more than once: paragraphs of at least 80 characters that occur twice or
/// more, and lines of at least 60 characters (table rules aside) that occur three times or
/// more, each with its count (first 100 characters).
fn repeated_text(text: &str) -> Vec<(String, usize)> {
    let mut paragraphs: HashMap<&str, usize> = HashMap::new();
    for paragraph in text.split("\n\n").map(str::trim) {
        if paragraph.len() >= MIN_REPEATED_PARAGRAPH_CHARS {
            *paragraphs.entry(paragraph).or_default() += 1;
        }
    }
    let mut lines: HashMap<&str, usize> = HashMap::new();
    for line in text.lines().map(str::trim) {
        let rule = line.chars().all(|c| "|:- ".contains(c));
        if line.len() >= MIN_REPEATED_LINE_CHARS && !rule {
            *lines.entry(line).or_default() += 1;
        }
    }
    let mut repeated: Vec<(String, usize)> = paragraphs
        .into_iter()
        .filter(|&(_, n)| n > 1)
        .chain(lines.into_iter().filter(|&(_, n)| n > 2))
        .map(|(p, n)| (p.chars().take(100).collect(), n))
        .collect();
    repeated.sort();
    repeated
}

#[test]
fn no_text_file_is_over_one_megabyte() {
    let root = workspace_root();
    let files = repository_files(&root);
    assert!(
        files.len() > 50,
        "found only {} files under {}",
        files.len(),
        root.display()
    );
    let big: Vec<String> = files
        .iter()
        .filter(|p| std::fs::metadata(p).is_ok_and(|m| m.len() > MAX_TEXT_BYTES) && is_text(p))
        .map(|p| {
            format!(
                "{} ({} bytes)",
                p.strip_prefix(&root).unwrap_or(p).display(),
                std::fs::metadata(p).map_or(0, |m| m.len())
            )
        })
        .collect();
    assert!(
        big.is_empty(),
        "text files over 1 MB (generated bulk or a broken edit?): {big:?}"
    );
}

#[test]
fn no_readme_repeats_a_paragraph() {
    let root = workspace_root();
    let files = repository_files(&root);
    let docs: Vec<&PathBuf> = files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    assert!(
        docs.iter().any(|p| p.ends_with("impostors/README.md")),
        "no README found"
    );
    for doc in docs {
        let text = std::fs::read_to_string(doc).unwrap_or_default();
        // A run's own output (a test printing one table per scene) is not prose: written by
        // `cargo xtask evidence`, checked by `measured_files_are_the_outputs_of_their_runs`.
        if text.starts_with(GENERATED_PREFIX) {
            continue;
        }
        let repeated = repeated_text(&text);
        assert!(
            repeated.is_empty(),
            "{} repeats paragraphs (count, start): {repeated:?}",
            doc.display()
        );
    }
}

/// The targets of a markdown text's links and images (`[text](target)`, `src="target"`,
/// `href="target"`), fenced code blocks and inline code left out.
fn link_targets(text: &str) -> Vec<String> {
    let mut targets = Vec::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // Inline code spans: every other piece between backticks.
        let prose: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
        let mut rest = prose.as_str();
        while let Some(at) = rest.find("](") {
            rest = &rest[at + 2..];
            let end = rest.find(')').unwrap_or(rest.len());
            targets.push(rest[..end].trim().to_string());
        }
        for attribute in ["src=\"", "href=\""] {
            let mut rest = prose.as_str();
            while let Some(at) = rest.find(attribute) {
                rest = &rest[at + attribute.len()..];
                let end = rest.find('"').unwrap_or(rest.len());
                targets.push(rest[..end].to_string());
            }
        }
    }
    targets
}

/// `path` (relative to the repository's root) with `.` and `..` resolved lexically, or `None`
/// when a `..` climbs above the root.
fn within_root(path: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            std::path::Component::ParentDir => {
                if !out.pop() {
                    return None;
                }
            }
            std::path::Component::CurDir => {}
            std::path::Component::Normal(name) => out.push(name),
            _ => return None,
        }
    }
    Some(out)
}

/// The tracked files and every folder above them, relative to the root: what a clone has.
fn tracked_paths(root: &Path) -> std::collections::HashSet<PathBuf> {
    let mut paths = std::collections::HashSet::new();
    for file in repository_files(root) {
        let mut rel = file.strip_prefix(root).unwrap_or(&file).to_path_buf();
        loop {
            paths.insert(rel.clone());
            if !rel.pop() || rel.as_os_str().is_empty() {
                break;
            }
        }
    }
    paths
}

/// What is wrong with link `target` of the markdown file `doc` (relative to the root), if
/// anything: a relative link must name a tracked file or folder (a user's clone has nothing
/// else, and nothing beside it).
fn link_problem(
    tracked: &std::collections::HashSet<PathBuf>,
    doc: &Path,
    target: &str,
) -> Option<String> {
    let external = ["http://", "https://", "mailto:", "#"];
    // `<path>` and `path "title"` are markdown's forms of one path.
    let target = target.trim_start_matches('<').trim_end_matches('>');
    let target = target.split_whitespace().next().unwrap_or("");
    if target.is_empty() || external.iter().any(|p| target.starts_with(p)) {
        return None;
    }
    let file = target.split('#').next().unwrap_or("");
    if file.is_empty() {
        return None;
    }
    match within_root(&doc.parent().unwrap_or(Path::new("")).join(file)) {
        None => Some(format!("{target} leaves the repository")),
        Some(path) if !tracked.contains(&path) => Some(format!(
            "{target} is not a file or folder of the repository"
        )),
        Some(_) => None,
    }
}

/// Every relative link and image of the tracked markdown files resolves inside the repository.
#[test]
fn every_relative_link_resolves_inside_the_repository() {
    let root = workspace_root();
    let tracked = tracked_paths(&root);
    let mut checked = 0;
    let mut problems = Vec::new();
    for doc in repository_files(&root)
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
    {
        let text = std::fs::read_to_string(doc).unwrap_or_default();
        let rel = doc.strip_prefix(&root).unwrap_or(doc);
        for target in link_targets(&text) {
            checked += 1;
            if let Some(problem) = link_problem(&tracked, rel, &target) {
                problems.push(format!("{}: {problem}", rel.display()));
            }
        }
    }
    assert!(checked > 50, "only {checked} links found");
    assert!(problems.is_empty(), "{problems:#?}");
    // The check catches each failure: a link out of the repository (also one that comes back
    // in by the folder's name), a missing file, an untracked one (a run's output).
    let readme = Path::new("README.md");
    for bad in [
        "../shared/DESIGN.md",
        "../main/README.md",
        "docs/no-such-file.md#part",
        "out/index.html",
    ] {
        assert!(link_problem(&tracked, readme, bad).is_some(), "{bad}");
    }
    for good in [
        "docs/gltf.md#which-techniques-run-on-it",
        "<docs/gltf.md>",
        "docs/gltf.md \"the guide\"",
        "harness/",
    ] {
        assert_eq!(link_problem(&tracked, readme, good), None, "{good}");
    }
    assert_eq!(
        link_targets("[a](x.md) `[b](y.md)` <img src=\"z.png\">\n```\n[c](w.md)\n```"),
        vec!["x.md", "z.png"]
    );
}

/// The checks themselves catch the failure they exist for.
#[test]
fn the_checks_catch_a_block_inserted_before_every_character() {
    let block = "- **Caustics** only exist on the two caustic variants. Every other variant\n  \
                 misses the reference's caustic under the glass sphere: whole-image RMSE.\n\n";
    let readme = "# A crate\n\nSome text.\n";
    let broken = readme.chars().fold(block.to_string(), |mut s, c| {
        s.push(c);
        s.push_str(block);
        s
    });
    let repeated = repeated_text(&broken);
    assert!(
        repeated
            .iter()
            .any(|(line, n)| line.starts_with("misses the reference") && *n == readme.len() + 1),
        "{repeated:?}"
    );
    assert!(repeated_text(readme).is_empty());
    assert!(
        repeated_text(&format!("{block}{block}")).len() == 1,
        "a paragraph written twice"
    );
    let dir = std::env::temp_dir().join(format!("repo-check-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let big = dir.join("big.md");
    std::fs::write(&big, "x".repeat(MAX_TEXT_BYTES as usize + 1)).unwrap();
    let png = dir.join("image.png");
    std::fs::write(&png, [0x89, b'P', b'N', b'G', 0, 0, 0, 0]).unwrap();
    assert!(is_text(&big) && !is_text(&png));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The modules of a crate's `src/` (a file's module is its path: `html/mod.rs` is `html`,
/// and so would be any child file under `html/`), each with the top-level modules its code names through `crate::`
/// (comments and string literals left out). The crate root is not a module here: it declares
/// the others and holds the vocabulary they share.
fn module_imports(src: &Path) -> HashMap<String, Vec<String>> {
    let mut files = Vec::new();
    files_under(src, &mut files);
    let mut imports: HashMap<String, Vec<String>> = HashMap::new();
    for file in files
        .iter()
        .filter(|f| f.extension().is_some_and(|e| e == "rs"))
    {
        let rel = file.strip_prefix(src).unwrap();
        let first = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let module = first.trim_end_matches(".rs").to_string();
        if module == "lib" || module == "main" {
            continue;
        }
        let text = std::fs::read_to_string(file).unwrap();
        let names = imports.entry(module.clone()).or_default();
        for line in text.lines() {
            let code = line.split("//").next().unwrap_or("");
            let mut rest = code;
            while let Some(at) = rest.find("crate::") {
                rest = &rest[at + 7..];
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                let is_module = src.join(format!("{name}.rs")).is_file()
                    || src.join(&name).join("mod.rs").is_file();
                if is_module && name != module && !names.contains(&name) {
                    names.push(name);
                }
            }
        }
    }
    imports
}

/// A cycle of module imports, if there is one (depth-first search).
fn import_cycle(imports: &HashMap<String, Vec<String>>) -> Option<Vec<String>> {
    fn visit(
        m: &str,
        imports: &HashMap<String, Vec<String>>,
        path: &mut Vec<String>,
        done: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|p| p == m) {
            let mut cycle = path[at..].to_vec();
            cycle.push(m.to_string());
            return Some(cycle);
        }
        if done.iter().any(|d| d == m) {
            return None;
        }
        path.push(m.to_string());
        for next in imports.get(m).into_iter().flatten() {
            if let Some(cycle) = visit(next, imports, path, done) {
                return Some(cycle);
            }
        }
        path.pop();
        done.push(m.to_string());
        None
    }
    let mut modules: Vec<&String> = imports.keys().collect();
    modules.sort();
    let mut done = Vec::new();
    modules
        .into_iter()
        .find_map(|m| visit(m, imports, &mut Vec::new(), &mut done))
}

/// The harness's modules import one another without a circle: the runners (`compare`,
/// `sweep`, `bench`, `merge`) build on the engine and the writers, never on each other.
#[test]
fn the_harness_has_no_import_circle() {
    let src = workspace_root().join("harness/src");
    let imports = module_imports(&src);
    assert!(imports.contains_key("engine") && imports.contains_key("compare"));
    if let Some(cycle) = import_cycle(&imports) {
        panic!("harness/src imports in a circle: {}", cycle.join(" -> "));
    }
    for runner in ["compare", "sweep", "bench", "merge"] {
        for other in ["compare", "sweep", "bench", "merge"] {
            assert!(
                !imports[runner].iter().any(|m| m == other),
                "{runner} imports {other}: the runners build on the engine, not on each other"
            );
        }
    }
}

#[test]
fn the_cycle_check_finds_a_cycle() {
    let graph: HashMap<String, Vec<String>> = [("a", "b"), ("b", "c"), ("c", "a"), ("d", "a")]
        .iter()
        .map(|(k, v)| (k.to_string(), vec![v.to_string()]))
        .collect();
    let cycle = import_cycle(&graph).expect("a -> b -> c -> a");
    assert_eq!(cycle.first(), cycle.last());
    assert_eq!(cycle.len(), 4);
    let line: HashMap<String, Vec<String>> = [("a", "b"), ("b", "c")]
        .iter()
        .map(|(k, v)| (k.to_string(), vec![v.to_string()]))
        .collect();
    assert!(import_cycle(&line).is_none());
}

/// Functions of `text` longer than `max` lines: (name, first line, lines), for a file rustfmt
/// formats (a function ends at the first line that is its indentation and `}`).
fn long_functions(text: &str, max: usize) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut long = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let trimmed = line.trim_start();
        let signature = [
            "fn ",
            "pub fn ",
            "pub(crate) fn ",
            "pub(super) fn ",
            "async fn ",
        ]
        .iter()
        .find_map(|p| trimmed.strip_prefix(p));
        let Some(rest) = signature else { continue };
        if line.trim_end().ends_with(';') {
            continue;
        }
        let indent = &line[..line.len() - trimmed.len()];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        let close = format!("{indent}}}");
        if let Some(end) = lines[i + 1..].iter().position(|l| *l == close) {
            if end + 2 > max {
                long.push((name, i + 1, end + 2));
            }
        }
    }
    long
}

/// No runner function of the harness (the engine, the frames of a row, the plan builders, the
/// merge, the binary's commands) is longer than 80 lines: each reads as a short sequence of
/// named steps.
#[test]
fn harness_runner_functions_are_short() {
    const MAX_LINES: usize = 80;
    let src = workspace_root().join("harness/src");
    let runners = [
        "engine.rs",
        "measure.rs",
        "compare.rs",
        "sweep.rs",
        "bench.rs",
        "merge.rs",
        "plan.rs",
        "output.rs",
        "score.rs",
        "main.rs",
    ];
    let mut found = Vec::new();
    for file in runners {
        let text = std::fs::read_to_string(src.join(file)).unwrap();
        for (name, line, lines) in long_functions(&text, MAX_LINES) {
            found.push(format!("harness/src/{file}:{line} {name} ({lines} lines)"));
        }
    }
    assert!(
        found.is_empty(),
        "longer than {MAX_LINES} lines: {found:#?}"
    );
    let sample = "fn a() {\n    x;\n}\n\nfn b() {\n    x;\n    y;\n    z;\n}\n";
    assert_eq!(long_functions(sample, 4), vec![("b".to_string(), 5, 5)]);
}

/// The library crates whose sources the size bounds and the import-circle check read.
const LIBRARY_CRATES: [&str; 14] = [
    "gpu",
    "scene",
    "truth",
    "impostors",
    "volumes",
    "interior-mapping",
    "refractor-maps",
    "height-maps",
    "screen-photons",
    "image-space-refraction",
    "raytracer",
    "harness",
    "testkit",
    "example-framework",
];

/// A library source file's lines before its unit tests (`#[cfg(test)]` at the left margin).
fn code_lines(text: &str) -> Vec<&str> {
    text.lines()
        .take_while(|l| !l.starts_with("#[cfg(test)]"))
        .collect()
}

/// Every `.rs` file under each library crate's `src/`, relative to the workspace root.
fn library_sources(root: &Path) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for krate in LIBRARY_CRATES {
        let mut files = Vec::new();
        files_under(&root.join(krate).join("src"), &mut files);
        for file in files
            .iter()
            .filter(|f| f.extension().is_some_and(|e| e == "rs"))
        {
            let rel = file
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            out.push((rel, std::fs::read_to_string(file).unwrap()));
        }
    }
    out.sort();
    out
}

/// No library source file is over 900 lines and no function over 110 (issue #32: "~900" and
/// "~100"; tests, after a file's `#[cfg(test)]`, are not counted).
#[test]
fn library_files_and_functions_stay_short() {
    const MAX_FILE_LINES: usize = 900;
    const MAX_FUNCTION_LINES: usize = 110;
    let root = workspace_root();
    let mut over = Vec::new();
    for (file, text) in library_sources(&root) {
        let code = code_lines(&text);
        if code.len() > MAX_FILE_LINES {
            over.push(format!("{file}: {} lines", code.len()));
        }
        for (name, line, lines) in long_functions(&code.join("\n"), MAX_FUNCTION_LINES) {
            over.push(format!("{file}:{line} {name}: {lines} lines"));
        }
    }
    assert!(
        over.is_empty(),
        "over the bounds (files {MAX_FILE_LINES}, functions {MAX_FUNCTION_LINES} lines): \
         {over:#?}"
    );
}

/// No library crate's modules import one another in a circle (issue #32; the harness's
/// runners have a stricter rule above).
#[test]
fn no_library_crate_has_an_import_circle() {
    let root = workspace_root();
    for krate in LIBRARY_CRATES {
        let imports = module_imports(&root.join(krate).join("src"));
        if let Some(cycle) = import_cycle(&imports) {
            panic!("{krate}/src imports in a circle: {}", cycle.join(" -> "));
        }
    }
}

// The manifest's parser and the generated files' mark, as `cargo xtask evidence` has them.
#[path = "../../xtask/src/runs.rs"]
#[allow(dead_code)] // `Run::harness_page` is the runner's
mod runs;
use runs::{GENERATED_PREFIX, Run, RunKind};

/// Whether a generated file's "command line" is `run`'s command (a harness run's says the
/// binary's path and the `--out` xtask added; a test's says `cargo`).
fn made_by(text: &str, run: &Run) -> bool {
    let Some(line) = text
        .lines()
        .find_map(|l| l.strip_prefix("- command line: "))
    else {
        return false;
    };
    let args = run.args.join(" ");
    match run.kind {
        RunKind::Harness => line.contains(&format!("harness {args} --out ")),
        RunKind::CargoTest => line == format!("cargo {args}"),
    }
}

/// What is wrong with the files beside one manifest: a run without its file, a file not
/// generated or made by another command than its line's, a file (table or plot) of no run.
fn measured_problems(dir: &Path, manifest: &str) -> Vec<String> {
    let runs = match runs::parse_runs(manifest) {
        Ok(runs) => runs,
        Err(why) => return vec![format!("{}: {why}", dir.join("runs.txt").display())],
    };
    let mut problems = Vec::new();
    for run in &runs {
        let file = dir.join(format!("{}.md", run.name));
        match std::fs::read_to_string(&file) {
            Ok(t) if !t.starts_with(GENERATED_PREFIX) => {
                problems.push(format!("{} is not generated", file.display()))
            }
            Ok(t) if !made_by(&t, run) => problems.push(format!(
                "{} was not made by its line's command (rerun `cargo xtask evidence`)",
                file.display()
            )),
            Ok(_) => {}
            Err(_) => problems.push(format!("{} is missing", file.display())),
        }
    }
    for entry in std::fs::read_dir(dir).expect("lists").flatten() {
        let path = entry.path();
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
        let output = path.extension().is_some_and(|e| e == "md" || e == "svg");
        if output && !stem.is_some_and(|s| runs.iter().any(|r| r.name == s)) {
            problems.push(format!("{} is no run's output", path.display()));
        }
    }
    problems
}

/// Every run a crate lists has its generated file, made by its line's command, and every
/// table or plot beside the list is the output of one of its runs: a hand-written, stale or
/// orphaned file under `docs/measured/` is caught here.
#[test]
fn measured_files_are_the_outputs_of_their_runs() {
    let root = workspace_root();
    let mut problems = Vec::new();
    for entry in std::fs::read_dir(&root)
        .expect("the workspace root lists")
        .flatten()
    {
        let manifest = entry.path().join(runs::RUNS);
        let dir = manifest
            .parent()
            .expect("the manifest is in a folder")
            .to_path_buf();
        if !dir.is_dir() {
            continue;
        }
        match std::fs::read_to_string(&manifest) {
            Ok(manifest) => problems.extend(measured_problems(&dir, &manifest)),
            Err(_) => problems.push(format!("{} has no runs.txt", dir.display())),
        }
    }
    assert!(problems.is_empty(), "{problems:#?}");
}

#[test]
fn the_measured_check_catches_a_stale_missing_or_orphaned_file() {
    let dir = std::env::temp_dir().join(format!("measured-check-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let manifest = "a  harness sweep --param x=1,2\nb  cargo test --test t\n";
    let made = |command: &str| format!("{GENERATED_PREFIX}a` -->\n\n- command line: {command}\n");
    std::fs::write(
        dir.join("a.md"),
        made("/t/harness sweep --param x=1,2 --out /o"),
    )
    .unwrap();
    std::fs::write(dir.join("b.md"), made("cargo test --test t")).unwrap();
    assert!(measured_problems(&dir, manifest).is_empty());
    std::fs::write(
        dir.join("a.md"),
        made("/t/harness sweep --param x=1,2,4 --out /o"),
    )
    .unwrap();
    std::fs::write(dir.join("c.svg"), "<svg/>").unwrap();
    std::fs::remove_file(dir.join("b.md")).unwrap();
    let problems = measured_problems(&dir, manifest).join("\n");
    assert!(problems.contains("a.md was not made by"), "{problems}");
    assert!(problems.contains("b.md is missing"), "{problems}");
    assert!(problems.contains("c.svg is no run's output"), "{problems}");
    let unreadable = measured_problems(&dir, "lonely\n").join("\n");
    assert!(
        unreadable.contains("a run is a name and a command"),
        "{unreadable}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
