//! Interior mapping (van Dongen 2008, "Interior Mapping: a new technique for rendering
//! realistic buildings"): virtual rooms behind building facades by a per-pixel ray cast
//! against regularly spaced planes, plus the polygon baseline. See README.md.
//!
//! * [`rooms`]: the ray cast (Rust twin of `shaders/interior.wgsl`).
//! * [`technique`]: the `interior-mapping/...` techniques.
//! * [`pass`]: [`InteriorPass`], the buildings as a pass of a renderer's own frame (its
//!   targets and formats, its lights).
//! * [`geometry`], [`textures`]: real room geometry and interior textures, identical to the
//!   `city` scene's real interiors.

// Every public item says what it is for: users lift this crate into their own renderers.
#![warn(missing_docs)]

pub mod geometry;
pub mod pass;
pub mod rooms;
pub mod technique;
pub mod textures;

pub use pass::{Building, InteriorPass, PointLight};
pub use technique::{InteriorMapping, PolygonInteriors, Variant};

/// The WGSL twin of [`rooms`]: the module `interior_mapping::rooms` ([`ROOMS`]).
pub const INTERIOR_WGSL: &str = include_str!("shaders/interior.wgsl");
/// [`INTERIOR_WGSL`] as the module `interior_mapping::rooms`, which the technique's shader and
/// the conformance kernels import (`#import interior_mapping::rooms::cast_rooms`).
pub static ROOMS: gpu::wgsl::Module = gpu::wgsl::Module::new(
    INTERIOR_WGSL,
    "interior-mapping/src/shaders/interior.wgsl",
    &[],
);

/// This crate's family: [`techniques`] and [`image_checks`], listed once by the harness.
pub const FAMILY: scene::Family = scene::Family {
    name: "interior-mapping",
    techniques,
    image_checks,
};

/// All technique variants of this crate.
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    technique::all()
}

/// The image checks of this crate (run by the tests crate against the reference along the
/// camera path).
pub fn image_checks() -> Vec<scene::ImageCheck> {
    use scene::ImageCheck;
    let check =
        |technique, flip, rmse, reason| ImageCheck::new(technique, "city", flip, rmse, reason);
    vec![
        check(
            "interior-mapping/textured",
            0.021,
            0.0087,
            "the ray cast finds the same room planes as the reference's real geometry; left: \
             texture filtering and the window glass; measured FLIP 0.016, RMSE 0.0069 (64 x \
             64, worst of t = 0, 2, 4)",
        ),
        check(
            "interior-mapping/cubemap",
            0.021,
            0.0087,
            "the engine baseline (cube-map interiors) on box rooms sees the same surfaces and \
             texels as the ray cast: measured FLIP 0.016, RMSE 0.0069, as textured",
        ),
        check(
            "interior-mapping/cubemap-varied",
            0.023,
            0.0087,
            "cube-map interiors with a random room of four and mirrored axes per room, where \
             the reference has one room: measured FLIP 0.018, RMSE 0.0070",
        ),
        check(
            "interior-mapping/polygons",
            0.064,
            0.019,
            "the polygon baseline lit by the scene's shadow maps instead of exact window light: \
             measured FLIP 0.051, RMSE 0.015",
        ),
        check(
            "interior-mapping/reflection-only",
            0.56,
            0.25,
            "a baseline with no rooms at all (the facade reflects the street): large on purpose \
             near the buildings, measured FLIP 0.441 at t = 0, 0.009 at t = 4",
        ),
    ]
}
