//! glTF 2.0 import (`.gltf` and `.glb`) and binary glTF (`.glb`) export.
//!
//! The export is lossless for every [`Scene`] without a [`crate::Morph`]:
//! `import_slice(&to_glb_bytes(&s)?, ..) == s` (every built-in scene is checked by
//! `tests/gltf_roundtrip.rs`). A deforming object is exported as it is at time 0 (its
//! [`crate::Object::positions_at`] and [`crate::Object::normals_at`] of time 0 as the mesh)
//! and its morph target and weight keys are not written: the import reads glTF morph targets
//! no more than those of other files. The core glTF written
//! beside the exact data is chosen so that a viewer such as Blender shows something sensible;
//! the exact workspace data lives in `extras` under the key [`EXTRAS_KEY`] (`"scene_model"`).
//! The importer also reads files written by other tools, with the mapping below.
//!
//! # What maps to what (import)
//!
//! - **Scene**: the default glTF scene, else the first scene, else every root node. Its name
//!   is `extras.scene_model.name`, else the glTF scene name, else the file name without its
//!   extension. Nodes are visited depth first, children in order.
//! - **Objects**: one [`Object`] per triangle primitive of each node with a mesh. The mesh
//!   data stays in object space; `transform` is the product of the node matrices from the
//!   root down (a TRS node is `T * R * S`). The name is the node name, else the mesh name,
//!   else `node N`, with ` #k` appended when the mesh has several triangle primitives.
//! - **Mesh data**: `POSITION`, `NORMAL`, `TEXCOORD_n` (n = the base colour texture's
//!   `texCoord`, default 0) and `indices`, of any component type (normalized integers are
//!   scaled as the spec says; sparse accessors are applied). Missing indices are generated
//!   (0, 1, 2, ...); a missing `NORMAL` gives flat normals (the triangles are unwelded, as the
//!   spec asks); missing texture coordinates are zeros.
//! - **Primitive modes**: `TRIANGLES`, and `TRIANGLE_STRIP` and `TRIANGLE_FAN` unrolled into
//!   triangle lists. `POINTS` and the `LINE*` modes are **skipped**: they have no surface to
//!   render, and neither has a primitive with fewer than three vertices. A file with no
//!   triangle at all is an error.
//! - **Glass**: a material with a `KHR_materials_transmission` factor above 0.5 becomes
//!   [`Material::Glass`] with the `KHR_materials_ior` value (default 1.5).
//! - **Metal**: a material with `metallicFactor` >= 0.5 and `roughnessFactor` <= 0.5 becomes
//!   [`Material::Metal`] with k = 0 and n = (1 - sqrt(c)) / (1 + sqrt(c)) per channel, c =
//!   the base colour factor clamped to [0, 1]. The seeds' Fresnel approximation is Schlick's
//!   form F0 + (1 - F0)(1 - cos)^5 with F0 = ((n-1)^2 + k^2) / ((n+1)^2 + k^2), so this
//!   gives F0 = c and the reflectance, at every angle, of any (n, k) with that F0. A white
//!   base colour gives n = 0: a perfect mirror.
//! - **Diffuse**: every other material (a rough metal and the spec's default material
//!   included) becomes [`Material::Diffuse`]: albedo = the base colour factor (RGB, linear),
//!   texture = the base colour texture.
//! - **Textures**: the images used as base colour textures (every image, in files this
//!   module wrote), PNG or JPEG, from a buffer view, a base64 `data:` URI or a file relative
//!   to the `.gltf`, decoded to sRGB RGBA8, in image order. Samplers and
//!   `KHR_texture_transform` are ignored: textures always repeat and filter bilinearly.
//! - **Roles**: glass is refractor + caustic caster, metal is reflector + caustic caster,
//!   diffuse has none; `extras.scene_model.roles` overrides them.
//! - **Lights**: each `KHR_lights_punctual` point light becomes a [`PointLight`] at its
//!   node's world position with intensity (W/sr) = colour * intensity (cd) / 683, 683 lm/W
//!   being the luminous efficacy of 555 nm light that defines the candela. `range` is
//!   ignored; spot and directional lights are skipped. A file without any point light gets
//!   the default lighting of [`Scene::add_default_lighting`] (a key light from the camera's
//!   upper side and a uniform sky), and a note says so ([`import_noted`]).
//! - **Normals**: zero-length or non-finite normals are replaced by geometric ones
//!   ([`Mesh::repair_normals`]), with a note.
//! - **Camera**: the first perspective camera node met becomes [`Scene::camera`]: eye = the
//!   node's origin, looking down its -Z with its +Y up, fov = `yfov` in degrees, target on
//!   the view direction at the distance of the centre of the objects' bounds. Orthographic
//!   cameras are skipped. With no camera, the camera frames the bounds of all objects (45
//!   degrees, from the +Z side and a little above).
//!
//! Skins, morph targets, animations, emission, alpha and the remaining material inputs are
//! ignored. A node transform with a negative determinant is kept as it is (the winding of
//! its triangles is then mirrored in world space).
//!
//! # What the exporter writes
//!
//! One buffer (the `.glb` BIN chunk). Per object: one node (name = object name, `matrix` =
//! the object's transform, omitted when it is the identity), one mesh with one `TRIANGLES`
//! primitive whose `POSITION`, `NORMAL`, `TEXCOORD_0` are `f32` accessors and `indices` a
//! `u32` accessor, and one material:
//!
//! - diffuse: `baseColorFactor` = albedo clamped to [0, 1], `metallicFactor` 0,
//!   `roughnessFactor` 1, `baseColorTexture` = the texture;
//! - metal: `metallicFactor` 1, `roughnessFactor` 0, `baseColorFactor` = the normal-incidence
//!   reflectance ((n-1)^2 + k^2) / ((n+1)^2 + k^2) per channel;
//! - glass: white base colour, `metallicFactor` 0, `roughnessFactor` 0,
//!   `KHR_materials_transmission` 1 and `KHR_materials_ior` = ior (an ior below 1, which the
//!   extension does not allow, is written as 1 / ior: the same interface seen from the
//!   other side).
//!
//! Every texture becomes an embedded PNG image (RGBA8, exact) and a texture with a
//! repeat/linear sampler. Each point light becomes a node (translation = position) with a
//! `KHR_lights_punctual` point light of colour = intensity / max(intensity) and intensity
//! = 683 * max(intensity) candela. The scene camera becomes a camera node (`yfov` in
//! radians, `znear`/`zfar` = [`Camera::NEAR`]/[`Camera::FAR`]). Motion keys, building
//! room sizes, volumes and the camera path are not expressed in core glTF (no animations
//! are written); they exist only in `extras`.
//!
//! # The extras schema (version 1)
//!
//! Every exact value lives in the `extras` of the glTF object it belongs to, under the key
//! `"scene_model"`. Numbers are the model's `f32` values written as JSON numbers (the exact
//! `f64` of each `f32`, so they read back bit for bit); vectors are `[x, y, z]` arrays.
//! Roles are the names of [`Roles::ALL`].
//!
//! ```text
//! scenes[0].extras    { "scene_model": {
//!                         "version": 1, "name": "cornell-sphere", "background": [r, g, b],
//!                         "camera_path": [ { "time": t, "eye": [..], "target": [..],
//!                                            "up": [..], "fov_y_deg": f }, .. ],
//!                         "volumes": [ { "name": "smoke", "center": [..], "radius": r,
//!                                        "color": [..], "density": d, "particle": false,
//!                                        "profile": { "falloff": k, "noise": a,
//!                                                     "noise_frequency": f },
//!                                        "motion": [ { "time": t, "offset": [..] }, .. ] } ],
//!                         "medium": { "name": "water", "min": [..], "max": [..],
//!                                     "scattering": [..], "absorption": [..],
//!                                     "anisotropy": g } } }   ("medium": only when there is one)
//! nodes[i].extras     { "scene_model": {                       (an object's node)
//!                         "roles": ["refractor", "caustic-caster"],
//!                         "motion": [ { "time": t, "offset": [..] }, .. ],
//!                         "building": { "room_size": [..] } } }   ("building": buildings only)
//! nodes[i].extras     { "scene_model": { "eye": [..], "target": [..], "up": [..],
//!                                        "fov_y_deg": f } }   (the camera node)
//! materials[i].extras { "scene_model": { "kind": "diffuse", "albedo": [..] } }
//!                     { "scene_model": { "kind": "metal", "n": [..], "k": [..] } }
//!                     { "scene_model": { "kind": "glass", "ior": x } }
//! KHR_lights_punctual lights[i].extras
//!                     { "scene_model": { "intensity": [r, g, b] } }   (W/sr)
//! ```
//!
//! A diffuse material's texture is its core `baseColorTexture` (exact already).
//!
//! Object transforms and light positions are always read from the nodes (which hold them
//! exactly), so moving things in an editor is respected. The exact camera and light
//! intensity in `extras` are used only while they agree with the core glTF camera node and
//! light (to 1e-4); if an editor changed those, the core values win. Materials, roles,
//! motion, buildings, volumes, the camera path and the background come from `extras`
//! whenever present. An `extras.scene_model.version` above 1 is an error.
//!
//! # Errors
//!
//! A missing or unreadable file is [`SceneError::Io`]. Anything wrong with the content (bad
//! JSON, a truncated `.glb`, an accessor or index out of range, a non-finite node
//! transform, an undecodable image, a node hierarchy with a cycle, a scene that fails
//! [`Scene::validate`]) is [`SceneError::Gltf`] with one sentence naming the offending
//! element. Exporting a scene that fails [`Scene::validate`], has a non-finite value that
//! `validate` does not check, or has an empty mesh is [`SceneError::Invalid`].
//!
//! Files: the `.gltf`/`.glb` itself and every external buffer or image must be a regular file
//! (a FIFO, a device or a folder is refused before it is opened) of at most
//! [`MAX_FILE_BYTES`]; external files must lie inside the glTF's folder once `..`, `%2e%2e` and
//! symbolic links are resolved (absolute paths are refused), so a file cannot make the importer
//! read `/etc/passwd`; of a buffer only its declared `byteLength` is read; images may have at
//! most [`MAX_TEXTURE_SIDE`] texels per side. Messages escape control characters (a `%00` in a
//! URI prints as `\0`).
//!
//! No malformed input may panic, and no `catch_unwind` is used: the importer parses the
//! `.glb` container, resolves URIs and reads accessors with its own code, checking every
//! offset and length before touching buffer data. The `gltf` crate (1.4.1) is used for the
//! JSON schema and its validation, less the places where it panics on input that passes
//! its validation, which are avoided: its validation indexes `accessors[POSITION]` without
//! a bounds check (checked here first), and `Image::source` and `Camera::projection` unwrap
//! optional fields (their JSON is read directly). `tests/gltf_import.rs` fuzzes the
//! importer structurally (every JSON value removed or replaced) and with bit flips;
//! `tests/gltf_fuzz.rs` by random byte- and JSON-level mutations under an allocation cap, and
//! replays `tests/corpus/`.

