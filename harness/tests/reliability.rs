//! Bad input, real files and hard limits at the command line (issue #20): every case below
//! once panicked, hung, took memory without bound, was silently accepted or printed a wrong
//! message, and failed before its fix. Library-level cases: `tests/tests/reliability.rs`.

mod common;

use common::harness;
use std::path::{Path, PathBuf};
use std::process::Command;
use testkit::gltf::{Glb, small_scene};

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join(format!("harness-reliability-{}", std::process::id()))
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Asserts a clean failure (non-zero exit, one `error: ` line, no panic) within `seconds`,
/// and returns the line.
fn fails_within(seconds: u64, args: &[&str]) -> String {
    let start = std::time::Instant::now();
    let out = harness(args);
    let stderr = text(&out.stderr);
    assert!(!out.status.success(), "{args:?} succeeded: {stderr}");
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{args:?}: expected one line, got: {stderr}");
    assert!(lines[0].starts_with("error: "), "{args:?}: {stderr}");
    assert!(
        start.elapsed().as_secs() < seconds,
        "{args:?} took {:?}",
        start.elapsed()
    );
    lines[0].to_string()
}

/// The smallest `compare` of `raster` on `scenes`: 16 x 16, one timed frame, one error
/// frame, a reference without photons.
fn raster_compare(out: &Path, scenes: &str) -> std::process::Output {
    smallest_compare(out, scenes, "raster")
}

/// The smallest `compare` of `technique` on `scenes` (as [`raster_compare`]).
fn smallest_compare(out: &Path, scenes: &str, technique: &str) -> std::process::Output {
    harness(&[
        "compare",
        "--out",
        path(out),
        "--scenes",
        scenes,
        "--techniques",
        technique,
        "--size",
        "16x16",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--error-frames",
        "1",
        "--ref-photons",
        "0",
    ])
}

/// `harness render` of `scene` by `technique` into `png`: 24 x 24, a reference without photons.
fn render_small(scene: &str, technique: &str, png: &Path) -> std::process::Output {
    harness(&small_render_args(scene, technique, png))
}

