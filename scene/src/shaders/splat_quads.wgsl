// The paper's light-map splatting (section 5): one small quad per caustic-map texel, centred
// at the photon's light-map address, drawn into the light-map atlas with additive blending.
// The vertex shader reads the caustic map (the paper's vertex texture fetch, "caustcoord" =
// instance index) and moves quads of empty texels out of the clip volume; the fragment
// shader weights the photon power with a Gaussian over the quad. After the gpu prelude +
// chart.wgsl.

struct SplatQuadParams {
    // Atlas side L (texels), quad radius R (texels), 1 / (2 sigma^2) (per texel^2), and the
    // Gaussian's normalisation 1 / sum of its weights over the disc of radius R.
    atlas: vec4f,
    // Caustic map size C (photons per side).
    size: u32,
    _pad0: u32,
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
};

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
    if (address.w < 0.5) { return out; }
    let size = quads.atlas.x;
    let radius = quads.atlas.y;
    let corner = QUAD_CORNERS[vertex];
    let centre = address.xy * size;
    let p = (centre + corner * radius) / size;
    out.clip = vec4f(2.0 * p.x - 1.0, 1.0 - 2.0 * p.y, 0.0, 1.0);
    out.offset = corner * radius;
    out.power = textureLoad(photon_power, texel, 0).rgb;
    out.rect = splat_charts[i32(round(address.z))].rect * size;
    return out;
}

@fragment
fn splat_quad_fs(in: QuadOut) -> @location(0) vec4f {
    let r2 = dot(in.offset, in.offset);
    let radius = quads.atlas.y;
    let texel = in.clip.xy;
    if (r2 > radius * radius || any(texel < in.rect.xy) || any(texel > in.rect.zw)) {
        discard;
    }
    let w = exp(-r2 * quads.atlas.z) * quads.atlas.w;
    return vec4f(in.power * w, 0.0);
}
