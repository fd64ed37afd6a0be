// The module image_space_refraction::rect.
#define_import_path image_space_refraction::rect
// A rectangle impostor (Hu and Qin 2006, section 2.2): its placement, the parallel projection
// of a point onto its texture and its hit by a ray. Shared by nearby.wgsl (the lookups) and
// caustic.wgsl (caustic mapping); the Rust twin is `src/nearby.rs`'s `Rect`.

struct Rect {
    // xyz: centre; w: half extent along axis_u.
    centre: vec4f,
    // xyz: unit u axis; w: half extent along axis_v.
    axis_u: vec4f,
    // xyz: unit v axis (up); w: near depth.
    axis_v: vec4f,
    // xyz: unit projection direction; w: far depth.
    direction: vec4f,
    // xyz: depth origin; w: texture array layer.
    origin: vec4f,
};

struct RectHit {
    t: f32,
    uv: vec2f,
    hit: bool,
};

fn rect_project(r: Rect, p: vec3f) -> vec3f {
    let local = p - r.centre.xyz;
    return vec3f(0.5 + dot(local, r.axis_u.xyz) / (2.0 * r.centre.w),
                 0.5 - dot(local, r.axis_v.xyz) / (2.0 * r.axis_u.w),
                 dot(p - r.origin.xyz, r.direction.xyz));
}

fn rect_depth_of(r: Rect, normalized: f32) -> f32 {
    return r.axis_v.w + normalized * (r.direction.w - r.axis_v.w);
}

fn rect_hit(r: Rect, origin: vec3f, dir: vec3f) -> RectHit {
    var none = RectHit(0.0, vec2f(0.0), false);
    let denom = dot(dir, r.direction.xyz);
    if (abs(denom) < 1e-8) { return none; }
    let t = dot(r.centre.xyz - origin, r.direction.xyz) / denom;
    if (!(t > 0.0 && t < 3.0e38)) { return none; }
    let uv = rect_project(r, origin + dir * t).xy;
    if (any(uv < vec2f(0.0)) || any(uv > vec2f(1.0))) { return none; }
    return RectHit(t, uv, true);
}

