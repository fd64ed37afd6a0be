//! The on-disk reference cache: `DIR/.cache/reference-<hash>.{exr,ids,json}`.
//!
//! The key is the ground truth's own key (renderer and options), the scene spec, a hash of the
//! whole scene model (so an edited built-in scene or glTF file is never served stale), the
//! camera, the time and the size. The `.json` file holds the full key and the renderer's
//! statistics; an entry is used only when its stored key matches exactly. Delete the folder to
//! force new references. A miss says why ([`miss_reason`]): the cache holds no entry of the
//! scene, or what its nearest entry differs in.

use crate::{GroundTruth, Reference, ReferenceStats, Size, images};
use anyhow::{Context as _, Result};
use scene::{Camera, Scene};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// 64-bit FNV-1a, written to through `fmt::Write` so large `Debug` output is hashed without
/// being stored.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 ^= x as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

impl std::fmt::Write for Fnv {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.bytes(s.as_bytes());
        Ok(())
    }
}

/// Stable hash of a scene model (every mesh, material, light, camera and path).
pub fn scene_hash(scene: &Scene) -> u64 {
    let mut h = Fnv::new();
    let _ = write!(h, "{scene:?}");
    h.0
}

/// One view of one scene, as the reference renders it.
#[derive(Clone, Copy, Debug)]
pub struct RefView<'a> {
    /// The spec the scene was loaded from (built-in spec or path).
    pub spec: &'a str,
    pub scene: &'a Scene,
    pub camera: Camera,
    pub time: f32,
    pub size: Size,
}

/// The full cache key of one reference image.
pub fn reference_key(truth: &dyn GroundTruth, view: &RefView) -> String {
    format!(
        "v3 | {} | scene {} #{:016x} | camera {:?} | time {} | size {}",
        truth.key(),
        view.spec,
        scene_hash(view.scene),
        view.camera,
        view.time,
        view.size
    )
}

#[derive(serde::Serialize, serde::Deserialize)]
struct Entry {
    key: String,
    stats: ReferenceStats,
}

/// Where the files of one key live (without extension).
fn stem(dir: &Path, key: &str) -> PathBuf {
    let mut h = Fnv::new();
    h.bytes(key.as_bytes());
    dir.join(format!("reference-{:016x}", h.0))
}

/// Where a reference came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Cached {
    /// The cache's entry for this exact key.
    Hit,
    /// Rendered, and why the cache could not serve it ([`miss_reason`]).
    Miss(String),
}

/// Whether `cache_dir` holds this view's reference, and if not, why ([`miss_reason`]): what
/// a run asks of every view before it renders any, so that the reasons describe the cache as
/// the run found it.
pub fn status(cache_dir: &Path, truth: &dyn GroundTruth, view: &RefView) -> Cached {
    let key = reference_key(truth, view);
    let json = stem(cache_dir, &key).with_extension("json");
    let entry = std::fs::read_to_string(json).ok();
    match entry.and_then(|text| serde_json::from_str::<Entry>(&text).ok()) {
        Some(entry) if entry.key == key => Cached::Hit,
        _ => Cached::Miss(miss_reason(cache_dir, &key)),
    }
}

/// The reference for this view, from `cache_dir` if present, else rendered and stored; the
/// second value says whether it came from the cache. A broken cache entry is re-rendered.
pub fn reference(
    cache_dir: &Path,
    truth: &dyn GroundTruth,
    view: &RefView,
) -> Result<(Reference, bool)> {
    let (width, height) = (view.size.width, view.size.height);
    let key = reference_key(truth, view);
    let stem = stem(cache_dir, &key);
    let paths = (
        stem.with_extension("json"),
        stem.with_extension("exr"),
        stem.with_extension("ids"),
    );
    if let Some(found) = load(&paths, &key, width, height) {
        return Ok((found, true));
    }
    // Before the render: a folder that cannot be made fails now, not after minutes of work.
    std::fs::create_dir_all(cache_dir)
        .with_context(|| format!("cannot create the reference cache {}", cache_dir.display()))?;
    let reference = truth.render(view.scene, &view.camera, view.time, width, height)?;
    let n = (width * height) as usize;
    anyhow::ensure!(
        reference.image.width == width
            && reference.image.height == height
            && reference.image.pixels.len() == n
            && reference.object_ids.len() == n
            && reference.mask.len() == n,
        "the reference renderer returned an image of the wrong size"
    );
    images::write_exr(&paths.1, &reference.image)?;
    images::write_ids(
        &paths.2,
        width,
        height,
        &reference.object_ids,
        &reference.mask,
    )?;
    let entry = Entry {
        key,
        stats: reference.stats.clone(),
    };
    std::fs::write(&paths.0, serde_json::to_string_pretty(&entry)?)
        .with_context(|| format!("cannot write {}", paths.0.display()))?;
    Ok((reference, false))
}

/// [`reference`] with where it came from, given the view's [`status`] asked before rendering:
/// a hit, or a miss with its reason (an entry found but unreadable is a miss too).
pub fn reference_as_found(
    cache_dir: &Path,
    truth: &dyn GroundTruth,
    view: &RefView,
    found: Cached,
) -> Result<(Reference, Cached)> {
    let (reference, cached) = reference(cache_dir, truth, view)?;
    let how = match (cached, found) {
        (true, _) => Cached::Hit,
        (false, Cached::Miss(reason)) => Cached::Miss(reason),
        (false, Cached::Hit) => Cached::Miss(UNREADABLE.into()),
    };
    Ok((reference, how))
}

