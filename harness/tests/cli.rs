//! Bad input to the built binary: each case exits non-zero with one "error: ..." line on stderr
//! and never a panic.

mod common;

use common::harness;
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("harness-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Asserts a clean failure and returns the error line.
fn fails(args: &[&str]) -> String {
    let out = harness(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        !out.status.success(),
        "{args:?} succeeded; stderr: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{args:?}: expected one line, got: {stderr}");
    assert!(lines[0].starts_with("error: "), "{args:?}: {stderr}");
    lines[0].to_string()
}

fn out_dir() -> String {
    tmp("out").display().to_string()
}

#[test]
fn unknown_scene() {
    let e = fails(&["compare", "--out", &out_dir(), "--scenes", "no-such-scene"]);
    assert!(
        e.contains("unknown scene \"no-such-scene\"") && e.contains("cornell-sphere"),
        "{e}"
    );
    let e = fails(&[
        "sweep",
        "--scene",
        "nope",
        "--technique",
        "x",
        "--param",
        "a=1",
        "--out",
        &out_dir(),
    ]);
    assert!(e.contains("unknown"), "{e}");
}

#[test]
fn unknown_technique() {
    let e = fails(&[
        "compare",
        "--out",
        &out_dir(),
        "--techniques",
        "no/such-technique",
    ]);
    assert!(e.contains("unknown technique \"no/such-technique\""), "{e}");
    let e = fails(&[
        "render",
        "--scene",
        "cornell-sphere",
        "--technique",
        "nope",
        "--out",
        &tmp("x.png").display().to_string(),
    ]);
    assert!(e.contains("unknown technique"), "{e}");
    // A near miss gets the closest ids, not all of them.
    let e = fails(&[
        "compare",
        "--out",
        &out_dir(),
        "--techniques",
        "impostor/false-postion-4",
    ]);
    assert!(
        e.contains("did you mean one of impostors/false-position-4,") && !e.contains("volumes/"),
        "{e}"
    );
}

/// clap's tip survives on the one line: a misspelt option or subcommand names the right one.
#[test]
fn misspelt_arguments_get_clap_s_tip() {
    let e = fails(&["compare", "--out", &out_dir(), "--sizes", "8x8"]);
    assert!(
        e.contains("unexpected argument '--sizes'")
            && e.contains("tip: a similar argument exists: '--size'"),
        "{e}"
    );
    let e = fails(&["comapre"]);
    assert!(
        e.contains("tip: a similar subcommand exists: 'compare'"),
        "{e}"
    );
}

#[test]
fn missing_glb() {
    let missing = tmp("does-not-exist.glb").display().to_string();
    let e = fails(&["compare", "--out", &out_dir(), "--scenes", &missing]);
    assert!(e.contains("does-not-exist.glb"), "{e}");
    let e = fails(&[
        "export-scene",
        &missing,
        "--out",
        &tmp("x.glb").display().to_string(),
    ]);
    assert!(e.contains("does-not-exist.glb"), "{e}");
}

#[test]
fn malformed_gltf() {
    let bad = tmp("garbage.gltf");
    std::fs::write(&bad, b"{ this is not glTF \x00\x01").unwrap();
    let e = fails(&[
        "compare",
        "--out",
        &out_dir(),
        "--scenes",
        &bad.display().to_string(),
    ]);
    assert!(e.contains("garbage.gltf"), "{e}");
    let bad = tmp("garbage.glb");
    std::fs::write(&bad, b"glTF\x02\x00\x00\x00garbage").unwrap();
    fails(&[
        "compare",
        "--out",
        &out_dir(),
        "--scenes",
        &bad.display().to_string(),
    ]);
}

#[test]
fn nan_in_a_scene_parameter() {
    let e = fails(&[
        "compare",
        "--out",
        &out_dir(),
        "--scenes",
        "cornell-sphere:sphere_x=nan",
    ]);
    assert!(e.contains("sphere_x=nan is not a finite number"), "{e}");
}

/// A one-triangle glTF whose node translation is `translation` (JSON text).
fn triangle_gltf(translation: &str) -> String {
    let uri = "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA=";
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
 "nodes": [{{"mesh": 0, "translation": {translation}}}],
 "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
 "buffers": [{{"byteLength": 44, "uri": "{uri}"}}],
 "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 6}}],
 "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
               {{"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}}]}}"#
    )
}

#[test]
fn non_finite_transform_in_gltf() {
    // 1e39 does not fit an f32: the JSON parser refuses it as out of range (a reader that
    // rounds it to infinity leaves a non-finite translation, which the importer refuses).
    let bad = tmp("infinite-node.gltf");
    std::fs::write(&bad, triangle_gltf("[1e39, 0, -3]")).unwrap();
    let e = fails(&[
        "compare",
        "--out",
        &out_dir(),
        "--scenes",
        &bad.display().to_string(),
    ]);
    assert!(
        e.contains("infinite-node.gltf")
            && (e.contains("non-finite") || e.contains("out of range")),
        "{e}"
    );
    // The same file with a finite translation loads (the test above fails for the right reason).
    let good = tmp("finite-node.gltf");
    std::fs::write(&good, triangle_gltf("[0, 0, -3]")).unwrap();
    scene::load(&good.display().to_string()).expect("the finite twin loads");
}

#[test]
fn unparsable_size() {
    let e = fails(&["compare", "--out", &out_dir(), "--size", "abc"]);
    assert!(e.contains("\"abc\" is not a size"), "{e}");
    fails(&[
        "render",
        "--scene",
        "cornell-sphere",
        "--technique",
        "reference",
        "--out",
        "x.png",
        "--size",
        "0x4",
    ]);
}

#[test]
fn size_over_the_adapter_limit() {
    // Needs an adapter (the limit is the adapter's); the error names the limit.
    let e = fails(&[
        "compare",
        "--out",
        &out_dir(),
        "--scenes",
        "cornell-sphere",
        "--size",
        "100000x100000",
        "--frames",
        "1",
    ]);
    assert!(e.contains("100000x100000") && e.contains("limit"), "{e}");
}

#[test]
fn other_bad_arguments() {
    let e = fails(&[
        "render",
        "--scene",
        "cornell-sphere",
        "--technique",
        "reference",
        "--out",
        "x.jpg",
    ]);
    assert!(e.contains(".png or .exr"), "{e}");
    let e = fails(&[
        "sweep",
        "--scene",
        "cornell-sphere",
        "--technique",
        "x",
        "--param",
        "novalue",
        "--out",
        &out_dir(),
    ]);
    assert!(e.contains("NAME=v1,v2"), "{e}");
    let e = fails(&["export-scene", "cornell-sphere", "--out", "x.gltf"]);
    assert!(e.contains(".glb"), "{e}");
    let e = fails(&["compare"]);
    assert!(e.contains("--out"), "{e}");
    let e = fails(&["compare", "--out", &out_dir(), "--error-frames", "0"]);
    assert!(e.contains("--error-frames"), "{e}");
    let e = fails(&[
        "bench",
        "--scene",
        "cornell-sphere",
        "--technique",
        "raster",
    ]);
    assert!(e.contains("at least two techniques"), "{e}");
    let bench = [
        "bench",
        "--scene",
        "cornell-sphere",
        "--technique",
        "raster",
        "--technique",
    ];
    let e = fails(&[&bench[..], &["envmap/classic", "--rounds", "1"]].concat());
    assert!(e.contains("--rounds"), "{e}");
    let e = fails(&[&bench[..], &["raster:bogus"]].concat());
    assert!(e.contains("not name=value"), "{e}");
    fails(&["no-such-command"]);
}

#[test]
fn list_shows_scenes_and_parameters() {
    let out = harness(&["list", "--params"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for s in [
        "cornell-sphere",
        "cornell-box",
        "refraction-bunny",
        "city",
        "smoke",
        "material",
        "rooms_per_building",
        "Techniques",
    ] {
        assert!(text.contains(s), "missing {s} in:\n{text}");
    }
    assert!(harness(&["list"]).status.success());
    assert!(harness(&["--help"]).status.success());
}

#[test]
fn compare_with_the_registered_techniques_at_32x32() {
    let out = tmp("real-compare");
    let _ = std::fs::remove_dir_all(&out);
    let compare = |extra: &[&str]| {
        let mut args = vec![
            "compare".to_string(),
            "--out".to_string(),
            out.display().to_string(),
        ];
        args.extend(
            [
                "--scenes",
                "cornell-sphere",
                "--size",
                "32x32",
                "--frames",
                "2",
                "--warmup",
                "0",
                "--ref-photons",
                "20000",
                "--strict",
            ]
            .map(String::from),
        );
        args.extend(extra.iter().map(|a| a.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let run = harness(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        let stdout = String::from_utf8_lossy(&run.stdout);
        assert!(run.status.success(), "stdout: {stdout}\nstderr: {stderr}");
        assert!(stdout.contains("| scene | technique |"), "{stdout}");
        let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap())
                .unwrap();
        for row in json["rows"].as_array().unwrap() {
            assert!(row["error"].is_null(), "a row has an error: {row}");
        }
        csv
    };
    let scene = scene::load("cornell-sphere").unwrap();
    // Supported here: by the scene, and by the adapter (a variant that needs a feature the
    // adapter lacks, `raytracer/ray-query` on lavapipe, is skipped with the reason).
    let adapter = testkit::context();
    let supported: Vec<_> = harness::registry()
        .into_iter()
        .filter(|t| t.supports(&scene) && adapter.require(t.required_features()).is_ok())
        .collect();
    let representative: Vec<String> = supported
        .iter()
        .filter(|t| t.representative())
        .map(|t| t.id())
        .collect();
    assert!(representative.len() < supported.len());

    // The default: each family's representative variants, and only those.
    let csv = compare(&[]);
    assert_eq!(csv.lines().count(), 1 + representative.len(), "{csv}");
    for line in csv.lines().skip(1) {
        let id = line.split(',').nth(1).unwrap();
        assert!(
            representative.iter().any(|r| r == id),
            "{id} is not representative"
        );
    }
    assert!(out.join("images/cornell-sphere/reference.exr").is_file());

    // --all-variants: every supported variant (the references come from the cache).
    let csv = compare(&["--all-variants"]);
    assert_eq!(csv.lines().count(), 1 + supported.len(), "{csv}");

    // `report` writes the rows of chosen techniques with the run's provenance.
    let results = out.join("results.json").display().to_string();
    let evidence = out.join("evidence.md").display().to_string();
    let run = harness(&[
        "report",
        &results,
        "--techniques",
        "impostors,raster",
        "--markdown",
        &evidence,
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let text = std::fs::read_to_string(&evidence).unwrap();
    assert!(
        text.starts_with("# Results") && text.contains("- git commit:"),
        "{text}"
    );
    assert!(text.contains("results.json by `harness report"), "{text}");
    let picked = |id: &str| id == "raster" || id.starts_with("impostors/");
    let expected = csv
        .lines()
        .skip(1)
        .filter(|l| picked(l.split(',').nth(1).unwrap()));
    let rows: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("| cornell-sphere |"))
        .collect();
    assert!(rows.len() > 1, "{text}");
    assert_eq!(rows.len(), expected.count(), "{text}");
    assert!(
        rows.iter()
            .all(|l| picked(l.split('|').nth(2).unwrap().trim())),
        "{text}"
    );
    let e = fails(&[
        "report",
        &results,
        "--techniques",
        "no-such",
        "--markdown",
        &evidence,
    ]);
    assert!(
        e.contains("is of \"no-such\"; its rows are of ") && e.contains("raster"),
        "{e}"
    );
    // A family name is a whole path part: "impostor" is not "impostors".
    let e = fails(&[
        "report",
        &results,
        "--techniques",
        "impostor",
        "--markdown",
        &evidence,
    ]);
    assert!(e.contains("is of \"impostor\""), "{e}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn export_render_and_reimport() {
    let glb = tmp("exported.glb");
    let run = harness(&[
        "export-scene",
        "cornell-sphere:material=gold",
        "--out",
        &glb.display().to_string(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let exr = tmp("from-glb.exr");
    let cache = tmp("render-cache");
    let _ = std::fs::remove_dir_all(&cache);
    let (glb, exr_path) = (glb.display().to_string(), exr.display().to_string());
    let cache_path = cache.display().to_string();
    let render = |cache_args: &[&str]| {
        let mut args = vec![
            "render",
            "--scene",
            &glb,
            "--technique",
            "reference",
            "--ref-photons",
            "0",
            "--size",
            "16x12",
            "--out",
            &exr_path,
        ];
        args.extend_from_slice(cache_args);
        let run = harness(&args);
        let stderr = String::from_utf8_lossy(&run.stderr).into_owned();
        assert!(run.status.success(), "{stderr}");
        (stderr, harness::images::read_exr(&exr).unwrap())
    };
    let bits = |image: &gpu::HdrImage| -> Vec<u32> {
        image
            .pixels
            .iter()
            .flat_map(|p| p.map(f32::to_bits))
            .collect()
    };
    let (first, rendered) = render(&["--cache", &cache_path]);
    assert!(
        first.contains("reference: rendered into the cache in")
            && first.contains("(no cached reference of this scene)"),
        "{first}"
    );
    assert_eq!((rendered.width, rendered.height), (16, 12));
    // The second render of the same view reads the first one back: the same radiance, bit
    // for bit.
    let (second, cached) = render(&["--cache", &cache_path]);
    assert!(
        second.contains("reference: read from the cache in"),
        "{second}"
    );
    assert!(
        bits(&rendered) == bits(&cached),
        "the cached reference differs from the rendered one"
    );
    // --no-cache renders afresh, the same image, and says nothing of a cache.
    let _ = std::fs::remove_dir_all(&cache);
    let (third, fresh) = render(&["--no-cache"]);
    assert!(!third.contains("cache"), "{third}");
    assert!(
        bits(&fresh) == bits(&rendered),
        "--no-cache gave another image"
    );
    assert!(!cache.exists(), "--no-cache made {}", cache.display());
}

/// Every option of every subcommand says what it is for, and the top-level help ends with
/// examples and the environment variables that choose the adapter (#34 item 6).
#[test]
fn every_option_has_help_and_the_environment_is_named() {
    let top = harness(&["--help"]);
    let text = String::from_utf8_lossy(&top.stdout).into_owned();
    for needed in [
        "Examples:",
        "WGPU_ADAPTER_NAME",
        "WGPU_BACKEND",
        "VK_ICD_FILENAMES",
    ] {
        assert!(text.contains(needed), "{needed} missing from: {text}");
    }
    for command in [
        "list",
        "compare",
        "sweep",
        "bench",
        "render",
        "merge",
        "pareto",
        "report",
        "export-scene",
        "rays",
    ] {
        let out = harness(&[command, "--help"]);
        let help = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(out.status.success(), "{command}: {help}");
        for line in help.lines().filter(|l| l.trim_start().starts_with('-')) {
            let words: Vec<&str> = line.split_whitespace().collect();
            // `--name <VALUE>` or `-h, --help` and then at least one word of help.
            let option_words = words
                .iter()
                .take_while(|w| w.starts_with('-') || w.starts_with('<'))
                .count();
            assert!(
                words.len() > option_words,
                "{command}: option without help: {line:?}"
            );
        }
    }
}

/// `harness rays` measures the five ray sets and splits a reference render, prints the table
/// and writes it: every rate positive, every set's rays counted, the render's phases within its
/// total, the thread count it was asked for. A bad thread count is refused in one line.
#[test]
fn rays_reports_the_reference_throughput_and_its_render_split() {
    let md = tmp("rays.md");
    let out = harness(&[
        "rays",
        "--scenes",
        "cornell-sphere,smoke",
        "--size",
        "24x16",
        "--threads",
        "1",
        "--rounds",
        "2",
        "--ref-photons",
        "20000",
        "--markdown",
        md.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(std::fs::read_to_string(&md).unwrap(), stdout);
    assert!(stdout.contains(": 1 thread of "), "{stdout}");
    let cells = |first: &str, second: &str| -> Vec<String> {
        let row = |l: &&str| l.starts_with(&format!("| {first} | {second}"));
        let line = stdout.lines().find(row);
        let line = line.unwrap_or_else(|| panic!("no row {first} {second}: {stdout}"));
        line.split('|').map(|c| c.trim().to_string()).collect()
    };
    // The summary: ten cells a row; cornell-sphere's photon paths measured, smoke's empty (no
    // caustic caster).
    for (scene, photons) in [("cornell-sphere", true), ("smoke", false)] {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(&format!("| {scene} | ")));
        let row: Vec<&str> = line
            .unwrap()
            .trim_matches('|')
            .split('|')
            .map(str::trim)
            .collect();
        assert_eq!(row.len(), 10, "{row:?}");
        assert_eq!(!row[6].is_empty(), photons, "{row:?}");
    }
    assert!(
        stdout.contains("| cornell-sphere | photon paths"),
        "{stdout}"
    );
    assert!(!stdout.contains("| smoke | photon paths"), "{stdout}");
    for scene in ["cornell-sphere", "smoke"] {
        for set in [
            "coherent closest-hit",
            "incoherent closest-hit",
            "coherent any-hit",
            "incoherent any-hit",
        ] {
            let row = cells(scene, set);
            let rays: usize = row[4].parse().unwrap();
            let median: f64 = row[6].parse().unwrap();
            assert!(rays > 0 && rays <= 24 * 16, "{set}: {row:?}");
            assert!(median > 0.0 && median.is_finite(), "{set}: {row:?}");
        }
        // | scene | size | photons | camera | shadow | photon | whole | BVH | eye | light |
        // profiled: whole | eye | direct light | media | light | connections | beams |
        let split = cells(scene, "24x16");
        let seconds = |i: usize| -> f64 { split[i].parse().unwrap() };
        assert_eq!(split[3], "20000", "{split:?}");
        let (whole, phases) = (seconds(7), seconds(8) + seconds(9) + seconds(10));
        assert!(whole > 0.0 && phases <= whole * 1.001 + 1e-3, "{split:?}");
        let eye_parts = seconds(13) + seconds(14);
        assert!(eye_parts <= seconds(12) * 1.05 + 1e-3, "{split:?}");
        let light_parts = seconds(16) + seconds(17);
        assert!(light_parts <= seconds(15) * 1.05 + 1e-3, "{split:?}");
    }
    let e = fails(&["rays", "--scenes", "cornell-sphere", "--threads", "0"]);
    assert!(e.contains("--threads"), "{e}");
}
