// The paper's light-map splatting (section 5): one small quad per caustic-map texel, centred
// at the photon's light-map address, drawn into the light-map atlas with additive blending.
// The vertex shader reads the caustic map (the paper's vertex texture fetch, "caustcoord" =
// instance index) and moves quads of empty texels out of the clip volume; the fragment
// shader weights the photon power with a Gaussian over the quad. Imports gpu::prelude,
// scene::chart and scene::footprint.
#import gpu::prelude::PI
#import scene::chart::Chart
#import scene::footprint::{FIXED_CUT2, footprint_cut2, footprint_covariance, lattice_cell_edge}

// Photon footprints (photon differentials, Schjoth et al. 2007, in their finite-difference
// form): the photons leave the light on a lattice (the photon map's texels), so each photon
// stands for one lattice cell; where the caustic spreads, the cell lands on the atlas much
// larger than a fixed quad, and stretched (under a glass sphere, radially), and a lattice of
// fixed quads draws its rows as moire rings. With footprints on, a photon's Gaussian is its
// cell's: covariance sigma0^2 I + c^2 (ex ex^T + ey ey^T), ex and ey the cell's edges on the
// atlas measured from the landing points of its lattice neighbours (the neighbours that landed
// in the same chart and the same lattice tile). lightmap.rs's `Footprint` is the twin.

struct SplatQuadParams {
    // Atlas side L (texels), quad radius R (texels): the fixed Gaussian has sigma0 = R / 2,
    // cut at R; z, w unused.
    atlas: vec4f,
    // Caustic map size C (photons per side).
    size: u32,
    // Side of a lattice tile (photons): neighbours across a tile's edge belong to another
    // lattice (another caster's or light's tile); 0: no footprints, the fixed Gaussian.
    tile: u32,
    _pad1: u32,
    _pad2: u32,
};

@group(0) @binding(0) var photon_address: texture_2d<f32>;
@group(0) @binding(1) var photon_power: texture_2d<f32>;
@group(0) @binding(2) var<storage, read> splat_charts: array<Chart>;
@group(0) @binding(3) var<uniform> quads: SplatQuadParams;

struct QuadOut {
    @builtin(position) clip: vec4f,
    // Offset from the photon in texels (the paper's filter coordinates).
    @location(0) offset: vec2f,
    @location(1) @interpolate(flat) power: vec3f,
    // The chart's rectangle in atlas texels: the splat stays inside its own chart.
    @location(2) @interpolate(flat) rect: vec4f,
    // The footprint's inverse covariance (xx, xy, yy) and its normalisation.
    @location(3) @interpolate(flat) gauss: vec4f,
    // Its cut (squared Mahalanobis distance).
    @location(4) @interpolate(flat) cut2: f32,
};

// The landing point (atlas texels) of the photon at lattice texel `at` if it landed in `chart`
// within the same tile as `origin`; z = 0 where it did not.
fn lattice_neighbour(origin: vec2i, at: vec2i, chart: f32) -> vec3f {
    let tile = i32(quads.tile);
    if (any(at < vec2i(0)) || any(at >= vec2i(i32(quads.size))) || any(at / tile != origin / tile)) {
        return vec3f(0.0);
    }
    let a = textureLoad(photon_address, at, 0);
    let same = a.w >= 0.5 && round(a.z) == round(chart);
    return select(vec3f(0.0), vec3f(a.xy * quads.atlas.x, 1.0), same);
}

// One edge of the photon's lattice cell on the atlas along lattice axis `axis`
// (footprint.wgsl's lattice_cell_edge of its two neighbours).
fn lattice_edge(texel: vec2i, axis: vec2i, centre: vec2f, chart: f32) -> vec2f {
    let ahead = lattice_neighbour(texel, texel + axis, chart);
    let behind = lattice_neighbour(texel, texel - axis, chart);
    return lattice_cell_edge(vec3f(ahead.xy - centre, ahead.z), vec3f(behind.xy - centre, behind.z));
}

const QUAD_CORNERS = array<vec2f, 6>(
    vec2f(-1.0, -1.0), vec2f(1.0, -1.0), vec2f(1.0, 1.0),
    vec2f(-1.0, -1.0), vec2f(1.0, 1.0), vec2f(-1.0, 1.0),
);

@vertex
fn splat_quad_vs(@builtin(vertex_index) vertex: u32, @builtin(instance_index) photon: u32) -> QuadOut {
    var out: QuadOut;
    let texel = vec2i(i32(photon % quads.size), i32(photon / quads.size));
    let address = textureLoad(photon_address, texel, 0);
    // No photon through this texel: outside the clip volume (the listing's hpos.z = 2).
    out.clip = vec4f(0.0, 0.0, 2.0, 1.0);
    out.offset = vec2f(0.0);
    out.power = vec3f(0.0);
    out.rect = vec4f(0.0);
    out.gauss = vec4f(0.0);
    out.cut2 = 0.0;
    if (address.w < 0.5) { return out; }
    let size = quads.atlas.x;
    let centre = address.xy * size;
    var ex = vec2f(0.0);
    var ey = vec2f(0.0);
    var cut2 = FIXED_CUT2;
    if (quads.tile > 0u) {
        ex = lattice_edge(texel, vec2i(1, 0), centre, address.z);
        ey = lattice_edge(texel, vec2i(0, 1), centre, address.z);
        cut2 = footprint_cut2(quads.atlas.y, ex, ey);
    }
    let cov = footprint_covariance(quads.atlas.y, ex, ey, cut2);
    let det = cov.x * cov.z - cov.y * cov.y;
    out.gauss = vec4f(vec3f(cov.z, -cov.y, cov.x) / det,
                      1.0 / (2.0 * PI * sqrt(det) * (1.0 - exp(-0.5 * cut2))));
    out.cut2 = cut2;
    let half_extent = sqrt(cut2 * cov.xz);
    let offset = QUAD_CORNERS[vertex] * half_extent;
    let p = (centre + offset) / size;
    out.clip = vec4f(2.0 * p.x - 1.0, 1.0 - 2.0 * p.y, 0.0, 1.0);
    out.offset = offset;
    out.power = textureLoad(photon_power, texel, 0).rgb;
    out.rect = splat_charts[i32(round(address.z))].rect * size;
    return out;
}

@fragment
fn splat_quad_fs(in: QuadOut) -> @location(0) vec4f {
    let d = in.offset;
    let q = in.gauss.x * d.x * d.x + 2.0 * in.gauss.y * d.x * d.y + in.gauss.z * d.y * d.y;
    let texel = in.clip.xy;
    if (q > in.cut2 || any(texel < in.rect.xy) || any(texel > in.rect.zw)) {
        discard;
    }
    return vec4f(in.power * exp(-0.5 * q) * in.gauss.w, 0.0);
}
