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
//! * [`technique`]: `raytracer/whitted`, `raytracer/caustics` and `raytracer/ray-query` (the
//!   caustics variant with the hardware's ray queries in place of the BVH traversal, where the
//!   adapter offers wgpu's experimental ray queries).

pub mod bvh;
pub mod technique;
pub mod tracer;

pub use technique::{RayTracer, Variant};
pub use tracer::{GpuTracer, RayCounts, TracerSettings, Traversal};

/// All variants: `raytracer/whitted`, `raytracer/caustics` and `raytracer/ray-query`.
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    technique::variants()
}

/// The image checks of this crate (run by the tests crate against the reference along the
/// camera path).
pub fn image_checks() -> Vec<scene::ImageCheck> {
    Vec::new()
}
