//! Mutation fuzzing of the glTF importer on stable Rust: proptest draws a valid seed file
//! (`.glb`, or `.gltf` with a base64 buffer) and a list of byte-level and JSON-level
//! mutations of it, and the importer must return `Ok` with a scene that validates, or an
//! error: never a panic, never an allocation past [`ALLOCATION_CAP`] (a counting global
//! allocator refuses it, which aborts the test process: a failure nobody can miss).
//!
//! `cargo test -p rtapprox-scene --test gltf_fuzz` runs a short campaign ([`DEFAULT_CASES`] cases) and
//! fuzzes the file sandbox with built URIs ([`mutated_uris_stay_in_the_folder`]);
//! `GLTF_FUZZ_CASES=1000000 cargo test -p rtapprox-scene --test gltf_fuzz -- --nocapture` (the dev
//! profile builds `scene` at opt-level 3)
//! runs a long one (docs/reliability.md has the count and the findings of the
//! last). Every input that ever failed is a file in `tests/corpus/`, imported by
//! [`corpus_inputs_never_panic`].

use proptest::prelude::*;
use proptest::test_runner::{Config, FileFailurePersistence, TestRunner};
use serde_json::Value;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use testkit::gltf::{Glb, base64, small_scene};

/// Most bytes the fuzzed process may hold at once: the importer must bound what a file can
/// make it allocate (declared counts, lengths and image sizes are checked before use).
pub const ALLOCATION_CAP: usize = 1 << 30;
/// Cases of the short campaign that `cargo test` runs.
pub const DEFAULT_CASES: u32 = 3000;

struct CountingAllocator;

static LIVE: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size() > ALLOCATION_CAP {
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
            return std::ptr::null_mut();
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

/// The seeds: the small scene as `.glb`, the same with a texture, camera path, volume and
/// motion (every extras field), and a `.gltf` with its buffer as a data URI.
fn seeds() -> Vec<Vec<u8>> {
    let small = small_scene();
    let mut rich = small.clone();
    rich.textures
        .push(scene::builtin::textures::checker_texture(
            "checker",
            8,
            2,
            [200, 200, 200],
            [40, 40, 40],
        ));
    rich.objects[0].material = scene::Material::Diffuse {
        albedo: glam::Vec3::ONE,
        texture: Some(0),
        cutout: None,
    };
    rich.objects[1].motion.keys = vec![(0.0, glam::Vec3::ZERO), (1.0, glam::Vec3::X)];
    rich.camera_path.keys = vec![(0.0, rich.camera), (2.0, rich.camera)];
    rich.volumes.push(scene::Volume {
        name: "smoke".into(),
        center: glam::Vec3::new(0.0, 0.5, 0.0),
        radius: 0.4,
        color: glam::Vec3::splat(0.5),
        density: 1.0,
        profile: scene::DensityProfile::UNIFORM,
        particle: false,
        motion: Default::default(),
    });
    let glb = Glb::from_scene(&small);
    let mut gltf = glb.json.clone();
    gltf["buffers"][0]["uri"] = Value::String(format!(
        "data:application/octet-stream;base64,{}",
        base64(&glb.bin)
    ));
    vec![
        glb.to_bytes(),
        Glb::from_scene(&rich).to_bytes(),
        serde_json::to_vec(&gltf).unwrap(),
    ]
}

/// One edit of a file.
#[derive(Clone, Debug)]
enum Mutation {
    /// Flip bit `bit` of byte `at` (positions are taken modulo the length).
    FlipBit { at: usize, bit: u8 },
    /// Overwrite bytes from `at` with `bytes`.
    Overwrite { at: usize, bytes: Vec<u8> },
    /// Remove `len` bytes from `at`.
    Delete { at: usize, len: usize },
    /// Insert `bytes` at `at`.
    Insert { at: usize, bytes: Vec<u8> },
    /// Cut the file at `at`.
    Truncate { at: usize },
    /// Replace the `node`-th JSON value (pre-order, modulo the count) with `value`.
    JsonReplace { node: usize, value: Value },
    /// Remove the `node`-th JSON value from its object or array.
    JsonRemove { node: usize },
    /// Replace the `node`-th JSON value by a copy of the `from`-th.
    JsonCopy { node: usize, from: usize },
}

/// Values a broken or hostile writer puts where a number, index, string or array belongs.
fn nasty_value() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(Value::Null),
        Just(serde_json::json!(0)),
        Just(serde_json::json!(-1)),
        Just(serde_json::json!(1)),
        Just(serde_json::json!(4294967295u64)),
        Just(serde_json::json!(18446744073709551615u64)),
        Just(serde_json::json!(-9223372036854775808i64)),
        Just(serde_json::json!(1e30)),
        Just(serde_json::json!(-1e30)),
        Just(serde_json::json!(1e-30)),
        Just(serde_json::json!(1.7976931348623157e308)),
        Just(serde_json::json!(0.5)),
        Just(serde_json::json!("")),
        Just(serde_json::json!("../../etc/passwd")),
        Just(serde_json::json!("/dev/zero")),
        Just(serde_json::json!("data:;base64,AAAA")),
        Just(serde_json::json!("%00")),
        Just(serde_json::json!([])),
        Just(serde_json::json!([0, 0, 0])),
        Just(serde_json::json!([1e30, -1e30, 0])),
        Just(serde_json::json!({})),
        Just(serde_json::json!(true)),
        any::<i64>().prop_map(|v| serde_json::json!(v)),
        any::<f32>()
            .prop_filter("finite", |v| v.is_finite())
            .prop_map(|v| serde_json::json!(v)),
    ]
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let bytes = proptest::collection::vec(
        prop_oneof![Just(0u8), Just(0xff), Just(0x7f), Just(0x80), any::<u8>()],
        1..16,
    );
    // Mostly JSON-level edits: a byte edit usually breaks the container or the JSON syntax,
    // which the importer refuses at its first step.
    prop_oneof![
        2 => (any::<usize>(), 0u8..8).prop_map(|(at, bit)| Mutation::FlipBit { at, bit }),
        1 => (any::<usize>(), bytes.clone()).prop_map(|(at, bytes)| Mutation::Overwrite { at, bytes }),
        1 => (any::<usize>(), 1usize..64).prop_map(|(at, len)| Mutation::Delete { at, len }),
        1 => (any::<usize>(), bytes).prop_map(|(at, bytes)| Mutation::Insert { at, bytes }),
        1 => any::<usize>().prop_map(|at| Mutation::Truncate { at }),
        10 => (any::<usize>(), nasty_value())
            .prop_map(|(node, value)| Mutation::JsonReplace { node, value }),
        4 => any::<usize>().prop_map(|node| Mutation::JsonRemove { node }),
        3 => (any::<usize>(), any::<usize>())
            .prop_map(|(node, from)| Mutation::JsonCopy { node, from }),
    ]
}

