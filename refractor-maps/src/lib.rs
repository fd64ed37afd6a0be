//! Refractor distance maps (Dancsik and Minarik: "Real-time multi-bounce many-object ray
//! tracing with distance-normal impostors", ../shared/papers/
//! distance-normal-impostors-and-refractor-height-maps.md, sections 3-4): the surface of each
//! kind of refracting piece stored once as a cube map of outward normal and distance from its
//! centre, searched from inside for the exit of a refracted ray and from *outside* (section
//! 4.1, `gpu::distance_map::hit_from_outside`) for the hit of a ray coming from elsewhere, so
//! that rays can bounce between many pieces (section 4.2) using these maps alone.
//!
//! - [`pieces`]: kinds (one map per mesh), where each piece stands at a time.
//! - [`grid`]: the board grid and the nearest-piece search along a ray (Rust twin of
//!   `shaders/grid_search.wgsl`).
//! - [`technique`]: the [`RefractorMaps`] tracer (section 4) and its variants.
//! - [`environment`]: the [`EnvironmentMaps`] technique (section 5): per-piece environment
//!   impostors holding multi-bounce radiance, fully updated or with the moving piece
//!   separated.
//!
//! See `README.md` for the mapping to the paper, the departures and the failure cases.

#![warn(missing_docs)]

pub mod environment;
pub mod grid;
pub mod pieces;
pub mod technique;

pub use environment::{EnvSettings, EnvironmentMaps};
pub use technique::{RefractorMaps, Search, Settings};

/// All technique variants of this crate: `refractor-maps/single-bounce`,
/// `refractor-maps/multi-bounce-2`, `refractor-maps/multi-bounce-4`,
/// `refractor-maps/first-square`, `refractor-maps/all-pieces`, `refractor-maps/full-update`,
/// `refractor-maps/separated`.
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    let mut all = technique::variants();
    all.extend(environment::variants());
    all
}

/// The image checks of this crate (run by the tests crate against the reference along the
/// camera path).
pub fn image_checks() -> Vec<scene::ImageCheck> {
    Vec::new()
}
