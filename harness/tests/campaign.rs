//! The bad-input campaign of issue #20, re-runnable: several hundred runs of the built binary
//! as a user would make them (malformed and hostile glTF files, real-world shapes of files,
//! out-of-range arguments and scene parameters, scale), each classified by its outcome:
//!
//! - **clean error**: non-zero exit with one `error: ` line on stderr and no panic;
//! - **accepted**: exit 0 and every image finite;
//! - **NaN**: exit 0 but NaN or infinite pixels;
//! - **panic**: exit 101, a panic message, or the harness's exit 4 for a caught panic;
//! - **hang**: still running after [`timeout`] (killed);
//! - **unclean error**: non-zero exit without a one-line error.
//!
//! `cargo test -p rtapprox-harness --test campaign -- --ignored --nocapture` runs it (under a minute on
//! two cores when nothing hangs; each hang costs the timeout) and writes `target/campaign/campaign.md` with the counts per group and every
//! case that was not a clean error or accepted (`CAMPAIGN_HARNESS=<path>` runs another build
//! of the binary instead, an older commit's for the counts before a fix). It is ignored in
//! `cargo xtask test`: the regression tests of each case it once found are in
//! `reliability.rs`.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use testkit::gltf::{Glb, small_scene};

/// A run still going after this long counts as a hang (`CAMPAIGN_TIMEOUT` seconds overrides
/// it).
fn timeout() -> Duration {
    let seconds = std::env::var("CAMPAIGN_TIMEOUT")
        .ok()
        .and_then(|v| v.parse().ok());
    Duration::from_secs(seconds.unwrap_or(120))
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Outcome {
    CleanError,
    Accepted,
    NaN,
    Panic,
    Hang,
    UncleanError,
}

impl Outcome {
    fn label(self) -> &'static str {
        match self {
            Outcome::CleanError => "clean error",
            Outcome::Accepted => "accepted",
            Outcome::NaN => "NaN",
            Outcome::Panic => "panic",
            Outcome::Hang => "hang",
            Outcome::UncleanError => "unclean error",
        }
    }
}

struct Case {
    group: &'static str,
    name: String,
    args: Vec<String>,
}

fn run(case: &Case, logs: &Path) -> (Outcome, String) {
    // Output goes to files, not pipes: a child that writes more than a pipe holds (a panic's
    // backtrace from several threads) would block on its write and look like a hang.
    let stdout_path = logs.join("stdout.txt");
    let stderr_path = logs.join("stderr.txt");
    // CAMPAIGN_HARNESS runs another build (an older commit's, for the counts before a fix).
    let binary = std::env::var("CAMPAIGN_HARNESS").unwrap_or(env!("CARGO_BIN_EXE_harness").into());
    let mut child = Command::new(binary)
        .args(&case.args)
        .env("NODEVICE_SELECT", "1")
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&stdout_path).unwrap())
        .stderr(std::fs::File::create(&stderr_path).unwrap())
        .spawn()
        .expect("start the harness");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break Some(status);
        }
        if start.elapsed() > timeout() {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr = String::from_utf8_lossy(&std::fs::read(&stderr_path).unwrap()).into_owned();
    let Some(status) = status else {
        return (Outcome::Hang, format!("killed after {:?}", timeout()));
    };
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    let first_error = lines
        .iter()
        .find(|l| l.starts_with("error: "))
        .copied()
        .unwrap_or("")
        .to_string();
    let outcome =
        if status.code() == Some(101) || status.code() == Some(4) || stderr.contains("panicked") {
            Outcome::Panic
        } else if status.success() {
            if stderr.contains("NaN or infinite") {
                Outcome::NaN
            } else {
                Outcome::Accepted
            }
        } else if lines.iter().filter(|l| !l.starts_with("warning: ")).count() == 1
            && !first_error.is_empty()
        {
            Outcome::CleanError
        } else {
            Outcome::UncleanError
        };
    let detail = if first_error.is_empty() {
        lines.last().copied().unwrap_or("").to_string()
    } else {
        first_error
    };
    (outcome, detail.chars().take(300).collect())
}

/// A small deterministic generator (SplitMix64) for the mutations.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn s(v: &str) -> String {
    v.to_string()
}

