//! The scene side of the workspace: the scene model (with the volumes' density field),
//! built-in scenes, glTF import/export, the BVH with exact ray queries, the GPU upload with the
//! shared raster pass, depth peeling of the uploaded scene ([`DepthPeeler`]), and the
//! `Technique` trait. The CPU reference renderer (the ground truth) and the image metrics are
//! the `truth` crate's, so that a technique crate, which depends on this crate, compiles
//! neither rayon nor nv-flip.

pub mod builtin;
#[cfg(feature = "bvh")]
pub mod bvh;
pub mod density;
pub mod depth_peel;
pub mod emission;
pub mod foundation;
#[cfg(feature = "gltf")]
pub mod gltf_io;
mod gpu_scene;
pub mod hosted;
pub mod kinds;
pub mod layer_count;
pub mod lightmap;
pub mod medium;
pub mod mesh;
mod model;
pub mod multi_object;
pub mod runner;
mod shading;
pub mod technique;

pub use depth_peel::DepthPeeler;
pub use gpu_scene::{
    BACKGROUND_DISTANCE, CasterShadowMaps, CubeFace, DrawRange, GpuScene, MIN_SHADOW_MAP_SIZE,
    ObjectFilter, RasterTarget, SHADOW_BUDGET_BYTES, SHADOW_MAP_SIZE, albedo_array_extent,
    begin_scene_pass, shadow_map_size, sphere_meets_cube_face,
};
pub use kinds::Kinds;
pub use medium::Medium;
pub use model::*;
pub use shading::{
    RASTER_WGSL, SCENE_VS_WGSL, SHADING, SHADING_WGSL, proxy_pipeline, proxy_pipeline_for,
    scene_pipeline, scene_pipeline_entries, scene_pipeline_for, scene_pipeline_with,
    scene_pipeline_with_depth, scene_vertex_module, shader, shader_importing, shader_of,
};
pub use technique::{
    Contained, Declared, Family, Frame, ImageCheck, PINHOLE_ONLY, Param, ParamValue, Settings,
    Technique, TechniqueError, TechniqueResult, Timing, View, orthographic_refusal,
    point_lights_only,
};

use std::path::Path;

/// Everything that can go wrong when making or loading a scene, each one sentence.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("unknown scene \"{0}\" (built-in scenes: {1}; or give a path to a .gltf/.glb file)")]
    UnknownScene(String, String),
    #[error("bad scene parameter: {0}")]
    BadParam(String),
    #[error("cannot read {0}: {1}")]
    Io(String, String),
    #[error("cannot write {0}: {1}")]
    Write(String, String),
    #[error("cannot load glTF {0}: {1}")]
    Gltf(String, String),
    #[error("invalid scene: {0}")]
    Invalid(String),
    #[error(transparent)]
    Gpu(#[from] gpu::GpuError),
}

/// Loads a scene from a spec: a built-in name (`cornell-sphere`, `city:buildings=64`, see
/// [`builtin::builtin_scenes`]) or a path to a `.gltf` / `.glb` file.
pub fn load(spec: &str) -> Result<Scene, SceneError> {
    load_noted(spec).map(|(scene, _)| scene)
}

/// [`load`], with the notes of what the glTF importer supplied or repaired (default lighting,
/// replaced normals; see `gltf_io::import_noted`, with the `gltf` feature); built-in scenes
/// have none.
pub fn load_noted(spec: &str) -> Result<(Scene, Vec<String>), SceneError> {
    if is_file_spec(spec) {
        let (scene, notes) = import_file(Path::new(spec))?;
        scene.validate()?;
        return Ok((scene, notes));
    }
    let (name, params) = builtin::parse_spec(spec)?;
    Ok((builtin::build(&name, &params)?, Vec::new()))
}

#[cfg(feature = "gltf")]
fn import_file(path: &Path) -> Result<(Scene, Vec<String>), SceneError> {
    gltf_io::import_noted(path)
}

#[cfg(not(feature = "gltf"))]
fn import_file(path: &Path) -> Result<(Scene, Vec<String>), SceneError> {
    Err(SceneError::Gltf(
        path.display().to_string(),
        "this build of the scene crate has no glTF importer (enable its `gltf` feature)".into(),
    ))
}

/// Whether a scene spec names a file (`.gltf`, `.glb`, or an existing path) rather than a
/// built-in scene.
pub fn is_file_spec(spec: &str) -> bool {
    let lower = spec.to_lowercase();
    lower.ends_with(".gltf") || lower.ends_with(".glb") || Path::new(spec).exists()
}
