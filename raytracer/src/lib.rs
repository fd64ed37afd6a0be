//! The exact GPU ray tracer: the yardstick the approximations are timed against.
//!
//! Every paper this workspace implements compared itself with a CPU ray tracer running at a
//! fraction of a frame per second. Our users ask a different question: on *this* GPU, at this
//! error, is the approximation faster than tracing the rays exactly? This crate traces exactly
//! what the CPU reference (`truth::reference`) computes, on the same adapter as the
//! techniques, so that the harness can set each technique's frame time against it
//! (`speedup_vs_raytracer`) and draw error against time (the Pareto view).
//!
//! * [`bvh`]: the scene's BVH (obvhs, the reference's build parameters) flattened into storage
//!   buffers, and the Rust twin of the GPU traversal.
//! * [`tracer`]: the compute passes: the Whitted eye pass with shadow rays, Fresnel-split
//!   specular chains (n/k Fresnel for metals, glass with total internal reflection), the
//!   emission-absorption volumes and the scattering medium's transmittance and direct
//!   in-scattering; the light pass of caustic photons into a fixed-point accumulator.
//! * [`pass`]: the tracer as a pass of a renderer's own frame ([`pass::TracerPass`]): its
//!   colour and depth formats, its camera's matrices, its world as a `scene::Scene`, no
//!   `GpuScene`, the timer optional.
//! * [`technique`]: `raytracer/whitted`, `raytracer/caustics` and `raytracer/ray-query` (the
//!   caustics variant with the hardware's ray queries in place of the BVH traversal, where the
//!   adapter offers wgpu's experimental ray queries).

pub mod bvh;
pub mod pass;
mod resolve;
mod tables;
pub mod technique;
pub mod tracer;

pub use pass::TracerPass;
pub use technique::{RayTracer, Variant};
pub use tracer::{GpuTracer, RayCounts, TracerSettings, Traversal};

/// This crate's family: [`techniques`] and [`image_checks`], listed once by the harness.
pub const FAMILY: scene::Family = scene::Family {
    name: "raytracer",
    techniques,
    image_checks,
};

/// All variants: `raytracer/whitted`, `raytracer/caustics` and `raytracer/ray-query`.
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    technique::variants()
}

/// The image checks of this crate (run by the tests crate against the reference along the
/// camera path).
pub fn image_checks() -> Vec<scene::ImageCheck> {
    /// 16 frames of a sixteenth of the reference's photons: its density.
    const CONVERGED: &[(&str, f64)] = &[("converge", 16.0)];
    use scene::ImageCheck;
    // Measured with `harness compare --size 64x64 --error-frames 3 --ref-photons 249856` (the
    // reference's photon density at 64 x 64, what the image-check test renders): the worst of
    // t = start, middle, end; bounds about 1.25 x the measured values. The caustic checks are
    // the noise of two independent photon sets of the same size (tests/images.rs shows the
    // reference differs from itself with another seed by as much). They accumulate 16 frames
    // (`converge=16`), the reference's density: the default, 4, holds a quarter of it.
    vec![
        ImageCheck::new(
            "raytracer/caustics",
            "cornell-sphere",
            0.011,
            0.0045,
            "the reference traced on the GPU, caustic included: measured FLIP 0.0089, RMSE \
             0.0034 (photon noise)",
        )
        .with_params(CONVERGED),
        ImageCheck::new(
            "raytracer/caustics",
            "hu-qin:refractor=morph",
            0.0095,
            0.0105,
            "a deforming refractor, the BVH rebuilt every frame: measured FLIP 0.0074, RMSE 0.0082",
        )
        .with_params(CONVERGED),
        ImageCheck::new(
            "raytracer/caustics",
            "murky-pool",
            0.11,
            0.078,
            "light shafts (photon beams) and caustics under the waves, lit by photons alone: \
             measured FLIP 0.089, RMSE 0.062, the noise of 61 photons per pixel",
        )
        .with_params(CONVERGED),
        ImageCheck::new(
            "raytracer/whitted",
            "smoke",
            0.001,
            0.001,
            "emission-absorption volumes marched as the reference marches them: measured FLIP \
             and RMSE below 5e-5",
        ),
    ]
}