fn render(scene: &Path, technique: &str, out: &Path) -> Vec<String> {
    vec![
        s("render"),
        s("--no-cache"),
        s("--scene"),
        scene.display().to_string(),
        s("--technique"),
        s(technique),
        s("--out"),
        out.display().to_string(),
        s("--size"),
        s("32x32"),
        s("--ref-photons"),
        s("20000"),
    ]
}

/// Every JSON value's path in pre-order, as (keys or indices).
fn paths(
    v: &serde_json::Value,
    here: &mut Vec<serde_json::Value>,
    out: &mut Vec<Vec<serde_json::Value>>,
) {
    out.push(here.clone());
    match v {
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                here.push(serde_json::json!(i));
                paths(x, here, out);
                here.pop();
            }
        }
        serde_json::Value::Object(o) => {
            for (k, x) in o {
                here.push(serde_json::json!(k));
                paths(x, here, out);
                here.pop();
            }
        }
        _ => {}
    }
}

fn at<'a>(v: &'a mut serde_json::Value, path: &[serde_json::Value]) -> &'a mut serde_json::Value {
    path.iter().fold(v, |v, k| match k {
        serde_json::Value::String(k) => &mut v[k.as_str()],
        k => &mut v[k.as_u64().unwrap() as usize],
    })
}

const NASTY: &[&str] = &[
    "null",
    "0",
    "-1",
    "1",
    "4294967295",
    "18446744073709551615",
    "1e30",
    "-1e30",
    "1e-30",
    "1.7976931348623157e308",
    "0.5",
    "\"\"",
    "\"../../etc/passwd\"",
    "\"/dev/zero\"",
    "\"%00\"",
    "[]",
    "[0,0,0]",
    "[1e30,-1e30,0]",
    "{}",
    "true",
    "1e19",
    "[0,1,0]",
];

