#define_import_path scene::footprint
// A photon's Gaussian footprint on the light-map atlas (no bindings): the covariance and cut
// that splat_quads.wgsl's quads weight with. lightmap.rs's `Footprint` is the twin; the
// conformance test runs this file against it. The cell's edges come from lattice_cell_edge,
// which screen-photons' splats use too.

// A lattice cell's width in standard deviations: c in the covariance
// sigma0^2 I + c^2 (ex ex^T + ey ey^T), ex and ey the cell's edges on the atlas. Cut at three
// standard deviations, a lattice of such Gaussians sums to within 3 % of flat (lightmap.rs's
// tests; cut at two, as the fixed quad is, the sum ripples by 16 %).
const FOOTPRINT_CELL_SIGMA: f32 = 0.6;
// The largest half extent of a footprint's quad (texels): a cell measured across a fold or a
// silhouette can be arbitrarily large; its Gaussian is shrunk to fit.
const MAX_FOOTPRINT: f32 = 64.0;
// Squared Mahalanobis distance at which a Gaussian is cut, normalised over what remains
// (1 - exp(-cut2 / 2) of a whole Gaussian): the fixed quad's disc R = 2 sigma0; a footprint
// goes from there to three standard deviations as its cell outgrows the fixed quad
// (footprint_cut2), so that the focus of a caustic, where cells are small, keeps the paper's
// quad.
const FIXED_CUT2: f32 = 4.0;
const FOOTPRINT_CUT2: f32 = 9.0;

// A footprint's cut: FIXED_CUT2 plus the cell's share of the Gaussian's largest variance
// (0 for no cell, towards 1 for cells much larger than the fixed quad) of the way to
// FOOTPRINT_CUT2.
fn footprint_cut2(radius: f32, ex: vec2f, ey: vec2f) -> f32 {
    let s0 = 0.25 * radius * radius;
    let cell = FOOTPRINT_CELL_SIGMA * FOOTPRINT_CELL_SIGMA * max(dot(ex, ex), dot(ey, ey));
    return FIXED_CUT2 + (FOOTPRINT_CUT2 - FIXED_CUT2) * cell / (s0 + cell);
}

// The covariance (xx, xy, yy) of a photon's Gaussian: the fixed sigma0 = R / 2 widened by its
// cell (edges ex, ey; zero for none), shrunk so that its quad's half extents (sqrt(cut2)
// sigma) stay within MAX_FOOTPRINT.
fn footprint_covariance(radius: f32, ex: vec2f, ey: vec2f, cut2: f32) -> vec3f {
    let s0 = 0.25 * radius * radius;
    let c2 = FOOTPRINT_CELL_SIGMA * FOOTPRINT_CELL_SIGMA;
    var cov = vec3f(s0 + c2 * (ex.x * ex.x + ey.x * ey.x),
                    c2 * (ex.x * ex.y + ey.x * ey.y),
                    s0 + c2 * (ex.y * ex.y + ey.y * ey.y));
    let half_extent = sqrt(cut2 * max(cov.x, cov.z));
    if (half_extent > MAX_FOOTPRINT) {
        let shrink = MAX_FOOTPRINT / half_extent;
        cov *= shrink * shrink;
    }
    return cov;
}

// One edge of a photon's lattice cell from its two neighbours along one lattice axis (xy: the
// neighbour's landing point less the photon's; z: 1 where it landed on the same surface, 0
// where not): the shorter of the two (the longer may span a fold or a silhouette), or the one
// that exists; zero where neither does.
fn lattice_cell_edge(ahead: vec3f, behind: vec3f) -> vec2f {
    let backward = -behind.xy;
    if (ahead.z > 0.0 && behind.z > 0.0) {
        return select(backward, ahead.xy, dot(ahead.xy, ahead.xy) <= dot(backward, backward));
    }
    if (ahead.z > 0.0) { return ahead.xy; }
    if (behind.z > 0.0) { return backward; }
    return vec2f(0.0);
}
