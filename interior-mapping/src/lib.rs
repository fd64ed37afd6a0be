//! Interior mapping (van Dongen 2008, "Interior Mapping: a new technique for rendering
//! realistic buildings"): virtual rooms behind building facades by a per-pixel ray cast
//! against regularly spaced planes, plus the polygon baseline. See README.md.
//!
//! * [`rooms`]: the ray cast (Rust twin of `shaders/interior.wgsl`).
//! * [`technique`]: the `interior/...` techniques.
//! * [`geometry`], [`textures`]: real room geometry and interior textures, identical to the
//!   `city` scene's real interiors.

pub mod geometry;
pub mod rooms;
pub mod technique;
pub mod textures;

pub use technique::{InteriorMapping, PolygonInteriors, Variant};

/// The WGSL twin of [`rooms`] (needs the `gpu` prelude).
pub const INTERIOR_WGSL: &str = include_str!("shaders/interior.wgsl");

/// All technique variants of this crate.
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    technique::all()
}