use crate::{
    Building, Camera, CameraPath, DensityProfile, Material, Mesh, Motion, Object, PointLight,
    Roles, Scene, SceneError, Texture, Volume,
};
use glam::{Mat3, Mat4, Quat, Vec2, Vec3};
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};
use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The key under which the exact workspace data sits in every `extras` object.
pub const EXTRAS_KEY: &str = "scene_model";
/// Version of the extras schema this module writes and the newest it reads.
pub const EXTRAS_VERSION: u32 = 1;
/// Luminous efficacy (lm/W) used to convert between candela and W/sr.
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Imports a `.gltf` (with its external buffers and images, resolved relative to it) or a
/// `.glb` file.
pub fn import(path: &Path) -> Result<Scene, SceneError> {
    import_noted(path).map(|(scene, _)| scene)
}

/// [`import`], with the notes of what the importer supplied or repaired (default lighting
/// for a file without lights, replaced degenerate normals), one sentence each: the harness
/// prints them as warnings and writes them to `results.json`.
pub fn import_noted(path: &Path) -> Result<(Scene, Vec<String>), SceneError> {
    let shown = shown_path(path);
    let bytes = read_regular_file(path, MAX_FILE_BYTES, false, false)
        .map_err(|e| SceneError::Io(shown.clone(), e))?;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let base = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    finish(import_impl(&bytes, &stem, Some(base)), &shown)
}

/// Imports a `.gltf` or `.glb` held in memory; `name` is used in error messages and as the
/// scene name when the file has none. External file references are errors (there is no
/// folder to resolve them against); `data:` URIs and `.glb` buffers work.
pub fn import_slice(bytes: &[u8], name: &str) -> Result<Scene, SceneError> {
    import_slice_noted(bytes, name).map(|(scene, _)| scene)
}

/// [`import_slice`] with the importer's notes (see [`import_noted`]).
pub fn import_slice_noted(bytes: &[u8], name: &str) -> Result<(Scene, Vec<String>), SceneError> {
    let stem = name
        .strip_suffix(".glb")
        .or_else(|| name.strip_suffix(".gltf"))
        .unwrap_or(name);
    let stem = Path::new(stem)
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    finish(import_impl(bytes, &stem, None), &printable(name))
}

/// Writes `scene` as a binary glTF file.
pub fn export_glb(scene: &Scene, path: &Path) -> Result<(), SceneError> {
    let bytes = to_glb_bytes(scene)?;
    std::fs::write(path, bytes).map_err(|e| SceneError::Write(shown_path(path), e.to_string()))
}

/// Encodes `scene` as binary glTF (see the module documentation for the layout).
pub fn to_glb_bytes(scene: &Scene) -> Result<Vec<u8>, SceneError> {
    scene.validate()?;
    check_finite_extras(scene).map_err(SceneError::Invalid)?;
    Exporter::default().run(scene)
}

fn finish(
    result: Result<(Scene, Vec<String>), String>,
    shown: &str,
) -> Result<(Scene, Vec<String>), SceneError> {
    let (scene, notes) = result.map_err(|m| SceneError::Gltf(shown.to_string(), m))?;
    let invalid =
        |m: String| SceneError::Gltf(shown.to_string(), format!("the scene is invalid: {m}"));
    scene.validate().map_err(|e| match e {
        SceneError::Invalid(m) => invalid(m),
        other => other,
    })?;
    // What `validate` does not look at (volumes, motion keys, the camera path, ...).
    check_finite_extras(&scene).map_err(invalid)?;
    Ok((scene, notes))
}

/// Largest `.gltf`/`.glb` file, and largest external buffer or image file, the importer reads
/// (1 GiB): a bound on what a path to `/dev/zero` or a runaway file can cost.
pub const MAX_FILE_BYTES: u64 = 1 << 30;
/// Largest width or height of a decoded texture, and most bytes its decoder may allocate.
pub const MAX_TEXTURE_SIDE: u32 = 16384;
const MAX_IMAGE_DECODE_BYTES: u64 = 512 << 20;

/// A path as messages show it: control characters (a NUL from `%00`) escaped.
fn shown_path(path: &Path) -> String {
    printable(&path.display().to_string())
}

/// `text` with control characters escaped (`\0`, `\n`), so no message prints raw bytes.
fn printable(text: &str) -> String {
    text.chars()
        .flat_map(|c| {
            let escaped: Vec<char> = if c.is_control() {
                c.escape_debug().collect()
            } else {
                vec![c]
            };
            escaped
        })
        .collect()
}

/// Reads a regular file: all of it when it holds at most `limit` bytes, else, with
/// `first_bytes`, its first `limit` bytes (a buffer's declared byteLength) and without, an
/// error. FIFOs, devices and folders are refused without reading (a FIFO would block forever,
/// `/dev/zero` never ends). `resolved`: the path has been resolved and checked to lie in the
/// glTF's folder, so a symbolic link in its last component can only be a swap since then,
/// and is refused.
fn read_regular_file(
    path: &Path,
    limit: u64,
    first_bytes: bool,
    resolved: bool,
) -> Result<Vec<u8>, String> {
    use std::io::Read as _;
    // Opened without blocking (a FIFO would block in `open` itself) and, where the system
    // has it, without following a symbolic link in the last component; the *open handle* is
    // then checked, so a file swapped after the folder check cannot slip through.
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        let no_follow = if resolved { libc::O_NOFOLLOW } else { 0 };
        options.custom_flags(libc::O_NONBLOCK | no_follow);
    }
    #[cfg(not(unix))]
    let _ = resolved;
    let file = options.open(path).map_err(|e| e.to_string())?;
    let meta = file.metadata().map_err(|e| e.to_string())?;
    if !meta.is_file() {
        return Err("it is not a regular file (a folder, device or FIFO)".into());
    }
    if meta.len() > limit && !first_bytes {
        return Err(format!(
            "it holds {} bytes, more than the {limit} the importer reads",
            meta.len()
        ));
    }
    let mut bytes = Vec::with_capacity(meta.len().min(limit) as usize);
    file.take(limit)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    Ok(bytes)
}

// ---------------------------------------------------------------------------------------
// Extras schema
// ---------------------------------------------------------------------------------------

type V3 = [f64; 3];

fn v3(v: Vec3) -> V3 {
    [v.x as f64, v.y as f64, v.z as f64]
}
fn vec3(a: V3) -> Vec3 {
    Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32)
}

#[derive(Serialize, Deserialize)]
struct SceneExtras {
    version: u32,
    name: String,
    background: V3,
    #[serde(default)]
    camera_path: Vec<CameraKeyExtras>,
    #[serde(default)]
    volumes: Vec<VolumeExtras>,
    /// The homogeneous scattering medium, when the scene has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    medium: Option<MediumExtras>,
}

