// The two-interface searches of Hu and Qin (2006, section 2.1) and of Wyman (2005): the WGSL
// of the Rust twin `src/search.rs` (same algorithms, constants and names; read its comments).
// The module image_space_refraction::search. The searches read the two buffers the caller
// passes, `front` and `back` (texture_2d<f32>, Rgba32Float: outward normal, view depth; depth 0
// where the refractor is not), seen by the eye `e`: the Rust twin's `buffers` and `eye`.
#define_import_path image_space_refraction::search
#import gpu::prelude::refract_dir

struct EyeParams {
    view_proj: mat4x4f,
    inverse_view_proj: mat4x4f,
    // xyz: eye position.
    position: vec4f,
    // xyz: unit forward axis.
    forward: vec4f,
    // width, height (pixels), unused, unused.
    size: vec4f,
};

const SIDE_FRONT: u32 = 0u;
const SIDE_BACK: u32 = 1u;
const STRATEGY_ANGLE_TEST: u32 = 0u;
const STRATEGY_BACK_FIRST: u32 = 1u;
const MAX_SILHOUETTE_STEPS: u32 = 24u;

fn eye_project(e: EyeParams, p: vec3f) -> vec3f {
    let clip = e.view_proj * vec4f(p, 1.0);
    let ndc = clip.xy / clip.w;
    return vec3f((ndc.x * 0.5 + 0.5) * e.size.x, (0.5 - ndc.y * 0.5) * e.size.y,
                 dot(p - e.position.xyz, e.forward.xyz));
}

fn eye_unproject(e: EyeParams, pixel: vec2f, depth: f32) -> vec3f {
    let ndc = vec2f(pixel.x / e.size.x * 2.0 - 1.0, 1.0 - pixel.y / e.size.y * 2.0);
    let far = e.inverse_view_proj * vec4f(ndc, 1.0, 1.0);
    let dir = normalize(far.xyz / far.w - e.position.xyz);
    return e.position.xyz + dir * (depth / dot(dir, e.forward.xyz));
}

// (outward normal, view depth) of `side` under pixel coordinates p; depth 0: none.
fn buffer_texel(front: texture_2d<f32>, back: texture_2d<f32>, side: u32, p: vec2f) -> vec4f {
    let size = vec2i(textureDimensions(back));
    let xy = vec2i(floor(p));
    if (p.x < 0.0 || p.y < 0.0 || any(xy >= size)) { return vec4f(0.0); }
    if (side == SIDE_FRONT) { return textureLoad(front, xy, 0); }
    return textureLoad(back, xy, 0);
}

fn covered(front: texture_2d<f32>, back: texture_2d<f32>, p: vec2f) -> bool {
    return buffer_texel(front, back, SIDE_BACK, p).w > 0.0;
}

struct Silhouette {
    inside: vec2f,
    outside: vec2f,
    steps: u32,
};

fn silhouette_search(front: texture_2d<f32>, back: texture_2d<f32>, e: EyeParams, p1: vec2f, t1: vec2f, tolerance: f32) -> Silhouette {
    let initial = 0.75 * max(e.size.x, e.size.y);
    var lo = 0.0;
    var hi = initial;
    var steps = 1u;
    if (covered(front, back, p1 + hi * t1)) {
        lo = hi;
        hi = 2.0 * initial;
    }
    loop {
        if (!(hi - lo > max(tolerance, 1e-3) && steps < MAX_SILHOUETTE_STEPS)) { break; }
        let mid = 0.5 * (lo + hi);
        if (covered(front, back, p1 + mid * t1)) { lo = mid; } else { hi = mid; }
        steps += 1u;
    }
    return Silhouette(p1 + lo * t1, p1 + hi * t1, steps);
}

fn exit_side(v: vec3f, p1: vec3f, t1: vec3f, pe: vec3f) -> u32 {
    var to_silhouette = t1;
    let d = pe - p1;
    let l2 = dot(d, d);
    if (l2 > 0.0 && l2 < 1e30) { to_silhouette = d / sqrt(l2); }
    return select(SIDE_BACK, SIDE_FRONT, dot(v, t1) < dot(v, to_silhouette));
}

fn projected_direction(e: EyeParams, p1: vec3f, t1: vec3f) -> vec2f {
    let a = eye_project(e, p1).xy;
    let reach = 1e-2 * max(length(p1 - e.position.xyz), 1e-3);
    let b = eye_project(e, p1 + t1 * reach).xy;
    let d = b - a;
    let len = length(d);
    if (len > 1e-6 && len < 1e30) { return d / len; }
    return vec2f(0.0);
}

struct Iteration {
    tolerance: f32,
    max_iterations: u32,
    initial_step: f32,
};

