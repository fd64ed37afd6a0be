//! The board grid of the many-object tracer (paper section 4.2) and the search for the nearest
//! piece along a ray through it: the Rust twin of `shaders/grid_search.wgsl`.
//!
//! The paper partitions the search domain with "a uniform grid aligned on the squares of the
//! chessboard", assumes one piece per square, and searches only "the first non-empty square
//! along the ray". We keep the grid and the walk (`gpu::prelude::grid_walk`, the 2D DDA) but
//! build the grid from the pieces themselves, so that any scene's refractors can be traced:
//!
//! - the cell side is the largest footprint (x or z extent) of any piece, so a piece overlaps
//!   at most 2 x 2 cells; it is registered in every cell its footprint overlaps;
//! - a cell holds up to [`CELL_CAPACITY`] pieces; if some cell would hold more, the side is
//!   halved until none does (pieces that overlap each other cannot be separated: an error);
//! - the walk stops at the first cell whose nearest hit lies within the cell (no later cell
//!   can hold a nearer one: every piece reaching into this cell is registered in it), or,
//!   with `max_cells = 1`, after the first occupied cell whatever it found: the paper's
//!   shortcut, which misses a piece behind one the ray passes by.

use glam::{IVec2, Vec2, Vec3};
use gpu::prelude::{grid_walk, grid_walk_next};

/// Pieces one cell can list (a `vec4<u32>` on the GPU).
pub const CELL_CAPACITY: usize = 4;
/// An unused slot of a cell.
pub const EMPTY: u32 = u32::MAX;
/// Most cells along either axis.
pub const MAX_CELLS_PER_AXIS: i32 = 256;

/// A uniform grid of square cells on the xz plane, each listing the pieces whose footprint
/// overlaps it.
#[derive(Clone, Debug, PartialEq)]
pub struct BoardGrid {
    /// (x, z) of the grid's corner.
    pub min: Vec2,
    /// Side of a cell (metres).
    pub cell: f32,
    /// Cells along x and z.
    pub count: IVec2,
    /// Row-major (z rows of x columns) piece lists, [`EMPTY`] in unused slots.
    pub cells: Vec<[u32; CELL_CAPACITY]>,
}

/// Why no grid could be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GridError {
    /// Footprints overlap so much that some cell lists too many pieces at any cell size.
    #[error(
        "{0} refractors overlap one another too closely for the board grid (more than {CELL_CAPACITY} share a cell however small)"
    )]
    Crowded(usize),
    /// The pieces spread over too many cells.
    #[error("the refractors spread over more than {MAX_CELLS_PER_AXIS} grid cells along an axis")]
    TooLarge,
}

impl BoardGrid {
    /// The grid over the xz `footprints` (min, max) of the pieces, indexed as given.
    pub fn build(footprints: &[(Vec2, Vec2)]) -> Result<BoardGrid, GridError> {
        let largest = footprints
            .iter()
            .map(|(lo, hi)| (*hi - *lo).max_element())
            .fold(0.0f32, f32::max)
            .max(1e-4);
        let mut cell = largest;
        for _ in 0..8 {
            match Self::with_cell(footprints, cell)? {
                Some(grid) => return Ok(grid),
                None => cell *= 0.5,
            }
        }
        Err(GridError::Crowded(footprints.len()))
    }

    /// The grid of side `cell`, or `None` when some cell would list too many pieces.
    fn with_cell(footprints: &[(Vec2, Vec2)], cell: f32) -> Result<Option<BoardGrid>, GridError> {
        let (lo, hi) = footprints.iter().fold(
            (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)),
            |(a, b), (lo, hi)| (a.min(*lo), b.max(*hi)),
        );
        if footprints.is_empty() {
            return Ok(Some(BoardGrid {
                min: Vec2::ZERO,
                cell,
                count: IVec2::ZERO,
                cells: Vec::new(),
            }));
        }
        let count = ((hi - lo) / cell).ceil().as_ivec2().max(IVec2::ONE);
        if count.max_element() > MAX_CELLS_PER_AXIS {
            return Err(GridError::TooLarge);
        }
        let mut cells = vec![[EMPTY; CELL_CAPACITY]; (count.x * count.y) as usize];
        for (piece, (a, b)) in footprints.iter().enumerate() {
            let first = ((*a - lo) / cell)
                .floor()
                .as_ivec2()
                .clamp(IVec2::ZERO, count - 1);
            let last = ((*b - lo) / cell)
                .floor()
                .as_ivec2()
                .clamp(IVec2::ZERO, count - 1);
            for j in first.y..=last.y {
                for i in first.x..=last.x {
                    let slots = &mut cells[(j * count.x + i) as usize];
                    let Some(free) = slots.iter_mut().find(|s| **s == EMPTY) else {
                        return Ok(None);
                    };
                    *free = piece as u32;
                }
            }
        }
        Ok(Some(BoardGrid {
            min: lo,
            cell,
            count,
            cells,
        }))
    }
}

/// How many occupied cells the search examines.
pub const ALL_CELLS: u32 = u32::MAX;

/// The nearest piece hit along `o + t d` (t > 0) and its ray parameter: the cells the ray
/// crosses, in order, each piece listed there (except `skip`) tested with `hit` (the ray
/// parameter of its hit, if any), stopping as the module docs say. `max_cells`: occupied
/// cells to examine at most (1 = the paper's first non-empty square, [`ALL_CELLS`]).
pub fn nearest_piece(
    grid: &BoardGrid,
    o: Vec3,
    d: Vec3,
    skip: u32,
    max_cells: u32,
    mut hit: impl FnMut(u32) -> Option<f32>,
) -> Option<(u32, f32)> {
    let mut best: Option<(u32, f32)> = None;
    let mut walk = grid_walk(o, d, grid.min, grid.cell, grid.count);
    let mut examined = 0;
    let max_steps = (grid.count.x + grid.count.y + 2).max(0) as u32;
    for _ in 0..max_steps {
        if walk.done() {
            break;
        }
        let slots = grid.cells[(walk.cell.y * grid.count.x + walk.cell.x) as usize];
        let mut occupied = false;
        for piece in slots {
            if piece == EMPTY || piece == skip {
                continue;
            }
            occupied = true;
            if let Some(t) = hit(piece)
                && best.is_none_or(|(_, b)| t < b)
            {
                best = Some((piece, t));
            }
        }
        if best.is_some_and(|(_, t)| t <= walk.t_exit) {
            break;
        }
        if occupied {
            examined += 1;
            if examined >= max_cells {
                break;
            }
        }
        walk = grid_walk_next(walk, grid.count);
    }
    best
}

/// The nearest piece over all of them (the slow exact-visibility search).
pub fn nearest_piece_brute(
    pieces: u32,
    skip: u32,
    mut hit: impl FnMut(u32) -> Option<f32>,
) -> Option<(u32, f32)> {
    (0..pieces)
        .filter(|&p| p != skip)
        .filter_map(|p| hit(p).map(|t| (p, t)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}