/// Pre-order count of the JSON values under `v` (itself included).
fn count(v: &Value) -> usize {
    1 + match v {
        Value::Array(a) => a.iter().map(count).sum(),
        Value::Object(o) => o.values().map(count).sum(),
        _ => 0,
    }
}

/// The `n`-th value in pre-order (n < count(v)).
fn nth(v: &mut Value, n: usize) -> &mut Value {
    if n == 0 {
        return v;
    }
    let mut n = n - 1;
    let children: Vec<&mut Value> = match v {
        Value::Array(a) => a.iter_mut().collect(),
        Value::Object(o) => o.values_mut().collect(),
        _ => unreachable!("n < count"),
    };
    for child in children {
        let c = count(child);
        if n < c {
            return nth(child, n);
        }
        n -= c;
    }
    unreachable!("n < count")
}

/// Removes the `n`-th value (n >= 1) from its parent.
fn remove_nth(v: &mut Value, n: usize) {
    let mut n = n - 1;
    match v {
        Value::Array(a) => {
            for i in 0..a.len() {
                let c = count(&a[i]);
                if n == 0 {
                    a.remove(i);
                    return;
                }
                if n < c {
                    return remove_nth(&mut a[i], n);
                }
                n -= c;
            }
        }
        Value::Object(o) => {
            let keys: Vec<String> = o.keys().cloned().collect();
            for k in keys {
                let c = count(&o[&k]);
                if n == 0 {
                    o.remove(&k);
                    return;
                }
                if n < c {
                    return remove_nth(o.get_mut(&k).unwrap(), n);
                }
                n -= c;
            }
        }
        _ => {}
    }
}

