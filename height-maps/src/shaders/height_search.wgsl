// ---------------------------------------------------------------------------------------------
// The search in a refractor height map (Dancsik and Minarik, section 6): the WGSL twin of
// height-maps/src/search.rs (same algorithm, constants and names; read that file's header for
// the method). The module height_maps::search; the caller passes the maps, `maps`
// (texture_2d_array<f32>, Rgba32Float: normal.xyz, height; a layer per kind: the twin's
// `field`), and each map's layer and bounds.
// ---------------------------------------------------------------------------------------------
#define_import_path height_maps::search
#import gpu::prelude::{BIG, ray_box}

const PARALLEL: f32 = 1e-6;
const CASE_IN_FRONT: u32 = 0u;
const CASE_BOX_IN_FRONT: u32 = 1u;
const CASE_BEHIND: u32 = 2u;

// Even samples before the binary search (0: the paper's search) and halvings.
struct Steps {
    linear: u32,
    binary: u32,
};

struct HeightBounds {
    half_width: f32,
    v_min: f32,
    v_max: f32,
    height: f32,
};

struct Billboard {
    centre: vec3f,
    u: vec3f,
    v: vec3f,
    w: vec3f,
};

// The billboard at `centre` whose w axis points horizontally toward `origin`.
fn billboard_facing(centre: vec3f, origin: vec3f) -> Billboard {
    let to = vec3f(origin.x - centre.x, 0.0, origin.z - centre.z);
    var b: Billboard;
    b.centre = centre;
    b.w = vec3f(0.0, 0.0, 1.0);
    if (length(to) > 1e-6) { b.w = to / length(to); }
    b.v = vec3f(0.0, 1.0, 0.0);
    b.u = cross(b.v, b.w);
    return b;
}

fn dir_to_plane(b: Billboard, d: vec3f) -> vec3f {
    return vec3f(dot(d, b.u), dot(d, b.v), dot(d, b.w));
}

fn to_plane(b: Billboard, p: vec3f) -> vec3f {
    return dir_to_plane(b, p - b.centre);
}

fn dir_to_world(b: Billboard, d: vec3f) -> vec3f {
    return b.u * d.x + b.v * d.y + b.w * d.z;
}

fn height_box_min(hb: HeightBounds) -> vec3f {
    return vec3f(-hb.half_width, hb.v_min, -hb.height);
}

fn height_box_max(hb: HeightBounds) -> vec3f {
    return vec3f(hb.half_width, hb.v_max, hb.height);
}

fn height_texel(maps: texture_2d_array<f32>, layer: i32, i: i32, j: i32) -> vec4f {
    let size = vec2i(textureDimensions(maps));
    return textureLoad(maps, clamp(vec2i(i, j), vec2i(0), size - 1), layer, 0);
}

// (normal.xyz, height) at plane point (u, v): bilinear between texel centres, clamped at the
// edges, empty outside the map (SampledField::sample).
fn height_sample(maps: texture_2d_array<f32>, layer: i32, hb: HeightBounds, u: f32, v: f32) -> vec4f {
    let c = vec2f((u + hb.half_width) / (2.0 * hb.half_width),
                  (hb.v_max - v) / (hb.v_max - hb.v_min));
    if (c.x < 0.0 || c.y < 0.0 || c.x > 1.0 || c.y > 1.0) {
        return vec4f(0.0, 0.0, 0.0, -hb.height);
    }
    let size = vec2f(textureDimensions(maps));
    let x = c.x * size.x - 0.5;
    let y = c.y * size.y - 0.5;
    let i = floor(x);
    let j = floor(y);
    let fx = x - i;
    let fy = y - j;
    let ii = i32(i);
    let jj = i32(j);
    let top = mix(height_texel(maps, layer, ii, jj), height_texel(maps, layer, ii + 1, jj), fx);
    let bottom = mix(height_texel(maps, layer, ii, jj + 1), height_texel(maps, layer, ii + 1, jj + 1), fx);
    return mix(top, bottom, fy);
}

fn height_inside(maps: texture_2d_array<f32>, layer: i32, hb: HeightBounds, p: vec3f) -> bool {
    return abs(p.z) < height_sample(maps, layer, hb, p.x, p.y).w;
}

struct Segments {
    case_id: u32,
    near: f32,
    plane: f32,
    far: f32,
    // False: the ray misses the box.
    valid: bool,
};

fn select_segment(o: vec3f, d: vec3f, hb: HeightBounds) -> Segments {
    var s: Segments;
    s.valid = false;
    let hit = ray_box(o, d, height_box_min(hb), height_box_max(hb));
    if (hit.x > hit.y || hit.y < 0.0) { return s; }
    s.valid = true;
    s.near = max(hit.x, 0.0);
    s.far = hit.y;
    s.plane = BIG;
    if (abs(d.z) >= PARALLEL) {
        let t = -o.z / d.z;
        if (t >= 0.0) { s.plane = t; }
    }
    if (s.plane < s.near) {
        s.case_id = CASE_BEHIND;
    } else if (s.plane <= s.far) {
        s.case_id = CASE_IN_FRONT;
    } else {
        s.case_id = CASE_BOX_IN_FRONT;
    }
    return s;
}

