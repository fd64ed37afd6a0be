//! Refractor height maps (Dancsik and Minarik: "Real-time multi-bounce many-object ray
//! tracing with distance-normal impostors", ../shared/papers/
//! distance-normal-impostors-and-refractor-height-maps.md, section 6): a piece with a plane of
//! symmetry stored as a height map of its half in front of that plane, stood on a billboard
//! that turns about the vertical to face the ray's origin, and searched by binary search for
//! the ray's entry and, after refraction, its exit. Where a refractor *distance* map misses
//! the surface hidden from the piece's centre (the stepped bases, the knight's jaw), a height
//! map holds every point that an orthographic view of the plane sees.
//!
//! - [`search`]: segment selection (figure 7), binary search, the search from outside and from
//!   inside: the Rust twin of `shaders/height_search.wgsl`.
//! - [`map`]: the height map of each kind of piece (an orthographic render).
//! - [`technique`]: the [`HeightMaps`] technique and its variants.
//!
//! See `README.md` for the mapping to the paper, the departures and the failure cases.

#![warn(missing_docs)]

pub mod map;
pub mod search;
pub mod technique;

pub use technique::{HeightMaps, Refraction, Settings};

/// All technique variants of this crate: `height-maps/single`,
/// `height-maps/double-refraction`.
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    technique::variants()
}

/// The image checks of this crate (run by the tests crate against the reference along the
/// camera path).
pub fn image_checks() -> Vec<scene::ImageCheck> {
    vec![]
}