#[derive(Serialize, Deserialize)]
struct MediumExtras {
    name: String,
    min: V3,
    max: V3,
    scattering: V3,
    absorption: V3,
    anisotropy: f64,
}

impl MediumExtras {
    fn from_medium(m: &crate::Medium) -> Self {
        Self {
            name: m.name.clone(),
            min: v3(m.min),
            max: v3(m.max),
            scattering: v3(m.scattering),
            absorption: v3(m.absorption),
            anisotropy: m.anisotropy as f64,
        }
    }
    fn medium(&self) -> crate::Medium {
        crate::Medium {
            name: self.name.clone(),
            min: vec3(self.min),
            max: vec3(self.max),
            scattering: vec3(self.scattering),
            absorption: vec3(self.absorption),
            anisotropy: self.anisotropy as f32,
        }
    }
}

#[derive(Serialize, Deserialize)]
struct CameraExtras {
    eye: V3,
    target: V3,
    up: V3,
    fov_y_deg: f64,
}

impl CameraExtras {
    fn from_camera(c: &Camera) -> Self {
        Self {
            eye: v3(c.eye),
            target: v3(c.target),
            up: v3(c.up),
            fov_y_deg: c.fov_y_deg as f64,
        }
    }
    fn camera(&self) -> Camera {
        Camera {
            eye: vec3(self.eye),
            target: vec3(self.target),
            up: vec3(self.up),
            fov_y_deg: self.fov_y_deg as f32,
        }
    }
}

#[derive(Serialize, Deserialize)]
struct CameraKeyExtras {
    time: f64,
    #[serde(flatten)]
    camera: CameraExtras,
}

#[derive(Serialize, Deserialize)]
struct KeyExtras {
    time: f64,
    offset: V3,
}

fn motion_extras(m: &Motion) -> Vec<KeyExtras> {
    m.keys
        .iter()
        .map(|(t, o)| KeyExtras {
            time: *t as f64,
            offset: v3(*o),
        })
        .collect()
}
fn motion_from(keys: &[KeyExtras]) -> Motion {
    Motion {
        keys: keys
            .iter()
            .map(|k| (k.time as f32, vec3(k.offset)))
            .collect(),
    }
}

#[derive(Serialize, Deserialize)]
struct VolumeExtras {
    name: String,
    center: V3,
    radius: f64,
    color: V3,
    density: f64,
    /// Absent in files written before the density profile existed: a uniform ball.
    #[serde(default)]
    profile: Option<ProfileExtras>,
    particle: bool,
    #[serde(default)]
    motion: Vec<KeyExtras>,
}

#[derive(Serialize, Deserialize)]
struct ProfileExtras {
    falloff: f64,
    noise: f64,
    noise_frequency: f64,
}

impl ProfileExtras {
    fn from_profile(p: &DensityProfile) -> Self {
        Self {
            falloff: p.falloff as f64,
            noise: p.noise as f64,
            noise_frequency: p.noise_frequency as f64,
        }
    }
    fn profile(&self) -> DensityProfile {
        DensityProfile {
            falloff: self.falloff as f32,
            noise: self.noise as f32,
            noise_frequency: self.noise_frequency as f32,
        }
    }
}

#[derive(Serialize, Deserialize)]
struct BuildingExtras {
    room_size: V3,
}

#[derive(Serialize, Deserialize)]
struct ObjectExtras {
    #[serde(default)]
    roles: Vec<String>,
    #[serde(default)]
    motion: Vec<KeyExtras>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    building: Option<BuildingExtras>,
}

#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
enum MaterialExtras {
    Diffuse { albedo: V3 },
    Metal { n: V3, k: V3 },
    Glass { ior: f64 },
}

#[derive(Serialize, Deserialize)]
struct LightExtras {
    intensity: V3,
}

/// `{"scene_model": value}`.
fn wrap<T: Serialize>(value: &T) -> Value {
    let mut map = serde_json::Map::new();
    map.insert(
        EXTRAS_KEY.to_string(),
        serde_json::to_value(value).unwrap_or(Value::Null),
    );
    Value::Object(map)
}

/// Reads `extras.scene` of a glTF object as `T`, `None` when absent.
fn read_extras<T: for<'de> Deserialize<'de>>(
    extras: &gltf::json::Extras,
    what: &str,
) -> Result<Option<T>, String> {
    let Some(raw) = extras else { return Ok(None) };
    let value: Value = serde_json::from_str(raw.get())
        .map_err(|e| format!("the extras of {what} are not JSON: {e}"))?;
    match value.get(EXTRAS_KEY) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => T::deserialize(v).map(Some).map_err(|e| {
            format!("the extras.{EXTRAS_KEY} of {what} do not follow the schema: {e}")
        }),
    }
}

// ---------------------------------------------------------------------------------------
// Import
// ---------------------------------------------------------------------------------------

/// Largest number of components an accessor without a buffer view (all zeros) may have.
const MAX_ZERO_COMPONENTS: usize = 1 << 28;

fn import_impl(
    bytes: &[u8],
    fallback_name: &str,
    base: Option<&Path>,
) -> Result<(Scene, Vec<String>), String> {
    let (json_bytes, bin) = if bytes.starts_with(b"glTF") {
        split_glb(bytes)?
    } else {
        (bytes, None)
    };
    let root: gltf::json::Root = gltf::json::deserialize::from_slice(json_bytes)
        .map_err(|e| format!("the glTF JSON is malformed: {e}"))?;
    prevalidate(&root)?;
    let doc = gltf::Document::from_json(root).map_err(describe_gltf_error)?;
    let buffers = load_buffers(&doc, bin, base)?;
    Importer {
        doc: &doc,
        buffers,
        base,
        objects: vec![],
        pending: vec![],
        lights: vec![],
        camera: None,
        notes: vec![],
        triangles: 0,
    }
    .run(fallback_name)
}

/// Checks what the `gltf` crate's own validation would index without checking: its
/// primitive hook reads `accessors[POSITION]` directly (gltf-json 1.4.1, mesh.rs) and
/// panics when that index is out of range.
fn prevalidate(root: &gltf::json::Root) -> Result<(), String> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= root.accessors.len() {
                    let name = match semantic {
                        gltf::json::validation::Checked::Valid(s) => s.to_string(),
                        gltf::json::validation::Checked::Invalid => "an attribute".into(),
                    };
                    return Err(format!(
                        "mesh {m} primitive {p} uses accessor {} for {name}, but there are only {} accessors",
                        index.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    Ok(())
}

fn describe_gltf_error(e: gltf::Error) -> String {
    match e {
        gltf::Error::Validation(errors) => {
            let shown: Vec<String> = errors
                .iter()
                .take(3)
                .map(|(path, err)| format!("{path}: {err}"))
                .collect();
            let more = if errors.len() > 3 {
                format!(" (and {} more)", errors.len() - 3)
            } else {
                String::new()
            };
            format!("the glTF does not validate: {}{more}", shown.join("; "))
        }
        other => format!("the glTF cannot be read: {other}"),
    }
}

/// Splits a `.glb` into its JSON and optional BIN chunks, checking every length.
fn split_glb(b: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let word = |o: usize| -> Option<usize> {
        b.get(o..o + 4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]) as usize)
    };
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        return Err(format!(
            "the .glb file is truncated: {} bytes is shorter than its 12-byte header",
            b.len()
        ));
    };
    if version != 2 {
        return Err(format!(
            "the .glb container has version {version}; only version 2 is supported"
        ));
    }
    if length > b.len() {
        return Err(format!(
            "the .glb file is truncated: its header declares {length} bytes but only {} are present",
            b.len()
        ));
    }
    if length < 20 {
        return Err(format!(
            "the .glb header declares a length of {length} bytes, too short for a JSON chunk"
        ));
    }
    let b = &b[..length];
    let (mut json, mut bin) = (None, None);
    let mut pos = 12;
    while pos < length {
        let (Some(chunk_len), Some(kind)) = (word(pos), word(pos + 4)) else {
            return Err(format!(
                "the .glb file is truncated inside the chunk header at byte {pos}"
            ));
        };
        let start = pos + 8;
        let end = start.checked_add(chunk_len).filter(|&e| e <= length).ok_or_else(|| {
            format!("the .glb chunk at byte {pos} declares {chunk_len} bytes, past the end of the file (truncated?)")
        })?;
        match kind {
            0x4E4F_534A if json.is_none() && pos == 12 => json = Some(&b[start..end]),
            0x004E_4942 if json.is_some() && bin.is_none() => bin = Some(&b[start..end]),
            _ if pos == 12 => return Err("the first .glb chunk is not the JSON chunk".into()),
            _ => {} // unknown chunks are ignored, as the spec asks
        }
        pos = end;
    }
    let json = json.ok_or("the .glb file has no JSON chunk")?;
    Ok((json, bin))
}

