//! Refractor height maps (Dancsik and Minarik: "Real-time multi-bounce many-object ray
//! tracing with distance-normal impostors", section 6): a piece with a plane of
//! symmetry stored as a height map of its half in front of that plane, stood on a billboard
//! that turns about the vertical to face the ray's origin, and searched by binary search for
//! the ray's entry and, after refraction, its exit. Where a refractor *distance* map misses
//! the surface hidden from the piece's centre (the stepped bases, the knight's jaw), a height
//! map holds every point that an orthographic view of the plane sees.
//!
//! - [`search`]: segment selection (figure 7), binary search, the search from outside and from
//!   inside: the Rust twin of `shaders/height_search.wgsl`.
//! - [`map`]: the height map of each kind of piece (an orthographic render).
//! - [`technique`]: the [`HeightMaps`] technique (billboards drawn and searched from the eye)
//!   and its variants `single` and `double-refraction`.
//! - [`in_chess`]: `height-maps/in-chess`: `scene`'s many-object tracer, the one
//!   `refractor-maps` drives with distance maps, searching height maps ([`HeightSearch`]):
//!   section 6's closing remark, "the refractor distance map can be replaced by the refractor
//!   height map".
//! - [`pass`]: [`HeightMapPass`], the billboards as a pass of a renderer's own frame (its
//!   targets and formats, its world asked through `gpu::DrawScene`).
//! - [`separated`]: `height-maps/separated` and `height-maps/full-update`: the paper's own
//!   place for height maps, section 5.2's per-piece environment impostors (`scene`'s
//!   `PieceImpostors`, the driver `refractor-maps/separated` runs on distance maps) with every
//!   search in height maps and every piece a billboard deciding its own visibility.
//!
//! See `README.md` for the mapping to the paper, the departures and the failure cases.

#![warn(missing_docs)]

pub mod in_chess;
pub mod map;
pub mod pass;
pub mod search;
pub mod separated;
pub mod technique;

pub use in_chess::{HeightMapsInChess, HeightSearch, InChessSettings};
pub use pass::{HeightMapPass, HeightPiece};
pub use separated::{HeightMapsSeparated, SeparatedSettings};
pub use technique::{HeightMaps, MapSettings, Refraction, Settings};

/// This crate's family: [`techniques`] and [`image_checks`], listed once by the harness.
pub const FAMILY: scene::Family = scene::Family {
    name: "height-maps",
    techniques,
    image_checks,
};

/// All technique variants of this crate: `height-maps/single`,
/// `height-maps/double-refraction`, `height-maps/in-chess`, `height-maps/separated`,
/// `height-maps/full-update`.
pub fn techniques() -> Vec<Box<dyn scene::Technique>> {
    let mut all = technique::variants();
    all.push(Box::new(HeightMapsInChess::new()));
    all.extend(separated::variants());
    all
}

/// The image checks of this crate (run by the tests crate against the reference along the
/// camera path).
pub fn image_checks() -> Vec<scene::ImageCheck> {
    use scene::ImageCheck;
    vec![
        ImageCheck::new(
            "height-maps/double-refraction",
            "chess",
            0.068,
            0.052,
            "one piece per path through height maps: measured FLIP 0.0568 / 0.0652 / 0.0578, \
             RMSE 0.0454 / 0.0485 / 0.0457 at t = 0, 1, 2 (64 x 64); the FLIP bound lies below \
             refractor-maps/single-bounce's best frame (0.0685), the same path through \
             distance maps",
        ),
        ImageCheck::new(
            "height-maps/single",
            "chess",
            0.140,
            0.084,
            "one interface: measured FLIP 0.1016 / 0.1321 / 0.1032, RMSE 0.0661 / 0.0789 / \
             0.0665; without the exit the pieces show the board through one bend",
        ),
        ImageCheck::new(
            "height-maps/in-chess",
            "chess",
            0.055,
            0.040,
            "scene's many-object tracer with height maps: measured FLIP 0.0386 / 0.0486 / \
             0.0386, RMSE 0.0318 / 0.0359 / 0.0322 at t = 0, 1, 2 (64 x 64); the bounds lie \
             below refractor-maps/multi-bounce-4's best frame (FLIP 0.0612, RMSE 0.0461), the \
             same tracer with distance maps",
        ),
        ImageCheck::new(
            "height-maps/separated",
            "chess:material=mirror-mover",
            0.066,
            0.052,
            "section 5.2 with height maps on the paper's figure 9 scene: measured FLIP 0.0555 / \
             0.0627 / 0.0565, RMSE 0.0459 / 0.0474 / 0.0465 at t = 0, 1, 2 (64 x 64); the FLIP \
             bound lies below refractor-maps/separated's best frame (0.0667), the same \
             impostors searched through distance maps",
        ),
        ImageCheck::new(
            "height-maps/double-refraction",
            "cornell-sphere",
            0.090,
            0.52,
            "a sphere seen from above: measured FLIP 0.0835 / 0.0546 / 0.0835 (refractor maps \
             0.0707 / 0.0465: the binary search misses the top's far half, README \
             \"Failure cases\"); RMSE 0.4867 / 0.3919 is the reference's caustic",
        ),
    ]
}
