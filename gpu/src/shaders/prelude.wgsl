#define_import_path gpu::prelude
// ---------------------------------------------------------------------------------------------
// Workspace WGSL prelude: ray math, reflection/refraction, the seeds' Fresnel with n and k,
// cube-map addressing, packing and hashing. Every function here has a Rust twin with the same
// name in `gpu::prelude`, checked against it on the GPU by `gpu/tests/prelude_conformance.rs`.
// Conventions: right-handed, +Y up; a ray is origin + t * dir with dir unit length.
// ---------------------------------------------------------------------------------------------

const PI: f32 = 3.14159265358979;
// Empty-interval marker: ray_sphere / ray_box return (1, -1) on a miss (t_near > t_far).
const MISS: vec2f = vec2f(1.0, -1.0);
const BIG: f32 = 1e30;

// Ray / plane dot(n, x) = c. Returns t, or -1 when the ray is parallel to the plane.
fn ray_plane(o: vec3f, d: vec3f, n: vec3f, c: f32) -> f32 {
    let denom = dot(n, d);
    if (abs(denom) < 1e-12) { return -1.0; }
    return (c - dot(n, o)) / denom;
}

// Ray / sphere: entry and exit parameters (t_near <= t_far), or MISS.
fn ray_sphere(o: vec3f, d: vec3f, center: vec3f, radius: f32) -> vec2f {
    let oc = o - center;
    let b = dot(oc, d);
    let c = dot(oc, oc) - radius * radius;
    let disc = b * b - c;
    if (disc < 0.0) { return MISS; }
    let s = sqrt(disc);
    return vec2f(-b - s, -b + s);
}

// Ray / axis-aligned box by slabs: (t_near, t_far), MISS when empty. A direction component
// below 1e-30 in magnitude (zero, -0.0, denormal) is "flat": that slab does not limit t when the
// origin lies in it (boundary planes included: the box is closed) and empties the interval
// otherwise. This avoids 1/0 and 0 * inf (NaN for an origin on a slab plane), which WGSL
// implementations may not handle as IEEE does.
fn ray_box(o: vec3f, d: vec3f, bmin: vec3f, bmax: vec3f) -> vec2f {
    let flat = abs(d) < vec3f(1e-30);
    let inside = (o >= bmin) & (o <= bmax);
    let inv = 1.0 / select(d, vec3f(1.0), flat);
    let t0 = (bmin - o) * inv;
    let t1 = (bmax - o) * inv;
    let open = select(vec3f(BIG), vec3f(-BIG), inside);
    let tmin = select(min(t0, t1), open, flat);
    let tmax = select(max(t0, t1), -open, flat);
    let t_near = max(max(tmin.x, tmin.y), tmin.z);
    let t_far = min(min(tmax.x, tmax.y), tmax.z);
    if (t_near > t_far) { return MISS; }
    return vec2f(t_near, t_far);
}

// Parallax-corrected ("box-projected") cube-map lookup (Lagarde & Zanuttini 2012, the
// localized probes of today's engines): the ray x + t r is intersected with a proxy box
// [bmin, bmax] standing for the surroundings, and the cube map captured at `probe` is looked up
// toward the point where the ray leaves the box. Returns (probe-relative exit point, t_exit);
// the xyz is the (unnormalised) lookup direction. When the ray leaves the box nowhere ahead of
// x (x outside and the box behind or missed) or the exit point is the probe itself, the
// direction-only lookup is returned instead: (r, -1).
fn box_project(x: vec3f, r: vec3f, probe: vec3f, bmin: vec3f, bmax: vec3f) -> vec4f {
    let t = ray_box(x, r, bmin, bmax);
    if (t.x > t.y || t.y <= 0.0) { return vec4f(r, -1.0); }
    let l = x + r * t.y - probe;
    if (dot(l, l) < 1e-12) { return vec4f(r, -1.0); }
    return vec4f(l, t.y);
}