struct Exit {
    point: vec3f,
    normal: vec3f,
    side: u32,
    distance: f32,
    iterations: u32,
    converged: bool,
    left_silhouette: bool,
};

fn exit_distance(front: texture_2d<f32>, back: texture_2d<f32>, e: EyeParams, p1: vec3f, t1: vec3f, side: u32, it: Iteration) -> Exit {
    let flag = select(-1.0, 1.0, side == SIDE_BACK);
    var exit = Exit(p1, -t1, side, 0.0, 0u, false, false);
    var lo = 0.0;
    var hi = 3.0e38;
    var d = 0.0;
    var step = it.initial_step;
    for (var i = 0u; i < it.max_iterations; i++) {
        exit.iterations += 1u;
        var candidate = d + step;
        if (hi < 3.0e38 && !(candidate > lo && candidate < hi)) {
            candidate = 0.5 * (lo + hi);
        }
        let p2 = p1 + t1 * candidate;
        let q = eye_project(e, p2);
        let texel = buffer_texel(front, back, side, q.xy);
        if (texel.w <= 0.0) {
            exit.left_silhouette = true;
            hi = min(hi, candidate);
            step = 0.0;
            continue;
        }
        d = candidate;
        exit.point = p2;
        exit.normal = texel.xyz;
        exit.distance = d;
        step = flag * (texel.w - q.z);
        if (abs(step) <= it.tolerance) {
            exit.converged = true;
            break;
        }
        if (step > 0.0) { lo = max(lo, d); } else { hi = min(hi, d); }
        if (hi - lo <= it.tolerance) {
            exit.converged = true;
            break;
        }
    }
    return exit;
}

fn side_by_angle(front: texture_2d<f32>, back: texture_2d<f32>, e: EyeParams, p1: vec3f, v: vec3f, t1: vec3f) -> u32 {
    let dir = projected_direction(e, p1, t1);
    if (all(dir == vec2f(0.0))) { return SIDE_BACK; }
    let start = eye_project(e, p1).xy;
    let s = silhouette_search(front, back, e, start, dir, 1.0);
    let f = buffer_texel(front, back, SIDE_FRONT, s.inside);
    let b = buffer_texel(front, back, SIDE_BACK, s.inside);
    if (b.w <= 0.0) { return SIDE_BACK; }
    let depth = select(b.w, 0.5 * (f.w + b.w), f.w > 0.0);
    let pe = eye_unproject(e, s.inside, depth);
    return exit_side(v, p1, t1, pe);
}

fn hu_qin_exit(front: texture_2d<f32>, back: texture_2d<f32>, e: EyeParams, p1: vec3f, v: vec3f, t1: vec3f, strategy: u32, it: Iteration) -> Exit {
    if (strategy == STRATEGY_BACK_FIRST) {
        let back_exit = exit_distance(front, back, e, p1, t1, SIDE_BACK, it);
        if (back_exit.left_silhouette) {
            return exit_distance(front, back, e, p1, t1, SIDE_FRONT, it);
        }
        return back_exit;
    }
    let side = side_by_angle(front, back, e, p1, v, t1);
    return exit_distance(front, back, e, p1, t1, side, it);
}

fn wyman_exit(front: texture_2d<f32>, back: texture_2d<f32>, e: EyeParams, p1: vec3f, v: vec3f, n1: vec3f, t1: vec3f, d_n: f32) -> Exit {
    let q1 = eye_project(e, p1);
    let b1 = buffer_texel(front, back, SIDE_BACK, q1.xy);
    var d_v = 0.0;
    if (b1.w > 0.0) { d_v = max(b1.w - q1.z, 0.0) / max(dot(v, e.forward.xyz), 1e-4); }
    let inward = -n1;
    let theta_i = acos(clamp(dot(v, inward), -1.0, 1.0));
    let theta_t = acos(clamp(dot(t1, inward), -1.0, 1.0));
    let ratio = select(1.0, theta_t / theta_i, theta_i > 1e-4);
    let d = ratio * d_v + (1.0 - ratio) * d_n;
    let point = p1 + t1 * d;
    let texel = buffer_texel(front, back, SIDE_BACK, eye_project(e, point).xy);
    let hit = texel.w > 0.0;
    return Exit(point, select(t1, texel.xyz, hit), SIDE_BACK, d, 0u, hit, !hit);
}

fn exit_direction(exit: Exit, t1: vec3f, ior: f32) -> vec4f {
    var n = t1;
    if (dot(exit.normal, exit.normal) > 1e-12) { n = normalize(exit.normal); }
    let facing = select(n, -n, dot(n, t1) > 0.0);
    return refract_dir(t1, facing, ior);
}
