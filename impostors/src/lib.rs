//! Distance impostors (Szirmay-Kalos, Aszódi, Lazányi, Premecz: "Approximate Ray-Tracing on
//! the GPU with Distance Impostors", 2005): environment maps that also store the distance of
//! the visible surface, so reflections and refractions can be *localized* by an approximate
//! ray hit (`gpu::distance_map::hit`) found with a few map lookups; refractor maps for double refraction.
//!
//! - `Hit()` itself (Rust twin, WGSL, property tests) is shared by every distance-map
//!   technique and lives in `gpu::distance_map`.
//! - [`technique`]: the [`Impostor`] technique and its variants ([`techniques`]): classic,
//!   localized (initial guess, secant, false position; packed or split distances), double
//!   refraction through a refractor map, caustics.
//! - [`caustics`]: caustic maps and the two splat paths (the paper's light maps, a compute
//!   scatter); the receivers' light-map charts and the Gaussian quad splat are shared in
//!   `scene::lightmap`.
//!
//! See `README.md` for the mapping of variants to the paper, departures and failure cases.

pub mod caustics;
pub mod technique;

pub use technique::{Impostor, Mode, Settings};

/// All technique variants of this crate: `impostors/classic`, `impostors/initial-guess`,
/// `impostors/secant-{1..8}`, `impostors/false-position-{1..8}`,
/// `impostors/false-position-4-split`, `impostors/double-refraction`, `impostors/caustics`,
/// `impostors/caustics-compute`.
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    technique::variants()
}

/// The image checks of this crate (run by the tests crate against the reference along the
/// camera path).
pub fn image_checks() -> Vec<scene::ImageCheck> {
    let check = |technique, scene, max_flip_mean, max_rmse, reason| scene::ImageCheck {
        technique,
        scene,
        size: 64,
        max_flip_mean,
        max_rmse,
        reason,
    };
    vec![
        check(
            "impostors/false-position-4",
            "cornell-box",
            1.0,
            1.0,
            "MEASURE",
        ),
        check("impostors/classic", "cornell-box", 1.0, 1.0, "MEASURE"),
        check(
            "impostors/double-refraction",
            "cornell-sphere",
            1.0,
            1.0,
            "MEASURE",
        ),
        check("impostors/caustics", "cornell-sphere", 1.0, 1.0, "MEASURE"),
        check(
            "impostors/false-position-4",
            "cornell-sphere:material=gold",
            1.0,
            1.0,
            "MEASURE",
        ),
    ]
}
