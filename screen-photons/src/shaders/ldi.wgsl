// ---------------------------------------------------------------------------------------------
// The screen-space march of a ray over a layered depth image (LDI): the WGSL twin of
// `src/march.rs` (same algorithm, names and constants; see its documentation).
//
// Its inputs are its own bindings, at @group(#{LDI_GROUP}) from @binding(#{LDI_FIRST_BINDING})
// (the technique's passes: group 2 from 0, `LDI_DEFS`; the conformance kernel: group 0 from 2):
//   ldi: LdiParams
//   ldi_layers: texture_2d_array<f32>    // xyz authored normal, w distance (0 = empty)
//   ldi_surfaces: texture_2d_array<f32>  // x object index, yz uv, w 1
//   refractor_layers, refractor_surfaces // the same for the LDI of the refractors alone
// and `ldi_kind(object)`, an object's material kind (0 diffuse, 1 metal, 2 glass): the scene's
// materials, unless the shader overrides it (`override fn screen_photons::ldi::ldi_kind`, as the
// conformance kernel does with kinds of its own).
// Every function reading an LDI takes `which`: LDI_SCENE (all objects) or LDI_REFRACTORS.
// ---------------------------------------------------------------------------------------------
#define_import_path screen_photons::ldi

#import gpu::prelude::ray_box
#import scene::shading::objects

struct LdiParams {
    // World to clip of the eye the LDI was peeled from (depth in [0, 1]).
    view_proj: mat4x4f,
    // Its inverse (clip to world).
    inv_view_proj: mat4x4f,
    // xyz: the eye.
    eye: vec4f,
    // Width, height, layers, the longest line in samples.
    size: vec4u,
    // x: tolerance (the paper's test), y: thickness (the DDA's), z: t_skip, w: unused.
    tests: vec4f,
    // The scene's bounding box (rays are marched only inside it).
    bounds_min: vec4f,
    bounds_max: vec4f,
};

