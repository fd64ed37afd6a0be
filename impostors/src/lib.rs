//! Distance impostors (Szirmay-Kalos, Aszódi, Lazányi, Premecz: "Approximate Ray-Tracing on
//! the GPU with Distance Impostors", 2005): environment maps that also store the distance of
//! the visible surface, so reflections and refractions can be *localized* by an approximate
//! ray hit ([`hit`]) found with a few map lookups; refractor maps for double refraction.
//!
//! - [`hit`]: `Hit()` in Rust (the twin of `shaders/hit.wgsl`), distance-map abstraction,
//!   exact box-room and read-back cube maps.
//! - [`technique`]: the [`Impostor`] technique and its variants ([`techniques`]): classic,
//!   localized (initial guess, secant, false position; packed or split distances), double
//!   refraction through a refractor map, caustics.
//! - [`caustics`]: caustic maps and the two splat paths (the paper's light maps, a compute
//!   scatter); [`lightmap`]: the receivers' light-map charts.
//!
//! See `README.md` for the mapping of variants to the paper, departures and failure cases.

pub mod caustics;
pub mod hit;
pub mod lightmap;
pub mod technique;

pub use technique::{HIT_WGSL, Impostor, Mode, Settings};

/// All technique variants of this crate: `impostors/classic`, `impostors/initial-guess`,
/// `impostors/secant-{1..8}`, `impostors/false-position-{1..8}`,
/// `impostors/false-position-4-split`, `impostors/double-refraction`, `impostors/caustics`,
/// `impostors/caustics-compute`.
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    technique::variants()
}

/// Same as [`techniques`] (the name the harness registry comment uses).
pub fn variants() -> Vec<Box<dyn scene::Technique>> {
    technique::variants()
}