/// Applies the JSON mutations to the file's JSON (the `.glb`'s JSON chunk or the whole
/// `.gltf`), then the byte mutations to the file.
fn apply(seed: &[u8], mutations: &[Mutation]) -> Vec<u8> {
    let is_glb = seed.starts_with(b"glTF");
    let mut json: Value = if is_glb {
        Glb::parse(seed).json
    } else {
        serde_json::from_slice(seed).unwrap()
    };
    for m in mutations {
        let total = count(&json);
        match m {
            Mutation::JsonReplace { node, value } => *nth(&mut json, node % total) = value.clone(),
            Mutation::JsonRemove { node } if total > 1 => {
                remove_nth(&mut json, 1 + node % (total - 1))
            }
            Mutation::JsonCopy { node, from } => {
                let copied = nth(&mut json, from % total).clone();
                if count(&copied) < 10_000 {
                    *nth(&mut json, node % total) = copied;
                }
            }
            _ => {}
        }
    }
    let mut bytes = if is_glb {
        Glb {
            json,
            bin: Glb::parse(seed).bin,
        }
        .to_bytes()
    } else {
        serde_json::to_vec(&json).unwrap()
    };
    for m in mutations {
        let len = bytes.len().max(1);
        match m {
            Mutation::FlipBit { at, bit } if !bytes.is_empty() => bytes[at % len] ^= 1 << bit,
            Mutation::Overwrite { at, bytes: b } => {
                for (i, v) in b.iter().enumerate() {
                    if let Some(x) = bytes.get_mut((at % len) + i) {
                        *x = *v;
                    }
                }
            }
            Mutation::Delete { at, len: n } if !bytes.is_empty() => {
                let start = at % len;
                let end = (start + n).min(bytes.len());
                bytes.drain(start..end);
            }
            Mutation::Insert { at, bytes: b } => {
                let at = at % (bytes.len() + 1);
                bytes.splice(at..at, b.iter().copied());
            }
            Mutation::Truncate { at } => bytes.truncate(at % len),
            _ => {}
        }
    }
    bytes
}

/// Imports `bytes`: an error is fine, a scene must validate with finite numbers.
fn check(bytes: &[u8], name: &str) -> Result<bool, TestCaseError> {
    match scene::gltf_io::import_slice(bytes, name) {
        Ok(scene) => {
            prop_assert!(scene.validate().is_ok(), "{:?}", scene.validate());
            prop_assert!(!scene.objects.is_empty() && !scene.lights.is_empty());
            Ok(true)
        }
        Err(e) => {
            let message = e.to_string();
            prop_assert!(!message.contains('\0'), "raw NUL in {message:?}");
            Ok(false)
        }
    }
}

/// The fuzz campaign: `GLTF_FUZZ_CASES` cases (default [`DEFAULT_CASES`]); prints how many
/// inputs imported and how many were refused.
#[test]
fn mutated_files_import_or_fail_cleanly() {
    let cases = std::env::var("GLTF_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    let seeds = seeds();
    let strategy = (0..seeds.len(), proptest::collection::vec(mutation(), 1..4));
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::Off)),
        ..Config::default()
    });
    let imported = std::cell::Cell::new(0u64);
    let start = std::time::Instant::now();
    let result = runner.run(&strategy, |(seed, mutations)| {
        let bytes = apply(&seeds[seed], &mutations);
        let name = if seeds[seed].starts_with(b"glTF") {
            "fuzz.glb"
        } else {
            "fuzz.gltf"
        };
        if check(&bytes, name)? {
            imported.set(imported.get() + 1);
        }
        Ok(())
    });
    println!(
        "gltf fuzz: {cases} cases in {:.1} s, {} imported, {} refused with an error",
        start.elapsed().as_secs_f64(),
        imported.get(),
        cases as u64 - imported.get()
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    assert!(
        imported.get() > 0,
        "no mutated file imported: the mutations are too coarse"
    );
}