fn binary_search(maps: texture_2d_array<f32>, layer: i32, hb: HeightBounds, o: vec3f, d: vec3f, a0: f32, b0: f32, steps: u32,
                 entering: bool) -> f32 {
    var a = a0;
    var b = b0;
    for (var i = 0u; i < steps; i++) {
        let m = 0.5 * (a + b);
        if (height_inside(maps, layer, hb, o + d * m) == entering) { b = m; } else { a = m; }
    }
    return 0.5 * (a + b);
}

// One segment's search for the boundary (from outside when `entering`); a negative result:
// none on it.
fn search_segment(maps: texture_2d_array<f32>, layer: i32, hb: HeightBounds, o: vec3f, d: vec3f, a: f32, b: f32,
                  steps: Steps, entering: bool) -> f32 {
    // An entry whose start is inside: the box face is the surface there. An exit's start is
    // taken to be inside.
    if (entering && height_inside(maps, layer, hb, o + d * a)) { return a; }
    if (steps.linear == 0u) {
        if (height_inside(maps, layer, hb, o + d * b) != entering) { return -1.0; }
        return binary_search(maps, layer, hb, o, d, a, b, steps.binary, entering);
    }
    let dt = (b - a) / f32(steps.linear);
    var previous = a;
    for (var k = 1u; k <= steps.linear; k++) {
        var t = a + dt * f32(k);
        if (k == steps.linear) { t = b; }
        if (height_inside(maps, layer, hb, o + d * t) == entering) {
            return binary_search(maps, layer, hb, o, d, previous, t, steps.binary, entering);
        }
        previous = t;
    }
    return -1.0;
}

struct HeightHit {
    t: f32,
    point: vec3f,
    normal: vec3f,
    found: bool,
};

// The outward normal of the box face nearest to plane-frame point p (box_face_normal).
fn box_face_normal(hb: HeightBounds, p: vec3f) -> vec3f {
    let lo = height_box_min(hb);
    let hi = height_box_max(hb);
    var best = abs(p.x - lo.x);
    var n = vec3f(-1.0, 0.0, 0.0);
    if (abs(hi.x - p.x) < best) { best = abs(hi.x - p.x); n = vec3f(1.0, 0.0, 0.0); }
    if (abs(p.y - lo.y) < best) { best = abs(p.y - lo.y); n = vec3f(0.0, -1.0, 0.0); }
    if (abs(hi.y - p.y) < best) { best = abs(hi.y - p.y); n = vec3f(0.0, 1.0, 0.0); }
    if (abs(p.z - lo.z) < best) { best = abs(p.z - lo.z); n = vec3f(0.0, 0.0, -1.0); }
    if (abs(hi.z - p.z) < best) { n = vec3f(0.0, 0.0, 1.0); }
    return n;
}

fn box_face_hit(hb: HeightBounds, o: vec3f, d: vec3f, t: f32) -> HeightHit {
    var h: HeightHit;
    h.found = true;
    h.t = t;
    h.point = o + d * t;
    h.normal = box_face_normal(hb, h.point);
    return h;
}

fn height_hit(maps: texture_2d_array<f32>, layer: i32, hb: HeightBounds, o: vec3f, d: vec3f, t: f32) -> HeightHit {
    var h: HeightHit;
    h.found = true;
    h.t = t;
    h.point = o + d * t;
    var n = height_sample(maps, layer, hb, h.point.x, h.point.y).xyz;
    if (h.point.z < 0.0) { n.z = -n.z; }
    h.normal = -normalize(d);
    if (length(n) > 1e-6) { h.normal = normalize(n); }
    return h;
}

fn search_from_outside(maps: texture_2d_array<f32>, layer: i32, hb: HeightBounds, o: vec3f, d: vec3f, steps: Steps) -> HeightHit {
    var miss: HeightHit;
    miss.found = false;
    let s = select_segment(o, d, hb);
    if (!s.valid) { return miss; }
    var first_end = s.far;
    if (s.case_id == CASE_IN_FRONT) { first_end = s.plane; }
    var t = search_segment(maps, layer, hb, o, d, s.near, first_end, steps, true);
    if (t < 0.0 && s.case_id == CASE_IN_FRONT) {
        t = search_segment(maps, layer, hb, o, d, s.plane, s.far, steps, true);
    }
    if (t < 0.0) { return miss; }
    if (t == s.near && height_inside(maps, layer, hb, o + d * t)) {
        return box_face_hit(hb, o, d, t);
    }
    return height_hit(maps, layer, hb, o, d, t);
}

fn exit_from_inside(maps: texture_2d_array<f32>, layer: i32, hb: HeightBounds, o: vec3f, d: vec3f, steps: Steps) -> HeightHit {
    var miss: HeightHit;
    miss.found = false;
    let far = ray_box(o, d, height_box_min(hb), height_box_max(hb)).y;
    if (!(far > 0.0) || far >= BIG) { return miss; }
    let t = search_segment(maps, layer, hb, o, d, 0.0, far, steps, false);
    // Still inside where the ray leaves the box: out through the box face.
    if (t < 0.0) { return box_face_hit(hb, o, d, far); }
    return height_hit(maps, layer, hb, o, d, t);
}