fn cases(dir: &Path) -> Vec<Case> {
    let mut out = Vec::new();
    let png = dir.join("out.png");
    let o = dir.join("compare-out").display().to_string();
    let scene = small_scene();
    let base = Glb::from_scene(&scene);
    let mut rng = Rng(0x20);

    // Malformed glTF: JSON-level mutations (every value replaced, removed) and byte-level
    // (bit flips, truncation) of a valid file.
    let mut all = Vec::new();
    paths(&base.json, &mut Vec::new(), &mut all);
    for i in 0..260 {
        let mut glb = base.clone();
        let path = &all[rng.below(all.len())];
        if path.is_empty() {
            continue;
        }
        let label;
        if i % 4 == 3 {
            let (parent, last) = path.split_at(path.len() - 1);
            match (at(&mut glb.json, parent), &last[0]) {
                (serde_json::Value::Object(m), serde_json::Value::String(k)) => {
                    m.remove(k);
                }
                (serde_json::Value::Array(a), k) => {
                    a.remove(k.as_u64().unwrap() as usize);
                }
                _ => {}
            }
            label = format!("remove {path:?}");
        } else {
            let value = NASTY[rng.below(NASTY.len())];
            *at(&mut glb.json, path) = serde_json::from_str(value).unwrap();
            label = format!("{path:?} = {value}");
        }
        let file = glb.write_glb(dir, &format!("json{i}"));
        let technique = if i % 5 == 0 { "reference" } else { "raster" };
        out.push(Case {
            group: "glTF JSON mutations",
            name: label,
            args: render(&file, technique, &png),
        });
    }
    let bytes = base.to_bytes();
    for i in 0..160 {
        let mut b = bytes.clone();
        let label = match i % 4 {
            0 => {
                let n = 1 + rng.below(8);
                for _ in 0..n {
                    let p = rng.below(b.len());
                    b[p] ^= 1 << rng.below(8);
                }
                format!("{n} bit flips")
            }
            1 => {
                let cut = rng.below(b.len());
                b.truncate(cut);
                format!("truncated at {cut}")
            }
            2 => {
                let p = rng.below(b.len().min(64));
                let end = (p + 4).min(b.len());
                b[p..end].fill(0xff);
                format!("0xff at header byte {p}")
            }
            _ => {
                let p = rng.below(b.len());
                let n = 1 + rng.below(64);
                b.drain(p..(p + n).min(b.len()));
                format!("{n} bytes deleted at {p}")
            }
        };
        let file = dir.join(format!("bytes{i}.glb"));
        std::fs::write(&file, &b).unwrap();
        out.push(Case {
            group: "glTF byte mutations",
            name: label,
            args: render(&file, "raster", &png),
        });
    }

    // Hostile and unusual files: URIs, special files, the corpus, files without lights.
    let folder = dir.join("uris");
    for (i, uri) in [
        "/etc/passwd",
        "/dev/zero",
        "/dev/urandom",
        "../../../../etc/passwd",
        "%2e%2e/%2e%2e/etc/passwd",
        "..%2F..%2Fetc%2Fpasswd",
        "a%00b.bin",
        "nonexistent.bin",
        "",
        ".",
        "..",
        "uris.gltf",
        "file:///etc/passwd",
        "http://example.invalid/x.bin",
        "data:,notbase64",
        "data:application/octet-stream;base64,!!!!",
    ]
    .iter()
    .enumerate()
    {
        let file = base.write_gltf(&folder, &format!("uri{i}"), Some(uri));
        out.push(Case {
            group: "hostile URIs",
            name: format!("buffer uri {uri:?}"),
            args: render(&file, "raster", &png),
        });
    }
    let fifo = dir.join("fifo.glb");
    let _ = Command::new("mkfifo").arg(&fifo).status();
    for (name, path) in [
        ("a FIFO as the scene", fifo.clone()),
        ("/dev/zero as the scene", PathBuf::from("/dev/zero")),
        ("a folder as the scene", dir.join("folder.glb")),
        ("a missing file", dir.join("missing.glb")),
        ("an empty file", dir.join("empty.glb")),
    ] {
        if name.contains("folder") {
            std::fs::create_dir_all(&path).unwrap();
        }
        if name.contains("empty") {
            std::fs::write(&path, b"").unwrap();
        }
        out.push(Case {
            group: "hostile URIs",
            name: s(name),
            args: render(&path, "raster", &png),
        });
    }
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scene/tests/corpus");
    let mut corpus_files: Vec<PathBuf> = std::fs::read_dir(&corpus)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "gltf" || e == "glb"))
        .collect();
    corpus_files.sort();
    for file in corpus_files {
        for technique in ["reference", "raster"] {
            out.push(Case {
                group: "corpus files",
                name: format!(
                    "{} {technique}",
                    file.file_name().unwrap().to_string_lossy()
                ),
                args: render(&file, technique, &png),
            });
        }
    }
    let bunny = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scene/assets/bunny.glb");
    for technique in ["reference", "raster"] {
        out.push(Case {
            group: "corpus files",
            name: format!("assets/bunny.glb {technique}"),
            args: render(&bunny, technique, &png),
        });
    }

    // Cameras and materials through the file: any orientation, inside objects.
    for i in 0..24 {
        let mut glb = base.clone();
        let eye = glam::Vec3::new(
            rng.below(9) as f32 * 0.5 - 2.0,
            rng.below(6) as f32 * 0.5,
            rng.below(9) as f32 * 0.5 - 2.0,
        );
        let target = if i % 3 == 0 {
            eye - glam::Vec3::Y
        } else {
            glam::Vec3::new(0.0, 0.3, 0.0)
        };
        let up = [
            glam::Vec3::Y,
            glam::Vec3::NEG_Y,
            glam::Vec3::ZERO,
            (target - eye),
        ][i % 4];
        if eye == target {
            continue;
        }
        glb.set_camera(eye, target, up);
        let file = glb.write_glb(dir, &format!("camera{i}"));
        for technique in ["reference", "raster", "impostors/false-position-4"] {
            out.push(Case {
                group: "cameras",
                name: format!("eye {eye} target {target} up {up} {technique}"),
                args: render(&file, technique, &png),
            });
        }
    }
    for (i, extras) in [
        r#"{"kind":"glass","ior":0.5}"#,
        r#"{"kind":"glass","ior":2.5}"#,
        r#"{"kind":"glass","ior":1.0}"#,
        r#"{"kind":"glass","ior":0.0}"#,
        r#"{"kind":"glass","ior":-1.5}"#,
        r#"{"kind":"glass","ior":1e9}"#,
        r#"{"kind":"metal","n":[0,0,0],"k":[10,10,10]}"#,
        r#"{"kind":"metal","n":[10,10,10],"k":[0,0,0]}"#,
        r#"{"kind":"metal","n":[-1,-1,-1],"k":[1,1,1]}"#,
        r#"{"kind":"metal","n":[0.2,0.2,0.2],"k":[1e30,1,1]}"#,
        r#"{"kind":"diffuse","albedo":[1e30,0,0]}"#,
        r#"{"kind":"diffuse","albedo":[-1,0.5,0.5]}"#,
    ]
    .iter()
    .enumerate()
    {
        let mut glb = base.clone();
        glb.set_material_extras(2, serde_json::from_str(extras).unwrap());
        let file = glb.write_glb(dir, &format!("material{i}"));
        for technique in ["reference", "raster", "impostors/double-refraction"] {
            out.push(Case {
                group: "materials",
                name: format!("{extras} {technique}"),
                args: render(&file, technique, &png),
            });
        }
    }

    // Arguments and scene parameters.
    let arg_cases: &[&[&str]] = &[
        &["compare", "--out", &o, "--frames", "0"],
        &["compare", "--out", &o, "--frames", "4294967295"],
        &["compare", "--out", &o, "--frames", "-1"],
        &["compare", "--out", &o, "--warmup", "4000000000"],
        &["compare", "--out", &o, "--error-frames", "0"],
        &["compare", "--out", &o, "--error-frames", "1000"],
        &["compare", "--out", &o, "--ref-photons", "1000000000000"],
        &["compare", "--out", &o, "--ref-spp", "4000000000"],
        &["compare", "--out", &o, "--ref-spp", "0"],
        &["compare", "--out", &o, "--ref-depth", "4000000000"],
        &["compare", "--out", &o, "--size", "0x0"],
        &["compare", "--out", &o, "--size", "16384x16384"],
        &["compare", "--out", &o, "--size", "11600x11600"],
        &["compare", "--out", &o, "--size", "99999999999x2"],
        &["compare", "--out", &o, "--size", "abc"],
        &["compare", "--out", &o, "--scenes", ""],
        &["compare", "--out", &o, "--scenes", ",,,"],
        &["compare", "--out", &o, "--scenes", "nope"],
        &["compare", "--out", &o, "--techniques", ""],
        &["compare", "--out", &o, "--techniques", "nope"],
        &["compare", "--out", "/proc/x"],
        &["compare", "--out", "/dev/null/x"],
        &["compare"],
        &[
            "render",
            "--scene",
            "cornell-sphere",
            "--technique",
            "raster",
            "--out",
            "/tmp/x.jpg",
        ],
        &[
            "render",
            "--scene",
            "cornell-sphere",
            "--technique",
            "nope",
            "--out",
            "/tmp/x.png",
        ],
        &[
            "render",
            "--scene",
            "cornell-sphere",
            "--technique",
            "raster",
            "--out",
            "/proc/x.png",
            "--size",
            "8x8",
        ],
        &[
            "render",
            "--scene",
            "cornell-sphere",
            "--technique",
            "impostors",
            "--out",
            "/tmp/x.png",
        ],
        &[
            "sweep",
            "--scene",
            "cornell-sphere",
            "--technique",
            "raster",
            "--param",
            "sphere_x=0,5",
            "--out",
            &o,
        ],
        &[
            "sweep",
            "--scene",
            "cornell-sphere",
            "--technique",
            "impostors/secant-4",
            "--param",
            "iterations=1e30",
            "--out",
            &o,
        ],
        &[
            "sweep",
            "--scene",
            "cornell-sphere",
            "--technique",
            "impostors/secant-4",
            "--param",
            "nope=1",
            "--out",
            &o,
        ],
        &[
            "sweep",
            "--scene",
            "cornell-sphere",
            "--technique",
            "impostors/secant-4",
            "--param",
            "iterations=",
            "--out",
            &o,
        ],
        &[
            "bench",
            "--scene",
            "cornell-sphere",
            "--technique",
            "raster",
        ],
        &[
            "bench",
            "--scene",
            "cornell-sphere",
            "--technique",
            "raster",
            "--technique",
            "raster:nope=1",
        ],
        &[
            "bench",
            "--scene",
            "cornell-sphere",
            "--technique",
            "raster",
            "--technique",
            "raster",
            "--rounds",
            "0",
        ],
        &[
            "bench",
            "--scene",
            "cornell-sphere",
            "--technique",
            "raster",
            "--technique",
            "raster",
            "--time",
            "nan",
        ],
        &["export-scene", "cornell-sphere", "--out", "/proc/x.glb"],
        &["export-scene", "cornell-sphere", "--out", "x.txt"],
        &["export-scene", "nope", "--out", "/tmp/x.glb"],
        &["list", "--nope"],
    ];
    for args in arg_cases {
        out.push(Case {
            group: "arguments",
            name: args.join(" "),
            args: args.iter().map(|a| s(a)).collect(),
        });
    }
    for spec in [
        "smoke:particles=100000000",
        "smoke:particles=-1",
        "smoke:particles=2.5",
        "smoke:particles=nan",
        "smoke:particles=1024",
        "cornell-sphere:sphere_x=1e30",
        "cornell-sphere:sphere_x=0.6",
        "cornell-sphere:material=unobtainium",
        "cornell-sphere:nope=1",
        "cornell-sphere:sphere_x",
        "city:buildings=1000000",
        "city:buildings=1",
        "city:buildings=4096",
        "city:rooms_per_building=0",
        "city:rooms_per_building=1e30",
        "city:interiors=2",
        "refraction-bunny:ior=0",
        "refraction-bunny:ior=1e9",
        "refraction-bunny:ior=0.25",
        "cornell-box:material=gold,sphere_x=-0.6",
    ] {
        out.push(Case {
            group: "scene parameters",
            name: s(spec),
            args: vec![
                s("render"),
                s("--scene"),
                s(spec),
                s("--technique"),
                s("raster"),
                s("--out"),
                png.display().to_string(),
                s("--size"),
                s("32x32"),
            ],
        });
    }

    // Scale.
    let mut many_lights = scene.clone();
    many_lights.lights = (0..1000)
        .map(|i| scene::Light {
            name: format!("l{i}"),
            position: glam::Vec3::new(
                (i % 10) as f32 * 0.3 - 1.5,
                2.0,
                (i / 100) as f32 * 0.3 - 1.5,
            ),
            intensity: glam::Vec3::splat(0.01),
            kind: scene::LightKind::Point,
        })
        .collect();
    let mut spheres = scene.clone();
    for i in 0..200 {
        spheres.objects.push(
            scene::Object::new(
                &format!("s{i}"),
                scene::mesh::uv_sphere(0.05, 16, 24),
                scene::Material::glass(1.5),
                glam::Mat4::from_translation(glam::Vec3::new(
                    (i % 20) as f32 * 0.2 - 2.0,
                    0.5,
                    (i / 20) as f32 * 0.2 - 1.0,
                )),
            )
            .with_roles(scene::Roles::REFRACTOR | scene::Roles::CAUSTIC_CASTER),
        );
    }
    for (name, model) in [("1000 lights", many_lights), ("200 glass spheres", spheres)] {
        let file = Glb::from_scene(&model).write_glb(dir, &name.replace(' ', "-"));
        for technique in [
            "reference",
            "raster",
            "envmap/classic",
            "impostors/classic",
            "impostors/caustics",
        ] {
            out.push(Case {
                group: "scale",
                name: format!("{name} {technique}"),
                args: render(&file, technique, &png),
            });
        }
    }
    // 300 nodes sharing one mesh of 16384 triangles: 4.9 million triangles in the scene.
    let mut one = scene.clone();
    one.objects.push(scene::Object::new(
        "ball",
        scene::mesh::uv_sphere(0.05, 64, 128),
        scene::Material::diffuse(0.5, 0.5, 0.5),
        glam::Mat4::IDENTITY,
    ));
    let mut shared = Glb::from_scene(&one);
    let ball = shared.node("ball");
    for i in 0..300 {
        let mut node = shared.json["nodes"][ball].clone();
        node["matrix"] = serde_json::json!([
            1,
            0,
            0,
            0,
            0,
            1,
            0,
            0,
            0,
            0,
            1,
            0,
            (i % 20) as f32 * 0.2 - 2.0,
            0.3,
            (i / 20) as f32 * 0.2 - 1.5,
            1
        ]);
        shared.json["nodes"].as_array_mut().unwrap().push(node);
        let index = shared.json["nodes"].as_array().unwrap().len() - 1;
        shared.json["scenes"][0]["nodes"]
            .as_array_mut()
            .unwrap()
            .push(serde_json::json!(index));
    }
    let file = shared.write_glb(dir, "shared-mesh-300");
    for technique in ["reference", "raster"] {
        out.push(Case {
            group: "scale",
            name: format!("300 nodes of a 16384-triangle mesh {technique}"),
            args: render(&file, technique, &png),
        });
    }
    out
}