/// Reads the bytes a URI points at: a base64 `data:` URI, or a file relative to `base`.
///
/// A file must be a regular file inside `base` once `..` and symbolic links are resolved
/// (absolute paths, `../`, `%2e%2e/` and links out of the folder are refused, so a glTF file
/// cannot make the importer read `/etc/passwd`), and at most `limit` bytes are read from it.
fn read_uri(
    uri: &str,
    base: Option<&Path>,
    what: &str,
    limit: u64,
    first_bytes: bool,
) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest
            .split_once(";base64,")
            .ok_or_else(|| format!("{what} has a data URI that is not base64"))?;
        return base64_decode(payload)
            .map_err(|e| format!("{what} has a malformed base64 data URI: {e}"));
    }
    let shown = printable(uri);
    if uri.contains(':') {
        return Err(format!(
            "{what} refers to \"{shown}\", whose URI scheme is not supported (only data: URIs and relative paths)"
        ));
    }
    let relative =
        percent_decode(uri).ok_or_else(|| format!("{what} has a malformed URI \"{shown}\""))?;
    if relative.chars().any(char::is_control) {
        return Err(format!(
            "{what} refers to \"{}\", a file name with control characters",
            printable(&relative)
        ));
    }
    let Some(base) = base else {
        return Err(format!(
            "{what} refers to the external file \"{relative}\", which cannot be resolved when importing from memory"
        ));
    };
    if Path::new(&relative).has_root() {
        return Err(format!(
            "{what} refers to the absolute path \"{relative}\"; only files inside the glTF's folder are read"
        ));
    }
    let outside = || {
        format!(
            "{what} refers to \"{relative}\", outside the glTF's folder; only files inside it are read"
        )
    };
    let folder = base
        .canonicalize()
        .map_err(|e| format!("the glTF's folder {} cannot be read: {e}", shown_path(base)))?;
    let full = base.join(&relative);
    let resolved = match full.canonicalize() {
        Ok(p) => p,
        // A missing file: say so, unless the name climbs out of the folder.
        Err(_) if relative.split(['/', '\\']).any(|c| c == "..") => return Err(outside()),
        Err(e) => {
            return Err(format!(
                "{what} refers to {}, which cannot be read: {e}",
                shown_path(&full)
            ));
        }
    };
    if !resolved.starts_with(&folder) {
        return Err(outside());
    }
    read_regular_file(&resolved, limit, first_bytes, true).map_err(|e| {
        format!(
            "{what} refers to {}, which cannot be read: {e}",
            shown_path(&full)
        )
    })
}

fn base64_decode(text: &str) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0u32);
    for (i, c) in text.bytes().enumerate() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => break,
            b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return Err(format!("character {:?} at position {i}", c as char)),
        } as u32;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Ok(out)
}

fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

fn load_buffers(
    doc: &gltf::Document,
    bin: Option<&[u8]>,
    base: Option<&Path>,
) -> Result<Vec<Vec<u8>>, String> {
    let mut bin = bin;
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let what = format!("buffer {}", buffer.index());
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => bin
                .take()
                .ok_or_else(|| format!("{what} refers to the .glb binary chunk, which is missing"))?
                .to_vec(),
            // No more than the declared length is read: the rest of a file is not the buffer.
            gltf::buffer::Source::Uri(uri) => read_uri(
                uri,
                base,
                &what,
                (buffer.length() as u64).min(MAX_FILE_BYTES),
                true,
            )?,
        };
        if data.len() < buffer.length() {
            return Err(format!(
                "{what} holds {} bytes but declares a byteLength of {} (truncated?)",
                data.len(),
                buffer.length()
            ));
        }
        out.push(data);
    }
    Ok(out)
}

fn view_bytes<'b>(buffers: &'b [Vec<u8>], view: &gltf::buffer::View) -> Result<&'b [u8], String> {
    let index = view.buffer().index();
    let buf = buffers
        .get(index)
        .ok_or_else(|| format!("buffer view {} uses missing buffer {index}", view.index()))?;
    let start = view.offset();
    start
        .checked_add(view.length())
        .and_then(|end| buf.get(start..end))
        .ok_or_else(|| {
            format!(
                "buffer view {} (offset {start}, {} bytes) lies outside buffer {index} ({} bytes)",
                view.index(),
                view.length(),
                buf.len()
            )
        })
}

fn component_f32(b: &[u8], ty: gltf::accessor::DataType, normalized: bool) -> f32 {
    use gltf::accessor::DataType::*;
    match (ty, normalized) {
        (F32, _) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        (U8, false) => b[0] as f32,
        (U8, true) => b[0] as f32 / 255.0,
        (I8, false) => b[0] as i8 as f32,
        (I8, true) => (b[0] as i8 as f32 / 127.0).max(-1.0),
        (U16, false) => u16::from_le_bytes([b[0], b[1]]) as f32,
        (U16, true) => u16::from_le_bytes([b[0], b[1]]) as f32 / 65535.0,
        (I16, false) => i16::from_le_bytes([b[0], b[1]]) as f32,
        (I16, true) => (i16::from_le_bytes([b[0], b[1]]) as f32 / 32767.0).max(-1.0),
        (U32, false) => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
        (U32, true) => {
            (u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64 / u32::MAX as f64) as f32
        }
    }
}

fn component_u32(b: &[u8], ty: gltf::accessor::DataType) -> u32 {
    match b.len() {
        1 => b[0] as u32,
        2 => u16::from_le_bytes([b[0], b[1]]) as u32,
        _ if ty == gltf::accessor::DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        _ => 0,
    }
}

/// Reads every component of `acc` (count * components values) with `conv`, checking every
/// offset against the buffer view and applying sparse substitution.
fn read_accessor<T: Copy + Default>(
    acc: &gltf::Accessor,
    buffers: &[Vec<u8>],
    what: &str,
    conv: impl Fn(&[u8]) -> T,
) -> Result<Vec<T>, String> {
    let index = acc.index();
    let count = acc.count();
    let ncomp = acc.dimensions().multiplicity();
    let csize = acc.data_type().size();
    let elem = ncomp * csize;
    let total = count
        .checked_mul(ncomp)
        .ok_or_else(|| format!("accessor {index} ({what}) has an impossible count {count}"))?;
    let range_err = |need: Option<usize>, view: usize, have: usize| {
        format!(
            "accessor {index} ({what}) is out of range: it needs {} bytes of buffer view {view}, which has {have}",
            need.map(|n| n.to_string())
                .unwrap_or_else(|| "more than addressable".into())
        )
    };
    let mut out = match acc.view() {
        Some(view) => {
            let bytes = view_bytes(buffers, &view)?;
            let stride = view.stride().unwrap_or(elem);
            if stride < elem {
                return Err(format!(
                    "accessor {index} ({what}) has elements of {elem} bytes but buffer view {} has a stride of {stride}",
                    view.index()
                ));
            }
            let start = acc.offset();
            let need = if count == 0 {
                Some(start)
            } else {
                stride
                    .checked_mul(count - 1)
                    .and_then(|s| s.checked_add(start))
                    .and_then(|s| s.checked_add(elem))
            };
            if need.is_none_or(|n| n > bytes.len()) {
                return Err(range_err(need, view.index(), bytes.len()));
            }
            let mut out = Vec::with_capacity(total);
            for i in 0..count {
                let e = start + i * stride;
                for c in 0..ncomp {
                    let o = e + c * csize;
                    out.push(conv(&bytes[o..o + csize]));
                }
            }
            out
        }
        None => {
            if total > MAX_ZERO_COMPONENTS {
                return Err(format!(
                    "accessor {index} ({what}) has no data and an implausible count {count}"
                ));
            }
            vec![T::default(); total]
        }
    };
    if let Some(sparse) = acc.sparse() {
        let n = sparse.count();
        let indices = sparse.indices();
        let iview = indices.view();
        let ibytes = view_bytes(buffers, &iview)?;
        let isize = match indices.index_type() {
            gltf::accessor::sparse::IndexType::U8 => 1,
            gltf::accessor::sparse::IndexType::U16 => 2,
            gltf::accessor::sparse::IndexType::U32 => 4,
        };
        let istart = indices.offset();
        let ineed = n.checked_mul(isize).and_then(|s| s.checked_add(istart));
        if ineed.is_none_or(|x| x > ibytes.len()) {
            return Err(range_err(ineed, iview.index(), ibytes.len()));
        }
        let values = sparse.values();
        let vview = values.view();
        let vbytes = view_bytes(buffers, &vview)?;
        let vstart = values.offset();
        let vneed = n.checked_mul(elem).and_then(|s| s.checked_add(vstart));
        if vneed.is_none_or(|x| x > vbytes.len()) {
            return Err(range_err(vneed, vview.index(), vbytes.len()));
        }
        for j in 0..n {
            let io = istart + j * isize;
            let target =
                component_u32(&ibytes[io..io + isize], gltf::accessor::DataType::U32) as usize;
            if target >= count {
                return Err(format!(
                    "accessor {index} ({what}) has sparse index {target}, out of range for its {count} elements"
                ));
            }
            for c in 0..ncomp {
                let o = vstart + j * elem + c * csize;
                out[target * ncomp + c] = conv(&vbytes[o..o + csize]);
            }
        }
    }
    Ok(out)
}

