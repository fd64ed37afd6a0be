// Nearby geometry as rectangle impostors (Hu and Qin 2006, section 2.2): the WGSL of the Rust
// twin `src/nearby.rs` (same algorithms and names; read its comments). The module
// image_space_refraction::nearby: its resources (the rectangles, their parameters and their
// colour and depth textures) are bound at group NEARBY_GROUP from binding NEARBY_FIRST_BINDING
// (shader definitions: 3 and 0 in the technique, the kernel's slots in the conformance test).
// `nearby_hit` is the search; image_space_refraction::nearby_radiance, which overrides
// image_space_refraction::refract's `outgoing_radiance`, reads the texel it finds.
#define_import_path image_space_refraction::nearby
#import image_space_refraction::rect::{Rect, RectHit, rect_depth_of, rect_hit, rect_project}

struct NearbyParams {
    count: u32,
    // 0: uncorrected (figure 13); 1: corrected (figures 16 and 17).
    corrected: u32,
    seeds: u32,
    iterations: u32,
    tolerance: f32,
    _a: f32,
    _b: f32,
    _c: f32,
};

@group(#{NEARBY_GROUP}) @binding(#{NEARBY_FIRST_BINDING} + 0u) var<storage, read> rects: array<Rect>;
@group(#{NEARBY_GROUP}) @binding(#{NEARBY_FIRST_BINDING} + 1u) var<uniform> nearby: NearbyParams;
@group(#{NEARBY_GROUP}) @binding(#{NEARBY_FIRST_BINDING} + 2u) var impostor_color: texture_2d_array<f32>;
@group(#{NEARBY_GROUP}) @binding(#{NEARBY_FIRST_BINDING} + 3u) var impostor_depth: texture_depth_2d_array;

fn impostor_texel(r: Rect, uv: vec2f) -> vec2i {
    let size = vec2f(textureDimensions(impostor_depth));
    return vec2i(min(floor(uv * size), size - 1.0));
}

// Normalized stored depth at uv, or -1 where the object does not cover it (cleared to 1).
fn impostor_depth_at(r: Rect, uv: vec2f) -> f32 {
    if (any(uv < vec2f(0.0)) || any(uv > vec2f(1.0))) { return -1.0; }
    let d = textureLoad(impostor_depth, impostor_texel(r, uv), i32(r.origin.w), 0);
    return select(d, -1.0, d >= 1.0);
}

fn select_seed(r: Rect, origin: vec3f, dir: vec3f, t_rect: f32, seeds: u32) -> f32 {
    var closest_gap = 3.0e38;
    var closest_t = t_rect;
    let n = max(seeds, 1u);
    for (var j = 0u; j <= n; j++) {
        let t = t_rect * (f32(j) / f32(n));
        let q = rect_project(r, origin + dir * t);
        let stored = impostor_depth_at(r, q.xy);
        if (stored < 0.0) { continue; }
        let gap = q.z - rect_depth_of(r, stored);
        if (gap >= 0.0) { return t; }
        if (-gap < closest_gap) {
            closest_gap = -gap;
            closest_t = t;
        }
    }
    return closest_t;
}

fn correct(r: Rect, origin: vec3f, dir: vec3f, t_start: f32, iterations: u32, tolerance: f32) -> RectHit {
    var none = RectHit(0.0, vec2f(0.0), false);
    let cos_theta = dot(dir, r.direction.xyz);
    if (abs(cos_theta) < 1e-3) { return none; }
    var t = t_start;
    for (var i = 0u; i < iterations; i++) {
        let q = rect_project(r, origin + dir * t);
        let stored = impostor_depth_at(r, q.xy);
        if (stored < 0.0) { return none; }
        let gap = rect_depth_of(r, stored) - q.z;
        if (abs(gap) <= tolerance) { return RectHit(t, q.xy, true); }
        t = max(t + gap / cos_theta, 0.0);
    }
    let uv = rect_project(r, origin + dir * t).xy;
    return RectHit(t, uv, impostor_depth_at(r, uv) >= 0.0);
}

struct NearbyHit {
    rect: u32,
    t: f32,
    uv: vec2f,
    hit: bool,
};

fn nearby_hit(origin: vec3f, dir: vec3f) -> NearbyHit {
    var best = NearbyHit(0u, 3.0e38, vec2f(0.0), false);
    for (var i = 0u; i < nearby.count; i++) {
        let r = rects[i];
        let h = rect_hit(r, origin, dir);
        if (!h.hit) { continue; }
        var found = RectHit(h.t, h.uv, impostor_depth_at(r, h.uv) >= 0.0);
        if (nearby.corrected == 1u) {
            let t0 = select_seed(r, origin, dir, h.t, nearby.seeds);
            found = correct(r, origin, dir, t0, nearby.iterations, nearby.tolerance);
        }
        if (found.hit && found.t < best.t) {
            best = NearbyHit(i, found.t, found.uv, true);
        }
    }
    return best;
}