/// Why an entry whose key matches was still rendered again.
const UNREADABLE: &str = "its cache entry could not be read back";

/// The parts of a key ([`reference_key`]) with what a difference in each means to a user.
const KEY_PARTS: [(&str, &str); 6] = [
    ("v", "the cache's format"),
    ("cpu-reference", "the ground truth's options (--ref-*)"),
    (
        "scene",
        "the scene model (an edited scene or glTF file, or another version of a built-in scene)",
    ),
    ("camera", "the camera"),
    ("time", "the time"),
    ("size", "the image size"),
];

/// A key's six parts ([`reference_key`]): format, ground truth, scene (spec and model hash),
/// camera, time, size. The ground truth's key may itself hold the separator, so the last four
/// are taken from the right.
fn key_parts(key: &str) -> Option<Vec<String>> {
    let parts: Vec<&str> = key.split(" | ").collect();
    let n = parts.len();
    if n < KEY_PARTS.len() {
        return None;
    }
    let mut out = vec![parts[0].to_string(), parts[1..n - 4].join(" | ")];
    out.extend(parts[n - 4..].iter().map(|p| p.to_string()));
    Some(out)
}

/// Why `cache_dir` holds no entry for `key`: that it holds none of this scene, or what the
/// nearest entry of the same scene (the fewest parts different) differs in.
pub fn miss_reason(cache_dir: &Path, key: &str) -> String {
    let none = "no cached reference of this scene".to_string();
    let Some(wanted) = key_parts(key) else {
        return none;
    };
    let spec_of = |p: &[String]| p[2].rsplit_once(" #").map(|(spec, _)| spec.to_string());
    let entries: Vec<Vec<String>> = std::fs::read_dir(cache_dir)
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| e.path().extension().is_some_and(|x| x == "json"))
        .filter_map(|e| std::fs::read_to_string(e.path()).ok())
        .filter_map(|text| serde_json::from_str::<Entry>(&text).ok())
        .filter_map(|entry| key_parts(&entry.key))
        .filter(|p| spec_of(p) == spec_of(&wanted))
        .collect();
    let differing = |p: &Vec<String>| -> Vec<&str> {
        (0..wanted.len())
            .filter(|&i| p[i] != wanted[i])
            .map(|i| KEY_PARTS[i].1)
            .collect()
    };
    match entries.iter().map(differing).min_by_key(|d| d.len()) {
        None => none,
        Some(d) if d.is_empty() => UNREADABLE.into(),
        Some(d) => format!(
            "the nearest cached reference of this scene differs in {}",
            d.join(" and ")
        ),
    }
}

fn load(
    paths: &(PathBuf, PathBuf, PathBuf),
    key: &str,
    width: u32,
    height: u32,
) -> Option<Reference> {
    let entry: Entry = serde_json::from_str(&std::fs::read_to_string(&paths.0).ok()?).ok()?;
    if entry.key != key {
        return None;
    }
    let image = images::read_exr(&paths.1).ok()?;
    let (w, h, object_ids, mask) = images::read_ids(&paths.2).ok()?;
    if (image.width, image.height, w, h) != (width, height, width, height) {
        return None;
    }
    Some(Reference {
        image,
        object_ids,
        mask,
        stats: entry.stats,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(options: &str, hash: &str, time: &str) -> String {
        format!(
            "v3 | cpu-reference {options} | scene my.glb #{hash} | camera C | time {time} | size 64x64"
        )
    }

    fn store(dir: &Path, key: &str) {
        let entry = Entry {
            key: key.to_string(),
            stats: ReferenceStats::default(),
        };
        let path = stem(dir, key).with_extension("json");
        std::fs::write(path, serde_json::to_string(&entry).unwrap()).unwrap();
    }

    /// A miss names what the nearest cached entry of the same scene differs in (the fewest
    /// parts), or that the cache holds none of the scene.
    #[test]
    fn a_miss_names_what_the_nearest_entry_of_the_scene_differs_in() {
        let dir = std::env::temp_dir().join(format!("harness-cache-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let none = "no cached reference of this scene";
        assert_eq!(miss_reason(&dir, &key("a", "01", "0")), none);
        store(&dir, &key("a", "01", "0"));
        store(&dir, &key("b", "02", "0.5"));
        let says = |k: &str, what: &str| {
            let reason = miss_reason(&dir, k);
            assert!(reason.ends_with(&format!("differs in {what}")), "{reason}");
        };
        says(&key("a", "02", "0"), KEY_PARTS[2].1);
        says(&key("a", "01", "1"), "the time");
        says(&key("c", "01", "0"), "the ground truth's options (--ref-*)");
        says(
            &key("c", "03", "2"),
            "the ground truth's options (--ref-*) and the scene model \
             (an edited scene or glTF file, or another version of a built-in scene) and the time",
        );
        let other_scene = key("a", "01", "0").replace("my.glb", "other.glb");
        assert_eq!(miss_reason(&dir, &other_scene), none);
        // A ground truth whose own key holds the separator: the parts are read from the right.
        store(&dir, &key("x | y", "01", "0"));
        says(&key("x | y", "01", "9"), "the time");
        // An entry whose key matches but whose files are gone reads as broken, not as a match.
        assert_eq!(
            miss_reason(&dir, &key("a", "01", "0")),
            "its cache entry could not be read back"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