fn read_floats(
    acc: &gltf::Accessor,
    buffers: &[Vec<u8>],
    what: &str,
    dims: gltf::accessor::Dimensions,
) -> Result<Vec<f32>, String> {
    if acc.dimensions() != dims {
        return Err(format!(
            "accessor {} ({what}) is {:?}, expected {:?}",
            acc.index(),
            acc.dimensions(),
            dims
        ));
    }
    let (ty, normalized) = (acc.data_type(), acc.normalized());
    read_accessor(acc, buffers, what, |b| component_f32(b, ty, normalized))
}

fn read_indices(acc: &gltf::Accessor, buffers: &[Vec<u8>], what: &str) -> Result<Vec<u32>, String> {
    use gltf::accessor::DataType::*;
    let ty = acc.data_type();
    if acc.dimensions() != gltf::accessor::Dimensions::Scalar
        || !matches!(ty, U8 | U16 | U32)
        || acc.normalized()
    {
        return Err(format!(
            "accessor {} ({what}) is not a scalar unsigned-integer index accessor",
            acc.index()
        ));
    }
    read_accessor(acc, buffers, what, |b| component_u32(b, ty))
}

/// A material as imported: the model material, its default roles, and its base colour
/// texture as (glTF image index, texture-coordinate set).
type ImportedMaterial = (Material, Roles, Option<(usize, u32)>);

/// An object whose diffuse texture is still a glTF image index.
struct Pending {
    object: usize,
    image: usize,
}

struct Importer<'a> {
    doc: &'a gltf::Document,
    buffers: Vec<Vec<u8>>,
    base: Option<&'a Path>,
    objects: Vec<Object>,
    pending: Vec<Pending>,
    lights: Vec<PointLight>,
    camera: Option<FoundCamera>,
    /// What the importer supplied or repaired, one sentence each.
    notes: Vec<String>,
    /// Triangles of the objects made so far.
    triangles: usize,
}

/// The first perspective camera: exact from the extras, or from the node (its target is
/// placed once the scene's bounds are known).
enum FoundCamera {
    Exact(Camera),
    Derived {
        eye: Vec3,
        forward: Vec3,
        up: Vec3,
        fov_y_deg: f32,
    },
}