/// The arguments of [`render_small`].
fn small_render_args<'a>(scene: &'a str, technique: &'a str, png: &'a Path) -> [&'a str; 12] {
    [
        "render",
        "--no-cache",
        "--scene",
        scene,
        "--technique",
        technique,
        "--out",
        path(png),
        "--size",
        "24x24",
        "--ref-photons",
        "0",
    ]
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Item 1: a top-down camera with up = +Y (before: exit 101 in obvhs, a black raster image).
#[test]
fn top_down_camera_renders() {
    let dir = tmp("top-down");
    let mut glb = Glb::from_scene(&small_scene());
    glb.set_camera(
        glam::Vec3::new(0.0, 4.0, 0.0),
        glam::Vec3::ZERO,
        glam::Vec3::Y,
    );
    let scene = glb.write_glb(&dir, "top-down");
    for technique in ["reference", "raster"] {
        let png = dir.join(format!("{technique}.png"));
        let out = render_small(path(&scene), technique, &png);
        let stderr = text(&out.stderr);
        assert!(out.status.success(), "{technique}: {stderr}");
        assert!(!stderr.contains("NaN"), "{technique}: {stderr}");
        let image = image::open(&png).unwrap().to_rgb8();
        assert!(
            image.pixels().any(|p| p.0 != [0, 0, 0]),
            "{technique}: black"
        );
    }
}

/// Item 2: sizes the adapter's limit allows but memory does not (before: "Out of Memory"
/// panics in Target::new).
#[test]
fn sizes_beyond_memory_fail_before_allocating() {
    let out = tmp("huge").join("x.png");
    for size in ["11600x11600", "16384x16384"] {
        // On a machine that can hold such a run (the GPU machine has 128 GiB and a bigger
        // adapter) it is not an error: the case is the 2-core, 24 GB machine of the issue.
        let s: harness::Size = size.parse().unwrap();
        let (gpu, cpu) = harness::limits::estimate(s, harness::Frames::default());
        if harness::limits::available_memory().is_some_and(|m| gpu + cpu <= m) {
            eprintln!("skipped {size}: this machine has the memory for it");
            continue;
        }
        let e = fails_within(
            30,
            &[
                "render",
                "--scene",
                "cornell-sphere",
                "--technique",
                "raster",
                "--out",
                path(&out),
                "--size",
                size,
            ],
        );
        assert!(e.contains(size) && e.contains("smaller --size"), "{e}");
    }
}

/// Item 6: every option and scene parameter has a range (before: 14 GB within 30 s, hangs,
/// or silently accepted).
#[test]
fn arguments_outside_their_range_are_refused() {
    let out = tmp("ranges");
    let o = path(&out);
    let cases: &[(&[&str], &str)] = &[
        (
            &[
                "compare",
                "--out",
                o,
                "--scenes",
                "smoke:particles=100000000",
            ],
            "outside its range [0, 1024]",
        ),
        (
            &["compare", "--out", o, "--scenes", "smoke:particles=-1"],
            "outside its range",
        ),
        (
            &["compare", "--out", o, "--scenes", "smoke:particles=2.5"],
            "whole number",
        ),
        (
            &[
                "compare",
                "--out",
                o,
                "--scenes",
                "cornell-sphere:sphere_x=1e30",
            ],
            "[-0.6, 0.6]",
        ),
        (
            &["compare", "--out", o, "--scenes", "city:buildings=1000000"],
            "outside its range",
        ),
        (&["compare", "--out", o, "--scenes", ""], "names no scene"),
        (
            &["compare", "--out", o, "--scenes", ",,,"],
            "names no scene",
        ),
        (
            &["compare", "--out", o, "--frames", "4294967295"],
            "--frames",
        ),
        (&["compare", "--out", o, "--frames", "0"], "--frames"),
        (
            &["compare", "--out", o, "--warmup", "4000000000"],
            "--warmup",
        ),
        (
            &["compare", "--out", o, "--ref-photons", "1000000000000"],
            "--ref-photons",
        ),
        (
            &["compare", "--out", o, "--ref-spp", "4000000000"],
            "--ref-spp",
        ),
        (&["compare", "--out", o, "--ref-spp", "0"], "--ref-spp"),
        (
            &["compare", "--out", o, "--ref-depth", "100000"],
            "--ref-depth",
        ),
        (
            &[
                "sweep",
                "--scene",
                "cornell-sphere",
                "--technique",
                "raster",
                "--param",
                "sphere_x=0,5",
                "--out",
                o,
            ],
            "outside its range",
        ),
    ];
    for (args, expected) in cases {
        let e = fails_within(20, args);
        assert!(e.contains(expected), "{args:?}: {e}");
    }
}

/// Item 8: `render --technique reference` honours the --ref-* options (before: the
/// registry's default reference, byte-identical EXRs for 0 and 4 million photons).
#[test]
fn render_reference_uses_the_reference_options() {
    let dir = tmp("ref-options");
    let render = |photons: &str| {
        let exr = dir.join(format!("p{photons}.exr"));
        let out = harness(&[
            "render",
            "--no-cache",
            "--scene",
            "cornell-sphere",
            "--technique",
            "reference",
            "--out",
            path(&exr),
            "--size",
            "24x24",
            "--ref-photons",
            photons,
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        std::fs::read(&exr).unwrap()
    };
    assert_ne!(
        render("0"),
        render("200000"),
        "the caustic photons change the image"
    );
}

/// Item 9: scenes whose files share a name get their own image folders, and a second run
/// into a folder in use is refused (before: the second overwrote the first; two compares
/// into one --out lost rows in 7 of 7 trials).
#[test]
fn outputs_never_collide() {
    let dir = tmp("collisions");
    let scene = small_scene();
    let x = Glb::from_scene(&scene).write_glb(&dir.join("x"), "scene");
    let y = Glb::from_scene(&scene).write_glb(&dir.join("y"), "scene");
    let out = dir.join("out");
    let scenes = format!("{},{}", path(&x), path(&y));
    let run = raster_compare(&out, &scenes);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let folders: Vec<String> = std::fs::read_dir(out.join("images"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(folders.len(), 2, "{folders:?}");
    for f in &folders {
        assert!(
            out.join("images").join(f).join("raster.png").exists(),
            "{f}"
        );
    }
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(
        csv.lines().count(),
        1 + 2,
        "a header and a row per scene: {csv}"
    );

    // A run into a folder another run holds fails at once.
    let _held = harness::OutputLock::acquire(&out).unwrap();
    let e = fails_within(
        20,
        &[
            "compare",
            "--out",
            path(&out),
            "--scenes",
            "cornell-sphere",
            "--techniques",
            "raster",
            "--size",
            "16x16",
        ],
    );
    assert!(e.contains("another harness run is writing to"), "{e}");
}

/// Item 10: messages name a file once, say "write" when writing, show the real texture size
/// and never print a raw NUL.
#[test]
fn messages_are_right() {
    let dir = tmp("messages");
    let bad = dir.join("bad.glb");
    std::fs::write(&bad, b"glTF\x02\0\0\0\xff\xff\0\0").unwrap();
    let e = fails_within(
        20,
        &[
            "render",
            "--scene",
            path(&bad),
            "--technique",
            "raster",
            "--out",
            path(&dir.join("x.png")),
        ],
    );
    assert_eq!(e.matches("bad.glb").count(), 1, "{e}");

    let e = fails_within(
        20,
        &["export-scene", "cornell-sphere", "--out", "/proc/x.glb"],
    );
    assert!(e.contains("cannot write /proc/x.glb"), "{e}");

    let glb = Glb::from_scene(&small_scene());
    let nul = glb.write_gltf(&dir, "nul", Some("a%00b.bin"));
    let e = fails_within(
        20,
        &[
            "render",
            "--scene",
            path(&nul),
            "--technique",
            "raster",
            "--out",
            path(&dir.join("y.png")),
        ],
    );
    assert!(e.contains("a\\0b.bin") && !e.contains('\0'), "{e:?}");

    // A 20000 x 1 texture: the message gives its real size.
    let mut wide = small_scene();
    wide.textures.push(scene::Texture {
        name: "wide".into(),
        width: 20000,
        height: 1,
        rgba8: vec![200; 4 * 20000],
    });
    wide.objects[0].material = scene::Material::Diffuse {
        albedo: glam::Vec3::ONE,
        texture: Some(0),
        cutout: None,
    };
    let wide_path = Glb::from_scene(&wide).write_glb(&dir, "wide");
    let e = fails_within(
        30,
        &[
            "render",
            "--scene",
            path(&wide_path),
            "--technique",
            "raster",
            "--out",
            path(&dir.join("z.png")),
        ],
    );
    assert!(!e.contains("20000x20000") && e.contains("20000"), "{e}");
}

/// Item 5: a file without lights is lit by default, with a warning and a note in
/// results.json; item 11: the run has no panic and exits 0.
#[test]
fn files_without_lights_warn_and_are_recorded() {
    let dir = tmp("no-lights");
    let mut glb = Glb::from_scene(&small_scene());
    glb.remove_lights();
    let scene = glb.write_glb(&dir, "dark");
    let out = dir.join("out");
    let run = raster_compare(&out, path(&scene));
    let stderr = text(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning:") && stderr.contains("default key light"),
        "{stderr}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(json["scene_notes"].as_array().unwrap().len(), 1, "{json}");
    assert!(json["panics"].as_array().unwrap().is_empty());
    let row = &json["rows"][0];
    assert_eq!(row["technique"], "raster");
    assert!(row["error"].is_null(), "{row}");
    assert!(row["psnr_db"].as_f64().is_some_and(f64::is_finite), "{row}");
}

/// `harness list | head`: a closed stdout ends the program quietly (before: `println!`
/// panicked with "failed printing to stdout: Broken pipe", exit 101).
#[test]
fn closed_stdout_is_not_a_panic() {
    for args in [&["list", "--params"][..], &["list"][..]] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_harness"))
            .args(args)
            .env("NODEVICE_SELECT", "1")
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let stderr = text(&out.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(out.status.success(), "{args:?}: {:?} {stderr}", out.status);
    }
}

/// A technique asked to render a scene it refuses says why: the families whose photons leave
/// a point light name the scene's sun or spot.
#[test]
fn a_refused_scene_is_refused_with_the_reason() {
    let out = tmp("refused").join("x.png");
    for (scene, technique, light) in [
        (
            "pool:light=sun",
            "screen-photons/lines",
            "\"sun\" is a directional light",
        ),
        (
            "cornell-sphere:light=spot",
            "impostors/caustics",
            "\"ceiling spot\" is a spot light",
        ),
    ] {
        let e = fails_within(
            120,
            &[
                "render",
                "--scene",
                scene,
                "--technique",
                technique,
                "--size",
                "16x16",
                "--out",
                path(&out),
            ],
        );
        assert!(
            e.contains("does not support scene") && e.contains("needs point lights"),
            "{e}"
        );
        assert!(e.contains(light), "{e}");
    }
}

/// An orthographic camera: `render` draws it with the reference, and a technique that needs a
/// pinhole refuses it with one line naming the reason and a non-zero exit (#37 item 3).
#[test]
fn an_orthographic_camera_is_rendered_exactly_or_refused_with_the_reason() {
    let dir = tmp("orthographic");
    let scene = "cornell-sphere:camera=orthographic";
    for exact in ["reference", "raster"] {
        let png = dir.join(format!("{exact}.png"));
        let out = render_small(scene, exact, &png);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let image = image::open(&png).unwrap().to_rgb8();
        assert!(image.pixels().any(|p| p.0 != [0, 0, 0]), "{exact}: black");
    }
    let technique = "envmap/classic";
    let png = dir.join("classic.png");
    let e = fails_within(60, &small_render_args(scene, technique, &png));
    assert!(e.contains("envmap/classic needs a pinhole camera"), "{e}");
    assert!(e.contains("orthographic"), "{e}");
    // `compare` leaves the technique out with one line for the scene.
    let out = smallest_compare(&dir.join("compare"), scene, technique);
    let stderr = text(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "skipped: {scene}: 1 techniques, which need a pinhole camera"
        )),
        "{stderr}"
    );
    let csv = std::fs::read_to_string(dir.join("compare/results.csv")).unwrap();
    assert_eq!(
        csv.lines().count(),
        1,
        "no row ({technique} was the only technique): {csv}"
    );
}
