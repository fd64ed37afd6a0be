//! The one place where the harness calls the renderers and file writers of the `scene` and
//! `truth` crates (the CPU reference renderer, glTF export, the GPU upload; the per-frame scene update
//! is `scene::runner`'s). Every other module goes through these functions, so following a changed scene or
//! reference API is a change here.

use crate::{Reference, ReferenceStats};
use anyhow::Result;
use gpu::Context;
use scene::{Camera, GpuScene, Scene};
use std::path::Path;
use truth::reference::ReferenceOptions;

/// Uploads a scene to the GPU (validated first); GPU validation errors become the error.
pub fn upload_scene(ctx: &Context, scene: &Scene) -> Result<GpuScene> {
    Ok(ctx.validated(|| GpuScene::new(ctx, scene))??)
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
