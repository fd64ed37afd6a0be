// ---------------------------------------------------------------------------------------------
// The scene's triangles as every traversal of the ray tracer sees them (raytracer::bvh): their
// intersection data in `bvh_triangles` (obvhs' RtTriangle layout), their shading attributes in
// `bvh_attributes`, a query's result (`TraceHit`) and the hit with what shading needs
// (`surface_hit`). The including shader declares the two storage buffers; a traversal
// (bvh.wgsl: the BVH in software; ray_query.wgsl: the hardware's) defines `trace`.
// ---------------------------------------------------------------------------------------------

struct BvhTriangle {
    v0: vec3f,
    // e1 = v0 - v1, e2 = v2 - v0, ng = e1 x e2 (computed on the CPU).
    e1: vec3f,
    e2: vec3f,
    ng: vec3f,
};

struct BvhAttributes {
    n0: vec3f,
    object: u32,
    n1: vec3f,
    triangle: u32,
    n2: vec3f,
    geometric_normal: vec3f,
    uv01: vec4f,
    uv2: vec2f,
};

const NO_HIT: u32 = 0xffffffffu;

struct TraceHit {
    // Triangle index in leaf order, NO_HIT for none.
    triangle: u32,
    t: f32,
};

// Barycentrics (u, v), weights (1 - u - v, u, v) of (v0, v1, v2): obvhs'
// RtTriangle::compute_barycentric.
fn hit_barycentrics(tri: BvhTriangle, o: vec3f, d: vec3f) -> vec2f {
    let r = cross(d, tri.v0 - o);
    return vec2f(dot(r, tri.e2), dot(r, tri.e1)) / dot(tri.ng, d);
}

// A hit with what shading needs (scene::bvh::Hit).
struct SurfaceHit {
    t: f32,
    object: u32,
    position: vec3f,
    // Interpolated shading normal, as authored.
    normal: vec3f,
    geometric_normal: vec3f,
    uv: vec2f,
};

// TriangleInfo::hit: the interpolation the reference does.
fn surface_hit(h: TraceHit, o: vec3f, d: vec3f) -> SurfaceHit {
    let a = bvh_attributes[h.triangle];
    let b = hit_barycentrics(bvh_triangles[h.triangle], o, d);
    let w = 1.0 - b.x - b.y;
    let n = a.n0 * w + a.n1 * b.x + a.n2 * b.y;
    var s: SurfaceHit;
    s.t = h.t;
    s.object = a.object;
    s.position = o + d * h.t;
    s.normal = select(a.geometric_normal, normalize(n), dot(n, n) > 0.0);
    s.geometric_normal = a.geometric_normal;
    s.uv = a.uv01.xy * w + a.uv01.zw * b.x + a.uv2 * b.y;
    return s;
}

// The two queries every traversal answers through its `trace`.
fn trace_closest(o: vec3f, d: vec3f, t_max: f32) -> TraceHit {
    return trace(o, d, t_max, false);
}

fn trace_any(o: vec3f, d: vec3f, t_max: f32) -> bool {
    return trace(o, d, t_max, true).triangle != NO_HIT;
}