impl Importer<'_> {
    fn run(mut self, fallback_name: &str) -> Result<(Scene, Vec<String>), String> {
        let doc = self.doc;
        let gscene = doc.default_scene().or_else(|| doc.scenes().next());
        let roots: Vec<gltf::Node> = match &gscene {
            Some(s) => s.nodes().collect(),
            None => {
                let mut is_child = vec![false; doc.nodes().len()];
                for n in doc.nodes() {
                    for c in n.children() {
                        is_child[c.index()] = true;
                    }
                }
                doc.nodes().filter(|n| !is_child[n.index()]).collect()
            }
        };
        let scene_extras: Option<SceneExtras> = match &gscene {
            Some(s) => read_extras(s.extras(), &format!("scene {}", s.index()))?,
            None => None,
        };
        if let Some(x) = &scene_extras
            && x.version > EXTRAS_VERSION
        {
            return Err(format!(
                "the file uses extras schema version {}, newer than the supported {EXTRAS_VERSION}",
                x.version
            ));
        }

        // Depth-first, children in order; a node met twice means a cycle or a shared child.
        let mut visited = vec![false; doc.nodes().len()];
        let mut stack: Vec<(gltf::Node, Option<Mat4>)> =
            roots.into_iter().rev().map(|n| (n, None)).collect();
        while let Some((node, parent)) = stack.pop() {
            if std::mem::replace(&mut visited[node.index()], true) {
                return Err(format!(
                    "node {} is reached twice: the node hierarchy has a cycle or a node with two parents",
                    node.index()
                ));
            }
            let local = node_matrix(&node)?;
            let world = match parent {
                Some(p) => p * local,
                None => local,
            };
            if !world.is_finite() {
                return Err(format!(
                    "node {} has a non-finite world transform (overflow)",
                    describe_node(&node)
                ));
            }
            self.visit(&node, world)?;
            let children: Vec<gltf::Node> = node.children().collect();
            stack.extend(children.into_iter().rev().map(|c| (c, Some(world))));
        }
        if self.objects.is_empty() {
            return Err("the file contains no triangle geometry".into());
        }

        // Textures: the images used as base colour textures (every image in our own files),
        // in image order.
        let mut needed: BTreeSet<usize> = self.pending.iter().map(|p| p.image).collect();
        if scene_extras.is_some() {
            needed.extend(0..doc.images().len());
        }
        let mut textures = Vec::new();
        let mut slot = BTreeMap::new();
        for image in doc.images().filter(|i| needed.contains(&i.index())) {
            slot.insert(image.index(), textures.len());
            textures.push(self.decode_image(&image)?);
        }
        for p in &self.pending {
            if let Material::Diffuse { texture, .. } = &mut self.objects[p.object].material {
                *texture = slot.get(&p.image).copied();
            }
        }

        let camera = match self.camera {
            Some(FoundCamera::Exact(c)) => c,
            Some(FoundCamera::Derived {
                eye,
                forward,
                up,
                fov_y_deg,
            }) => {
                let (lo, hi) = crate::world_bounds(&self.objects);
                let d = ((lo + hi) * 0.5 - eye).length();
                let d = if d.is_finite() && d > 1e-3 { d } else { 1.0 };
                Camera {
                    eye,
                    target: eye + forward * d,
                    up,
                    fov_y_deg,
                }
            }
            None => frame_objects(&self.objects),
        };
        let medium = scene_extras
            .as_ref()
            .and_then(|x| x.medium.as_ref().map(MediumExtras::medium));
        let (name, background, camera_path, volumes) = match scene_extras {
            Some(x) => (
                x.name,
                vec3(x.background),
                CameraPath {
                    keys: x
                        .camera_path
                        .iter()
                        .map(|k| (k.time as f32, k.camera.camera()))
                        .collect(),
                },
                x.volumes
                    .iter()
                    .map(|v| Volume {
                        name: v.name.clone(),
                        center: vec3(v.center),
                        radius: v.radius as f32,
                        color: vec3(v.color),
                        density: v.density as f32,
                        profile: v
                            .profile
                            .as_ref()
                            .map_or(DensityProfile::UNIFORM, |p| p.profile()),
                        particle: v.particle,
                        motion: motion_from(&v.motion),
                    })
                    .collect(),
            ),
            None => (
                gscene
                    .as_ref()
                    .and_then(|s| s.name())
                    .unwrap_or(fallback_name)
                    .to_string(),
                Vec3::ZERO,
                CameraPath::default(),
                vec![],
            ),
        };
        let mut scene = Scene {
            name,
            objects: self.objects,
            textures,
            lights: self.lights,
            camera,
            camera_path,
            volumes,
            medium,
            background,
        };
        let mut notes = self.notes;
        if scene.lights.is_empty() {
            notes.push(scene.add_default_lighting());
        }
        Ok((scene, notes))
    }

    fn visit(&mut self, node: &gltf::Node, world: Mat4) -> Result<(), String> {
        if let Some(mesh) = node.mesh() {
            let extras: Option<ObjectExtras> =
                read_extras(node.extras(), &format!("node {}", node.index()))?;
            let base_name = node
                .name()
                .or(mesh.name())
                .map(str::to_string)
                .unwrap_or_else(|| format!("node {}", node.index()));
            let triangle_prims = mesh
                .primitives()
                .filter(|p| triangle_mode(p.mode()))
                .count();
            for prim in mesh.primitives().filter(|p| triangle_mode(p.mode())) {
                let what = format!("mesh {} primitive {}", describe_mesh(&mesh), prim.index());
                let (material, default_roles, texture) = self.material(&prim.material())?;
                let uv_set = match &texture {
                    Some((_, set)) => *set,
                    None => 0,
                };
                let object_mesh = self.primitive_mesh(&prim, uv_set, &what)?;
                if object_mesh.indices.is_empty() {
                    continue; // fewer than three vertices: nothing to render
                }
                let name = if triangle_prims > 1 {
                    format!("{base_name} #{}", prim.index())
                } else {
                    base_name.clone()
                };
                let mut object = Object::new(&name, object_mesh, material, world);
                object.roles = default_roles;
                if let Some(x) = &extras {
                    object.roles = roles_from(&x.roles, &name)?;
                    object.motion = motion_from(&x.motion);
                    object.building = x.building.as_ref().map(|b| Building {
                        room_size: vec3(b.room_size),
                    });
                }
                if let (Some((image, _)), Material::Diffuse { .. }) = (texture, &object.material) {
                    self.pending.push(Pending {
                        object: self.objects.len(),
                        image,
                    });
                }
                self.objects.push(object);
                // Checked as objects are made, not after: a file of many nodes sharing one big
                // mesh must not make the importer copy that mesh past the limit first.
                self.triangles += self.objects.last().map_or(0, |o| o.mesh.triangle_count());
                if self.triangles > crate::MAX_TRIANGLES {
                    return Err(format!(
                        "the scene has more than {} triangles (node {} brings it to {}); the \
                         renderers accept at most {}",
                        crate::MAX_TRIANGLES,
                        describe_node(node),
                        self.triangles,
                        crate::MAX_TRIANGLES
                    ));
                }
            }
        }
        if let Some(light) = node.light()
            && let gltf::khr_lights_punctual::Kind::Point = light.kind()
        {
            let what = format!("light {}", light.index());
            let c = Vec3::from(light.color());
            let derived = c * light.intensity() / LUMENS_PER_WATT;
            let exact: Option<LightExtras> = read_extras(light.extras(), &what)?;
            let intensity = match exact {
                Some(x) if close(vec3(x.intensity), derived, 1e-4) => vec3(x.intensity),
                _ => derived,
            };
            let name = light
                .name()
                .or(node.name())
                .map(str::to_string)
                .unwrap_or_else(|| format!("light {}", light.index()));
            self.lights.push(PointLight {
                name,
                position: world.transform_point3(Vec3::ZERO),
                intensity,
            });
        }
        // The camera's JSON is read directly: `gltf::Camera::projection` unwraps the
        // projection named by `type`, which validation does not require to be present.
        let perspective = node
            .camera()
            .and_then(|c| self.doc.as_json().cameras.get(c.index()))
            .filter(|c| {
                c.type_
                    == gltf::json::validation::Checked::Valid(gltf::json::camera::Type::Perspective)
            })
            .and_then(|c| c.perspective.as_ref());
        if let (None, Some(p)) = (&self.camera, perspective) {
            let eye = world.transform_point3(Vec3::ZERO);
            let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
            let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
            if forward == Vec3::ZERO || up == Vec3::ZERO {
                return Err(format!(
                    "camera node {} has a degenerate transform",
                    describe_node(node)
                ));
            }
            // A node that carries other extras under our key is not an error here: the
            // camera is then derived from the node.
            let exact: Option<CameraExtras> =
                read_extras(node.extras(), &format!("node {}", node.index()))
                    .ok()
                    .flatten();
            let fov_y_deg = p.yfov.to_degrees();
            let camera = match exact.map(|x| x.camera()) {
                Some(c)
                    if close(c.eye, eye, 1e-4)
                        && (c.target - c.eye).normalize_or_zero().dot(forward) > 1.0 - 1e-4
                        && (c.fov_y_deg - fov_y_deg).abs() <= 1e-3 * c.fov_y_deg.abs() =>
                {
                    FoundCamera::Exact(c)
                }
                _ => FoundCamera::Derived {
                    eye,
                    forward,
                    up,
                    fov_y_deg,
                },
            };
            self.camera = Some(camera);
        }
        Ok(())
    }

    /// The model material, its default roles and its base colour texture (image index and
    /// texture-coordinate set) if it is diffuse and has one.
    fn material(&self, m: &gltf::Material) -> Result<ImportedMaterial, String> {
        let what = match m.index() {
            Some(i) => format!("material {i}"),
            None => "the default material".to_string(),
        };
        let pbr = m.pbr_metallic_roughness();
        let base = pbr.base_color_factor();
        let base_rgb = Vec3::new(base[0], base[1], base[2]);
        let texture = pbr
            .base_color_texture()
            .map(|info| (info.texture().source().index(), info.tex_coord()));
        let exact: Option<MaterialExtras> = read_extras(m.extras(), &what)?;
        let material = match exact {
            Some(MaterialExtras::Diffuse { albedo }) => Material::Diffuse {
                albedo: vec3(albedo),
                texture: None,
            },
            Some(MaterialExtras::Metal { n, k }) => Material::Metal {
                n: vec3(n),
                k: vec3(k),
            },
            Some(MaterialExtras::Glass { ior }) => Material::Glass { ior: ior as f32 },
            None => {
                let transmission = m
                    .transmission()
                    .map(|t| t.transmission_factor())
                    .unwrap_or(0.0);
                if transmission > 0.5 {
                    Material::Glass {
                        ior: m.ior().unwrap_or(1.5),
                    }
                } else if pbr.metallic_factor() >= 0.5 && pbr.roughness_factor() <= 0.5 {
                    let s = base_rgb.clamp(Vec3::ZERO, Vec3::ONE).powf(0.5);
                    Material::Metal {
                        n: (Vec3::ONE - s) / (Vec3::ONE + s),
                        k: Vec3::ZERO,
                    }
                } else {
                    Material::Diffuse {
                        albedo: base_rgb,
                        texture: None,
                    }
                }
            }
        };
        let roles = match material {
            Material::Diffuse { .. } => Roles::NONE,
            Material::Metal { .. } => Roles::REFLECTOR | Roles::CAUSTIC_CASTER,
            Material::Glass { .. } => Roles::REFRACTOR | Roles::CAUSTIC_CASTER,
        };
        let texture = if matches!(material, Material::Diffuse { .. }) {
            texture
        } else {
            None
        };
        Ok((material, roles, texture))
    }

    fn primitive_mesh(
        &mut self,
        prim: &gltf::Primitive,
        uv_set: u32,
        what: &str,
    ) -> Result<Mesh, String> {
        use gltf::accessor::Dimensions;
        use gltf::mesh::Semantic;
        let b = &self.buffers;
        let pos_acc = prim
            .get(&Semantic::Positions)
            .ok_or_else(|| format!("{what} has no POSITION attribute"))?;
        let positions: Vec<Vec3> =
            read_floats(&pos_acc, b, &format!("{what} POSITION"), Dimensions::Vec3)?
                .chunks_exact(3)
                .map(Vec3::from_slice)
                .collect();
        let n = positions.len();
        let normals: Option<Vec<Vec3>> = match prim.get(&Semantic::Normals) {
            Some(acc) => Some(
                read_floats(&acc, b, &format!("{what} NORMAL"), Dimensions::Vec3)?
                    .chunks_exact(3)
                    .map(Vec3::from_slice)
                    .collect(),
            ),
            None => None,
        };
        let uvs: Vec<Vec2> = match prim.get(&Semantic::TexCoords(uv_set)) {
            Some(acc) => read_floats(
                &acc,
                b,
                &format!("{what} TEXCOORD_{uv_set}"),
                Dimensions::Vec2,
            )?
            .chunks_exact(2)
            .map(Vec2::from_slice)
            .collect(),
            None => vec![Vec2::ZERO; n],
        };
        if normals.as_ref().is_some_and(|v| v.len() != n) || uvs.len() != n {
            return Err(format!("{what} has attributes of different lengths"));
        }
        let mut indices = match prim.indices() {
            Some(acc) => read_indices(&acc, b, &format!("{what} indices"))?,
            None => (0..n as u32).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
            return Err(format!(
                "{what} has index {bad}, out of range for its {n} vertices"
            ));
        }
        indices = match prim.mode() {
            gltf::mesh::Mode::TriangleStrip => (0..indices.len().saturating_sub(2))
                .flat_map(|i| {
                    if i % 2 == 0 {
                        [indices[i], indices[i + 1], indices[i + 2]]
                    } else {
                        [indices[i], indices[i + 2], indices[i + 1]]
                    }
                })
                .collect(),
            gltf::mesh::Mode::TriangleFan => (1..indices.len().saturating_sub(1))
                .flat_map(|i| [indices[i], indices[i + 1], indices[0]])
                .collect(),
            _ => indices,
        };
        if !indices.len().is_multiple_of(3) {
            return Err(format!(
                "{what} has {} indices, not a multiple of 3",
                indices.len()
            ));
        }
        Ok(match normals {
            Some(normals) => {
                let mut mesh = Mesh {
                    positions,
                    normals,
                    uvs,
                    indices,
                };
                let repaired = mesh.repair_normals();
                if repaired > 0 {
                    self.notes.push(format!(
                        "{what}: {repaired} zero-length or non-finite normals replaced by geometric normals"
                    ));
                }
                mesh
            }
            None => flat_shaded(&positions, &uvs, &indices),
        })
    }

    fn decode_image(&self, image: &gltf::Image) -> Result<Texture, String> {
        let what = format!("image {}", image.index());
        // The image's JSON is read directly: `gltf::Image::source` unwraps `mimeType` and
        // `uri`, which validation does not require.
        let json = &self.doc.as_json().images[image.index()];
        let view = json
            .buffer_view
            .and_then(|v| self.doc.views().nth(v.value()));
        let bytes: Cow<[u8]> = match (view, &json.uri) {
            (Some(view), _) => Cow::Borrowed(view_bytes(&self.buffers, &view)?),
            (None, Some(uri)) => {
                Cow::Owned(read_uri(uri, self.base, &what, MAX_FILE_BYTES, false)?)
            }
            (None, None) => return Err(format!("{what} has neither a bufferView nor a uri")),
        };
        let reader = || {
            image::ImageReader::new(std::io::Cursor::new(&bytes[..]))
                .with_guessed_format()
                .map_err(|e| format!("{what} cannot be decoded: {e}"))
        };
        let (width, height) = reader()?
            .into_dimensions()
            .map_err(|e| format!("{what} cannot be decoded: {e}"))?;
        if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
            return Err(format!(
                "{what} is {width}x{height} texels; textures may have at most {MAX_TEXTURE_SIDE} per side"
            ));
        }
        let mut reader = reader()?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_TEXTURE_SIDE);
        limits.max_image_height = Some(MAX_TEXTURE_SIDE);
        limits.max_alloc = Some(MAX_IMAGE_DECODE_BYTES);
        reader.limits(limits);
        let decoded = reader
            .decode()
            .map_err(|e| format!("{what} cannot be decoded: {e}"))?;
        let rgba = decoded.to_rgba8();
        Ok(Texture {
            name: image.name().map(str::to_string).unwrap_or(what),
            width: rgba.width(),
            height: rgba.height(),
            rgba8: rgba.into_raw(),
        })
    }
}