// A uniform grid of square cells on the xz plane (cell (i, j) spans
// [min + (i, j) size, min + (i + 1, j + 1) size], unbounded in y), walked by a ray in the order
// it crosses the cells (2D DDA, Amanatides and Woo 1987): the first non-empty cell along a ray,
// as the chessboard's grid of the many-object tracer (Dancsik and Minarik 4.2). grid_walk
// starts the walk where the ray enters the grid's rectangle (or at t = 0 inside it);
// grid_walk_next moves to the next cell. The walk is over once t_enter >= t_end. A flat
// direction component (|d| < 1e-30) never steps along its axis.
struct GridWalk {
    cell: vec2i,
    // The ray's parameter interval inside the current cell.
    t_enter: f32,
    t_exit: f32,
    step: vec2i,
    // Ray parameters of the next cell boundary along x and z, and between boundaries.
    t_next: vec2f,
    t_delta: vec2f,
    // Where the ray leaves the grid's rectangle.
    t_end: f32,
};

fn grid_walk(o: vec3f, d: vec3f, grid_min: vec2f, size: f32, count: vec2i) -> GridWalk {
    var w: GridWalk;
    let grid_max = grid_min + size * vec2f(count);
    let t = ray_box(o, d, vec3f(grid_min.x, -BIG, grid_min.y), vec3f(grid_max.x, BIG, grid_max.y));
    w.t_end = t.y;
    w.t_enter = max(t.x, 0.0);
    if (t.x > t.y || t.y <= 0.0 || count.x <= 0 || count.y <= 0) {
        w.t_enter = BIG;
        w.t_end = BIG;
        w.t_exit = BIG;
        return w;
    }
    let p = o.xz + d.xz * w.t_enter;
    w.cell = clamp(vec2i(floor((p - grid_min) / size)), vec2i(0), count - 1);
    let dxz = d.xz;
    let flat = abs(dxz) < vec2f(1e-30);
    w.step = select(select(vec2i(-1), vec2i(1), dxz > vec2f(0.0)), vec2i(0), flat);
    let boundary = grid_min + size * vec2f(w.cell + select(vec2i(0), vec2i(1), w.step > vec2i(0)));
    let safe = select(dxz, vec2f(1.0), flat);
    w.t_next = select((boundary - o.xz) / safe, vec2f(BIG), flat);
    w.t_delta = select(size / abs(safe), vec2f(BIG), flat);
    w.t_exit = min(min(w.t_next.x, w.t_next.y), w.t_end);
    return w;
}

fn grid_walk_next(w_in: GridWalk, count: vec2i) -> GridWalk {
    var w = w_in;
    if (w.t_next.x <= w.t_next.y) {
        w.cell.x += w.step.x;
        w.t_enter = w.t_next.x;
        w.t_next.x += w.t_delta.x;
    } else {
        w.cell.y += w.step.y;
        w.t_enter = w.t_next.y;
        w.t_next.y += w.t_delta.y;
    }
    if (any(w.cell < vec2i(0)) || any(w.cell >= count)) { w.t_enter = w.t_end; }
    w.t_exit = min(min(w.t_next.x, w.t_next.y), w.t_end);
    return w;
}

// Mirror direction of incident direction i about unit normal n.
fn reflect_dir(i: vec3f, n: vec3f) -> vec3f {
    return i - 2.0 * dot(n, i) * n;
}

// Snell refraction of unit incident direction i at unit normal n facing against i
// (dot(i, n) < 0), eta = n_incident / n_transmitted. Returns (direction, 1) or, on total
// internal reflection, (reflected direction, 0).
fn refract_dir(i: vec3f, n: vec3f, eta: f32) -> vec4f {
    let cos_i = -dot(n, i);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if (k < 0.0) { return vec4f(reflect_dir(i, n), 0.0); }
    return vec4f(normalize(eta * i + (eta * cos_i - sqrt(k)) * n), 1.0);
}

// The seeds' Fresnel approximation (Lazanyi & Szirmay-Kalos 2005), per channel:
// F = ((n-1)^2 + k^2 + 4n (1 - cos)^5) / ((n+1)^2 + k^2).
fn fresnel_nk(cos_theta: f32, n: vec3f, k: vec3f) -> vec3f {
    let c = clamp(cos_theta, 0.0, 1.0);
    let m = pow(1.0 - c, 5.0);
    let k2 = k * k;
    return ((n - 1.0) * (n - 1.0) + k2 + 4.0 * n * m) / ((n + 1.0) * (n + 1.0) + k2);
}

