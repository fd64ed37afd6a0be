// Caustic mapping (Hu and Qin 2006, section 3.3, figure 23); imports gpu::prelude and
// scene::shading and image_space_refraction::rect: each receiver is drawn again over the shaded scene, its
// fragment projected into its rectangle's caustic texture by the rectangle's parallel
// projection, and the irradiance found there turned into diffuse radiance (albedo / pi E) and
// added (additive blending). As in shadow mapping, the fragment is compared with the depth the
// rectangle's impostor texture holds there: surfaces hidden from the refractor behind the
// object's own front receive none.
#import gpu::prelude::PI
#import scene::shading::{SceneVertexOut, in_cutout_hole, surface_albedo}
#import image_space_refraction::rect::{Rect, rect_project, rect_depth_of}

struct CausticMapParams {
    // Side of each caustic texture.
    resolution: u32,
    _a: u32,
    // Depth slack of the visibility test, as a fraction of the rectangle's depth range.
    bias: f32,
    _b: f32,
};

@group(2) @binding(0) var<storage, read> rects: array<Rect>;
@group(2) @binding(1) var<storage, read> caustic: array<vec4f>;
@group(2) @binding(2) var impostor_depth: texture_depth_2d_array;
@group(2) @binding(3) var<uniform> map: CausticMapParams;
// The rectangle of each scene object in `rects` (-1: none).
@group(2) @binding(4) var<storage, read> rect_of_object: array<i32>;

fn caustic_irradiance(object: u32, p: vec3f) -> vec3f {
    let index = rect_of_object[object];
    if (index < 0) { return vec3f(0.0); }
    let r = rects[u32(index)];
    let q = rect_project(r, p);
    if (any(q.xy < vec2f(0.0)) || any(q.xy > vec2f(1.0))) { return vec3f(0.0); }
    let layer = i32(r.origin.w);
    let depth_size = vec2f(textureDimensions(impostor_depth));
    let stored = textureLoad(impostor_depth, vec2i(min(floor(q.xy * depth_size), depth_size - 1.0)), layer, 0);
    if (stored >= 1.0 || q.z > rect_depth_of(r, stored) + map.bias * (r.direction.w - r.axis_v.w) + 1e-3) { return vec3f(0.0); }
    // Bilinear between texel centres (clamped at the border): the caustic texture is much
    // coarser than a receiver seen up close.
    let res = f32(map.resolution);
    let x = clamp(q.xy * res - 0.5, vec2f(0.0), vec2f(res - 1.0));
    let x0 = vec2u(floor(x));
    let x1 = min(x0 + 1u, vec2u(map.resolution - 1u));
    let w = x - floor(x);
    let base = u32(layer) * map.resolution;
    let c00 = caustic[(base + x0.y) * map.resolution + x0.x].rgb;
    let c10 = caustic[(base + x0.y) * map.resolution + x1.x].rgb;
    let c01 = caustic[(base + x1.y) * map.resolution + x0.x].rgb;
    let c11 = caustic[(base + x1.y) * map.resolution + x1.x].rgb;
    return mix(mix(c00, c10, w.x), mix(c01, c11, w.x), w.y);
}

@fragment
fn caustic_fs(in: SceneVertexOut) -> @location(0) vec4f {
    if (in_cutout_hole(in.object, in.uv)) { discard; }
    let e = caustic_irradiance(in.object, in.world);
    return vec4f(surface_albedo(in.object, in.uv) / PI * e, 0.0);
}
