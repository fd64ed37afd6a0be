//! The on-disk reference cache: `DIR/.cache/reference-<hash>.{exr,ids,json}`.
//!
//! The key is the ground truth's own key (renderer and options), the scene spec, a hash of the
//! whole scene model (so an edited built-in scene or glTF file is never served stale), the
//! camera, the time and the size. The `.json` file holds the full key and the renderer's
//! statistics; an entry is used only when its stored key matches exactly. Delete the folder to
//! force new references.

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

/// The reference for this view, from `cache_dir` if present, else rendered and stored.
/// Returns it and whether it came from the cache. A broken cache entry is re-rendered.
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
    std::fs::create_dir_all(cache_dir)
        .with_context(|| format!("cannot create {}", cache_dir.display()))?;
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