#[test]
#[ignore = "hundreds of harness runs; run it with --ignored"]
fn campaign() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../target")
        .join(std::env::var("CAMPAIGN_NAME").unwrap_or("campaign".into()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let cases = cases(&dir.join("files"));
    let start = Instant::now();
    let mut results = Vec::new();
    for (i, case) in cases.iter().enumerate() {
        let (outcome, detail) = run(case, &dir);
        if i % 50 == 0 {
            eprintln!(
                "{i}/{} ({:.0} s)",
                cases.len(),
                start.elapsed().as_secs_f64()
            );
        }
        results.push((case, outcome, detail));
    }
    let outcomes = [
        Outcome::CleanError,
        Outcome::Accepted,
        Outcome::NaN,
        Outcome::Panic,
        Outcome::Hang,
        Outcome::UncleanError,
    ];
    let made = harness::provenance::Provenance::capture(String::new());
    let mut md = format!(
        "# Bad-input campaign\n\n{} runs of {} in {:.0} s (`cargo test -p rtapprox-harness --test campaign -- --ignored`), commit {}, {}.\n\n| group | runs | {} |\n| --- | --- |{}\n",
        results.len(),
        std::env::var("CAMPAIGN_HARNESS").unwrap_or("this build's harness".into()),
        start.elapsed().as_secs_f64(),
        made.git_commit,
        made.date_utc,
        outcomes.map(|o| o.label()).join(" | "),
        " --- |".repeat(outcomes.len())
    );
    let mut groups: Vec<&str> = results.iter().map(|(c, _, _)| c.group).collect();
    groups.dedup();
    for group in groups.iter().copied().chain(["all"]) {
        let of_group: Vec<_> = results
            .iter()
            .filter(|(c, _, _)| group == "all" || c.group == group)
            .collect();
        let counts: Vec<String> = outcomes
            .iter()
            .map(|o| {
                of_group
                    .iter()
                    .filter(|(_, x, _)| x == o)
                    .count()
                    .to_string()
            })
            .collect();
        md.push_str(&format!(
            "| {group} | {} | {} |\n",
            of_group.len(),
            counts.join(" | ")
        ));
    }
    md.push_str("\n## Every run that was not a clean error or accepted\n\n");
    for (case, outcome, detail) in &results {
        if !matches!(outcome, Outcome::CleanError | Outcome::Accepted) {
            md.push_str(&format!(
                "- {} / {}: **{}** {detail}\n",
                case.group,
                case.name,
                outcome.label()
            ));
        }
    }
    md.push_str(
        "\n## Every run\n\n| group | case | outcome | message |\n| --- | --- | --- | --- |\n",
    );
    for (case, outcome, detail) in &results {
        md.push_str(&format!(
            "| {} | {} | {} | {} |\n",
            case.group,
            case.name.replace('|', "\\|"),
            outcome.label(),
            detail.replace('|', "\\|")
        ));
    }
    std::fs::write(dir.join("campaign.md"), &md).unwrap();
    println!("{}", md.split("\n## Every run\n").next().unwrap());
    let bad = results
        .iter()
        .filter(|(_, o, _)| !matches!(o, Outcome::CleanError | Outcome::Accepted))
        .count();
    assert_eq!(bad, 0, "see {}", dir.join("campaign.md").display());
}