// Fresnel reflectance at a dielectric interface with the same approximation (k = 0).
// cos_i: cosine of the incident angle; eta_rel = n_transmitted / n_incident (may be < 1).
// The approximation is evaluated with the angle on the optically thinner side and the
// ratio >= 1, so it is symmetric; total internal reflection gives 1.
fn fresnel_dielectric(cos_i: f32, eta_rel: f32) -> f32 {
    let c = clamp(cos_i, 0.0, 1.0);
    if (eta_rel >= 1.0) {
        return fresnel_nk(c, vec3f(eta_rel), vec3f(0.0)).x;
    }
    let sin2_t = (1.0 - c * c) / (eta_rel * eta_rel);
    if (sin2_t >= 1.0) { return 1.0; }
    return fresnel_nk(sqrt(1.0 - sin2_t), vec3f(1.0 / eta_rel), vec3f(0.0)).x;
}

// Cube-map addressing, Vulkan/D3D convention; faces in layer order +X,-X,+Y,-Y,+Z,-Z;
// (u, v) in [0,1]^2 with v = 0 on texel row 0. Returns (face, u, v).
fn cube_dir_to_face_uv(d: vec3f) -> vec3f {
    let a = abs(d);
    var face: f32; var sc: f32; var tc: f32; var ma: f32;
    if (a.x >= a.y && a.x >= a.z) {
        ma = a.x;
        if (d.x >= 0.0) { face = 0.0; sc = -d.z; tc = -d.y; } else { face = 1.0; sc = d.z; tc = -d.y; }
    } else if (a.y >= a.z) {
        ma = a.y;
        if (d.y >= 0.0) { face = 2.0; sc = d.x; tc = d.z; } else { face = 3.0; sc = d.x; tc = -d.z; }
    } else {
        ma = a.z;
        if (d.z >= 0.0) { face = 4.0; sc = d.x; tc = -d.y; } else { face = 5.0; sc = -d.x; tc = -d.y; }
    }
    return vec3f(face, 0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0));
}

// Inverse of cube_dir_to_face_uv: the (unnormalised) direction through (u, v) of a face.
fn cube_face_uv_to_dir(face: u32, u: f32, v: f32) -> vec3f {
    let sc = 2.0 * u - 1.0;
    let tc = 2.0 * v - 1.0;
    switch face {
        case 0u: { return vec3f(1.0, -tc, -sc); }
        case 1u: { return vec3f(-1.0, -tc, sc); }
        case 2u: { return vec3f(sc, 1.0, tc); }
        case 3u: { return vec3f(sc, -1.0, -tc); }
        case 4u: { return vec3f(sc, -tc, 1.0); }
        default: { return vec3f(-sc, -tc, -1.0); }
    }
}

// Octahedral encoding of a unit vector into [-1,1]^2 (for packing normals) and its inverse.
fn oct_encode(n: vec3f) -> vec2f {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if (n.z >= 0.0) { return p; }
    return (1.0 - abs(p.yx)) * select(vec2f(-1.0), vec2f(1.0), p >= vec2f(0.0));
}

fn oct_decode(e: vec2f) -> vec3f {
    var n = vec3f(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) {
        let xy = (1.0 - abs(n.yx)) * select(vec2f(-1.0), vec2f(1.0), n.xy >= vec2f(0.0));
        n = vec3f(xy, n.z);
    }
    return normalize(n);
}

// PCG hash (O'Neill) and a uniform float in [0, 1) from it: deterministic per-pixel noise.
fn pcg_hash(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn hash_to_unit(x: u32) -> f32 {
    return f32(pcg_hash(x) >> 8u) * (1.0 / 16777216.0);
}

// Relative luminance of linear RGB (Rec. 709).
fn luminance(c: vec3f) -> f32 {
    return dot(c, vec3f(0.2126, 0.7152, 0.0722));
}