@group(#{LDI_GROUP}) @binding(#{LDI_FIRST_BINDING} + 0u) var<uniform> ldi: LdiParams;
@group(#{LDI_GROUP}) @binding(#{LDI_FIRST_BINDING} + 1u) var ldi_layers: texture_2d_array<f32>;
@group(#{LDI_GROUP}) @binding(#{LDI_FIRST_BINDING} + 2u) var ldi_surfaces: texture_2d_array<f32>;
@group(#{LDI_GROUP}) @binding(#{LDI_FIRST_BINDING} + 3u) var refractor_layers: texture_2d_array<f32>;
@group(#{LDI_GROUP}) @binding(#{LDI_FIRST_BINDING} + 4u) var refractor_surfaces: texture_2d_array<f32>;

virtual fn ldi_kind(object: u32) -> u32 {
    // The material kind of `object` (scene::shading's MATERIAL_*: 0 diffuse, 1 metal, 2
    // glass). Not after a line comment: naga_oil 0.23's `virtual` rewrite also takes the
    // whitespace before it, which would join this line to the comment.
    return u32(objects[object].material.x);
}

struct LdiTexel {
    distance: f32,
    normal: vec3f,
    object: u32,
    // Metal or glass: a photon reflects or refracts here.
    specular: bool,
    // Glass: the side rule applies (side_ok).
    glass: bool,
};

const KIND_DIFFUSE: u32 = 0u;
const KIND_GLASS: u32 = 2u;

const LDI_SCENE: u32 = 0u;
const LDI_REFRACTORS: u32 = 1u;

fn ldi_texel(which: u32, x: u32, y: u32, layer: u32) -> LdiTexel {
    var a: vec4f;
    var object: u32;
    if (which == LDI_SCENE) {
        a = textureLoad(ldi_layers, vec2u(x, y), layer, 0);
        object = u32(textureLoad(ldi_surfaces, vec2u(x, y), layer, 0).x);
    } else {
        a = textureLoad(refractor_layers, vec2u(x, y), layer, 0);
        object = u32(textureLoad(refractor_surfaces, vec2u(x, y), layer, 0).x);
    }
    var t: LdiTexel;
    t.distance = a.w;
    t.normal = a.xyz;
    t.object = object;
    let kind = ldi_kind(object);
    t.specular = a.w > 0.0 && kind != KIND_DIFFUSE;
    t.glass = a.w > 0.0 && kind == KIND_GLASS;
    return t;
}

struct Segment {
    origin: vec3f,
    dir: vec3f,
    t_start: f32,
    t_end: f32,
    w_start: f32,
    w_end: f32,
    p_start: vec2f,
    p_end: vec2f,
    steps: u32,
    // false: no part of the ray is in view.
    visible: bool,
};

fn ldi_pixel_of(c: vec4f) -> vec2f {
    let size = vec2f(ldi.size.xy);
    return vec2f((c.x / c.w + 1.0) * 0.5 * size.x, (1.0 - c.y / c.w) * 0.5 * size.y);
}

// The part of the ray origin + t dir, t >= 0, inside the scene's bounding box (empty: x > y).
fn scene_range(origin: vec3f, dir: vec3f) -> vec2f {
    let r = ray_box(origin, dir, ldi.bounds_min.xyz, ldi.bounds_max.xyz);
    return vec2f(max(r.x, 0.0), r.y);
}

// Liang-Barsky clip of origin + t dir, t in [t_min, t_max], to the view frustum, projected.
fn clip_segment(origin: vec3f, dir: vec3f, t_min: f32, t_max: f32) -> Segment {
    var s: Segment;
    s.origin = origin;
    s.dir = dir;
    s.visible = false;
    let a = ldi.view_proj * vec4f(origin, 1.0);
    let b = ldi.view_proj * vec4f(dir, 0.0);
    var fa = array<f32, 6>(a.w + a.x, a.w - a.x, a.w + a.y, a.w - a.y, a.z, a.w - a.z);
    var fb = array<f32, 6>(b.w + b.x, b.w - b.x, b.w + b.y, b.w - b.y, b.z, b.w - b.z);
    var t0 = t_min;
    var t1 = t_max;
    for (var i = 0; i < 6; i++) {
        if (fb[i] == 0.0) {
            if (fa[i] < 0.0) { return s; }
        } else {
            let t = -fa[i] / fb[i];
            if (fb[i] > 0.0) { t0 = max(t0, t); } else { t1 = min(t1, t); }
        }
    }
    if (!(t0 < t1)) { return s; }
    let c0 = a + b * t0;
    let c1 = a + b * t1;
    if (!(c0.w > 0.0 && c1.w > 0.0)) { return s; }
    s.t_start = t0;
    s.t_end = t1;
    s.w_start = c0.w;
    s.w_end = c1.w;
    s.p_start = ldi_pixel_of(c0);
    s.p_end = ldi_pixel_of(c1);
    let span = abs(s.p_end - s.p_start);
    // At least one sample per 2 * tolerance of ray length (the minimum line length).
    let along = ceil((t1 - t0) / (2.0 * ldi.tests.x));
    s.steps = clamp(u32(min(max(ceil(max(span.x, span.y)), along), 1e6)), 1u, ldi.size.w);
    s.visible = true;
    return s;
}

// The ray parameter at screen fraction s (1/w is linear in screen space).
fn segment_t_at(s: Segment, f: f32) -> f32 {
    let u = f * s.w_start / ((1.0 - f) * s.w_end + f * s.w_start);
    return s.t_start + u * (s.t_end - s.t_start);
}

fn segment_fraction(s: Segment, k: u32) -> f32 {
    return (f32(k) + 0.5) / f32(s.steps);
}

fn segment_pixel(s: Segment, k: u32) -> vec2u {
    let p = s.p_start + (s.p_end - s.p_start) * segment_fraction(s, k);
    return min(vec2u(max(floor(p), vec2f(0.0))), ldi.size.xy - vec2u(1u));
}

// The point of the LDI's texel (x, y) at `distance` from the eye (on the pixel centre's ray).
fn ldi_point(x: u32, y: u32, distance: f32) -> vec3f {
    let size = vec2f(ldi.size.xy);
    let ndc = vec2f(2.0 * (f32(x) + 0.5) / size.x - 1.0, 1.0 - 2.0 * (f32(y) + 0.5) / size.y);
    let far = ldi.inv_view_proj * vec4f(ndc, 1.0, 1.0);
    return ldi.eye.xyz + normalize(far.xyz / far.w - ldi.eye.xyz) * distance;
}

// Where a ray that hit texel `texel` at parameter `t` (a sample's, up to a pixel's travel off
// the surface) meets the surface: its intersection with the texel's tangent plane when that
// lies within `reach` of t, else the sample's point projected onto the plane.
fn point_on_surface(origin: vec3f, dir: vec3f, t: f32, texel: LdiTexel, x: u32, y: u32, reach: f32) -> vec3f {
    let on = ldi_point(x, y, texel.distance);
    let n = normalize(texel.normal);
    let denom = dot(dir, n);
    let p = origin + dir * t;
    if (abs(denom) > 1e-4) {
        let tp = dot(on - origin, n) / denom;
        if (abs(tp - t) <= reach) { return origin + dir * tp; }
    }
    return p - n * dot(p - on, n);
}

// The ray length one sample spans.
fn segment_step(s: Segment) -> f32 {
    return (s.t_end - s.t_start) / f32(s.steps);
}

fn segment_distance(s: Segment, t: f32) -> f32 {
    return length(s.origin + s.dir * t - ldi.eye.xyz);
}

// Which surfaces may stop a ray: a ray outside glass enters glass through its front faces, one
// inside leaves through the back faces; diffuse and metal surfaces (opaque) stop a ray from
// either side, and a shadow ray stops at anything.
const SIDE_OUTSIDE: u32 = 0u;
const SIDE_INSIDE: u32 = 1u;
const SIDE_ANY: u32 = 2u;

fn side_of(inside: bool) -> u32 {
    return select(SIDE_OUTSIDE, SIDE_INSIDE, inside);
}

// A glass surface stops a ray only from the side the ray is on.
fn side_ok(texel: LdiTexel, dir: vec3f, side: u32) -> bool {
    return side == SIDE_ANY || !texel.glass || ((dot(texel.normal, dir) > 0.0) == (side == SIDE_INSIDE));
}

const TEST_TOLERANCE: u32 = 0u;
const TEST_THICKNESS: u32 = 1u;

// A hit of a march: the ray parameter, the LDI sample (layer, pixel), the sample's index, the
// gap |ray distance - layer distance| (the tolerance test's; 0 for the others).
struct LdiHit {
    t: f32,
    layer: u32,
    pixel: vec2u,
    step: u32,
    found: bool,
    gap: f32,
};

fn no_hit() -> LdiHit {
    return LdiHit(0.0, 0u, vec2u(0u), 0u, false, 0.0);
}

// The layer hit at sample k under `test` (tolerance: the layer nearest the ray's distance;
// thickness: the first layer overlapping), if any.
fn test_sample(which: u32, s: Segment, k: u32, test: u32, side: u32) -> LdiHit {
    var hit = no_hit();
    let f = segment_fraction(s, k);
    let t = segment_t_at(s, f);
    if (t < ldi.tests.z) { return hit; }
    let px = segment_pixel(s, k);
    let d = segment_distance(s, t);
    var lo = d;
    var hi = d;
    if (test == TEST_THICKNESS) {
        let half = 0.5 / f32(s.steps);
        let da = segment_distance(s, segment_t_at(s, max(f - half, 0.0)));
        let db = segment_distance(s, segment_t_at(s, min(f + half, 1.0)));
        lo = min(min(da, db), d);
        hi = max(max(da, db), d);
    }
    var best_gap = 3.0e38;
    for (var layer = 0u; layer < ldi.size.z; layer++) {
        let texel = ldi_texel(which, px.x, px.y, layer);
        if (texel.distance <= 0.0) { break; }
        if (!side_ok(texel, s.dir, side)) { continue; }
        if (test == TEST_TOLERANCE) {
            let gap = abs(d - texel.distance);
            if (gap < ldi.tests.x && gap < best_gap) {
                best_gap = gap;
                hit = LdiHit(t, layer, px, k, true, gap);
            }
        } else if (lo <= texel.distance + ldi.tests.y && hi >= texel.distance) {
            hit = LdiHit(t, layer, px, k, true, 0.0);
            break;
        }
    }
    return hit;
}

// The DDA march: samples in order, the thickness test, the first hit.
fn march_dda(which: u32, s: Segment, side: u32) -> LdiHit {
    if (!s.visible) { return no_hit(); }
    for (var k = 0u; k < s.steps; k++) {
        let hit = test_sample(which, s, k, TEST_THICKNESS, side);
        if (hit.found) { return hit; }
    }
    return no_hit();
}

// The paper's tolerance test walked in order: the sample a line's fragments would report
// after the reduction (what the line marcher computes in parallel, for rays a pass traces one
// per pixel: section 4's view rays). The first sample that hits, then each next one for as
// long as it hits with a smaller gap: the sample nearest the crossing (march.rs explains why).
fn march_tolerance(which: u32, s: Segment, side: u32) -> LdiHit {
    if (!s.visible) { return no_hit(); }
    for (var k = 0u; k < s.steps; k++) {
        var hit = test_sample(which, s, k, TEST_TOLERANCE, side);
        if (hit.found) {
            for (var j = k + 1u; j < s.steps; j++) {
                let next = test_sample(which, s, j, TEST_TOLERANCE, side);
                if (!next.found || next.gap >= hit.gap) { break; }
                hit = next;
            }
            return hit;
        }
    }
    return no_hit();
}

// Section 4's monotone march: the ray's next intersection is assumed to be in `layer`, the
// last one it crossed in `layer - 1`; the first sample, from t_skip on (the ray starts on a
// surface), at which the ray is behind the next layer or in front of the current one
// (march.rs's `march_monotone`).
fn march_monotone(which: u32, s: Segment, layer: u32) -> LdiHit {
    if (!s.visible || layer >= ldi.size.z) { return no_hit(); }
    for (var k = 0u; k < s.steps; k++) {
        let t = segment_t_at(s, segment_fraction(s, k));
        if (t < ldi.tests.z) { continue; }
        let px = segment_pixel(s, k);
        let d = segment_distance(s, t);
        let next = ldi_texel(which, px.x, px.y, layer);
        if (next.distance > 0.0 && d >= next.distance) {
            return LdiHit(t, layer, px, k, true, 0.0);
        }
        if (layer > 0u) {
            let current = ldi_texel(which, px.x, px.y, layer - 1u);
            if (current.distance > 0.0 && d <= current.distance) {
                return LdiHit(t, layer - 1u, px, k, true, 0.0);
            }
        }
    }
    return no_hit();
}

const NO_LAYER: u32 = 0xffffffffu;

// Section 5's in-out test over consecutive layer pairs (march.rs's `solid_layer_at`): the layer
// of a face turned to the eye whose next layer is a face turned away, with distance d between
// the two (the point is inside that solid), else NO_LAYER.
fn solid_layer_at(which: u32, x: u32, y: u32, d: f32) -> u32 {
    let view = normalize(ldi_point(x, y, 1.0) - ldi.eye.xyz);
    for (var l = 0u; l + 1u < ldi.size.z; l++) {
        let front = ldi_texel(which, x, y, l);
        let back = ldi_texel(which, x, y, l + 1u);
        if (front.distance <= 0.0 || back.distance <= 0.0) { break; }
        if (dot(front.normal, view) < 0.0 && dot(back.normal, view) > 0.0
            && front.distance <= d && d <= back.distance) {
            return l;
        }
    }
    return NO_LAYER;
}

// The paper's shadow ray with its in-out test (march.rs's `march_shadow`): the first sample
// within the tolerance of any surface, or inside a solid.
fn march_shadow(which: u32, s: Segment) -> LdiHit {
    if (!s.visible) { return no_hit(); }
    for (var k = 0u; k < s.steps; k++) {
        let hit = test_sample(which, s, k, TEST_TOLERANCE, SIDE_ANY);
        if (hit.found) { return hit; }
        let t = segment_t_at(s, segment_fraction(s, k));
        if (t < ldi.tests.z) { continue; }
        let px = segment_pixel(s, k);
        let layer = solid_layer_at(which, px.x, px.y, segment_distance(s, t));
        if (layer != NO_LAYER) { return LdiHit(t, layer, px, k, true, 0.0); }
    }
    return no_hit();
}