fn triangle_mode(mode: gltf::mesh::Mode) -> bool {
    use gltf::mesh::Mode::*;
    matches!(mode, Triangles | TriangleStrip | TriangleFan)
}

fn describe_node(node: &gltf::Node) -> String {
    match node.name() {
        Some(n) => format!("{} (\"{n}\")", node.index()),
        None => node.index().to_string(),
    }
}

fn describe_mesh(mesh: &gltf::Mesh) -> String {
    match mesh.name() {
        Some(n) => format!("{} (\"{n}\")", mesh.index()),
        None => mesh.index().to_string(),
    }
}

/// The node's local matrix; every number must be finite.
fn node_matrix(node: &gltf::Node) -> Result<Mat4, String> {
    let bad = || {
        format!(
            "node {} has a non-finite transform (NaN or infinity)",
            describe_node(node)
        )
    };
    match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            let m = Mat4::from_cols_array_2d(&matrix);
            if m.is_finite() { Ok(m) } else { Err(bad()) }
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let (t, r, s) = (
                Vec3::from(translation),
                glam::Vec4::from(rotation),
                Vec3::from(scale),
            );
            if !(t.is_finite() && r.is_finite() && s.is_finite()) {
                return Err(bad());
            }
            let q = Quat::from_vec4(r);
            let len = q.length();
            if !(len.is_finite() && len > 0.0) {
                return Err(format!(
                    "node {} has a zero or non-finite rotation quaternion",
                    describe_node(node)
                ));
            }
            let m = Mat4::from_scale_rotation_translation(s, q / len, t);
            if m.is_finite() { Ok(m) } else { Err(bad()) }
        }
    }
}

fn roles_from(names: &[String], object: &str) -> Result<Roles, String> {
    names.iter().try_fold(Roles::NONE, |acc, n| {
        Roles::from_name(n)
            .map(|r| acc | r)
            .ok_or_else(|| format!("object \"{object}\" has an unknown role \"{n}\" in its extras"))
    })
}

fn close(a: Vec3, b: Vec3, rel: f32) -> bool {
    (a - b).abs().max_element() <= rel * a.abs().max_element().max(b.abs().max_element()).max(1e-6)
}

/// Unwelds the triangles and gives each its face normal (the spec's rule for primitives
/// without normals).
fn flat_shaded(positions: &[Vec3], uvs: &[Vec2], indices: &[u32]) -> Mesh {
    let mut m = Mesh::default();
    for (t, tri) in indices.chunks_exact(3).enumerate() {
        let [a, b, c] = [0, 1, 2].map(|k| positions[tri[k] as usize]);
        let normal = (b - a).cross(c - a).normalize_or(Vec3::Y);
        for &i in tri {
            m.positions.push(positions[i as usize]);
            m.uvs.push(uvs[i as usize]);
            m.normals.push(normal);
        }
        let base = 3 * t as u32;
        m.indices.extend([base, base + 1, base + 2]);
    }
    m
}

/// A camera that sees the world-space bounds of `objects` (45 degrees, from +Z and a little
/// above).
fn frame_objects(objects: &[Object]) -> Camera {
    let (lo, hi) = crate::world_bounds(objects);
    let (center, radius) = if lo.cmple(hi).all() {
        ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3))
    } else {
        (Vec3::ZERO, 1.0)
    };
    let fov_y_deg = 45.0f32;
    let distance = radius / (fov_y_deg.to_radians() * 0.5).sin() * 1.05;
    Camera {
        eye: center + Vec3::new(0.0, 0.25, 1.0).normalize() * distance,
        target: center,
        up: Vec3::Y,
        fov_y_deg,
    }
}

// ---------------------------------------------------------------------------------------
// Export
// ---------------------------------------------------------------------------------------

fn check_finite_extras(scene: &Scene) -> Result<(), String> {
    if scene.objects.is_empty() {
        return Err("the scene has no objects; a glTF file needs at least one mesh".into());
    }
    let keys_ok = |m: &Motion| m.keys.iter().all(|(t, v)| t.is_finite() && v.is_finite());
    let cam_ok = |c: &Camera| {
        c.eye.is_finite() && c.target.is_finite() && c.up.is_finite() && c.fov_y_deg.is_finite()
    };
    if !scene.background.is_finite() {
        return Err("the background colour is not finite".into());
    }
    if !cam_ok(&scene.camera) {
        return Err("the camera is not finite".into());
    }
    if !scene
        .camera_path
        .keys
        .iter()
        .all(|(t, c)| t.is_finite() && cam_ok(c))
    {
        return Err("the camera path has a non-finite key".into());
    }
    for o in &scene.objects {
        if !keys_ok(&o.motion) || o.building.is_some_and(|b| !b.room_size.is_finite()) {
            return Err(format!(
                "object \"{}\" has a non-finite motion key or room size",
                o.name
            ));
        }
        if !o.mesh.uvs.iter().all(|uv| uv.is_finite()) {
            return Err(format!(
                "object \"{}\" has non-finite texture coordinates",
                o.name
            ));
        }
        let material_ok = match o.material {
            Material::Diffuse { albedo, .. } => albedo.is_finite(),
            Material::Metal { n, k } => n.is_finite() && k.is_finite(),
            Material::Glass { .. } => true, // checked by validate()
        };
        if !material_ok {
            return Err(format!(
                "object \"{}\" has a non-finite material parameter",
                o.name
            ));
        }
        if o.mesh.indices.is_empty() {
            return Err(format!(
                "object \"{}\" has no triangles; glTF cannot store an empty mesh",
                o.name
            ));
        }
    }
    for v in &scene.volumes {
        if !(v.center.is_finite()
            && v.radius.is_finite()
            && v.color.is_finite()
            && v.density.is_finite()
            && keys_ok(&v.motion))
        {
            return Err(format!("volume \"{}\" is not finite", v.name));
        }
    }
    if let Some(m) = &scene.medium {
        m.validate().map_err(|e| e.to_string())?;
    }
    for t in &scene.textures {
        if t.width == 0
            || t.height == 0
            || t.rgba8.len() != 4 * t.width as usize * t.height as usize
        {
            return Err(format!(
                "texture \"{}\" is empty or its data does not match {}x{} RGBA8",
                t.name, t.width, t.height
            ));
        }
    }
    Ok(())
}

fn num(x: f32) -> Value {
    Value::from(x as f64)
}
fn arr(v: &[f32]) -> Value {
    Value::Array(v.iter().map(|&x| num(x)).collect())
}

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;