/// What each named corpus file must give: `Ok` (it loads and validates) or an error
/// containing the text. Files not named (fuzz findings) must only not panic.
const CORPUS_OUTCOMES: &[(&str, Result<(), &str>)] = &[
    ("valid-floor.gltf", Ok(())),
    ("no-lights.gltf", Ok(())),
    ("zero-normals.gltf", Ok(())),
    ("buffer-etc-passwd.gltf", Err("absolute path")),
    ("buffer-dev-zero.gltf", Err("absolute path")),
    ("buffer-parent-dirs.gltf", Err("outside the glTF's folder")),
    (
        "buffer-percent-parent.gltf",
        Err("outside the glTF's folder"),
    ),
    ("buffer-percent-nul.gltf", Err("control characters")),
    ("scale-1e19.gltf", Err("world coordinates up to")),
    ("scale-flat.gltf", Err("singular")),
    ("metal-negative-n.gltf", Err("outside [0, 10]")),
    ("metal-huge-k.gltf", Err("outside [0, 10]")),
    ("camera-up-parallel.gltf", Ok(())),
    ("camera-skewed-matrix.gltf", Ok(())),
];

/// Every file in `tests/corpus/` (inputs that once failed, from the campaign or from
/// fuzzing) imports or fails with an error, never a panic; the named ones give their outcome.
#[test]
fn corpus_inputs_never_panic() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/corpus");
    let mut seen = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !(name.ends_with(".glb") || name.ends_with(".gltf")) {
            continue;
        }
        let result = scene::gltf_io::import_noted(&path);
        if let Ok((scene, _)) = &result {
            scene.validate().unwrap();
            assert!(!scene.lights.is_empty(), "{name}: no light");
        }
        if let Some((_, expected)) = CORPUS_OUTCOMES.iter().find(|(n, _)| *n == name) {
            match (expected, &result) {
                (Ok(()), Err(e)) => panic!("{name} should load: {e}"),
                (Err(text), Ok(_)) => panic!("{name} loaded; expected an error with \"{text}\""),
                (Err(text), Err(e)) => {
                    assert!(e.to_string().contains(text), "{name}: {e}")
                }
                (Ok(()), Ok(_)) => {}
            }
        }
        seen.push(name);
    }
    for (name, _) in CORPUS_OUTCOMES {
        assert!(
            seen.iter().any(|s| s == name),
            "{name} is missing from the corpus"
        );
    }
}

/// The sandbox, fuzzed: buffer URIs built from path pieces (`..` in every spelling, slashes,
/// names of a file inside the folder, of one outside it, and of a symbolic link inside that
/// points outside) never import the outside file's bytes: a file that imports names the file
/// inside the folder.
#[test]
fn mutated_uris_stay_in_the_folder() {
    let root = std::env::temp_dir().join(format!("gltf-fuzz-uris-{}", std::process::id()));
    let folder = root.join("scene");
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&folder).unwrap();
    let glb = Glb::from_scene(&small_scene());
    std::fs::write(folder.join("inside.bin"), &glb.bin).unwrap();
    std::fs::write(root.join("outside.bin"), &glb.bin).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(root.join("outside.bin"), folder.join("link.bin")).unwrap();
    let piece = prop_oneof![
        Just(".."),
        Just("%2e%2e"),
        Just("%2E%2E"),
        Just(".%2e"),
        Just("."),
        Just("scene"),
        Just("inside.bin"),
        Just("outside.bin"),
        Just("link.bin"),
        Just("%2f"),
        Just(""),
        Just("%00"),
    ];
    let uri = (any::<bool>(), proptest::collection::vec(piece, 1..6))
        .prop_map(|(root, p)| format!("{}{}", if root { "/" } else { "" }, p.join("/")));
    let mut runner = TestRunner::new(Config {
        cases: 2000,
        failure_persistence: Some(Box::new(FileFailurePersistence::Off)),
        ..Config::default()
    });
    let imported = std::cell::Cell::new(0);
    runner
        .run(&uri, |uri| {
            let path = glb.write_gltf(&folder, "fuzz", Some(&uri));
            if scene::gltf_io::import(&path).is_ok() {
                imported.set(imported.get() + 1);
                let decoded = uri
                    .replace("%2e", ".")
                    .replace("%2E", ".")
                    .replace("%2f", "/");
                prop_assert!(
                    decoded.ends_with("inside.bin") && !decoded.contains("outside"),
                    "{uri} imported"
                );
            }
            Ok(())
        })
        .unwrap();
    println!(
        "uri fuzz: {} of 2000 URIs imported (all naming the file inside)",
        imported.get()
    );
    assert!(
        imported.get() > 0,
        "no URI reached the file inside the folder"
    );
}
