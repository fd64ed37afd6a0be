//! `harness render`: one image of a scene's view at time 0, from a technique or from the
//! ground truth. The ground truth comes through the reference cache, so a view `compare`
//! rendered is read back instead of rendered again, and one rendered here serves the next
//! `compare`.

use crate::cache::{self, Cached, RefView};
use crate::{CpuReference, Frames, GroundTruth as _, Size};
use anyhow::{Context as _, Result, bail};
use std::path::Path;

/// The reference image of `scene`'s view at time 0: from `cache_dir`, rendered and stored when
/// absent, with where it came from ([`Cached`]: a miss says why); rendered without a cache
/// when there is none (`None` beside the image).
pub fn reference_image(
    cache_dir: Option<&Path>,
    truth: &CpuReference,
    spec: &str,
    scene: &scene::Scene,
    size: Size,
) -> Result<(gpu::HdrImage, Option<Cached>)> {
    let view = RefView {
        spec,
        scene,
        camera: scene.camera_at(0.0),
        time: 0.0,
        size,
    };
    let Some(dir) = cache_dir else {
        let (w, h) = (size.width, size.height);
        let reference = truth.render(scene, &view.camera, view.time, w, h)?;
        return Ok((reference.image, None));
    };
    let found = cache::status(dir, truth, &view);
    let (reference, how) = cache::reference_as_found(dir, truth, &view, found)?;
    Ok((reference.image, Some(how)))
}

/// Technique `id`'s image of `scene` at time 0, after `frames` (a technique that refuses the
/// scene says why, as its `prepare` does).
pub fn technique_image(
    ctx: &gpu::Context,
    id: &str,
    spec: &str,
    scene: &scene::Scene,
    size: Size,
    frames: Frames,
) -> Result<gpu::HdrImage> {
    let mut t = crate::registry()
        .into_iter()
        .find(|t| t.id() == id)
        .with_context(|| format!("technique {id} vanished"))?;
    ctx.require(t.required_features())
        .with_context(|| format!("technique {id}"))?;
    if !t.supports(scene) {
        let gpu_scene = crate::backend::upload_scene(ctx, scene)?;
        bail!(
            "technique {id} does not support scene {spec}{}",
            unsupported_reason(ctx, t.as_mut(), &gpu_scene)
        );
    }
    let mut gpu_scene = crate::backend::upload_scene(ctx, scene)?;
    let run = crate::measure::run_technique(
        ctx,
        t.as_mut(),
        &mut gpu_scene,
        size,
        frames,
        &mut |_, _, _| {},
    )?;
    Ok(run.image().clone())
}

/// Why a technique refuses a scene, as its `prepare` says (": ..."), or nothing when it
/// prepares anyway or panics: `supports` gives no reason, `prepare` checks again and names it.
fn unsupported_reason(
    ctx: &gpu::Context,
    technique: &mut dyn scene::Technique,
    scene: &scene::GpuScene,
) -> String {
    let prepared = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        scene::runner::prepare(ctx, &mut gpu::GpuTimer::off(), technique, scene)
    }));
    match prepared {
        Ok(Err(e)) => format!(": {e}"),
        _ => String::new(),
    }
}
