// ---------------------------------------------------------------------------------------------
// The nearest piece along a ray through the board grid (Dancsik and Minarik section 4.2). Rust
// twin: scene/src/multi_object/grid.rs `nearest_piece` (same walk, same stopping rules; see its
// docs). Each candidate is searched by scene::pieces' piece_hit (the per-object search); the
// grid's cells (CELL_CAPACITY = 4 pieces per cell) are its own binding, at @group(#{GRID_GROUP})
// @binding(#{GRID_CELLS_BINDING}) (the tracer's: group 2, binding 2, `GRID_DEFS`).
// ---------------------------------------------------------------------------------------------
#define_import_path scene::grid_search

#import gpu::prelude::{grid_walk, grid_walk_next}
#import scene::pieces::piece_hit

@group(#{GRID_GROUP}) @binding(#{GRID_CELLS_BINDING}) var<storage, read> grid_cells: array<vec4u>;

const GRID_EMPTY: u32 = 0xffffffffu;

struct Grid {
    // (x, z) of the grid's corner, the side of a cell, unused.
    min_cell: vec4f,
    // Cells along x and z, unused, unused.
    count: vec4i,
};

struct PieceHit {
    // GRID_EMPTY for no hit.
    piece: u32,
    // The payload of piece_hit and the ray parameter in w.
    hit: vec4f,
};

// The nearest piece (other than `skip`) along o + t d; examines at most `max_cells` occupied
// cells (1: the paper's first non-empty square).
fn nearest_piece(grid: Grid, o: vec3f, d: vec3f, skip: u32, max_cells: u32) -> PieceHit {
    var best: PieceHit;
    best.piece = GRID_EMPTY;
    best.hit = vec4f(0.0, 0.0, 0.0, -1.0);
    let count = grid.count.xy;
    var walk = grid_walk(o, d, grid.min_cell.xy, grid.min_cell.z, count);
    var examined = 0u;
    let max_steps = u32(max(count.x + count.y + 2, 0));
    for (var step = 0u; step < max_steps; step++) {
        if (walk.t_enter >= walk.t_end) { break; }
        let slots = grid_cells[u32(walk.cell.y * count.x + walk.cell.x)];
        var occupied = false;
        for (var k = 0u; k < 4u; k++) {
            let p = slots[k];
            if (p == GRID_EMPTY || p == skip) { continue; }
            occupied = true;
            let h = piece_hit(p, o, d);
            if (h.w >= 0.0 && (best.piece == GRID_EMPTY || h.w < best.hit.w)) {
                best.piece = p;
                best.hit = h;
            }
        }
        if (best.piece != GRID_EMPTY && best.hit.w <= walk.t_exit) { break; }
        if (occupied) {
            examined++;
            if (examined >= max_cells) { break; }
        }
        walk = grid_walk_next(walk, count);
    }
    return best;
}

// The nearest over every piece: the slow exact-visibility search.
fn nearest_piece_brute(pieces: u32, o: vec3f, d: vec3f, skip: u32) -> PieceHit {
    var best: PieceHit;
    best.piece = GRID_EMPTY;
    best.hit = vec4f(0.0, 0.0, 0.0, -1.0);
    for (var p = 0u; p < pieces; p++) {
        if (p == skip) { continue; }
        let h = piece_hit(p, o, d);
        if (h.w >= 0.0 && (best.piece == GRID_EMPTY || h.w < best.hit.w)) {
            best.piece = p;
            best.hit = h;
        }
    }
    return best;
}
