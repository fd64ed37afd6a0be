//! The many-object multi-bounce tracer (Dancsik and Minarik, sections 4.1-4.2), with the search
//! in one object's map as its parameter (section 6 closes: "In the algorithm described in 5.2,
//! the refractor distance map can be replaced by the refractor height map").
//!
//! - [`grid`]: the board grid and the nearest piece along a ray (Rust twin of
//!   `shaders/grid_search.wgsl`).
//! - [`pieces`]: the piece table (where each specular object stands at a time, its kind).
//! - [`Tracer`]: the driver: the diffuse environment impostor, the raster pass, and the
//!   specular objects drawn with `trace.wgsl`, which follows each pixel's tree of reflected and
//!   refracted rays from piece to piece.
//! - [`ObjectSearch`]: what the driver asks of one object's map: the hit of a ray from
//!   outside, the normal there, and the exit of a ray from inside. `refractor-maps` implements
//!   it with refractor distance maps, `height-maps` with refractor height maps; neither crate
//!   depends on the other, both on this one.
//! - [`PieceImpostors`]: section 5's per-piece environment impostors (full update, or the
//!   moving piece separated from the static ones), shading the pieces through the same
//!   [`ObjectSearch`], each piece's first hit rasterized from its mesh or found by a proxy
//!   ([`PieceSurface`]: height maps' billboards).

mod environment;
pub mod grid;
pub mod pieces;
mod tracer;

pub use environment::{
    ENVIRONMENT_PIECE_FS_WGSL, ENVIRONMENT_PIECES, ENVIRONMENT_PIECES_WGSL, IMPOSTOR_FORMAT,
    ImpostorSettings, MAX_ENV_DEPTH, PIECE_IMPOSTOR_HELP, PieceImpostors, PieceSurface,
    piece_impostor_help,
};
pub use pieces::{PIECES, PIECES_WGSL};

pub use tracer::{
    DRIVER_MODULES, EnvironmentImpostor, GRID_DEFS, GRID_SEARCH, GRID_SEARCH_WGSL,
    MAX_CELLS_PARAM_MAX, MAX_DEPTH, ObjectSearch, SEARCH_FIRST_BINDING, Search, TRACE,
    TRACE_FS_WGSL, TRACE_WGSL, Tracer, TracerSettings, depth_declared, driver_shader,
    max_cells_declared, pieces_centre, raster_diffuse, storage,
};
