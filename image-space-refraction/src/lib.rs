//! Image-space refraction (Hu and Qin: "Interactive Approximate Rendering of Reflections,
//! Refractions, and Caustics", IEEE TVCG 2007, sections 2-5): the refractor's front- and
//! back-facing surfaces drawn from the eye every frame (no preprocessing, so a deforming
//! refractor works), the second interface found by a silhouette search, an angle test and an
//! iterative `d_T` on those buffers, and the exit ray looking up the environment; beside the
//! method it improves (Wyman 2005, with a precomputed thickness along the normal), plain
//! one-interface refraction and the engine's screen-space refraction with a thickness proxy.
//!
//! - [`search`]: the searches' Rust twins (silhouette, angle test, `d_T`, Wyman's estimate),
//!   mirrored by `shaders/search.wgsl`.
//! - [`technique`]: the [`Refraction`] technique and its variants ([`techniques`]).
//!
//! See `README.md` for the mapping of variants to the paper, departures and failure cases.

#![warn(missing_docs)]

pub mod caustics;
pub mod nearby;
pub mod rectangles;
pub mod search;
pub mod technique;

pub use technique::{Nearby, Refraction, Settings, Variant};

/// All variants: `image-space-refraction/one-interface`, `two-interface-baseline`, `hu-qin`,
/// `hu-qin-back-first`, `thickness-proxy` (the engine baseline).
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    technique::variants()
}

/// The image checks of this crate (run by the tests crate against the reference along the
/// camera path).
pub fn image_checks() -> Vec<scene::ImageCheck> {
    vec![]
}
