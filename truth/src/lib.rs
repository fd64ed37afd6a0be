//! The CPU ground truth and the image metrics: what every technique is measured against.
//!
//! - [`reference`](mod@reference): the CPU reference renderer (Whitted specular chains split by Fresnel,
//!   light-traced caustics, participating media), deterministic, on all cores with rayon; its
//!   module documentation states exactly what it computes and what it leaves out.
//! - [`media`]: the emission-absorption ray marcher the reference composites every eye ray
//!   through (the density field it integrates is the scene model's, `scene::density`).
//! - [`scattering`]: single scattering in the scene's homogeneous medium (direct in-scattering
//!   along the eye's rays, photon beams after specular events): the truth of light shafts.
//! - [`composite`]: the reference's media along the primary rays over another renderer's
//!   image (for tests that want the truth of the media alone).
//! - [`metrics`]: RMSE, PSNR, FLIP (nv-flip), masked FLIP, NaN count, sRGB conversion.
//! - [`techniques`]: the reference as a `scene::Technique` (`reference`), for the harness's
//!   registry.
//! - [`throughput`]: rays per second of the reference's BVH on five fixed ray sets (coherent
//!   and incoherent, closest-hit and any-hit, and the light pass's photon paths), what `harness rays` reports beside the
//!   reference's time by phase and part ([`reference::render_profiled`]).
//!
//! This is its own crate, beside `scene`, so that a technique crate (which depends on `gpu` and
//! `scene` only) never compiles rayon or nv-flip: technique crates use `truth` as a
//! dev-dependency only, in their tests and examples; the harness and the workspace tests use
//! it as a normal dependency.

pub mod composite;
pub mod media;
pub mod metrics;
pub mod reference;
pub mod scattering;
mod technique;
pub mod throughput;

pub use technique::ReferenceTechnique;

/// Distance new rays start off a surface at `p` (the reference's and the scattering passes'
/// one rule: `1e-4 * max(1, |p|)` metres).
pub fn offset_epsilon(p: glam::Vec3) -> f32 {
    1e-4 * p.length().max(1.0)
}

/// The pixel (row by row from the top) the continuous image point `p` falls in, `None` off
/// the `width` x `height` image: where the light pass splats what it lands.
pub(crate) fn pixel_at(p: glam::Vec2, width: u32, height: u32) -> Option<usize> {
    if !(p.x >= 0.0 && p.y >= 0.0 && p.x < width as f32 && p.y < height as f32) {
        return None;
    }
    let (x, y) = ((p.x as u32).min(width - 1), (p.y as u32).min(height - 1));
    Some((y * width + x) as usize)
}

/// This crate's family: `reference`, with no image check of its own (it is what the checks
/// measure against).
pub const FAMILY: scene::Family = scene::Family {
    name: "reference",
    techniques,
    image_checks: Vec::new,
};

/// This crate's technique, fresh: `reference` (the ground truth rendered on the CPU and
/// uploaded).
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    vec![Box::new(ReferenceTechnique::default())]
}
