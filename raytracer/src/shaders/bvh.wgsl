// ---------------------------------------------------------------------------------------------
// Ray queries on the scene's BVH (raytracer::bvh, its Rust twin): a binary tree in `bvh_nodes`,
// triangles in leaf order in `bvh_triangles` (obvhs' RtTriangle layout) and their shading
// attributes in `bvh_attributes`. The including shader declares those three storage buffers
// (its own group and bindings) before this file. Same traversal order, slab test and triangle
// test as the twin, so the GPU finds the same nearest triangle as the CPU reference.
// ---------------------------------------------------------------------------------------------

struct BvhNode {
    min: vec3f,
    // Triangles in this leaf; 0 for an inner node.
    count: u32,
    max: vec3f,
    // Inner node: first child (the second follows). Leaf: first triangle.
    first: u32,
};

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

const BVH_STACK_SIZE: u32 = 48u;
const BOX_SLACK: f32 = 1.000001;
const NO_HIT: u32 = 0xffffffffu;

// obvhs' safe_inverse: a zero component becomes a large finite number, never an infinity.
fn safe_inverse(x: f32) -> f32 {
    if (abs(x) <= 1.1920929e-7) {
        return select(-1.0, 1.0, x >= 0.0) / 1.1920929e-7;
    }
    return 1.0 / x;
}

// Entry distance into a node's box, or -1 when the ray misses it before t_max. An axis the ray
// runs parallel to bounds it only through the origin's place between the box's planes.
fn slab(n: BvhNode, o: vec3f, d: vec3f, inv: vec3f, t_max: f32) -> f32 {
    let t0 = (n.min - o) * inv;
    let t1 = (n.max - o) * inv;
    let parallel = abs(d) <= vec3f(1.1920929e-7);
    let between = o >= n.min & o <= n.max;
    if (any(parallel & !between)) { return -1.0; }
    let lo = select(min(t0, t1), vec3f(-3.4028235e38), parallel);
    let hi = select(max(t0, t1), vec3f(3.4028235e38), parallel);
    let near = max(max(max(lo.x, lo.y), lo.z), 0.0);
    let far = min(min(hi.x, hi.y), hi.z) * BOX_SLACK;
    return select(-1.0, near, near <= far && near <= t_max);
}

// The reference's triangle test (scene::bvh::intersect): Möller-Trumbore with an inside test
// that keeps hits exactly on shared edges. t in [0, t_max], or -1.
fn intersect_triangle(tri: BvhTriangle, o: vec3f, d: vec3f, t_max: f32) -> f32 {
    let c = tri.v0 - o;
    let r = cross(d, c);
    let det = dot(tri.ng, d);
    if (det == 0.0) { return -1.0; }
    let inv_det = 1.0 / det;
    let u = dot(r, tri.e2) * inv_det;
    let v = dot(r, tri.e1) * inv_det;
    if (u >= 0.0 && v >= 0.0 && u + v <= 1.0) {
        let t = dot(tri.ng, c) * inv_det;
        if (t >= 0.0 && t <= t_max) { return t; }
    }
    return -1.0;
}

struct TraceHit {
    // Triangle index in leaf order, NO_HIT for none.
    triangle: u32,
    t: f32,
};

// The nearest hit on o + t d, t in [0, t_max] (any = true: the first found).
fn trace(o: vec3f, d: vec3f, t_max_in: f32, any: bool) -> TraceHit {
    var best = TraceHit(NO_HIT, t_max_in);
    if (arrayLength(&bvh_nodes) == 0u) { return best; }
    let inv = vec3f(safe_inverse(d.x), safe_inverse(d.y), safe_inverse(d.z));
    var stack: array<u32, BVH_STACK_SIZE>;
    var top = 0u;
    var node = 0u;
    loop {
        let n = bvh_nodes[node];
        var descend = false;
        if (n.count > 0u) {
            for (var i = n.first; i < n.first + n.count; i++) {
                let t = intersect_triangle(bvh_triangles[i], o, d, best.t);
                if (t >= 0.0 && (best.triangle == NO_HIT || t < best.t)) {
                    best = TraceHit(i, t);
                    if (any) { return best; }
                }
            }
        } else {
            let a = n.first;
            let b = n.first + 1u;
            let ta = slab(bvh_nodes[a], o, d, inv, best.t);
            let tb = slab(bvh_nodes[b], o, d, inv, best.t);
            if (ta >= 0.0 && tb >= 0.0) {
                let near = select(a, b, tb < ta);
                let far = select(b, a, tb < ta);
                if (top < BVH_STACK_SIZE) {
                    stack[top] = far;
                    top += 1u;
                }
                node = near;
                descend = true;
            } else if (ta >= 0.0) {
                node = a;
                descend = true;
            } else if (tb >= 0.0) {
                node = b;
                descend = true;
            }
        }
        if (!descend) {
            if (top == 0u) { break; }
            top -= 1u;
            node = stack[top];
        }
    }
    return best;
}

fn trace_closest(o: vec3f, d: vec3f, t_max: f32) -> TraceHit {
    return trace(o, d, t_max, false);
}

fn trace_any(o: vec3f, d: vec3f, t_max: f32) -> bool {
    return trace(o, d, t_max, true).triangle != NO_HIT;
}

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
