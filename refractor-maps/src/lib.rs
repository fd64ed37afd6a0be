//! Refractor distance maps (Dancsik and Minarik: "Real-time multi-bounce many-object ray
//! tracing with distance-normal impostors", sections 3-4): the surface of each
//! kind of refracting piece stored once as a cube map of outward normal and distance from its
//! centre, searched from inside for the exit of a refracted ray and from *outside* (section
//! 4.1, `gpu::distance_map::hit_from_outside`) for the hit of a ray coming from elsewhere, so
//! that rays can bounce between many pieces (section 4.2) using these maps alone.
//!
//! - [`pieces`]: kinds (one map per mesh) and each kind's refractor map.
//! - [`technique`]: the [`RefractorMaps`] variants of section 4: `scene`'s many-object tracer
//!   (`scene::multi_object`: the board grid, the tree of rays, section 6's exchangeable
//!   per-object search) searching refractor distance maps ([`technique::DistanceSearch`]).
//! - [`environment`]: the [`EnvironmentMaps`] technique (section 5): per-piece environment
//!   impostors holding multi-bounce radiance, fully updated or with the moving piece
//!   separated.
//! - [`pass`]: [`RefractorMapsPass`], the tracer as a pass of a renderer's own frame (its
//!   targets and formats, its world asked through `gpu::DrawScene`).
//! - [`caustics`]: caustics on the chessboard (section 7): photon maps through the refractor
//!   maps, light maps of the static pieces (once) and of the moving piece (every frame).
//!
//! See `README.md` for the mapping to the paper, the departures and the failure cases.

#![warn(missing_docs)]

pub mod caustics;
pub mod environment;
pub mod pass;
pub mod pieces;
pub mod technique;

pub use caustics::CausticSettings;
pub use environment::{EnvSettings, EnvironmentMaps};
pub use pass::{Bounces, Piece, RefractorMapsPass, Surface};
pub use technique::{Maps, RefractorMaps, Search, Settings};

/// This crate's family: [`techniques`] and [`image_checks`], listed once by the harness.
pub const FAMILY: scene::Family = scene::Family {
    name: "refractor-maps",
    techniques,
    image_checks,
};

/// All technique variants of this crate: `refractor-maps/single-bounce`,
/// `refractor-maps/multi-bounce-2`, `refractor-maps/multi-bounce-4`,
/// `refractor-maps/first-square`, `refractor-maps/all-pieces`, `refractor-maps/caustics`,
/// `refractor-maps/full-update`, `refractor-maps/separated`.
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    let mut all = technique::variants();
    all.extend(environment::variants());
    all
}

/// The image checks of this crate (run by the tests crate against the reference along the
/// camera path).
pub fn image_checks() -> Vec<scene::ImageCheck> {
    use scene::ImageCheck;
    vec![
        ImageCheck::new(
            "refractor-maps/multi-bounce-4",
            "chess",
            0.074,
            0.056,
            "rays through up to four interfaces between the pieces: measured FLIP 0.0612 / \
             0.0687 / 0.0626 and RMSE 0.0461 / 0.0522 / 0.0473 at t = 0, 1, 2 (64 x 64); the FLIP \
             bound lies below single-bounce's worst frame (0.0777): more bounces must stay better",
        ),
        ImageCheck::new(
            "refractor-maps/single-bounce",
            "chess",
            0.083,
            0.059,
            "one piece per path, the rest from the diffuse environment: measured FLIP 0.0685 / \
             0.0777 / 0.0699, RMSE 0.0483 / 0.0546 / 0.0495",
        ),
        ImageCheck::new(
            "refractor-maps/separated",
            "chess:material=mirror-mover",
            0.080,
            0.058,
            "static impostors built once, the mirror pawn's rebuilt each frame and found from \
             outside (the paper's figure 9 scene): measured FLIP 0.0667 / 0.0742 / 0.0673, RMSE \
             0.0471 / 0.0537 / 0.0475; full-update's FLIP at the same size is within 1e-4 \
             of these",
        ),
        ImageCheck::new(
            "refractor-maps/caustics",
            "chess",
            0.068,
            0.056,
            "multi-bounce-4 with the light maps of section 7: measured FLIP 0.0602 / 0.0662 / \
             0.0616, RMSE 0.0461 / 0.0528 / 0.0473 at t = 0, 1, 2 (64 x 64); the FLIP bound lies \
             below multi-bounce-4's worst frame (0.0687): the caustics must bring it closer",
        ),
        ImageCheck::new(
            "refractor-maps/caustics",
            "cornell-sphere",
            0.02,
            0.66,
            "the caustic under the glass sphere: measured FLIP 0.0169 / 0.0148 / 0.0169 \
             (multi-bounce-4 without it: 0.0707 / 0.0465 / 0.0707); RMSE 0.1337 / 0.6190 / \
             0.1337 against multi-bounce-4's 0.4865 at every frame, so t = 0 and t = 2 are held \
             to 0.16, which a missing caustic fails; t = 1 needs 0.66 for the focus: one pixel \
             reads 64.2 from the light map's point sample where the reference's pixel average \
             is 24.5 (the rest agree within ~10%)",
        )
        .with_rmse_per_frame(&[0.16, 0.66, 0.16]),
        ImageCheck::new(
            "refractor-maps/multi-bounce-4",
            "cornell-sphere",
            0.076,
            0.52,
            "one glass sphere: measured FLIP 0.0707 / 0.0465 / 0.0707; the RMSE (0.4865) is the \
             reference's caustic under the sphere, which no variant here renders",
        ),
    ]
}