#[derive(Default)]
struct Exporter {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Exporter {
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut v = json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() });
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    fn accessor(
        &mut self,
        bytes: &[u8],
        target: u32,
        component: u32,
        count: usize,
        ty: &str,
    ) -> usize {
        let view = self.view(bytes, Some(target));
        self.accessors.push(
            json!({ "bufferView": view, "componentType": component, "count": count, "type": ty }),
        );
        self.accessors.len() - 1
    }

    fn run(mut self, scene: &Scene) -> Result<Vec<u8>, SceneError> {
        let (mut nodes, mut meshes, mut materials) = (vec![], vec![], vec![]);
        for o in &scene.objects {
            // A deforming object is written as it is at time 0 (its morph is not exported).
            let at_zero;
            let m = match &o.morph {
                None => &o.mesh,
                Some(_) => {
                    at_zero = crate::Mesh {
                        positions: o.positions_at(0.0).into_owned(),
                        normals: o.normals_at(0.0).into_owned(),
                        ..o.mesh.clone()
                    };
                    &at_zero
                }
            };
            let pos = self.accessor(
                bytemuck::cast_slice(&m.positions),
                ARRAY_BUFFER,
                FLOAT,
                m.positions.len(),
                "VEC3",
            );
            let (lo, hi) = m.bounds();
            self.accessors[pos]["min"] = arr(&lo.to_array());
            self.accessors[pos]["max"] = arr(&hi.to_array());
            let nor = self.accessor(
                bytemuck::cast_slice(&m.normals),
                ARRAY_BUFFER,
                FLOAT,
                m.normals.len(),
                "VEC3",
            );
            let uv = self.accessor(
                bytemuck::cast_slice(&m.uvs),
                ARRAY_BUFFER,
                FLOAT,
                m.uvs.len(),
                "VEC2",
            );
            let idx = self.accessor(
                bytemuck::cast_slice(&m.indices),
                ELEMENT_ARRAY_BUFFER,
                UNSIGNED_INT,
                m.indices.len(),
                "SCALAR",
            );
            materials.push(material_json(o));
            meshes.push(json!({
                "name": o.name,
                "primitives": [{
                    "attributes": { "POSITION": pos, "NORMAL": nor, "TEXCOORD_0": uv },
                    "indices": idx,
                    "material": materials.len() - 1,
                    "mode": 4,
                }],
            }));
            let extras = ObjectExtras {
                roles: o.roles.names().iter().map(|s| s.to_string()).collect(),
                motion: motion_extras(&o.motion),
                building: o.building.map(|b| BuildingExtras {
                    room_size: v3(b.room_size),
                }),
            };
            let mut node =
                json!({ "name": o.name, "mesh": meshes.len() - 1, "extras": wrap(&extras) });
            if o.transform != Mat4::IDENTITY {
                node["matrix"] = arr(&o.transform.to_cols_array());
            }
            nodes.push(node);
        }

        let mut lights = vec![];
        for l in &scene.lights {
            let peak = l.intensity.max_element().max(0.0);
            let color = if peak > 0.0 {
                (l.intensity / peak).max(Vec3::ZERO)
            } else {
                Vec3::ONE
            };
            lights.push(json!({
                "name": l.name,
                "type": "point",
                "color": arr(&color.to_array()),
                "intensity": num(peak * LUMENS_PER_WATT),
                "extras": wrap(&LightExtras { intensity: v3(l.intensity) }),
            }));
            nodes.push(json!({
                "name": l.name,
                "translation": arr(&l.position.to_array()),
                "extensions": { "KHR_lights_punctual": { "light": lights.len() - 1 } },
            }));
        }

        let c = &scene.camera;
        let rotation = camera_rotation(c);
        nodes.push(json!({
            "name": "camera",
            "camera": 0,
            "translation": arr(&c.eye.to_array()),
            "rotation": arr(&rotation.to_array()),
            "extras": wrap(&CameraExtras::from_camera(c)),
        }));
        let cameras = json!([{
            "name": "camera",
            "type": "perspective",
            "perspective": { "yfov": num(c.fov_y_deg.to_radians()), "znear": num(Camera::NEAR), "zfar": num(Camera::FAR) },
        }]);

        let (mut images, mut textures) = (vec![], vec![]);
        for (i, t) in scene.textures.iter().enumerate() {
            let png = encode_png(t).map_err(|e| SceneError::Gltf(scene.name.clone(), e))?;
            let view = self.view(&png, None);
            images.push(json!({ "name": t.name, "mimeType": "image/png", "bufferView": view }));
            textures.push(json!({ "name": t.name, "sampler": 0, "source": i }));
        }

        let scene_extras = SceneExtras {
            version: EXTRAS_VERSION,
            name: scene.name.clone(),
            background: v3(scene.background),
            camera_path: scene
                .camera_path
                .keys
                .iter()
                .map(|(t, c)| CameraKeyExtras {
                    time: *t as f64,
                    camera: CameraExtras::from_camera(c),
                })
                .collect(),
            volumes: scene
                .volumes
                .iter()
                .map(|v| VolumeExtras {
                    name: v.name.clone(),
                    center: v3(v.center),
                    radius: v.radius as f64,
                    color: v3(v.color),
                    density: v.density as f64,
                    profile: Some(ProfileExtras::from_profile(&v.profile)),
                    particle: v.particle,
                    motion: motion_extras(&v.motion),
                })
                .collect(),
            medium: scene.medium.as_ref().map(MediumExtras::from_medium),
        };

        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut used = vec![];
        let any = |f: &dyn Fn(&Material) -> bool| scene.objects.iter().any(|o| f(&o.material));
        if !lights.is_empty() {
            used.push("KHR_lights_punctual");
        }
        if any(&|m| matches!(m, Material::Glass { .. })) {
            used.extend(["KHR_materials_transmission", "KHR_materials_ior"]);
        }
        let node_count = nodes.len();
        let mut root = json!({
            "asset": { "version": "2.0", "generator": concat!("scene crate ", env!("CARGO_PKG_VERSION"), " (gltf_io)") },
            "scene": 0,
            "scenes": [{ "name": scene.name, "nodes": (0..node_count).collect::<Vec<_>>(), "extras": wrap(&scene_extras) }],
            "nodes": nodes,
            "meshes": meshes,
            "materials": materials,
            "cameras": cameras,
            "accessors": self.accessors,
            "bufferViews": self.views,
            "buffers": [{ "byteLength": self.bin.len() }],
        });
        if !used.is_empty() {
            root["extensionsUsed"] = json!(used);
        }
        if !lights.is_empty() {
            root["extensions"] = json!({ "KHR_lights_punctual": { "lights": lights } });
        }
        if !images.is_empty() {
            root["images"] = json!(images);
            root["textures"] = json!(textures);
            // LINEAR filters, REPEAT wrapping: what Texture::sample does.
            root["samplers"] =
                json!([{ "magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497 }]);
        }
        let json_text = serde_json::to_vec(&root).map_err(|e| {
            SceneError::Gltf(
                scene.name.clone(),
                format!("cannot encode the glTF JSON: {e}"),
            )
        })?;
        Ok(glb(json_text, self.bin))
    }
}

/// The camera node's rotation: the camera looks down its -Z with +Y up.
fn camera_rotation(c: &Camera) -> Quat {
    let (forward, right, up) = c.basis();
    Quat::from_mat3(&Mat3::from_cols(right, up, -forward)).normalize()
}

fn material_json(o: &Object) -> Value {
    let name = format!("{} material", o.name);
    match &o.material {
        Material::Diffuse { albedo, texture } => {
            let c = albedo.clamp(Vec3::ZERO, Vec3::ONE);
            let mut pbr = json!({ "baseColorFactor": arr(&[c.x, c.y, c.z, 1.0]), "metallicFactor": 0.0, "roughnessFactor": 1.0 });
            if let Some(t) = texture {
                pbr["baseColorTexture"] = json!({ "index": t });
            }
            json!({ "name": name, "pbrMetallicRoughness": pbr, "extras": wrap(&MaterialExtras::Diffuse { albedo: v3(*albedo) }) })
        }
        Material::Metal { n, k } => {
            let k2 = *k * *k;
            let f0 = (((*n - 1.0) * (*n - 1.0) + k2) / ((*n + 1.0) * (*n + 1.0) + k2))
                .clamp(Vec3::ZERO, Vec3::ONE);
            json!({
                "name": name,
                "pbrMetallicRoughness": { "baseColorFactor": arr(&[f0.x, f0.y, f0.z, 1.0]), "metallicFactor": 1.0, "roughnessFactor": 0.0 },
                "extras": wrap(&MaterialExtras::Metal { n: v3(*n), k: v3(*k) }),
            })
        }
        Material::Glass { ior } => {
            let shown = if *ior >= 1.0 { *ior } else { 1.0 / *ior };
            json!({
                "name": name,
                "pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.0 },
                "extensions": {
                    "KHR_materials_transmission": { "transmissionFactor": 1.0 },
                    "KHR_materials_ior": { "ior": num(shown) },
                },
                "extras": wrap(&MaterialExtras::Glass { ior: *ior as f64 }),
            })
        }
    }
}

fn encode_png(t: &Texture) -> Result<Vec<u8>, String> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(&t.rgba8, t.width, t.height, image::ExtendedColorType::Rgba8)
        .map_err(|e| format!("cannot encode texture \"{}\" as PNG: {e}", t.name))?;
    Ok(out)
}

/// Assembles a `.glb`: 12-byte header, JSON chunk padded with spaces, BIN chunk padded
/// with zeros (omitted when empty).
pub fn glb(mut json_text: Vec<u8>, mut bin: Vec<u8>) -> Vec<u8> {
    while !json_text.len().is_multiple_of(4) {
        json_text.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json_text.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_text.len() as u32).to_le_bytes());
    out.extend_from_slice(&0x4E4F_534Au32.to_le_bytes());
    out.extend_from_slice(&json_text);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(&0x004E_4942u32.to_le_bytes());
        out.extend_from_slice(&bin);
    }
    out
}
