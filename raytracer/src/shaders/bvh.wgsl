// ---------------------------------------------------------------------------------------------
// Ray queries on the scene's BVH (raytracer::bvh, its Rust twin): a binary tree in `bvh_nodes`
// (@group(0) @binding(#{TRACE_FIRST_BINDING})), triangles in leaf order (raytracer::triangles). Same traversal
// order, slab test and triangle test as the twin, so the GPU finds the same nearest triangle as
// the CPU reference.
// ---------------------------------------------------------------------------------------------
#define_import_path raytracer::bvh

#import raytracer::triangles::{BvhTriangle, NO_HIT, TraceHit, bvh_triangles, hit_barycentrics, in_hole}

struct BvhNode {
    min: vec3f,
    // Triangles in this leaf; 0 for an inner node.
    count: u32,
    max: vec3f,
    // Inner node: first child (the second follows). Leaf: first triangle.
    first: u32,
};

@group(0) @binding(#{TRACE_FIRST_BINDING}) var<storage, read> bvh_nodes: array<BvhNode>;

const BVH_STACK_SIZE: u32 = 48u;
const BOX_SLACK: f32 = 1.000001;

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
    let c = tri.va - o;
    let r = cross(d, c);
    let det = dot(tri.ng, d);
    if (det == 0.0) { return -1.0; }
    let inv_det = 1.0 / det;
    let u = dot(r, tri.c_minus_a) * inv_det;
    let v = dot(r, tri.a_minus_b) * inv_det;
    if (u >= 0.0 && v >= 0.0 && u + v <= 1.0) {
        let t = dot(tri.ng, c) * inv_det;
        if (t >= 0.0 && t <= t_max) { return t; }
    }
    return -1.0;
}

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
                if (t >= 0.0 && (best.triangle == NO_HIT || t < best.t)
                    && !in_hole(i, hit_barycentrics(bvh_triangles[i], o, d))) {
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
