//! The one place where the harness calls the renderers and file writers of the `scene` and
//! `truth` crates (the CPU reference renderer, glTF export, the GPU upload and its per-frame
//! update). Every other module goes through these functions, so following a changed scene or
//! reference API is a change here.

use crate::{Reference, ReferenceStats};
use anyhow::Result;
use gpu::Context;
use scene::{Camera, Frame, GpuScene, Scene};
use std::path::Path;
use truth::reference::ReferenceOptions;

/// Uploads a scene to the GPU (validated first); GPU validation errors become the error.
pub fn upload_scene(ctx: &Context, scene: &Scene) -> Result<GpuScene> {
    Ok(ctx.validated(|| GpuScene::new(ctx, scene))??)
}

/// Moves the uploaded scene's objects to `time` (and re-renders its shadow maps when something
/// moved), recording into `frame`. The harness calls this in its own submission before each
/// frame, so the shared scene update is not part of any technique's frame time.
pub fn set_scene_time(scene: &mut GpuScene, frame: &mut Frame, time: f32) {
    scene.set_time(frame, time);
}

/// A string that changes whenever the reference renderer's options change: part of the
/// reference cache key.
pub fn reference_options_key(options: &ReferenceOptions) -> String {
    format!("{options:?}")
}

/// Renders the ground truth with the CPU reference renderer.
pub fn render_reference(
    scene: &Scene,
    camera: &Camera,
    time: f32,
    width: u32,
    height: u32,
    options: &ReferenceOptions,
) -> Result<Reference> {
    let r = truth::reference::render(scene, camera, time, width, height, options);
    Ok(Reference {
        image: r.image,
        object_ids: r.object_ids,
        mask: r.mask,
        stats: ReferenceStats {
            camera_rays: r.stats.camera_rays,
            shadow_rays: r.stats.shadow_rays,
            photon_rays: r.stats.photon_rays,
            photons_stored: r.stats.photons_stored,
            seconds: r.stats.seconds,
            rays_per_second: r.stats.rays_per_second,
        },
    })
}

/// Writes a scene as binary glTF.
pub fn export_glb(scene: &Scene, path: &Path) -> Result<()> {
    Ok(scene::gltf_io::export_glb(scene, path)?)
}
