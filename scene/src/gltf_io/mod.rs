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
//! - **Lights**: each `KHR_lights_punctual` light becomes a [`Light`] of its type
//!   ([`LightKind`]: point, spot with its inner and outer cone angles, directional) at its
//!   node's world position, pointing down the node's -Z, with intensity = colour * intensity
//!   / 683: W/sr from candela for point and spot lights, W/m^2 from lux for directional
//!   ones, 683 lm/W being the luminous efficacy of 555 nm light that defines the candela.
//!   `range` is ignored. A file without any light gets
//!   the default lighting of [`Scene::add_default_lighting`] (a key light from the camera's
//!   upper side and a uniform sky), and a note says so ([`import_noted`]).
//! - **Normals**: zero-length or non-finite normals are replaced by geometric ones
//!   ([`Mesh::repair_normals`]), with a note.
//! - **Camera**: the first camera node met, perspective or orthographic, becomes
//!   [`Scene::camera`]: eye = the node's origin, looking down its -Z with its +Y up, fov =
//!   `yfov` in degrees or [`Camera::orthographic`] = `ymag` (the view's width follows the
//!   rendered image's aspect; a note says so where `xmag` differs from `ymag`), target on the
//!   view direction at the distance of the centre of the objects' bounds (glTF marks no camera
//!   as active: a note names the one chosen, and each other camera as not used; a file this
//!   module wrote carries its camera exactly and gets no note). `znear` and `zfar` are not
//!   used. With no camera, the camera frames the bounds of all objects (45 degrees, from the
//!   +Z side and a little above).
//! - **Alpha**: a mask whose base colour alpha is below its `alphaCutoff`, and a blend of
//!   alpha 0, leave their primitives out, with a note (a texture only lowers alpha). Without a
//!   base colour texture, a mask at or above its cutoff and a blend of alpha 1 are opaque,
//!   exactly. A textured mask on a diffuse material is an alpha cut-out, exactly
//!   ([`Material::Diffuse`]'s `cutout`: the surface is absent where the texture's alpha is
//!   below the cutoff over the factor's alpha), which every renderer draws with its holes; on
//!   a material imported as metal or glass (which read no texture) it is rendered opaque, with
//!   a note. A textured blend, and a blend in between, are rendered opaque, with a note.
//! - **Emission**: a diffuse material's emissive factor times `KHR_materials_emissive_strength`
//!   becomes its objects' [`Object::emission`], radiance seen directly and in reflections and
//!   refractions that lights nothing; the emissive texture is left out, and so is the emission
//!   of a material imported as glass or metal. A note names each emissive material and says so.
//!
//! Skins, morph targets, animations, vertex colours, primitives that are not triangles, a
//! light's `range`, extensions the importer does not read (`KHR_materials_volume`'s
//! absorption, `KHR_texture_transform`, any other), blending and the remaining material
//! inputs are ignored, each named in a note: the skinned node, the mesh, the light, the
//! extension, and each material whose partial alpha (a blend, or a mask on metal or glass),
//! transmission roughness or metal roughness (a smooth mirror stands in for it) is left out,
//! once per material ([`import_noted`]). A node transform with a negative determinant is kept
//! as it is (the winding of its triangles is then mirrored in world space).
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
//! repeat/linear sampler. Each light becomes a node (translation = position, its -Z rotated
//! onto a spot's or directional light's direction) with a `KHR_lights_punctual` light of its
//! type, colour = intensity / max(intensity) and intensity = 683 * max(intensity) (candela
//! for point and spot lights, lux for directional ones), a spot with its cone angles (the
//! inner written a hair below the outer where they are equal, as glTF requires). A diffuse
//! material that emits gets `emissiveFactor` = emission / max(1, peak) and, past 1,
//! `KHR_materials_emissive_strength` = the peak. The scene camera becomes a camera node (`yfov` in
//! radians, or `xmag` = `ymag` = the orthographic half height; `znear`/`zfar` =
//! [`Camera::NEAR`]/[`Camera::FAR`]). Motion keys, building
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
//! materials[i].extras { "scene_model": { "kind": "diffuse", "albedo": [..],
//!                                        "emission": [..] } }   ("emission": emitters only)
//!                     { "scene_model": { "kind": "metal", "n": [..], "k": [..] } }
//!                     { "scene_model": { "kind": "glass", "ior": x } }
//! KHR_lights_punctual lights[i].extras
//!                     { "scene_model": { "intensity": [r, g, b],   (W/sr; W/m^2 for a sun)
//!                                        "direction": [..],        (spot and directional)
//!                                        "cone": [inner, outer] } } (spot; radians)
//! ```
//!
//! A diffuse material's texture is its core `baseColorTexture` (exact already).
//!
//! Object transforms and light positions are always read from the nodes (which hold them
//! exactly), so moving things in an editor is respected. The exact camera, light intensity,
//! direction and cone and emission in `extras` are used only while they agree with the core
//! glTF camera node, light and material (to 1e-4); if an editor changed those, the core
//! values win. Materials, roles,
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
    Building, Camera, CameraPath, DensityProfile, Light, LightKind, Material, Mesh, Motion, Object,
    Roles, Scene, SceneError, Texture, Volume,
};
use glam::{Mat3, Mat4, Quat, Vec2, Vec3};
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};
use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

mod export;
mod extras;
mod importer;
mod notes;
mod read;
pub use export::glb;
use export::*;
use extras::*;
use importer::*;
use notes::*;
use read::*;

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

/// [`import`], with the notes of what the importer supplied, repaired or left out (default
/// lighting for a file without lights, replaced degenerate normals, the camera chosen and
/// those not used, materials' emission (which lights nothing), alpha and roughness),
/// one sentence each naming the light, camera or material: the harness prints them as
/// warnings and writes them to `results.json`.
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
